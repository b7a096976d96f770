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
) -> npt.NDArray[np.uint8]:
    """The rimmed board; ``top_rim``: the rim drawn across its top; ``line_across``: a
    line of the rim's colour across the whole wall at the board's top row instead;
    ``over``: that many rows of the rim's colour over the board, between its sides;
    ``foot_rim``: the rim drawn across its foot; ``floor_lab``: the floor's colour."""
    lab = np.empty((H, W, 3), np.float64)
    lab[:] = WALL_LAB
    if over:
        lab[TOP - over : TOP, LEFT:RIGHT] = rim_lab
    lab[BOTTOM:] = floor_lab
    lab[TOP:BOTTOM, LEFT:RIGHT] = rim_lab
    lab[TOP + RIM : BOTTOM - RIM, LEFT + RIM : RIGHT - RIM] = PRINT_LAB
    if not foot_rim:
        lab[BOTTOM - RIM : BOTTOM, LEFT + RIM : RIGHT - RIM] = PRINT_LAB
    # the print's text: dark strokes every 12 rows
    for r in range(TOP + 8, BOTTOM - 8, 12):
        lab[r : r + 2, LEFT + 10 : RIGHT - 10, 0] -= 40.0
    if not top_rim:
        lab[TOP : TOP + RIM, LEFT + RIM : RIGHT - RIM] = PRINT_LAB
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
    # a rim of chroma about 15 (under RIM_CHROMA 20), 24 Lab from the print
    assert raised(board(rim_lab=(130.0, 117.0, 117.0))) == FOUND


def test_the_reach_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # the rim's line is BOTTOM - TOP = 140 rows (0.467 m at 300 px/m) over the foot
    monkeypatch.setattr(region, "RIM_REACH_M", (BOTTOM - TOP - 3) / 300.0 * DEPTH)
    assert raised(board()) == FOUND
    monkeypatch.setattr(region, "RIM_REACH_M", (BOTTOM - TOP + 3) / 300.0 * DEPTH)
    assert abs(raised(board()) - TOP) <= 1
