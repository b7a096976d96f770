"""The colour rescue's top past a band's edge behind the face
(:func:`~obstacle_fusion.vision.fused.region.raise_top_past_band`): a face standing in front
of a skirting steps far from the band beside its sides and little from the wall above it;
the walks up stop at the band's edge, though the face's own colour goes on (room
procedural/1113, with the rig: the rescue's top at the band's edge, height -43 %)."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import region
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import View

H, W = 240, 320
BOTTOM, LEFT, RIGHT = 200, 100, 220
BAND_TOP = 170  # the skirting's top edge: rows 170..199 beside the face
DEPTH = 1.0
WALL = (100, 138, 120)  # BGR: a greyish green
FACE = (110, 148, 142)  # the face: about 12 Lab from the wall
BAND = (156, 30, 36)  # a blue skirting
FLOOR = (120, 80, 130)


def _view() -> View:
    k = np.array([[300.0, 0.0, W / 2], [0.0, 300.0, H / 2], [0.0, 0.0, 1.0]])
    return View(CameraModel(k, np.zeros(5), W, H), Rig(), "level")


def _scene(top: int, band: bool = True) -> npt.NDArray[np.uint8]:
    """The wall, a skirting below BAND_TOP (``band``: else the wall down to the floor), the
    floor below BOTTOM, the face from ``top`` to BOTTOM in front of them."""
    img = np.empty((H, W, 3), np.float64)
    img[:] = WALL
    if band:
        img[BAND_TOP:BOTTOM] = BAND
    img[BOTTOM:] = FLOOR
    img[top:BOTTOM, LEFT:RIGHT] = FACE
    img += np.random.default_rng(0).normal(0, 2.0, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def _ay(img: npt.NDArray[np.uint8]) -> npt.NDArray[np.float32]:
    grey = img.mean(axis=2)
    ay = np.zeros(grey.shape, np.float32)
    ay[1:-1] = np.abs(grey[2:] - grey[:-2])
    return ay


def _raised(img: npt.NDArray[np.uint8], top: int) -> int:
    return region.raise_top_past_band(img, _view(), _ay(img), BOTTOM, top, LEFT, RIGHT, DEPTH)


def test_a_top_at_the_skirtings_edge_is_carried_up_to_the_face_s() -> None:
    img = _scene(120)
    assert abs(_raised(img, BAND_TOP) - 120) <= 2


def test_a_face_ending_at_the_skirtings_edge_keeps_its_top() -> None:
    """Above the band the wall lies between the sides too: no step beside."""
    img = _scene(BAND_TOP)
    assert _raised(img, BAND_TOP) == BAND_TOP


def test_no_band_edge_beside_the_top_no_move() -> None:
    """The same top with the wall beside it down to the floor: the walks' own stop is
    left alone (no change of background beside both sides at that row)."""
    img = _scene(120, band=False)
    assert _raised(img, BAND_TOP) == BAND_TOP

