"""A board framed by a coloured rim is measured to the rim's line across its top
(``method.RIM_LINE_TOP``, ``region.raise_top_to_rim``).

The room is new10's photo 3458 (hard, with the rig): a grey text panel inside a thin teal
rim, before a grey wall of nearly the panel's shade. The colour rescue's walks stopped at a
row of the text (top 164, the rim's line at 128) and the height came out 31 % short. The
drawn boards below try each limit of the rule.
"""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import method, region
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import View

from tests.vision_fixtures import room_size_errors

# A drawn board (rows TOP..BOTTOM, columns LEFT..RIGHT) with a RIM-wide teal rim round a
# grey print, before a grey wall; the walks are taken to have stopped at row FOUND.
H, W = 240, 320
TOP, BOTTOM, LEFT, RIGHT = 60, 200, 100, 200
RIM = 2
FOUND = 130
DEPTH = 1.0
WALL_LAB = (120.0, 128.0, 128.0)
PRINT_LAB = (110.0, 128.0, 128.0)
RIM_LAB = (130.0, 108.0, 104.0)
FLOOR_LAB = (90.0, 128.0, 128.0)
#: Rows of the rim's colour over the board that put the band's top RIM_THIN_ROWS (6) rows
#: over the rim's lowest row (the rim is 2 rows).
RIM_FOOT_ROWS_OVER = 5


def level_view() -> View:
    """A distortion-free camera with no pitch (the horizon at row H / 2)."""
    k = np.array([[300.0, 0.0, W / 2], [0.0, 300.0, H / 2], [0.0, 0.0, 1.0]])
    return View(CameraModel(k, np.zeros(5), W, H), Rig(), "level")


def board(
    rim_lab: tuple[float, float, float] = RIM_LAB,
    top_rim: bool = True,
    line_across: bool = False,
    over: int = 0,
    foot_rim: bool = True,
    floor_lab: tuple[float, float, float] = FLOOR_LAB,
    print_lab: tuple[float, float, float] = PRINT_LAB,
    top_lab: tuple[float, float, float] | None = None,
    gap: int = 0,
    run_on: int = 0,
) -> npt.NDArray[np.uint8]:
    """The rimmed board; ``top_rim``: the rim drawn across its top; ``line_across``: a
    line of the rim's colour across the whole wall at the board's top row instead;
    ``over``: that many rows of the rim's colour over the board, between its sides;
    ``foot_rim``: the rim drawn across its foot; ``floor_lab``: the floor's colour;
    ``print_lab``: the print's; ``top_lab``: the top rim's, if not the rim's; ``gap``:
    that many of its columns (from the middle) left the print's colour; ``run_on``: the top
    rim run on that many columns over the left side's SIDE_SKIP (3) into the 6 beside it."""
    lab = np.empty((H, W, 3), np.float64)
    lab[:] = WALL_LAB
    if over:
        lab[TOP - over : TOP, LEFT:RIGHT] = rim_lab
    lab[BOTTOM:] = floor_lab
    lab[TOP:BOTTOM, LEFT:RIGHT] = rim_lab
    if top_lab is not None:
        lab[TOP : TOP + RIM, LEFT:RIGHT] = top_lab
    if run_on:
        lab[TOP : TOP + RIM, LEFT - 3 - run_on : LEFT] = rim_lab
    lab[TOP + RIM : BOTTOM - RIM, LEFT + RIM : RIGHT - RIM] = print_lab
    if gap:
        mid = (LEFT + RIGHT) // 2
        lab[TOP : TOP + RIM, mid - gap // 2 : mid - gap // 2 + gap] = print_lab
    if not foot_rim:
        lab[BOTTOM - RIM : BOTTOM, LEFT + RIM : RIGHT - RIM] = print_lab
    # the print's text: dark strokes every 12 rows
    for r in range(TOP + 8, BOTTOM - 8, 12):
        lab[r : r + 2, LEFT + 10 : RIGHT - 10, 0] -= 40.0
    if not top_rim:
        lab[TOP : TOP + RIM, LEFT + RIM : RIGHT - RIM] = print_lab
    if line_across:
        lab[TOP : TOP + RIM, :] = rim_lab
    lab += np.random.default_rng(5).normal(0, 1.5, lab.shape)
    return cv2.cvtColor(np.clip(lab, 0, 255).astype(np.uint8), cv2.COLOR_LAB2BGR)


def raised(img: npt.NDArray[np.uint8]) -> int:
    return region.raise_top_to_rim(img, level_view(), BOTTOM, FOUND, LEFT, RIGHT, DEPTH)


def test_the_rim_line_is_the_board_top() -> None:
    assert abs(raised(board()) - TOP) <= 1


def test_no_rim_across_the_top_keeps_the_found_top() -> None:
    assert raised(board(top_rim=False)) == FOUND


def test_a_line_across_the_whole_wall_is_not_the_rim() -> None:
    # the line runs on beside the sides: the wall's, not the board's
    assert raised(board(line_across=True)) == FOUND


def test_a_band_thicker_than_a_rim_is_no_line() -> None:
    # a band of the rim's colour RIM_THIN_ROWS rows over the rim's lowest row: no
    # background closes a line over the board (fresh procedural 2120 hard: a light rim
    # before a wall of its colour, the wall read up to the view's top, -8 -> +40 %)
    assert raised(board(over=RIM_FOOT_ROWS_OVER)) == FOUND


def test_a_line_as_thin_as_the_limit_is_a_rim() -> None:
    # one row less: the band's top 5 rows over the rim's lowest, under RIM_THIN_ROWS
    assert abs(raised(board(over=RIM_FOOT_ROWS_OVER - 1)) - (TOP - 4)) <= 1


def test_a_grey_rim_is_no_rim() -> None:
    # a rim of no hue is any row of a print
    assert raised(board(rim_lab=(140.0, 128.0, 128.0))) == FOUND


def test_the_chroma_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # the drawn rim's chroma is about 32 (8-bit Lab)
    monkeypatch.setattr(region, "RIM_CHROMA", 35.0)
    assert raised(board()) == FOUND


def test_the_span_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "RIM_SPAN", 1.01)
    assert raised(board()) == FOUND


def test_the_beside_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # with no limit beside, the wall's line is taken for the board's rim
    monkeypatch.setattr(region, "RIM_BESIDE", 1.01)
    assert abs(raised(board(line_across=True)) - TOP) <= 1


def test_a_rimmed_text_panel_is_measured_to_its_rim() -> None:
    eh, ew = room_size_errors("photo", 3458, True)
    assert eh < 0.05 and ew < 0.05


def test_without_the_rim_the_text_row_is_the_top(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method, "RIM_LINE_TOP", False)
    eh, _ = room_size_errors("photo", 3458, True)
    assert eh > 0.25


def test_the_apart_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # the drawn rim is about 37 (Lab) from the print inside
    monkeypatch.setattr(region, "RIM_APART", 40.0)
    assert raised(board()) == FOUND


def test_the_match_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # no pixel of the top's line within 1 of the foot's rim (the noise's 1.5)
    monkeypatch.setattr(region, "RIM_MATCH", 1.0)
    assert raised(board()) == FOUND


def test_the_thin_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # the band 6 rows over the rim's lowest row is a line under a limit one row wider
    monkeypatch.setattr(region, "RIM_THIN_ROWS", 7)
    assert abs(raised(board(over=RIM_FOOT_ROWS_OVER)) - (TOP - RIM_FOOT_ROWS_OVER)) <= 1


def test_a_floor_of_the_rim_colour_is_no_rim() -> None:
    # no rim across the foot, the floor (from the contact row down) of the top line's
    # colour: the rim is read over the contact row, the floor's colour there is no rim
    assert raised(board(foot_rim=False, floor_lab=RIM_LAB)) == FOUND


def test_a_faintly_hued_rim_is_no_rim() -> None:
    # a rim of chroma about 18 (under RIM_CHROMA 20; a little more through the image's
    # 8 bits), 27 Lab from the print
    assert raised(board(rim_lab=(130.0, 115.0, 115.0))) == FOUND


def test_the_reach_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # the rim's line is BOTTOM - TOP = 140 rows (0.467 m at 300 px/m) over the foot
    monkeypatch.setattr(region, "RIM_REACH_M", (BOTTOM - TOP - 3) / 300.0 * DEPTH)
    assert raised(board()) == FOUND
    monkeypatch.setattr(region, "RIM_REACH_M", (BOTTOM - TOP + 3) / 300.0 * DEPTH)
    assert abs(raised(board()) - TOP) <= 1


# Each limit bracketed by two drawn boards, either side of it. The columns read between
# the sides are the 83 from LEFT + 9 to RIGHT - 9 (SIDE_SKIP + BESIDE_COLUMNS in).


def test_the_span_limit_is_bracketed() -> None:
    # a gap of 13 of the 83 columns (0.84 of the rim, over RIM_SPAN 0.8): the rim's line
    assert abs(raised(board(gap=13)) - TOP) <= 1
    # a gap of 20 (0.76): no line
    assert raised(board(gap=20)) == FOUND


def test_the_beside_limit_is_bracketed() -> None:
    # the line runs on 3 of the 12 columns beside (0.25, under RIM_BESIDE 0.34): the rim's
    assert abs(raised(board(run_on=3)) - TOP) <= 1
    # 5 of them (0.42): the wall's line
    assert raised(board(run_on=5)) == FOUND


def test_the_chroma_limit_is_bracketed() -> None:
    # a rim of chroma 21 (over RIM_CHROMA 20; 18 is not, test above) is one
    assert abs(raised(board(rim_lab=(130.0, 113.0, 113.0))) - TOP) <= 1


def test_the_apart_limit_is_bracketed() -> None:
    # a rim 23 (Lab) from the print inside (over RIM_APART 20) is one ...
    assert abs(raised(board(rim_lab=(110.0, 112.0, 112.0))) - TOP) <= 1
    # ... 17 from it (a print of a hue near the rim's) is not
    near = (110.0, 124.0, 124.0)
    assert raised(board(rim_lab=(110.0, 112.0, 112.0), print_lab=near)) == FOUND


def test_the_match_limit_is_bracketed() -> None:
    # the top rim 11 (Lab) from the foot's (within RIM_MATCH 15 with the noise and the
    # image's 8 bits): its line
    assert abs(raised(board(top_lab=(130.0, 108.0, 115.0))) - TOP) <= 1
    # 14 from it: no line (the noise puts over a fifth of its columns past 15)
    assert raised(board(top_lab=(130.0, 108.0, 118.0))) == FOUND
