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


def _ay(at_end: float) -> np.ndarray:
    """|d/dy| of a face (columns 100-200) whose top edge (row 50) has strength 100 and a
    row 54 of strength ``at_end`` (the rows between: nothing)."""
    ay = np.zeros((120, 300), np.float32)
    ay[50, 100:201] = 100.0
    ay[54, 100:201] = at_end
    return ay


def test_the_sides_end_is_a_corner_only_where_an_edge_runs_there() -> None:
    assert refine.ENDS_NEED_EDGE and refine.ENDS_EDGE_SHARE == 0.1
    # the sides end at 54.4: a top face's front edge there (11 % of the top's) is a corner
    assert refine.edge_at_ends(_ay(11.0), 100, 200, 50, 54.4)
    # ... the face's colour running on unbroken (9 %): the sides faded, no corner
    assert not refine.edge_at_ends(_ay(9.0), 100, 200, 50, 54.4)
    # the rows read are the two round the end (53.9: rows 53 and 54)
    assert refine.edge_at_ends(_ay(11.0), 100, 200, 50, 53.9)
    assert not refine.edge_at_ends(_ay(11.0), 100, 200, 50, 55.2)


#: |d/dy| of a blurred top edge (row 50) a row either side and on: 3 rows either way still
#: hold its own response (12 % of it two rows off).
BLUR_TAIL = {0: 100.0, 1: 50.0, 2: 12.0, 3: 3.0}


def _blurred_ay(front: float = 0.0, front_row: int = 52) -> np.ndarray:
    """|d/dy| of the face of :func:`_ay` with a blurred top edge (BLUR_TAIL round row 50)
    and a front top edge of strength ``front`` on row ``front_row`` over it."""
    ay = np.zeros((120, 300), np.float32)
    for d, v in BLUR_TAIL.items():
        ay[50 + d, 100:201] = v
        ay[50 - d, 100:201] = v
    ay[front_row, 100:201] += front
    return ay


def test_the_top_edge_s_own_blur_passes_for_an_edge_at_the_ends() -> None:
    """A known limit (review of session 42): the sides ending 2.2 rows under a blurred top
    (rows 52 and 53 read) meet the top edge's own tail there (12 % of it) and pass for a
    corner with no front edge at all; 3 rows and more under it they do not. Reading a
    row less its mirror over the top (ENDS_TOP_BLUR_ROWS 3) made the test fail there but
    cost thin top faces whose front merges with the top (README, tried and dropped)."""
    assert refine.edge_at_ends(_blurred_ay(), 100, 200, 50, 52.2)
    assert not refine.edge_at_ends(_blurred_ay(), 100, 200, 50, 53.2)
    assert (refine.ENDS_SIDE_SKIP_PARTS, refine.ENDS_MIN_COLUMNS) == (10, 3)


def test_the_sides_end_needs_no_edge_when_switched_off(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(refine, "ENDS_NEED_EDGE", False)
    assert refine.edge_at_ends(_ay(0.0), 100, 200, 50, 54.4)


def test_sides_fading_against_a_wall_of_the_face_s_shade_keep_the_top() -> None:
    """procedural/3088 ordinary, with the rig: the box's sides fade three rows under its
    top where a skirting of the face's shade stands behind them; the top stays on the
    front top edge (-6.3 % high without the rule, within 2 % with it)."""
    from obstacle_fusion.sim.room_scene import render_room
    from obstacle_fusion.vision.camera import CameraModel
    from obstacle_fusion.vision.measure import Measurer

    cam = CameraModel.paper(500, 375)
    image, truth, spec = render_room("procedural", 3088, False, cam)
    res = Measurer(cam, spec.rig).measure(image, truth["range_m"])
    assert res.height_m is not None
    assert abs(res.height_m / truth["height_m"] - 1) < 0.02
