"""The C projection of a BGR frame on one channel (channel.face_floor_grey's) gives
cv2.transform's integers: on every 8-bit colour, odd sizes, row strides and the fallback."""

from __future__ import annotations

from typing import Any

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import channel
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import View

cmiddle = pytest.importorskip("obstacle_fusion.vision.fused._cmiddle")
needs_agreement = pytest.mark.skipif(
    channel._c_project3 is None, reason="OpenCV's build here rounds otherwise (no FMA)"
)


def rows(seed: int, n: int = 4) -> list[npt.NDArray[np.float32]]:
    """Rows as _turned makes them: weights of luminance length, a non-negative offset."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        w = rng.normal(size=3)
        w *= 0.6654 / np.linalg.norm(w)
        out.append(np.array([[*w, -255.0 * min(0.0, float(w[w < 0].sum()))]], np.float32))
    out.append(np.array([[0.3, 0.6, -0.2, 51.0]], np.float32))  # the probe's: ties
    out.append(np.array([[0.0, 0.5, 0.5, 0.0]], np.float32))  # a zero weight
    return out


def project(image: npt.NDArray[Any], matrix: npt.NDArray[np.float32]) -> npt.NDArray[np.uint8]:
    out = np.full(image.shape[:2], 7, np.uint8)
    cmiddle.project3(image, *(float(v) for v in matrix[0]), out)
    return out


@needs_agreement
def test_every_colour_is_opencv_s() -> None:
    v = np.arange(1 << 24, dtype=np.uint32)
    img = np.stack([v & 255, (v >> 8) & 255, v >> 16], -1).astype(np.uint8).reshape(4096, 4096, 3)
    for matrix in rows(1, 2)[-3:]:
        assert np.array_equal(project(img, matrix), cv2.transform(img, matrix))


@needs_agreement
@pytest.mark.parametrize(
    "shape", [(0, 5), (5, 0), (1, 1), (1, 3), (2, 5), (7, 13), (31, 4), (9, 502)]
)
def test_edge_sizes_and_strides(shape: tuple[int, int]) -> None:
    rng = np.random.default_rng(sum(shape))
    big = rng.integers(0, 256, (shape[0] + 3, shape[1] + 9, 3), np.uint8)
    for matrix in rows(sum(shape)):
        for img in (big[: shape[0], : shape[1]], big[1 : shape[0] + 1, 5 : shape[1] + 5]):
            if img.size == 0:
                out = np.empty(img.shape[:2], np.uint8)
                cmiddle.project3(img, *(float(v) for v in matrix[0]), out)
                continue
            assert np.array_equal(project(img, matrix), cv2.transform(img, matrix)), shape


def test_what_it_does_not_take_is_an_error() -> None:
    img = np.zeros((4, 6, 3), np.uint8)
    out = np.zeros((4, 6), np.uint8)
    with pytest.raises(ValueError):
        cmiddle.project3(img[:, ::2], 0.1, 0.2, 0.3, 0.0, out[:, :3])  # pixels not packed
    with pytest.raises(ValueError):
        cmiddle.project3(img, 0.1, 0.2, 0.3, 0.0, out[:3])  # another size
    with pytest.raises(ValueError):
        cmiddle.project3(img, 0.1, 1e-9, 0.3, 0.0, out)  # a weight too small to be exact
    with pytest.raises(ValueError):
        cmiddle.project3(img, 0.1, 0.2, 0.3000000001, 0.0, out)  # not a float32
    assert not out.any()


def test_face_floor_grey_is_the_same_with_and_without_c(monkeypatch: pytest.MonkeyPatch) -> None:
    view = View(CameraModel.paper(500, 375), Rig(camera_pitch_deg=6.0), "level")
    rng = np.random.default_rng(3)
    img = np.zeros((375, 500, 3), np.uint8)
    img[:, :] = (90, 140, 60)  # a green face ...
    img[200:] = (120, 120, 125)  # ... on grey floor
    img = np.clip(img + rng.integers(-6, 7, img.shape), 0, 255).astype(np.uint8)
    with_c = channel.face_floor_grey(img, view, 200.0, 1.0)
    assert with_c is not img  # turned: the colour step is there
    monkeypatch.setattr(channel, "_c_project3", None)
    assert np.array_equal(channel.face_floor_grey(img, view, 200.0, 1.0), with_c)
    # a frame whose pixels are not packed goes to OpenCV, the same values
    wide = np.zeros((375, 500, 4), np.uint8)
    wide[..., :3] = img
    monkeypatch.undo()
    assert np.array_equal(channel.face_floor_grey(wide[..., :3], view, 200.0, 1.0), with_c)
