"""The refinement's side-face test: a side face lies between its corner and the depth
direction's vanishing point, and its bottom rises towards that point."""

from __future__ import annotations

import numpy as np
import pytest
from obstacle_fusion.vision.fused import refine
from obstacle_fusion.vision.fused.refine import _BottomProfile, _side_face

ROW = 300.0  # the front face's bottom line, v = ROW
CORNER = 160  # the bottom steps up 1.5 rows to the right of this column
EDGE = 200.0  # the face's right side as the search found it


def stepped_bottom() -> _BottomProfile:
    """A bottom edge straight up to CORNER, 1.5 rows higher from there out to EDGE."""
    cols = np.arange(98, 203)
    dev = np.where(cols > CORNER, -1.5, 0.0)
    strength = np.full(cols.size, 50.0, np.float32)
    return _BottomProfile(cols, strength, ROW + dev, dev, 50.0, (cols <= CORNER).tolist())


def right_side(vp: tuple[float, float, float]) -> float:
    ax = np.zeros((400, 400), np.int16)
    a, b = _side_face(ax, stepped_bottom(), ROW, 0.0, 100, 200, 200, 300, 1, EDGE, 0.0, vp)
    return a + b * ROW


def test_a_side_face_that_fits_the_vanishing_point_moves_the_side_in() -> None:
    # the box far left of the vanishing point, its foot just under the horizon: a side
    # face rising 1.5 rows over 40 columns is what the geometry gives
    assert right_side((420.0, ROW - 10.0, 20.0)) == pytest.approx(CORNER + 0.5, abs=0.6)


def test_a_side_face_reaching_past_the_vanishing_point_is_a_seam() -> None:
    # the face straddles the image's centre: no right side face can show
    assert right_side((150.0, ROW - 10.0, 20.0)) == EDGE


def test_no_right_side_face_shows_right_of_the_vanishing_point() -> None:
    # the corner itself right of the farthest vanishing point a yaw allows
    assert right_side((130.0, ROW - 10.0, 20.0)) == EDGE


def test_a_side_face_rising_too_little_for_its_width_is_a_seam() -> None:
    # the vanishing point right of the box but the foot far under the horizon: a side
    # face 40 columns wide would rise ~10 rows, not 1.5
    assert right_side((420.0, ROW - 60.0, 20.0)) == EDGE


def test_the_rise_share_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # expected rise here 40 * 25 / 280 = 3.6 rows: half of it is over 1.5, a third not
    vp = (420.0, ROW - 25.0, 20.0)
    assert right_side(vp) == EDGE
    monkeypatch.setattr(refine, "SIDE_FACE_RISE_SHARE", 0.3)
    assert right_side(vp) == pytest.approx(CORNER + 0.5, abs=0.6)
