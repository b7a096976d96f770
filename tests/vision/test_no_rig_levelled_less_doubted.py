"""With no rig, the face found in the view levelled for the pitch its sides read,
disagreeing with the pitch-0 face on its size, is taken over it when surer by more than
LEVELLED_DOUBTED_MARGIN with each face's doubts applied, however the raw scores tie
(``measure.LEVELLED_LESS_DOUBTED``, ``measure._levelled_taken``): the levelled view is the
lens's geometry near enough, and the doubts the level guess's face carries (rivals near
its score) say the guess stood it on a wrong row.

The room is a diagnosis room (new10), measured with no rig. Photo 3454 (hard): a planked
box; the level face 13 columns short on one side and 8 rows high at 0.61 with
near_rivals and foot_above_contact (0.27 with them), the levelled face at 0.60 with no doubt, the pitch read 4.2
degrees against the true 4.1; 11.5 % -> 0.8 %. Only a levelled face on the pitch-0 face's
foot (within ROW_JITTER_PX) is taken so.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.fused.confidence import NEAR_RIVALS
from obstacle_fusion.vision.measure import _levelled_taken
from obstacle_fusion.vision.types import Measurement

from tests.vision_fixtures import room_size_errors


def _face(conf: float, doubts: list[str] | None = None, foot: float = 200.0) -> Measurement:
    return Measurement(
        True,
        "fused",
        2.0,
        box_px=(100.0, 100.0, 300.0, foot),
        confidence=conf,
        height_px=100.0,
        width_px=200.0,
        doubts=doubts or [],
    )


def test_the_planked_box_is_read_levelled() -> None:
    eh, ew = room_size_errors("photo", 3454, True, with_rig=False)
    assert eh < 0.03 and ew < 0.03


def test_without_the_rule_the_level_face_stays(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "LEVELLED_LESS_DOUBTED", False)
    eh, _ = room_size_errors("photo", 3454, True, with_rig=False)
    assert eh > 0.08


@pytest.mark.parametrize(("levelled", "taken"), [(0.39, True), (0.38, False)])
def test_the_margin(levelled: float, taken: bool) -> None:
    # the pitch-0 face at 0.4 with near_rivals (x 0.45) is 0.18 doubted; the levelled
    # face, no surer as measured, is taken over 0.18 + LEVELLED_DOUBTED_MARGIN 0.2
    assert _levelled_taken(_face(0.4, [NEAR_RIVALS]), _face(levelled)) is taken


@pytest.mark.parametrize(
    ("foot", "taken"), [(202.0, True), (198.0, True), (202.1, False), (197.9, False)]
)
def test_on_the_same_foot(foot: float, taken: bool) -> None:
    # ROW_JITTER_PX 2: the pitch read and the found foot's row give the camera height; a
    # levelled face on another foot (procedural 3499 hard: 4 rows up) is another reading
    assert _levelled_taken(_face(0.4, [NEAR_RIVALS]), _face(0.39, foot=foot)) is taken


def test_a_surer_levelled_face_is_taken_as_before(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "LEVELLED_LESS_DOUBTED", False)
    assert _levelled_taken(_face(0.4), _face(0.41))
    assert not _levelled_taken(_face(0.4), _face(0.4))
    assert not _levelled_taken(_face(0.4, [NEAR_RIVALS]), _face(0.39))


def test_the_levelled_faces_doubts_count_too() -> None:
    # both doubted alike: no margin between them
    assert not _levelled_taken(_face(0.4, [NEAR_RIVALS]), _face(0.39, [NEAR_RIVALS]))


def _box_face(conf: float, x0: float, x1: float, doubts: list[str] | None = None) -> Measurement:
    return Measurement(
        True,
        "fused",
        2.0,
        box_px=(x0, 100.0, x1, 200.0),
        confidence=conf,
        height_px=100.0,
        width_px=x1 - x0,
        doubts=doubts or [],
    )


@pytest.mark.parametrize(
    ("x0", "x1", "taken"),
    [
        (102.1, 297.9, False),  # both sides in by over ROW_JITTER_PX 2: a print on the face
        (102.0, 297.9, True),  # the left side within the jitter: the face read again
        (102.1, 298.0, True),  # the right side within the jitter
        (90.0, 297.9, True),  # wider on the left (photo 3454's case)
    ],
)
def test_a_levelled_face_inside_both_sides_is_a_print(x0: float, x1: float, taken: bool) -> None:
    found = _box_face(0.4, 100.0, 300.0, [NEAR_RIVALS])
    assert _levelled_taken(found, _box_face(0.39, x0, x1)) is taken


def test_without_the_inside_check_the_print_is_taken(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "LEVELLED_NOT_INSIDE", False)
    found = _box_face(0.4, 100.0, 300.0, [NEAR_RIVALS])
    assert _levelled_taken(found, _box_face(0.39, 110.0, 290.0))


def test_the_framed_print_stays_the_frames_face() -> None:
    # procedural 3247 hard (new5), no rig: the olive frame's face (0.4 % wide, framed_print)
    # against the text print 11 columns in on each side (-13 % wide)
    eh, ew = room_size_errors("procedural", 3247, True, with_rig=False)
    assert ew < 0.03 and eh < 0.09


def test_without_the_inside_check_the_framed_print_is_taken(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(measure, "LEVELLED_NOT_INSIDE", False)
    _, ew = room_size_errors("procedural", 3247, True, with_rig=False)
    assert ew > 0.1
