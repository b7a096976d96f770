"""The margin under a print brings a side in as well as out (`region.MARGIN_SIDES_IN`,
`MARGIN_IN_MIN_SHARE`, `MARGIN_IN_FLOOR`, `MARGIN_IN_FLOOR_ROWS`): where the margin's run
from the pair's middle ends well inside a side and the floor just under the foot shows
from there to that side, nothing stands on the contact row there; the side was what
stands farther back (its foot meets the floor higher up), the face's side is where its
margin ends.

The room is a diagnosis room (new5). Photo 3218 (hard, with the rig): a brick print in a
blue margin on gravel, a teal can standing farther back beside it, its foot on the row of
the print's lower edge: the edge search paired the print's left edge with the can's right
one (198-361), the outline round the print walked the margin out to the face's left side
(183) and kept the can's; w +52 %, with the rule +0.4 % (h +8.8 -> +0.5 %).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import region
from obstacle_fusion.vision.fused.region import widen_along_margin

from tests.vision.test_fused_outline import (
    BOTTOM,
    FACE,
    FLOOR,
    P_BOTTOM,
    P_LEFT,
    REACH,
    TOP,
    WALL,
    H,
    W,
    level_view,
)
from tests.vision.test_fused_rises_as_face import lab_shifted
from tests.vision_fixtures import room_size_errors

LEFT, FACE_RIGHT = 60, 200  # the face; its print inset 10 columns, its margin 6 rows
P_RIGHT = FACE_RIGHT - 10
FLOOR_UP = 20  # the floor farther back shows this many rows over the contact row
CAN = (40, 140, 230)  # BGR: an orange can farther back, right of the face
CAN_LEFT, CAN_RIGHT = 230, 260
CAN_FOOT = P_BOTTOM  # its foot on the row of the print's lower edge


def scene(behind: tuple[int, int, int] = FLOOR, can: bool = True) -> npt.NDArray[np.uint8]:
    """Wall over the floor; the floor seen farther back FLOOR_UP rows over the contact row
    (colour ``behind``); the face LEFT-FACE_RIGHT with a print of blocks inset in its
    margin; a can right of it whose foot stands on the print's lower edge's row."""
    rng = np.random.default_rng(7)
    img = np.empty((H, W, 3), np.float64)
    img[: BOTTOM - FLOOR_UP] = WALL
    img[BOTTOM - FLOOR_UP : BOTTOM] = behind
    img[BOTTOM:] = FLOOR
    img[TOP:BOTTOM, LEFT:FACE_RIGHT] = FACE
    for c in range(P_LEFT, P_RIGHT, 20):
        img[TOP + 10 : P_BOTTOM, c : min(c + 20, P_RIGHT)] = rng.uniform(0, 255, 3)
    if can:
        img[TOP - 20 : CAN_FOOT, CAN_LEFT:CAN_RIGHT] = CAN
    img += rng.normal(0, 4.0, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def walk(img: npt.NDArray[np.uint8], right: int = CAN_RIGHT) -> tuple[int, int] | None:
    return widen_along_margin(img, level_view(), P_BOTTOM, BOTTOM, P_LEFT, right, REACH)


def test_without_the_rule_the_cans_side_stays(monkeypatch: pytest.MonkeyPatch) -> None:
    """The scene is the failure: the margin walk moves the left side out to the face's and
    leaves the right one on the can."""
    monkeypatch.setattr(region, "MARGIN_SIDES_IN", False)
    sides = walk(scene())
    assert sides is not None
    assert abs(sides[0] - LEFT) <= 2 and sides[1] == CAN_RIGHT


def test_the_side_comes_in_to_where_the_margin_ends() -> None:
    sides = walk(scene())
    assert sides is not None
    assert abs(sides[0] - LEFT) <= 2 and abs(sides[1] - (FACE_RIGHT - 1)) <= 2


def test_a_side_on_the_margins_end_stays() -> None:
    sides = walk(scene(), FACE_RIGHT)
    assert sides is not None and sides[1] == FACE_RIGHT


@pytest.mark.parametrize(("apart", "cut"), [(10.0, True), (14.0, False)])
def test_the_floor_behind_within_margin_in_floor_is_the_floors(apart: float, cut: bool) -> None:
    """The floor seen over the contact row a shade off the floor under the foot: by 10
    (Lab), within MARGIN_IN_FLOOR (12), the same floor running on (the side comes in); by
    14 something else stands there (a low board of its own shade): the side stays."""
    behind = lab_shifted(FLOOR, (apart, 0.0, 0.0))
    sides = walk(scene(behind=behind, can=False))
    assert sides is not None
    assert (sides[1] < CAN_RIGHT) is cut
    assert not cut or abs(sides[1] - (FACE_RIGHT - 1)) <= 2


@pytest.mark.parametrize(("right", "cut"), [(213, True), (212, False)])
def test_a_side_only_a_little_past_the_margins_end_stays(right: int, cut: bool) -> None:
    """The margin's run ends at column 198 (its last column blurred off); a side at 213,
    15 columns past it, over MARGIN_IN_MIN_SHARE (0.1) of the pair's width (0.1 x 143 =
    14.3), comes in; at 212, 14 past it (0.1 x 142 = 14.2), stays: a side a few columns
    off is the refinement's to place (at 0.11, 15.7, the side at 213 stays too)."""
    sides = walk(scene(can=False), right)
    assert sides is not None
    assert (sides[1] < right) is cut


def test_the_floor_rows_are_read_under_the_foot(monkeypatch: pytest.MonkeyPatch) -> None:
    """Read MARGIN_IN_FLOOR_ROWS rows under the foot: reaching 30 rows down, the rows
    read include a dark band painted there (rows 210-229) and the floor is not the floor
    behind; 4 rows read only the floor."""
    img = scene(can=False).astype(np.float64)
    img[BOTTOM + 10 : BOTTOM + 30] = (20, 20, 20)
    img8 = img.astype(np.uint8)
    sides = walk(img8)
    assert sides is not None and sides[1] < CAN_RIGHT
    monkeypatch.setattr(region, "MARGIN_IN_FLOOR_ROWS", 30)
    sides = walk(img8)
    assert sides is not None and sides[1] == CAN_RIGHT


def test_the_floor_is_read_clear_of_the_foots_blur(monkeypatch: pytest.MonkeyPatch) -> None:
    """Each floor row its own grey: the floor read beyond the margin's end is the median
    of exactly the MARGIN_IN_FLOOR_ROWS (4) rows from EDGE_SKIP + 1 (3) under the foot,
    as every other floor reader's (one row more, one less, or one row nearer the foot,
    and the median moves)."""
    img = scene(can=False).astype(np.float64)
    img[BOTTOM:] = np.arange(H - BOTTOM, dtype=np.float64)[:, None, None] * 6.0 + 40.0
    img8 = np.clip(img, 0, 255).astype(np.uint8)
    read: list[tuple[int, int, int, int, npt.NDArray[np.float32]]] = []
    band = region._band

    def spy(
        image: npt.NDArray[np.uint8], view: object, r0: int, r1: int, c0: int, c1: int
    ) -> npt.NDArray[np.float32]:
        out = band(image, view, r0, r1, c0, c1)  # type: ignore[arg-type]
        if r0 > BOTTOM:  # the floor under the foot, not the margin's rows
            read.append((r0, r1, c0, c1, out))
        return out

    monkeypatch.setattr(region, "_band", spy)
    walk(img8)
    assert read, "the margin's end was not read against the floor"
    r0, r1, c0, c1, out = read[-1]
    lab = level_view().lab(img8, 0, H, c0, c1, 1).astype(np.float32)

    def median_rows(a: int, b: int) -> npt.NDArray[np.float32]:
        return np.asarray(np.median(lab[a:b].reshape(-1, 3), axis=0))

    got = np.median(np.asarray(out, np.float32).reshape(-1, 3), axis=0)
    start = BOTTOM + region.EDGE_SKIP + 1
    assert (r0, r1) == (start, start + 4)
    assert np.allclose(got, median_rows(start, start + 4), atol=0.6)
    for a, b in ((start - 1, start + 3), (start, start + 5), (start, start + 3)):
        assert not np.allclose(got, median_rows(a, b), atol=0.6)


def test_the_room_is_measured_to_the_faces_sides() -> None:
    eh, ew = room_size_errors("photo", 3218, True)
    assert ew < 0.05 and eh < 0.05


def test_without_the_rule_the_room_is_wide(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "MARGIN_SIDES_IN", False)
    assert room_size_errors("photo", 3218, True)[1] > 0.4


@pytest.mark.parametrize(("patch", "cut"), [(20, True), (22, False)])
def test_a_margin_resuming_past_a_gap_is_no_end(patch: int, cut: bool) -> None:
    """Past the margin's end (column 198, its last column blurred off) the margin's
    colour shows again over ``patch`` columns (``patch`` - 2 of them read as the margin's
    after the blur) of the 60 from 201 to the side: 20 leaves 42 of 60 off the margin,
    MARGIN_IN_OFF_SHARE (0.7), and the side comes in; 22 leaves 40: the margin resumes
    past a seam, its run's end is no side (the floor's median still under the limit)."""
    img = scene(can=False).astype(np.float64)
    img[P_BOTTOM:BOTTOM, 230 : 230 + patch] = FACE
    sides = walk(np.clip(img, 0, 255).astype(np.uint8))
    assert sides is not None
    assert (sides[1] < CAN_RIGHT) is cut
