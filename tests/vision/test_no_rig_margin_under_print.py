"""With no rig, a print whose frame runs on under the row tried is enclosed by its frame
(``method.MARGIN_UNDER_TRIED_ROW``, ``region.margin_under_print``).

Procedural 715 (a tuning room, ordinary) is a brick print in a dark green frame, 10-12 px
wide beside the print and 2-4 px over and under it. With no rig the print's lower edge is
the surest contact row; the margin under it was too thin for the fixed strips of
``region.enclose_by_margin`` and the one over it too thin for ``region.enclose_by_ring``
(which runs with a rig only): the print was answered, 12 % short in both sizes at
confidence 0.999. A face stands on the floor, and the floor runs on under its foot; a
thin band of the colour flanking the face, ending on the floor, is the frame's foot.
"""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import method, region

from tests.vision.test_fused_region import BOTTOM, TOP, level_view, scene
from tests.vision_fixtures import room_size_errors

WALL = (200, 120, 40)  # BGR: the room behind the face
FRAME = (60, 160, 60)  # the face's own paint
PRINT = (50, 60, 200)  # the print over most of it
COLUMNS = (100, 220)  # the face's sides
MARGIN = {"top": 2, "bottom": 4, "left": 8, "right": 8}


def framed(margin: dict[str, int] | None = None) -> npt.NDArray[np.uint8]:
    """A green face (columns COLUMNS, rows TOP..BOTTOM) on a grey floor before a blue wall,
    a red print over it inside a margin of the face's paint."""
    m = MARGIN if margin is None else margin
    img = scene(beyond=WALL)
    rng = np.random.default_rng(3)
    img[TOP:BOTTOM, : COLUMNS[0]] = WALL
    img[TOP:BOTTOM, COLUMNS[1] :] = WALL
    img[TOP:BOTTOM, COLUMNS[0] : COLUMNS[1]] = FRAME
    img[TOP + m["top"] : BOTTOM - m["bottom"], COLUMNS[0] + m["left"] : COLUMNS[1] - m["right"]] = (
        PRINT
    )
    noisy = img.astype(np.float64) + rng.normal(0, 3.0, img.shape)
    return np.clip(noisy, 0, 255).astype(np.uint8)


def frame_of(
    img: npt.NDArray[np.uint8], margin: dict[str, int] | None = None
) -> tuple[int, int, int, int] | None:
    """``region.margin_under_print`` on the print as found (its lower edge the row tried)."""
    m = MARGIN if margin is None else margin
    return region.margin_under_print(
        img,
        level_view(),
        BOTTOM - m["bottom"],
        TOP + m["top"],
        COLUMNS[0] + m["left"],
        COLUMNS[1] - m["right"],
    )


def test_the_frame_round_a_print_is_found_from_its_sides_and_foot() -> None:
    """Sharp edges (no blur): the bottom and right exclusive, exact; the top and left the
    first row and column without the margin's colour, one outside the face's own (see
    the blurred case below for why the frame is read so)."""
    assert frame_of(framed()) == (BOTTOM, TOP - 1, COLUMNS[0] - 1, COLUMNS[1])


@pytest.mark.parametrize("sigma", [0.8, 1.0, 1.3])
def test_on_a_blurred_image_the_frame_is_exact(sigma: float) -> None:
    """As rendered or photographed, each edge is blurred over a row or two: the margin's
    run stops short of the blend pixel, the first row or column without the margin's
    colour, and the face's edge lies inside that pixel. The frame's top and left are read
    on it, as its bottom is, so top, left and bottom come out exact (and the right within
    one column): taking top and left a row or column in (``+ 1``, as the rows inside the
    margin, the bottom being exclusive) reads every blurred frame one row short and one
    column narrow (procedural 715 o with no rig, the rule's scene: 1.8 -> 7.0 % off)."""
    margin = {"top": 3, "bottom": 3, "left": 6, "right": 10}
    img = cv2.GaussianBlur(framed(margin), (0, 0), sigma)
    found = frame_of(img, margin)
    assert found is not None
    bottom, top, left, right = found
    assert (bottom, top, left) == (BOTTOM, TOP, COLUMNS[0])
    assert COLUMNS[1] - 1 <= right <= COLUMNS[1]


def _at_the_image_s_left(columns: int) -> tuple[npt.NDArray[np.uint8], int]:
    """A framed print 4 columns of margin wide at the left, cropped so that ``columns``
    columns lie left of the print's found side; the print's left side in the crop."""
    margin = {**MARGIN, "left": 4}
    side = COLUMNS[0] + margin["left"]
    crop = side - columns
    return np.ascontiguousarray(framed(margin)[:, crop:]), crop


def _frame_at_the_left(columns: int) -> tuple[int, int, int, int] | None:
    img, crop = _at_the_image_s_left(columns)
    m = {**MARGIN, "left": 4}
    return region.margin_under_print(
        img,
        level_view(),
        BOTTOM - m["bottom"],
        TOP + m["top"],
        COLUMNS[0] + m["left"] - crop,
        COLUMNS[1] - m["right"] - crop,
    )


def test_a_side_margin_needs_its_columns_and_what_ends_it_in_the_image() -> None:
    """The side's margin is read from SIDE_MARGIN_COLUMNS columns past RING_SKIP, and must
    run RING_MIN on before another colour ends it: a print with fewer than RING_SKIP +
    SIDE_MARGIN_COLUMNS + RING_MIN (6) columns left of it in the image has no frame read."""
    least = region.RING_SKIP + region.SIDE_MARGIN_COLUMNS + region.RING_MIN
    assert least == 6
    found = _frame_at_the_left(least)
    assert found is not None and found[2] == 1  # the wall's last column, then the margin
    assert _frame_at_the_left(least - 1) is None


@pytest.mark.parametrize("name", ["SIDE_MARGIN_COLUMNS", "RING_MIN"])
def test_the_guard_is_what_refuses_the_print_at_the_edge(
    monkeypatch: pytest.MonkeyPatch, name: str
) -> None:
    """With either constant one less, 5 columns are enough (the same 3-column margin and
    one column of wall are read): the guard, not the runs, refused them."""
    monkeypatch.setattr(region, name, getattr(region, name) - 1)
    assert _frame_at_the_left(5) is not None


def test_a_face_on_the_floor_has_no_frame_under_it() -> None:
    """A plain face found whole: beside it the wall runs on past a margin's reach, and
    under its foot the floor runs on."""
    img = framed({"top": 0, "bottom": 0, "left": 0, "right": 0})
    img[TOP:BOTTOM, COLUMNS[0] : COLUMNS[1]] = PRINT
    assert frame_of(img, {"top": 0, "bottom": 0, "left": 0, "right": 0}) is None


def test_a_print_on_the_floor_with_its_margin_beside_only_is_no_frame_under() -> None:
    """The margin beside the print but none under it: the print's foot is the face's."""
    img = framed({**MARGIN, "bottom": 0})
    assert frame_of(img, {**MARGIN, "bottom": 0}) is None


@pytest.mark.parametrize("rows, found", [(2, True), (0, False)])
def test_a_frame_needs_its_margin_over_the_print_too(rows: int, found: bool) -> None:
    """A band of the sides' colour under the face but none over it (the print's top the
    face's: a seam's or a shade's blur beside a face over a band of the floor) is no
    frame: a frame is a ring round the print."""
    margin = {**MARGIN, "top": rows}
    assert (frame_of(framed(margin), margin) is not None) is found


def test_a_floor_of_the_margins_colour_is_no_margin_under() -> None:
    """The colour under the foot runs on past a margin's reach: a floor, not a frame."""
    img = framed()
    img[BOTTOM:] = FRAME
    assert frame_of(img) is None


@pytest.mark.parametrize("share, found", [(0.3, True), (0.2, False)])
def test_the_margin_under_must_end_within_its_reach(
    monkeypatch: pytest.MonkeyPatch, share: float, found: bool
) -> None:
    """The margin's colour 30 rows under a print 106 rows high (29 past the blur row
    skipped): the reach is int(share x 106) + 4 rows, 35 at 0.3 and 25 at 0.2 (the side
    margins, 8 columns, are within either reach)."""
    margin = {**MARGIN, "bottom": 12}
    img = framed(margin)
    img[BOTTOM : BOTTOM + 18, COLUMNS[0] : COLUMNS[1]] = FRAME
    monkeypatch.setattr(region, "MAX_MARGIN_SHARE", share)
    assert (frame_of(img, margin) is not None) is found


@pytest.mark.parametrize("agree, found", [(20.0, True), (5.0, False)])
def test_the_ring_tolerance_decides(
    monkeypatch: pytest.MonkeyPatch, agree: float, found: bool
) -> None:
    """The margin under the print lit a little otherwise than beside it (BGR +8: about
    8 Lab units off): one colour within RING_AGREE 20, not within 5."""
    img = framed()
    rows = slice(BOTTOM - MARGIN["bottom"], BOTTOM)
    img[rows, COLUMNS[0] : COLUMNS[1]] = np.clip(img[rows, COLUMNS[0] : COLUMNS[1]] + 8, 0, 255)
    monkeypatch.setattr(region, "RING_AGREE", agree)
    assert (frame_of(img) is not None) is found


def test_a_framed_brick_print_is_measured_as_its_frame_with_no_rig() -> None:
    eh, ew = room_size_errors("procedural", 715, False, with_rig=False)
    assert eh < 0.03 and ew < 0.03


def test_without_the_rule_the_print_is_answered(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method, "MARGIN_UNDER_TRIED_ROW", False)
    eh, ew = room_size_errors("procedural", 715, False, with_rig=False)
    assert eh > 0.1 and ew > 0.1
