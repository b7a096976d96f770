"""A last plank narrower than the walk's minimum move is still the face's when its top and
foot lines stand on the face's own rows and end together at its side, with the rig
(extent.NARROW_PLANK_ON_ROWS)."""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import extent
from obstacle_fusion.vision.fused.extent import widen_across_seams

from tests.vision_fixtures import gradients, room_size_errors

H, W = 240, 320
TOP, BOTTOM, LEFT, RIGHT = 80, 200, 60, 260  # the drawn face
PLANK = 14  # the last plank's columns: 0.07 of the face, under MIN_WIDEN_SHARE's 0.15


def plank_face(plank: int = PLANK, shelf: bool = False) -> npt.NDArray[np.uint8]:
    """Wall above row 130, floor below; a face whose last plank (left, ``plank`` columns)
    is darker than the rest, a dark seam between; ``shelf``: a dark line on the face's top
    row running on past its left side to the image's edge (a background line there)."""
    rng = np.random.default_rng(5)
    img = np.full((H, W), 170.0)
    img[130:] = 90
    img[TOP:BOTTOM, LEFT:RIGHT] = 135
    seam = LEFT + plank
    img[TOP:BOTTOM, LEFT:seam] = 118
    img[TOP:BOTTOM, seam - 1 : seam + 1] = 60
    if shelf:
        img[TOP - 1 : TOP + 1, :LEFT] = 60
    img += rng.normal(0, 1.5, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def widened(img: npt.NDArray[np.uint8], narrow: bool = True, plank: int = PLANK) -> int:
    """The left side after the walk from the seam (the search's side)."""
    ay, ax3, noise = gradients(img)
    left, right = widen_across_seams(
        ay, ax3, BOTTOM, TOP, LEFT + plank, RIGHT, noise, True, narrow=narrow
    )
    assert right == RIGHT
    return left


def test_a_narrow_last_plank_on_the_faces_rows_is_taken_in() -> None:
    assert abs(widened(plank_face()) - LEFT) <= 2


def test_without_the_switch_the_narrow_plank_is_left_out(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(extent, "NARROW_PLANK_ON_ROWS", False)
    assert widened(plank_face()) == LEFT + PLANK


def test_without_the_rig_the_narrow_plank_is_left_out() -> None:
    assert widened(plank_face(), narrow=False) == LEFT + PLANK


def test_a_top_line_running_on_past_the_side_is_no_plank_end() -> None:
    """The lines must end together at the side: a background line on the top row that
    runs on past it leaves the side where the search put it."""
    assert widened(plank_face(shelf=True)) == LEFT + PLANK


@pytest.mark.parametrize("plank, moved", [(2, False), (3, True)])
def test_the_plank_must_reach_past_the_walks_snap(plank: int, moved: bool) -> None:
    """Edges running on by at most SNAP_COLUMNS // 2 past the side are its own blur: a
    2-column strip (the walk ends 3 past the side) stays out, a 3-column one (4 past) is in."""
    assert extent.SNAP_COLUMNS // 2 == 3
    left = widened(plank_face(plank), plank=plank)
    assert (left == LEFT) == moved
    assert widened(plank_face(plank), narrow=False, plank=plank) == LEFT + plank


@pytest.mark.parametrize("plank", [4, 5, 6, 8])
def test_a_plank_of_a_few_columns_ends_at_its_own_side(plank: int) -> None:
    """A plank of 4-5 columns puts the seam's blurred edge (stronger than the plank's
    side) in the window searched: the side taken is the outermost reaching the need, at
    its peak (one column out of the drawn side, as for a wide plank), not the seam's blur."""
    assert widened(plank_face(plank), plank=plank) == LEFT - 1
    assert widened(plank_face(PLANK)) == LEFT - 1  # the 14-column plank: the same column


def test_the_outermost_side_reaching_the_need_is_taken() -> None:
    sides = np.array([1.0, 5.0, 7.0, 7.0, 3.0, 9.0, 20.0, 2.0], np.float32)
    # leftwards (step -1): the first column reaching 5, climbed inward to its peak (2)
    assert extent._outermost_peak(sides, 0, 6, -1, 5.0) == 2
    # rightwards: from the last column reaching 5 (6), nothing stronger further in
    assert extent._outermost_peak(sides, 0, 6, 1, 5.0) == 6
    assert extent._outermost_peak(sides, 0, 4, 1, 5.0) == 3
    assert extent._outermost_peak(sides, 0, 6, -1, 21.0) is None


def _side_over_rows(rows_present: int) -> int:
    """``_narrow_plank`` on drawn profiles: 100 rows, the side at 50 walked on to 44
    (leftwards); a vertical edge at column 45 (need 5) present over the face's top
    ``rows_present`` rows only (not down to the floor: it does not stand), the top and
    foot lines over 45-60 and none past 45."""
    sides = np.zeros(100, np.float32)
    sides[45] = 10.0
    ax_rows = np.zeros((100, 100), np.int16)
    ax_rows[:rows_present, 45] = 10
    line = np.zeros(100, bool)
    line[45:61] = True
    return extent._narrow_plank(ax_rows, sides, 50, 44, -1, 5.0, (line, line.copy()))


def test_a_side_not_down_to_the_floor_needs_the_lines_coverage() -> None:
    """A side that does not stand down to the floor must be present over
    LINES_SIDE_COVERAGE of the rows (with the lines ending there): 50 of 100 rows are
    enough, 49 are not."""
    assert extent.LINES_SIDE_COVERAGE == 0.5
    assert _side_over_rows(50) == 45
    assert _side_over_rows(49) == 50


def test_no_rig_never_reads_a_narrow_plank(monkeypatch: pytest.MonkeyPatch) -> None:
    """Through the whole measurement (FusedMethod under Measurer): with the rig given,
    photo 3090 ordinary's plank is read by ``_narrow_plank``; with no rig (the search's
    trials, the reading with the estimated rig as known, the rows read as with a rig) it
    never runs, the answer as with the switch off."""
    calls: list[int] = []
    narrow_plank = extent._narrow_plank

    def counted(*args: Any) -> int:
        calls.append(1)
        return narrow_plank(*args)

    monkeypatch.setattr(extent, "_narrow_plank", counted)
    room_size_errors("photo", 3090, False)
    assert calls
    calls.clear()
    on = room_size_errors("photo", 3090, False, with_rig=False)
    assert not calls
    monkeypatch.setattr(extent, "NARROW_PLANK_ON_ROWS", False)
    assert room_size_errors("photo", 3090, False, with_rig=False) == on


def test_photo_3090_with_the_rig_is_measured_whole() -> None:
    """photo/3090 ordinary (new2): a plank face whose darker leftmost plank, 15 of 153
    columns, was left out (-9.9 % wide)."""
    _, ew = room_size_errors("photo", 3090, False)
    assert ew < 0.03


def test_photo_3090_without_the_rule_is_a_plank_short(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(extent, "NARROW_PLANK_ON_ROWS", False)
    _, ew = room_size_errors("photo", 3090, False)
    assert ew > 0.08
