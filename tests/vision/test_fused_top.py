"""The fused method's top stage on drawn faces: a print inset in the face is no top face."""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import top
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import View

H, W = 240, 320
CY = 20.0  # the horizon: the lens looks down on the face, as on a low box
FACE_TOP, BOTTOM, LEFT, RIGHT = 80, 200, 60, 260  # the front face; cx = 160
INSET = 12  # the print's margin inside each side
PRINT_TOP = FACE_TOP + 4
DEPTH = 1.0


def high_view() -> View:
    k = np.array([[300.0, 0.0, W / 2], [0.0, 300.0, CY], [0.0, 0.0, 1.0]])
    return View(CameraModel(k, np.zeros(5), W, H), Rig(), "level")


def box(print_bottom: int = 190) -> npt.NDArray[np.uint8]:
    """Wall above the face, floor below; a light front face with a dark print inset by
    INSET columns from PRINT_TOP down to ``print_bottom``."""
    rng = np.random.default_rng(3)
    img = np.full((H, W), 90.0)
    img[BOTTOM:] = 60.0
    img[FACE_TOP:BOTTOM, LEFT:RIGHT] = 170.0
    img[PRINT_TOP:print_bottom, LEFT + INSET : RIGHT - INSET] = 110.0
    img += rng.normal(0, 1.5, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def gradients(
    img: npt.NDArray[np.uint8],
) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.int16], float]:
    """|d/dy|, d/dy and the noise level, as the method takes them."""
    dx = np.empty(img.shape, np.int16)
    dy = np.empty(img.shape, np.int16)
    cv2.spatialGradient(img, dx, dy)
    ay = np.abs(dy).astype(np.float32)
    return ay, dy, float(np.median(ay[::4, ::4])) / 0.6745 + 1.0


@pytest.mark.parametrize("inset_min, expected", [(3.0, FACE_TOP), (1000.0, PRINT_TOP)])
def test_a_prints_top_edge_is_not_the_front_top_edge(
    inset_min: float, expected: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Just under the face's top, the print's top edge is the lowest strong edge in reach;
    it ends INSET columns inside both sides, so the face's own top edge stays."""
    monkeypatch.setattr(top, "INSET_MIN_PX", inset_min)
    _, dy, noise = gradients(box())
    row, _ = top.front_top(high_view(), DEPTH, dy, BOTTOM, LEFT, RIGHT, FACE_TOP, noise)
    assert abs(row - expected) <= 1


def test_an_inset_print_is_not_a_receding_top_face() -> None:
    """A print centred on the principal point's column is narrower than the face by one
    scale about it, as a top face's back edge is; the row that scale predicts for the
    front edge holds only the print's own bottom edge, inset like its top: no top face."""
    scale = (RIGHT - LEFT - 2 * INSET) / (RIGHT - LEFT)
    front = int(round(CY + (PRINT_TOP - CY) / scale))
    ay, dy, _ = gradients(box(print_bottom=front))
    assert top.front_from_back(high_view(), DEPTH, ay, dy, BOTTOM, LEFT, RIGHT, PRINT_TOP) is None


def test_a_front_edge_from_side_to_side_makes_the_top_face() -> None:
    """The same narrow edge with a full-width edge on the predicted row (a top face's
    front): the front is taken there."""
    scale = (RIGHT - LEFT - 2 * INSET) / (RIGHT - LEFT)
    front = int(round(CY + (PRINT_TOP - CY) / scale))
    img = box(print_bottom=front).astype(np.float64)
    img[front:BOTTOM, LEFT:RIGHT] = 140.0  # below the predicted row, the front face
    ay, dy, _ = gradients(np.clip(img, 0, 255).astype(np.uint8))
    found = top.front_from_back(high_view(), DEPTH, ay, dy, BOTTOM, LEFT, RIGHT, PRINT_TOP)
    assert found is not None and abs(found[0] - front) <= 1


def lidded_box(lid_rows: int = 6) -> npt.NDArray[np.uint8]:
    """The face without print, under a lighter top face ``lid_rows`` rows thick."""
    img = box(print_bottom=PRINT_TOP).astype(np.float64)
    img[FACE_TOP - lid_rows : FACE_TOP, LEFT:RIGHT] = 220.0
    return np.clip(img, 0, 255).astype(np.uint8)


@pytest.mark.parametrize("slack, expected", [(0.0, FACE_TOP - 6), (30.0, FACE_TOP)])
def test_a_guessed_horizon_leaves_reach_for_the_front_top_edge(slack: float, expected: int) -> None:
    """A top face's back edge (the top found) at the guessed horizon: a level view leaves
    no reach below it; with the horizon possibly 30 rows higher (a pitch not read), the
    front top edge 6 rows down is found."""
    k = np.array([[300.0, 0.0, W / 2], [0.0, 300.0, FACE_TOP - 6.0], [0.0, 0.0, 1.0]])
    view = View(CameraModel(k, np.zeros(5), W, H), Rig(), "level")
    view.horizon_slack_px = slack
    _, dy, noise = gradients(lidded_box())
    row, _ = top.front_top(view, DEPTH, dy, BOTTOM, LEFT, RIGHT, FACE_TOP - 6, noise)
    assert abs(row - expected) <= 1


JOINT = FACE_TOP + 6  # a panel joint across the front face, a few rows under its top


def receding_box(back: int, joint: bool) -> npt.NDArray[np.uint8]:
    """The face without print under a lighter top face that recedes as seen from the
    lens: its back edge on row ``back`` spans the front's columns scaled by
    (back - CY) / (FACE_TOP - CY) about the principal point; with ``joint``, a dark line
    across the whole front face on row JOINT."""
    img = box(print_bottom=PRINT_TOP).astype(np.float64)
    s = (back - CY) / (FACE_TOP - CY)
    cx = W / 2
    for r in range(back, FACE_TOP):
        t = (r - back) / (FACE_TOP - back)  # 0 at the back edge, 1 at the front edge
        k = s + t * (1.0 - s)
        img[r, int(round(cx + k * (LEFT - cx))) : int(round(cx + k * (RIGHT - cx)))] = 220.0
    if joint:
        img[JOINT : JOINT + 2, LEFT:RIGHT] = 145.0
    return np.clip(img, 0, 255).astype(np.uint8)


@pytest.mark.parametrize("share, expected", [(top.FLAT_SHARE, FACE_TOP), (-1.0, JOINT + 2)])
def test_a_joint_under_a_front_top_edge_is_no_top_face(
    share: float, expected: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The top found is the front top edge (a receding top face above it): it runs on
    flat to both sides, where a top face's back edge over the joint would end well
    inside them, so the joint inside the front face is no front top edge (with no run
    on counted flat, the joint's lower edge would be taken)."""
    monkeypatch.setattr(top, "FLAT_SHARE", share)
    # (the joint's lower edge, under a dark line, is no step of its own either:
    # top.FRONT_EDGE_STEPS, tests/vision/test_fused_front_step.py; without that here)
    monkeypatch.setattr(top, "FRONT_EDGE_STEPS", False)
    _, dy, noise = gradients(receding_box(FACE_TOP - 8, joint=True))
    row, _ = top.front_top(high_view(), DEPTH, dy, BOTTOM, LEFT, RIGHT, FACE_TOP, noise)
    assert abs(row - expected) <= 1


def test_a_receding_top_faces_back_edge_keeps_the_front_edge_under_it() -> None:
    """The top found is the receding top face's back edge: it ends inside the sides as
    the front edge 8 rows down predicts, so that front edge is taken."""
    back = FACE_TOP - 8
    _, dy, noise = gradients(receding_box(back, joint=False))
    row, _ = top.front_top(high_view(), DEPTH, dy, BOTTOM, LEFT, RIGHT, back, noise)
    assert abs(row - FACE_TOP) <= 1


@pytest.mark.parametrize("outside, expected", [(top.OUTSIDE_PX, JOINT + 2), ((W, W + 1), FACE_TOP)])
def test_a_top_edge_running_on_past_the_sides_is_the_backgrounds(
    outside: tuple[int, int], expected: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The same face with the wall changing colour on the top edge's row beyond both
    sides: a line running on past the sides may stand behind a top face's back edge, so
    it does not make the top the front top edge (reading nothing beyond the sides, it
    would)."""
    monkeypatch.setattr(top, "OUTSIDE_PX", outside)
    monkeypatch.setattr(top, "FRONT_EDGE_STEPS", False)  # as above
    img = receding_box(FACE_TOP - 8, joint=True).astype(np.float64)
    img[:FACE_TOP, :LEFT] = 130.0
    img[:FACE_TOP, RIGHT:] = 130.0
    _, dy, noise = gradients(np.clip(img, 0, 255).astype(np.uint8))
    row, _ = top.front_top(high_view(), DEPTH, dy, BOTTOM, LEFT, RIGHT, FACE_TOP, noise)
    assert abs(row - expected) <= 1


def top_face_box(back: int, front: int) -> npt.NDArray[np.uint8]:
    """Wall above, floor below; a top face from its back edge on row ``back`` down to its
    front edge on row ``front`` (its sides receding towards the principal point as a
    top face's do), then the front face from ``front`` down to BOTTOM."""
    rng = np.random.default_rng(5)
    img = np.full((H, W), 90.0)
    img[BOTTOM:] = 60.0
    cx = W / 2
    for r in range(back, front):
        scale = (r - CY) / (front - CY)
        img[r, int(round(cx + (LEFT - cx) * scale)) : int(round(cx + (RIGHT - cx) * scale))] = 130.0
    img[front:BOTTOM, LEFT:RIGHT] = 170.0
    img += rng.normal(0, 1.5, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


@pytest.mark.parametrize("from_back, found", [(True, True), (False, False)])
def test_a_top_raised_to_the_back_edge_reaches_the_front_edge(from_back: bool, found: bool) -> None:
    """From a top raised up to a top face's back edge, the front edge lies further below
    it than from a top near the front edge (by 2 m / D, not 2 m / (D + 2 m), of the rows
    under the horizon): a top face 30 rows deep at 3 m is found only from the back."""
    back, front, depth = 80, 110, 3.0
    _, dy, noise = gradients(top_face_box(back, front))
    row, _ = top.front_top(
        high_view(), depth, dy, BOTTOM, LEFT, RIGHT, back, noise, from_back=from_back
    )
    assert (abs(row - front) <= 1) is found
    if not found:
        assert row < front - 3
