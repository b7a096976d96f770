"""A front top edge under the top is a step of its own (``top.FRONT_EDGE_STEPS``,
``top._front_step``): a top face lies at a level between the wall's and the front's, or,
lit from above, brighter than both; a band darker than both is the front's own dark line
under its top, and an edge much weaker than the top's is the top edge's blur tail or
ringing.

The room is a tuning room (procedural, seeds 2000-2099): procedural 2086 (hard) is a
face under a darker wall whose top edge's undershoot, a few rows under it, was taken for
the front top edge of a top face (height -12 %).
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


def face(
    wall: float, band: float, band_rows: int, front: float, lower: float = 0.0
) -> npt.NDArray[np.uint8]:
    """Wall above LOW_TOP, floor below LOW_BOTTOM; the face's top ``band_rows`` rows of
    ``band`` (a top face, or the front's own line under its top), the front ``front``
    below, stepping by ``lower`` five rows under the top; blurred as by the optics."""
    rng = np.random.default_rng(7)
    img = np.full((LOW_H, LOW_W), float(wall))
    img[LOW_BOTTOM:] = 60.0
    img[LOW_TOP:LOW_BOTTOM, LOW_LEFT:LOW_RIGHT] = front
    img[LOW_TOP : LOW_TOP + band_rows, LOW_LEFT:LOW_RIGHT] = band
    img[LOW_TOP + 5 : LOW_BOTTOM, LOW_LEFT:LOW_RIGHT] += lower
    img = cv2.GaussianBlur(img, (0, 0), 0.6)
    img += rng.normal(0, 1.0, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


@pytest.mark.parametrize("on", [True, False])
def test_a_dark_line_under_the_top_is_no_top_face(
    on: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A light wall, a dark line three rows thick under the top, the front lighter again:
    the line's lower edge is the lowest extremum in reach, but no top face is darker than
    both the wall and the front (without the rule it is taken)."""
    monkeypatch.setattr(top, "FRONT_EDGE_STEPS", on)
    row = low_box_front_row(face(200.0, 120.0, 3, 170.0))
    if on:
        assert abs(row - LOW_TOP) <= 1
    else:
        assert row >= LOW_TOP + 2


def test_a_top_face_brighter_than_both_is_taken() -> None:
    """A dark wall, a top face three rows thick brighter than the front: its front edge."""
    assert abs(low_box_front_row(face(90.0, 220.0, 3, 170.0)) - (LOW_TOP + 3)) <= 1


def test_a_top_face_between_wall_and_front_is_taken() -> None:
    """A staircase: a light wall, a top face three rows thick, the front darker still."""
    assert abs(low_box_front_row(face(200.0, 150.0, 3, 110.0)) - (LOW_TOP + 3)) <= 1


@pytest.mark.parametrize("share, expected", [(top.STAIR_MIN_SHARE, LOW_TOP), (0.02, LOW_TOP + 5)])
def test_a_weak_second_step_is_no_front_edge(
    share: float, expected: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Under a top edge falling by 80, a fall of 8 five rows down (a tenth of the top
    edge, below STAIR_MIN_SHARE) is the face's shading, not a top face's front edge
    (read on the share alone: running straight across, FAINT_STAIRS takes it, see
    test_fused_stair_across.py)."""
    monkeypatch.setattr(top, "FAINT_STAIRS", False)
    monkeypatch.setattr(top, "STAIR_MIN_SHARE", share)
    assert abs(low_box_front_row(face(200.0, 120.0, 0, 120.0, lower=-8.0)) - expected) <= 1


def test_the_shares_decide_at_their_limits() -> None:
    # the same sign as the top edge: a staircase's second step, STAIR_MIN_SHARE of it
    assert top._front_step(100.0, 16.0) == top.STEP
    assert top._front_step(100.0, 14.0) == top.WEAK
    # the opposite sign under a rising top edge: a bright top face's fall, BUMP_MIN_SHARE
    assert top._front_step(100.0, -5.0) == top.STEP
    assert top._front_step(100.0, -3.0) == top.WEAK
    # a rise under a falling top edge: a band darker than both, however strong
    assert top._front_step(-100.0, 90.0) == top.DIP


def test_an_undershoot_under_the_top_is_no_front_edge() -> None:
    eh, ew = room_size_errors("procedural", 2086, True)
    assert eh < 0.03 and ew < 0.05


def test_without_the_rule_the_undershoot_lowers_the_top(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(top, "FRONT_EDGE_STEPS", False)
    eh, _ = room_size_errors("procedural", 2086, True)
    assert eh > 0.1
