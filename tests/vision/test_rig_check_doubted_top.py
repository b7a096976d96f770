"""With the rig, one face read twice by the rig check keeps the rig's reading unless the
rig doubts its top for the band under it being unlike the face, the search, on the same
foot, stops the face lower with no doubt on its own top, and the band between the two
tops is not the colour of the face's side margins (``measure.CHECK_DOUBTED_TOP_LOWERS``,
``measure._doubted_top_lowered``, ``measure._band_frames_face``).

A synthetic case drives ``Measurer._checked_by_search`` with a made-up rig answer and
search answer (the search, the foot's band and the plausibility check stubbed) on a
drawn image: a grey background, an orange face (columns 100-300, rows 110-200); the rig's
top on the background at row 100, the search's on the face's top. Framed, the face is a
print inside a frame 10 px wide down its sides (rows 110-200) under the grey band: the
band between the tops has the margins' colour, and the rig's top (the frame's) stands. Photo 3480 ordinary (new10, a plank box under a
photographed skyline) is the room: the rig's top on the background 8 rows over the box
(+11.7 %, doubted `second_top_edge`, `top_runs_on`, `top_band_unlike_face`), the
search's on the box's front top edge (+1.2 %), the two boxes overlapping 0.91.
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused.confidence import (
    PITCH_UNREAD,
    SECOND_TOP,
    TOP_BAND_UNLIKE_FACE,
    TOP_RUNS_ON,
)
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import Measurement, Timer

from tests.vision_fixtures import room_size_errors

BAND = (60, 60, 60)  # the background (and the frame): grey
FACE = (40, 140, 220)  # the face (or the framed print): orange, BGR


def _image(frame: tuple[int, int, int] | None = None) -> npt.NDArray[np.uint8]:
    """The drawn room: the face under a grey background, or a print in a frame."""
    image = np.full((375, 500, 3), BAND, np.uint8)
    if frame is None:
        image[110:200, 100:300] = FACE
    else:
        image[110:200, 100:300] = frame  # its top margin the grey band over the face
        image[110:190, 110:290] = FACE
    return image


def _face(top: float, foot: float, confidence: float, doubts: list[str]) -> Measurement:
    return Measurement(
        detected=True,
        method="fused",
        range_m=2.0,
        distance_m=2.0,
        height_m=0.3 * (foot - top) / 100.0,
        width_m=0.6,
        box_px=(100.0, top, 300.0, foot),
        confidence=confidence,
        height_px=foot - top,
        width_px=200.0,
        doubts=doubts,
    )


def _checked(
    monkeypatch: pytest.MonkeyPatch,
    rig_face: Measurement,
    found: Measurement,
    image: npt.NDArray[np.uint8] | None = None,
) -> Measurement:
    """The rig check on a made-up pair: the search gives ``found``, standing on the rig's
    contact row and plausible."""
    monkeypatch.setattr(Measurer, "_searched", lambda *_a, **_k: found)
    monkeypatch.setattr(measure, "_foot_off_rig_row", lambda *_a, **_k: 0.0)
    monkeypatch.setattr(measure, "_plausible_face", lambda *_a, **_k: True)
    measurer = Measurer(CameraModel.paper(500, 375), Rig())
    fused: Any = SimpleNamespace(view=None)  # its view read only by the stubbed row
    drawn = _image() if image is None else image
    return measurer._checked_by_search(fused, rig_face, drawn, 2.0, Timer())


def test_a_doubted_top_gives_way_to_the_search_s_lower_one(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    rig_face = _face(100.0, 200.0, 0.06, [SECOND_TOP, TOP_BAND_UNLIKE_FACE])
    found = _face(110.0, 200.0, 0.3, [PITCH_UNREAD])  # overlap 0.9: one face read twice
    assert _checked(monkeypatch, rig_face, found) is found
    monkeypatch.setattr(measure, "CHECK_DOUBTED_TOP_LOWERS", False)
    assert _checked(monkeypatch, rig_face, found) is rig_face


@pytest.mark.parametrize("doubts", [[PITCH_UNREAD], [SECOND_TOP, TOP_RUNS_ON]])
def test_only_a_band_unlike_the_face_opens_the_rig_s_top(
    monkeypatch: pytest.MonkeyPatch, doubts: list[str]
) -> None:
    rig_face = _face(100.0, 200.0, 0.06, doubts)
    found = _face(110.0, 200.0, 0.3, [])
    assert _checked(monkeypatch, rig_face, found) is rig_face


@pytest.mark.parametrize("doubt", [SECOND_TOP, TOP_RUNS_ON, TOP_BAND_UNLIKE_FACE])
def test_a_doubted_search_top_is_no_better(monkeypatch: pytest.MonkeyPatch, doubt: str) -> None:
    rig_face = _face(100.0, 200.0, 0.06, [TOP_BAND_UNLIKE_FACE])
    found = _face(110.0, 200.0, 0.3, [doubt])
    assert _checked(monkeypatch, rig_face, found) is rig_face


def test_a_higher_search_top_is_not_taken(monkeypatch: pytest.MonkeyPatch) -> None:
    # the rule lowers a top only: a search raising it onto a line (photo 701 hard) stays out
    rig_face = _face(110.0, 200.0, 0.06, [TOP_BAND_UNLIKE_FACE])
    found = _face(100.0, 200.0, 0.3, [])
    assert _checked(monkeypatch, rig_face, found) is rig_face


@pytest.mark.parametrize(("limit", "taken"), [(14.0, False), (12.0, True)])
def test_a_band_framing_the_face_is_the_face_s(
    monkeypatch: pytest.MonkeyPatch, limit: float, taken: bool
) -> None:
    # a print whose side margins are 13 Lab from the band's grey (72 against 60): within
    # CHECK_FRAME_LAB the band is the frame's and the rig's top (the frame's) stands
    monkeypatch.setattr(measure, "CHECK_FRAME_LAB", limit)
    rig_face = _face(100.0, 200.0, 0.06, [TOP_BAND_UNLIKE_FACE])
    found = _face(110.0, 200.0, 0.3, [])
    image = _image(frame=(72, 72, 72))
    assert (_checked(monkeypatch, rig_face, found, image) is found) is taken


def test_the_shipped_frame_limit_keeps_a_frame(monkeypatch: pytest.MonkeyPatch) -> None:
    rig_face = _face(100.0, 200.0, 0.06, [TOP_BAND_UNLIKE_FACE])
    found = _face(110.0, 200.0, 0.3, [])
    image = _image(frame=BAND)
    assert _checked(monkeypatch, rig_face, found, image) is rig_face


@pytest.mark.parametrize(("lower_px", "taken"), [(2.0, True), (3.0, False)])
def test_the_top_must_move_more_than_an_edge_s_blur(
    monkeypatch: pytest.MonkeyPatch, lower_px: float, taken: bool
) -> None:
    # the search's top 2.5 rows lower: over CHECK_TOP_LOWER_PX 2 it is taken, over 3 not
    monkeypatch.setattr(measure, "CHECK_TOP_LOWER_PX", lower_px)
    rig_face = _face(100.0, 200.0, 0.06, [TOP_BAND_UNLIKE_FACE])
    found = _face(102.5, 200.0, 0.3, [])
    assert (_checked(monkeypatch, rig_face, found) is found) is taken


@pytest.mark.parametrize(("foot_px", "taken"), [(3.0, True), (2.0, False)])
def test_the_search_s_foot_must_be_the_rig_s(
    monkeypatch: pytest.MonkeyPatch, foot_px: float, taken: bool
) -> None:
    # the search's foot 2.5 rows off the rig's: within CHECK_SAME_FOOT_PX 3, not within 2
    monkeypatch.setattr(measure, "CHECK_SAME_FOOT_PX", foot_px)
    rig_face = _face(100.0, 200.0, 0.06, [TOP_BAND_UNLIKE_FACE])
    found = _face(110.0, 202.5, 0.3, [])
    assert (_checked(monkeypatch, rig_face, found) is found) is taken


@pytest.mark.rig_checked
def test_photo_3480_takes_the_box_s_front_top() -> None:
    eh, _ = room_size_errors("photo", 3480, False)
    assert eh < 0.03


@pytest.mark.rig_checked
def test_without_the_rule_photo_3480_keeps_the_background_s_top(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(measure, "CHECK_DOUBTED_TOP_LOWERS", False)
    eh, _ = room_size_errors("photo", 3480, False)
    assert eh > 0.1


@pytest.mark.parametrize(("found_top", "taken"), [(102.0, False), (102.5, True)])
def test_the_shipped_top_step(
    monkeypatch: pytest.MonkeyPatch, found_top: float, taken: bool
) -> None:
    # the shipped CHECK_TOP_LOWER_PX 2, its comparison strict: 2 rows lower is an edge's
    # blur (red at 1 or with ``<``), 2.5 rows a lower top (red at 3)
    rig_face = _face(100.0, 200.0, 0.06, [TOP_BAND_UNLIKE_FACE])
    found = _face(found_top, 200.0, 0.3, [])
    assert (_checked(monkeypatch, rig_face, found) is found) is taken


@pytest.mark.parametrize(
    ("found_foot", "taken"), [(203.0, True), (197.0, True), (203.5, False), (196.5, False)]
)
def test_the_shipped_foot_step(
    monkeypatch: pytest.MonkeyPatch, found_foot: float, taken: bool
) -> None:
    # the shipped CHECK_SAME_FOOT_PX 3 either way of the rig's foot: 3 rows off is the
    # same contact edge (red at 2 or with ``>=``), 3.5 rows another (red at 4, or with
    # the foot's offset read one way only)
    rig_face = _face(100.0, 200.0, 0.06, [TOP_BAND_UNLIKE_FACE])
    found = _face(110.0, found_foot, 0.3, [])
    assert (_checked(monkeypatch, rig_face, found) is found) is taken


@pytest.mark.parametrize(("frame", "taken"), [((74, 74, 74), False), ((72, 73, 74), True)])
def test_the_shipped_frame_limit(
    monkeypatch: pytest.MonkeyPatch, frame: tuple[int, int, int], taken: bool
) -> None:
    # side margins 15.0 Lab (8-bit OpenCV Lab) from the band's grey are a frame under the
    # shipped CHECK_FRAME_LAB 15 (red at 14 or with ``<``), 15.03 not (red at 16)
    rig_face = _face(100.0, 200.0, 0.06, [TOP_BAND_UNLIKE_FACE])
    found = _face(110.0, 200.0, 0.3, [])
    image = _image(frame=frame)
    assert (_checked(monkeypatch, rig_face, found, image) is found) is taken


def test_one_framed_side_is_enough(monkeypatch: pytest.MonkeyPatch) -> None:
    # the band is the face's where it matches the strip inside either side (red with
    # both required): a print framed down its left side only
    rig_face = _face(100.0, 200.0, 0.06, [TOP_BAND_UNLIKE_FACE])
    found = _face(110.0, 200.0, 0.3, [])
    image = _image()
    image[110:200, 100:110] = BAND
    assert _checked(monkeypatch, rig_face, found, image) is rig_face


SKY = (200, 150, 100)  # what stands behind the face over the band's middle: blue


@pytest.mark.parametrize(("grey_cols", "taken"), [(36, False), (34, True)])
def test_the_shipped_band_inset(
    monkeypatch: pytest.MonkeyPatch, grey_cols: int, taken: bool
) -> None:
    # a framed print (the frame the band's grey) under a band grey for ``30 + grey_cols``
    # columns in from either side and blue between: the band read between the sides
    # inset by the shipped CHECK_BAND_INSET 0.15 (columns 130-269) is grey at 36 (72 of
    # 140 columns: the frame's, red at 0.2) and blue at 34 (68 of 140: taken, red at 0.1)
    rig_face = _face(100.0, 200.0, 0.06, [TOP_BAND_UNLIKE_FACE])
    found = _face(110.0, 200.0, 0.3, [])
    image = _image(frame=BAND)
    image[100:110, 130 + grey_cols : 270 - grey_cols] = SKY
    assert (_checked(monkeypatch, rig_face, found, image) is found) is taken


def test_an_unread_band_keeps_the_rig_s_top(monkeypatch: pytest.MonkeyPatch) -> None:
    # the rig's top at 100.4, the search's at 102.5 (over 2 rows lower): no whole row
    # between them (rows 102 to 101) to test for a frame, and the rig's reading stands
    # (red where an unread band let the swap through)
    rig_face = _face(100.4, 200.0, 0.06, [TOP_BAND_UNLIKE_FACE])
    found = _face(102.5, 200.0, 0.3, [])
    assert _checked(monkeypatch, rig_face, found) is rig_face
    found = _face(103.5, 200.0, 0.3, [])  # one row read (102): grey, unlike the sides
    assert _checked(monkeypatch, rig_face, found) is found
