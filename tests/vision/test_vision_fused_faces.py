"""The fused method's face tests, one feature each: sides seen only against the wall,
floor seams that lean to the vanishing point, and a face's shade band by band."""

from __future__ import annotations

import logging

import cv2
import numpy as np
import pytest
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import FusedMethod
from obstacle_fusion.vision.fused.scoring import Candidate, band_face_share, sides_vertical
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import View

CAM = CameraModel.paper(500, 375)


def _rug_scene(depth: float, seed: int) -> tuple[np.ndarray, CameraModel, Rig, float, float]:
    """A box of the floor's own grey, standing at the far edge of a darker rug.

    Drawn straight in the levelled view (no distortion, no pitch): the face's bottom edge
    shows against the rug, its sides only above the line where the floor meets the
    wall; below it no side edge runs up from the floor-contact row. Returns the image,
    camera, rig and the face's true height and width.
    """
    w, h = 500, 375
    fx = fy = 420.0
    k = np.array([[fx, 0.0, 249.5], [0.0, fy, 187.5], [0.0, 0.0, 1.0]])
    cam = CameraModel(k, np.zeros(5), w, h)
    rig = Rig(camera_height_m=0.25, sonar_below_m=0.0)
    cy = 187.5
    rb = cy + fy * 0.25 / depth  # floor-contact row
    wall_row = cy + fy * 0.25 / (depth + 0.8)  # floor meets the wall 0.8 m behind
    height_m, width_m = 0.30, 0.36
    vt = rb - fy * height_m / depth
    ul = 249.5 - 0.5 * fx * width_m / depth
    ur = ul + fx * width_m / depth
    img = np.full((h, w), 185.0)  # wall
    rows = np.arange(h)[:, None] + 0.5
    cols = np.arange(w)[None, :] + 0.5
    img[(rows > wall_row).repeat(w, 1)] = 120.0  # floor
    img[(rows > rb).repeat(w, 1)] = 95.0  # the rug in front of the box
    face = (rows > vt) & (rows < rb) & (cols > ul) & (cols < ur)
    img[face] = 120.0
    rng = np.random.default_rng(seed)
    img = cv2.GaussianBlur(img, (0, 0), 0.7) + rng.normal(0.0, 3.0, img.shape)
    grey = np.clip(img, 0, 255).astype(np.uint8)
    return grey, cam, rig, height_m, width_m


@pytest.mark.parametrize(("depth", "seed"), [(1.1, 5), (1.6, 11), (2.2, 17)])
def test_box_in_the_floors_shade_is_measured_from_sides_seen_against_the_wall(
    depth: float, seed: int
) -> None:
    grey, cam, rig, height_m, width_m = _rug_scene(depth, seed)
    res = Measurer(cam, rig).measure(grey, rig.range_from_depth(depth))
    assert res.detected, res.reason
    assert res.height_m == pytest.approx(height_m, rel=0.03)
    assert res.width_m == pytest.approx(width_m, rel=0.03)


def _method() -> FusedMethod:
    return FusedMethod(View(CAM, Rig(camera_height_m=0.3, camera_pitch_deg=0.0), "level"))


def _edge_image(method: FusedMethod, columns_at: list[np.ndarray]) -> np.ndarray:
    """|d/dx| with a 2-column edge along each (row -> column) path."""
    h, w = CAM.height, CAM.width
    ax = np.zeros((h, w), np.int16)
    rows = np.arange(h)
    for cols in columns_at:
        c = np.round(cols).astype(int)
        ok = (c >= 1) & (c < w - 1)
        ax[rows[ok], c[ok]] = 200
        ax[rows[ok], c[ok] + 1] = 100
        ax[rows[ok], c[ok] - 1] = 100
    return ax


def test_sides_leaning_to_the_vanishing_point_are_no_face() -> None:
    """Plank seams through a patch's corners point at (cx, cy); a box's sides are columns."""
    method = _method()
    v = method.view
    rb, vt = int(v.cy + 120), int(v.cy + 104)
    ul, ur = int(v.cx + 25), int(v.cx + 45)
    cand = Candidate(1.0, rb, ul, ur, vt, 1.0)
    rows = np.arange(CAM.height, dtype=float)
    vertical = _edge_image(method, [np.full(CAM.height, ul), np.full(CAM.height, ur)])
    assert sides_vertical(method.view, vertical, cand)
    mid = 0.5 * (rb + vt)  # the column peak is where a seam crosses the strip's middle
    seams = [c + (rows - mid) * (c - v.cx) / (mid - v.cy) for c in (ul, ur)]
    assert not sides_vertical(method.view, _edge_image(method, seams), cand)


def test_sides_near_the_centre_column_are_not_judged() -> None:
    """Near the principal point a floor seam is nearly vertical too: no verdict, kept."""
    method = _method()
    v = method.view
    rb, vt = int(v.cy + 120), int(v.cy + 80)
    ul, ur = int(v.cx - 4), int(v.cx + 6)
    cand = Candidate(1.0, rb, ul, ur, vt, 1.0)
    rows = np.arange(CAM.height, dtype=float)
    mid = 0.5 * (rb + vt)
    seams = [c + (rows - mid) * (c - v.cx) / (mid - v.cy) for c in (ul, ur)]
    assert sides_vertical(method.view, _edge_image(method, seams), cand)


def test_a_band_of_wall_inside_a_candidate_face_is_seen_band_by_band() -> None:
    """A pair reaching past the face's weak side over floor and wall: the row means over
    the whole width still match the face's shade, one column band's do not."""
    rb, top = 100, 50
    grey = np.full((rb + 5, 240), 90, np.uint8)  # wall
    grey[80:, :] = 122  # floor, in the face's shade near the floor
    grey[top:rb, 100:160] = 120  # the face
    kf, noise = 4, 3.0
    tops = np.array([top], np.intp)
    pp = np.array([0], np.intp)

    def shares(ul: int, ur: int) -> float:
        m = max(1, (ur - ul) // 8)
        ps = [(ul, ur, ul + m, ur - m)]
        return float(band_face_share(grey, ps, tops, pp, rb, kf, noise)[0])

    assert shares(100, 160) > 0.95
    wide = shares(80, 160)
    assert wide < 0.7
    # the whole width's row means stay within the shade tolerance (the case bands catch)
    c0, c1 = 80 + 10, 160 - 10
    means = grey[top:rb, c0:c1].mean(axis=1)
    assert np.all(np.abs(means - 120.0) <= max(8.0, 0.08 * 120.0))


def test_debug_logging_of_every_stage_is_under_the_fused_logger(
    caplog: pytest.LogCaptureFixture,
) -> None:
    """`-vv` with logger obstacle_fusion.vision.fused shows the search, each pair's scores
    and the chosen face's confidence, though each stage logs from its own module."""
    image, cam, rig, _, _ = _rug_scene(1.2, 5)
    with caplog.at_level(logging.DEBUG, logger="obstacle_fusion.vision.fused"):
        res = Measurer(cam, rig).measure(image, rig.range_from_depth(1.2))
    assert res.detected
    by_module = {r.name: r.getMessage() for r in caplog.records}
    assert set(by_module) >= {
        "obstacle_fusion.vision.fused.search",
        "obstacle_fusion.vision.fused.scoring",
        "obstacle_fusion.vision.fused.confidence",
    }
    assert all(name.startswith("obstacle_fusion.vision.fused.") for name in by_module)
    assert "ambiguity" in by_module["obstacle_fusion.vision.fused.confidence"]
