"""One interface for both measurement methods: ``Measurer(camera, rig, method).measure(image, L)``.

Everything that depends only on the camera, the rig and the image size (undistortion and
levelling maps, buffers) is built once per image size and reused for every frame.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import asdict, dataclass, field
from typing import Any, Protocol

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.errors import UserError
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.rig import Rig, check_range

log = logging.getLogger(__name__)

FloatArray = npt.NDArray[np.float64]
Box = tuple[float, float, float, float]
Line = tuple[float, float, float, float]

METHODS = ("fused", "paper")


@dataclass
class Measurement:
    """One frame's answer. Pixel coordinates are in the input (distorted) image."""

    detected: bool
    method: str
    range_m: float
    distance_m: float | None = None  # sonar to face, forward (the obstacle's distance)
    height_m: float | None = None
    width_m: float | None = None
    box_px: Box | None = None  # x0, y0, x1, y1 of the front face
    confidence: float | None = 0.0  # None: the method has no such notion (paper)
    timings_ms: dict[str, float] = field(default_factory=dict)
    lines: list[Line] = field(default_factory=list)  # chosen edges, x0, y0, x1, y1
    height_px: float | None = None  # in the method's working view
    width_px: float | None = None
    reason: str = ""  # why nothing was detected

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["box_px"] = None if self.box_px is None else [round(v, 2) for v in self.box_px]
        d["lines"] = [[round(v, 2) for v in ln] for ln in self.lines]
        d["timings_ms"] = {k: round(v, 4) for k, v in self.timings_ms.items()}
        return d


class Timer:
    """Per-stage wall-clock times in ms, cheap enough for every frame."""

    def __init__(self) -> None:
        self.ms: dict[str, float] = {}
        self._t = time.perf_counter()

    def lap(self, name: str) -> None:
        now = time.perf_counter()
        self.ms[name] = self.ms.get(name, 0.0) + (now - self._t) * 1e3
        self._t = now


class View:
    """Per-camera (and per-rig) geometry of one working view, built once.

    ``kind`` "level": undistorted AND rotated to a virtual camera with no pitch (robot
    axes), so vertical world edges are vertical image columns and a face square to the
    robot images as an exact scaled copy. "plain": undistorted only (the paper's view).
    """

    def __init__(self, camera: CameraModel, rig: Rig, kind: str) -> None:
        self.camera = camera
        self.rig = rig
        self.kind = kind
        k = camera.camera_matrix.copy()
        k[0, 1] = 0.0
        if kind == "level":
            self.rotation = np.array(rig.camera_to_robot)  # camera -> level frame
            k[1, 2] = camera.cy - camera.fy * math.tan(rig.pitch_rad)
        else:
            self.rotation = np.eye(3)
        self.k = k
        self.fx, self.fy, self.cx, self.cy = k[0, 0], k[1, 1], k[0, 2], k[1, 2]
        self.map1, self.map2 = cv2.initUndistortRectifyMap(
            camera.camera_matrix, camera.dist_coeffs, self.rotation, k, camera.size, cv2.CV_16SC2
        )
        # input rows the first n view rows read (bilinear: the row below the lowest too),
        # so a colour frame is converted to grey only as far down as the remap looks
        lowest = np.maximum.accumulate(self.map1[:, :, 1].max(axis=1).astype(np.int64))
        self._src_rows = np.clip(lowest + 2, 1, camera.height).tolist()
        self.grey = np.empty((camera.height, camera.width), np.uint8)
        self.out = np.empty((camera.height, camera.width), np.uint8)

    def warp(self, image: npt.NDArray[Any], rows: int | None = None) -> npt.NDArray[np.uint8]:
        """Input frame (BGR or grey) to this view's grey image (a reused buffer).

        ``rows`` limits the work to the view's top rows when only they are needed.
        """
        n = self.out.shape[0] if rows is None else max(1, min(int(rows), self.out.shape[0]))
        if image.ndim == 3:
            k = self._src_rows[n - 1]
            src = cv2.cvtColor(image[:k], cv2.COLOR_BGR2GRAY, dst=self.grey[:k])
        else:
            src = image
        cv2.remap(
            src,
            self.map1[:n],
            self.map2[:n],
            cv2.INTER_LINEAR,
            dst=self.out[:n],
            borderMode=cv2.BORDER_REPLICATE,
        )
        return self.out[:n]

    def to_input(self, pts: npt.ArrayLike) -> FloatArray:
        """View pixels (N x 2) back to input-image pixels (through the lens distortion)."""
        p = np.asarray(pts, dtype=np.float64).reshape(-1, 2)
        rays = np.stack(
            [(p[:, 0] - self.cx) / self.fx, (p[:, 1] - self.cy) / self.fy, np.ones(len(p))], axis=1
        )
        cam = rays @ self.rotation  # R^T applied to row vectors: level -> camera frame
        return self.camera.project(cam)


class Method(Protocol):
    name: str

    def run(self, image: npt.NDArray[Any], range_m: float, timer: Timer) -> Measurement: ...


class Measurer:
    """Measure an obstacle's height and width from one frame and the sonar's range."""

    def __init__(
        self,
        camera: CameraModel,
        rig: Rig | None = None,
        method: str = "fused",
        min_confidence: float | None = None,
    ) -> None:
        if method not in METHODS:
            raise UserError(f"unknown method {method!r}; choose one of {', '.join(METHODS)}")
        if min_confidence is not None and not 0.0 <= min_confidence <= 1.0:
            raise UserError(f"min_confidence must be within 0..1, got {min_confidence}")
        self.camera = camera
        self.rig = rig if rig is not None else Rig()
        self.method = method
        self.min_confidence = min_confidence  # None: the method's default (fused only)
        self._per_size: dict[tuple[int, int], Method] = {}

    def _method_for(self, width: int, height: int) -> Method:
        key = (width, height)
        impl = self._per_size.get(key)
        if impl is None:
            cam = self.camera.scaled_to(width, height)  # CameraModelError if aspect differs
            if self.method == "paper":
                from obstacle_fusion.vision.paper import PaperMethod

                impl = PaperMethod(View(cam, self.rig, "plain"))
            else:
                from obstacle_fusion.vision.fused import FusedMethod

                fused = FusedMethod(View(cam, self.rig, "level"))
                if self.min_confidence is not None:
                    fused.min_confidence = self.min_confidence
                impl = fused
            self._per_size[key] = impl
        return impl

    def measure(self, image: npt.NDArray[Any], range_m: float) -> Measurement:
        if not isinstance(image, np.ndarray) or image.ndim not in (2, 3) or image.size == 0:
            raise UserError("image must be a non-empty grey or BGR array")
        if image.ndim == 3 and image.shape[2] not in (3, 4):
            raise UserError(f"image has {image.shape[2]} channels; give grey or BGR")
        if image.ndim == 3 and image.shape[2] == 4:
            image = cv2.cvtColor(image, cv2.COLOR_BGRA2BGR)
        if image.dtype != np.uint8:
            raise UserError(f"image must be 8-bit, got {image.dtype}")
        range_m = check_range(range_m)
        timer = Timer()
        impl = self._method_for(image.shape[1], image.shape[0])
        timer.lap("setup")
        result = impl.run(image, range_m, timer)
        result.timings_ms = dict(timer.ms)
        result.timings_ms["total"] = sum(timer.ms.values())
        return result


def parabola_peak(y0: float, y1: float, y2: float) -> float:
    """Sub-sample offset (-0.5..0.5) of a peak from three samples around it."""
    den = y0 - 2.0 * y1 + y2
    if den >= 0.0:
        return 0.0
    return float(np.clip(0.5 * (y0 - y2) / den, -0.5, 0.5))
