"""View.unseen_sides, point by point in Python, answers as the numpy sample grid did."""

from __future__ import annotations

from typing import Any

import numpy as np
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import _SIDE_NAMES, _SIDE_T, View


def grid_unseen(view: View, corners: Any, margin: float) -> list[str]:
    """The numpy version: all sides' samples in one array."""
    c = np.asarray(corners, dtype=np.float64).reshape(4, 2)
    bl, br, tr, tl = c
    start, end = np.stack([bl, br, tl, bl]), np.stack([tl, tr, tr, br])
    pts = start[:, None] + _SIDE_T * (end - start)[:, None]
    pts += np.array([(-margin, 0.0), (margin, 0.0), (0.0, -margin), (0.0, margin)])[:, None]
    h, w = view.map1.shape[:2]
    w_in, h_in = view.camera.size
    u = np.floor(pts[..., 0]).astype(np.int64)
    v = np.floor(pts[..., 1]).astype(np.int64)
    inside = (u >= 0) & (u < w) & (v >= 0) & (v < h)
    src = view.map1[np.where(inside, v, 0), np.where(inside, u, 0)].astype(np.int64)
    seen = (src[..., 0] >= 0) & (src[..., 0] < w_in) & (src[..., 1] >= 0) & (src[..., 1] < h_in)
    unseen = ~(inside & seen).all(axis=1)
    return [s for s, out in zip(_SIDE_NAMES, unseen.tolist(), strict=True) if out]


def test_random_faces_near_the_borders() -> None:
    rng = np.random.default_rng(7)
    some = 0
    for kind, pitch in (("level", 6.0), ("plain", 0.0)):
        view = View(CameraModel.paper(500, 375), Rig(camera_pitch_deg=pitch), kind)
        for i in range(3000):
            if i % 2:
                c = rng.uniform(-20.0, 520.0, (4, 2))
            else:  # whole and half pixels at the borders
                c = rng.integers(-6, 12, (4, 2)) + rng.choice([0, 490, 365], (4, 2)) + 0.5 * (i % 4)
            margin = float(rng.choice([4.0, 0.0, 2.5]))
            want = grid_unseen(view, c, margin)
            assert view.unseen_sides(c, margin) == want, c
            some += bool(want)
    assert 0 < some < 6000
