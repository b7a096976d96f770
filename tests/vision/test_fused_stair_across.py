"""A staircase step under the top is read along its row (``top.FAINT_STAIRS``,
``top._stair_across``): the front top edge is where two planes, each lit evenly, meet on
one straight line, so it steps alike from side to side; grain and a print's horizontal
structure come and go along the row. A faint step (STAIR_FAINT_SHARE up to
STAIR_MIN_SHARE of the top edge's peak) that runs straight across is taken; a weak one
(under STAIR_CHECK_SHARE) that steps against the top edge somewhere is not.

No tuning room has a faint front top edge missed (the 22 weak staircase extrema under
the tuning rooms' tops are grain: under STAIR_FAINT_SHARE or not straight): the rooms
here are synthetic, and a tuning room with a real staircase (procedural/115 hard, 0.23 of the
peak) must keep it.
"""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import top

from tests.vision_fixtures import (
    LOW_BOTTOM,
    LOW_H,
    LOW_LEFT,
    LOW_RIGHT,
    LOW_TOP,
    LOW_W,
    low_box_front_row,
    room_size_errors,
)


def face(lower: float, every_other: bool = False) -> npt.NDArray[np.uint8]:
    """A light wall (200) over a face (120) falling by 80 at LOW_TOP, then by ``lower``
    five rows under it: across the face, or (``every_other``) in every other block of
    15 columns only, as a print's structure; blurred as by the optics."""
    rng = np.random.default_rng(7)
    img = np.full((LOW_H, LOW_W), 200.0)
    img[LOW_BOTTOM:] = 60.0
    img[LOW_TOP:LOW_BOTTOM, LOW_LEFT:LOW_RIGHT] = 120.0
    below = img[LOW_TOP + 5 : LOW_BOTTOM, LOW_LEFT:LOW_RIGHT]
    if every_other:
        for c in range(0, LOW_RIGHT - LOW_LEFT, 30):
            below[:, c : c + 15] += lower
    else:
        below += lower
    img = cv2.GaussianBlur(img, (0, 0), 0.6)
    img += rng.normal(0, 1.0, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


@pytest.mark.parametrize("on", [True, False])
def test_a_faint_straight_staircase_is_a_front_top_edge(
    on: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A fall of 8 five rows under a top edge falling by 80 (0.1 of it, under
    STAIR_MIN_SHARE), alike from side to side: a top face's front edge (off: passed over)."""
    monkeypatch.setattr(top, "FAINT_STAIRS", on)
    row = low_box_front_row(face(-8.0))
    assert abs(row - (LOW_TOP + 5 if on else LOW_TOP)) <= 1


def test_a_faint_step_that_comes_and_goes_is_no_front_top_edge() -> None:
    """The same mean fall, made by every other block of columns falling twice as far:
    a print's structure, not a top face's front edge."""
    assert abs(low_box_front_row(face(-16.0, every_other=True)) - LOW_TOP) <= 1


def stair_dy(values: list[int], row: int = 5) -> npt.NDArray[np.int16]:
    """A signed d/dy whose row ``row`` holds ``values`` per group of 3 columns."""
    dy = np.zeros((12, 3 * len(values)), np.int16)
    dy[row] = np.repeat(np.array(values, np.int16), 3)
    return dy


def across(values: list[int], peak: float, step: str) -> str:
    dy = stair_dy(values)
    p = float(np.mean(values))
    return top._stair_across(dy, 5, 0, dy.shape[1], peak, p, step)


def test_the_faint_share_decides_at_its_limit() -> None:
    # straight across, a share of 0.09 is a faint staircase, 0.07 is grain
    assert across([9] * 8, 100.0, top.WEAK) == top.STEP
    assert across([7] * 8, 100.0, top.WEAK) == top.WEAK


def test_the_straight_share_decides_at_its_limit() -> None:
    # one group of eight weaker: 0.82 of the groups' mean runs straight, 0.73 does not
    assert across([10] * 7 + [8], 100.0, top.WEAK) == top.STEP
    assert across([10] * 7 + [7], 100.0, top.WEAK) == top.WEAK


def test_the_check_share_decides_at_its_limit() -> None:
    # a step stepping against the top edge in one group: dropped under STAIR_CHECK_SHARE
    assert across([32] * 7 + [-2], 100.0, top.STEP) == top.WEAK  # 0.28 of the peak
    assert across([37] * 7 + [-2], 100.0, top.STEP) == top.STEP  # 0.32
    # ... kept where every group steps with it; the opposite sign is not read here
    assert across([20] * 7 + [2], 100.0, top.STEP) == top.STEP
    assert across([-20] * 7 + [2], 100.0, top.STEP) == top.STEP


def test_a_real_staircase_is_kept() -> None:
    """procedural/115 hard: a top face whose front edge steps 0.23 of the top edge's peak,
    alike along the row (weakest group 0.78 of the mean)."""
    eh, ew = room_size_errors("procedural", 115, True)
    assert eh < 0.03 and ew < 0.05
