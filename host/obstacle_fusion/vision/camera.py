"""A calibrated pinhole camera with lens distortion (OpenCV's model).

The paper calibrates at full sensor resolution and measures at 500x375, so intrinsics must
move between resolutions correctly; and a live stream must not rebuild undistortion maps
per frame, so the maps are built once per model and cached on it.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.errors import UserError

FloatArray = npt.NDArray[np.float64]

#: Largest relative change of aspect ratio that scaled_to() accepts (1 %).
MAX_ASPECT_CHANGE = 0.01

#: Distortion vector lengths OpenCV understands (k1 k2 p1 p2 [k3 [k4 k5 k6 [s1..s4 [tx ty]]]]).
_DIST_LENGTHS = (4, 5, 8, 12, 14)

# The paper's intrinsics (section II), calibrated with MATLAB at the sensor's full size.
_PAPER_SIZE = (2592, 1944)
_PAPER_K = ((2378.0, 0.0, 1291.0), (0.0, 2374.0, 940.0), (0.0, 0.0, 1.0))
_PAPER_DIST = (-0.1356, 0.14432, -0.001021, 0.006401)


class CameraModelError(UserError):
    """A camera file or a camera/image combination that cannot be used as given."""


def _readonly(array: npt.ArrayLike, shape_ok: bool, what: str) -> FloatArray:
    out: FloatArray = np.array(array, dtype=np.float64, copy=True)
    if not shape_ok:
        raise CameraModelError(f"{what} has the wrong shape {out.shape}")
    out.setflags(write=False)
    return out


def _opencv_detail(exc: BaseException) -> str:
    """The readable part of an OpenCV error ("Parsing error: ... line 17 ..."), no paths."""
    # Some OpenCV builds wrap the cv2.error in a SystemError.
    cause = exc.__cause__ if isinstance(exc, SystemError) and exc.__cause__ else exc
    text = str(cause).strip()
    match = re.search(r"error: \(-?\d+:([^)]*)\) (.*)", text, re.S)
    if match:
        return f"{match.group(1)}: {' '.join(match.group(2).split())}"
    return text.splitlines()[-1] if text else "parse error"


@dataclass(frozen=True)
class CameraModel:
    """Intrinsics, distortion and the image size they belong to.

    ``dist_coeffs`` follow OpenCV's order: k1, k2, p1, p2[, k3, ...].
    """

    camera_matrix: FloatArray
    dist_coeffs: FloatArray
    width: int
    height: int
    rms_px: float | None = None

    def __post_init__(self) -> None:
        k = np.asarray(self.camera_matrix, dtype=np.float64)
        if k.shape != (3, 3):
            raise CameraModelError(f"camera_matrix must be 3x3, got shape {k.shape}")
        if not np.all(np.isfinite(k)) or k[0, 0] <= 0 or k[1, 1] <= 0:
            raise CameraModelError(f"camera_matrix needs finite, positive fx and fy: {k.tolist()}")
        d = np.asarray(self.dist_coeffs, dtype=np.float64).reshape(-1)
        if d.size not in _DIST_LENGTHS:
            raise CameraModelError(
                f"dist_coeffs must have one of {_DIST_LENGTHS} entries, got {d.size}"
            )
        if not np.all(np.isfinite(d)):
            raise CameraModelError(f"dist_coeffs must be finite: {d.tolist()}")
        if int(self.width) <= 0 or int(self.height) <= 0:
            raise CameraModelError(f"image size must be positive, got {self.width}x{self.height}")
        object.__setattr__(self, "camera_matrix", _readonly(k, True, "camera_matrix"))
        object.__setattr__(self, "dist_coeffs", _readonly(d, True, "dist_coeffs"))
        object.__setattr__(self, "width", int(self.width))
        object.__setattr__(self, "height", int(self.height))
        if self.rms_px is not None:
            object.__setattr__(self, "rms_px", float(self.rms_px))

    # Arrays make the generated __eq__/__hash__ unusable; compare by value instead.
    def __eq__(self, other: object) -> bool:
        if not isinstance(other, CameraModel):
            return NotImplemented
        return (
            self.width == other.width
            and self.height == other.height
            and self.rms_px == other.rms_px
            and np.array_equal(self.camera_matrix, other.camera_matrix)
            and np.array_equal(self.dist_coeffs, other.dist_coeffs)
        )

    def __hash__(self) -> int:
        return hash(
            (
                self.width,
                self.height,
                self.rms_px,
                self.camera_matrix.tobytes(),
                self.dist_coeffs.tobytes(),
            )
        )

    # ----------------------------------------------------------------- intrinsics
    @property
    def fx(self) -> float:
        return float(self.camera_matrix[0, 0])

    @property
    def fy(self) -> float:
        return float(self.camera_matrix[1, 1])

    @property
    def cx(self) -> float:
        return float(self.camera_matrix[0, 2])

    @property
    def cy(self) -> float:
        return float(self.camera_matrix[1, 2])

    @property
    def size(self) -> tuple[int, int]:
        """(width, height), the order OpenCV wants."""
        return (self.width, self.height)

    @property
    def fov_x_rad(self) -> float:
        """Full horizontal angle of view (the paper's alpha)."""
        return 2.0 * math.atan(self.width / (2.0 * self.fx))

    @property
    def fov_y_rad(self) -> float:
        """Full vertical angle of view (the paper's beta)."""
        return 2.0 * math.atan(self.height / (2.0 * self.fy))

    # ----------------------------------------------------------------- resolution
    def scaled_to(self, width: int, height: int) -> CameraModel:
        """The same camera seen at another resolution (same field of view).

        Pixel centres sit at integer coordinates, so the principal point maps as
        c' = (c + 0.5) * s - 0.5. Distortion is in normalised coordinates: unchanged.
        """
        width, height = int(width), int(height)
        if width <= 0 or height <= 0:
            raise CameraModelError(f"cannot scale a camera to {width}x{height}")
        if (width, height) == (self.width, self.height):
            return self
        sx = width / self.width
        sy = height / self.height
        if abs(sx / sy - 1.0) > MAX_ASPECT_CHANGE:
            raise CameraModelError(
                f"calibration is for {self.width}x{self.height} (aspect "
                f"{self.width / self.height:.4f}) but the image is {width}x{height} (aspect "
                f"{width / height:.4f}): a cropped or stretched stream needs its own "
                "calibration; calibrate at this resolution or capture at the calibrated aspect"
            )
        k = self.camera_matrix.copy()
        k[0, 0] *= sx
        k[0, 1] *= sx
        k[1, 1] *= sy
        k[0, 2] = (k[0, 2] + 0.5) * sx - 0.5
        k[1, 2] = (k[1, 2] + 0.5) * sy - 0.5
        rms = None if self.rms_px is None else self.rms_px * math.sqrt(sx * sy)
        return CameraModel(k, self.dist_coeffs.copy(), width, height, rms)

    def for_image(self, image: npt.NDArray[Any]) -> CameraModel:
        """This camera at the image's resolution; errors if the aspect ratio differs."""
        h, w = image.shape[:2]
        return self.scaled_to(w, h)

    # ----------------------------------------------------------------- the paper
    @classmethod
    def paper(cls, width: int = 500, height: int = 375) -> CameraModel:
        """The paper's calibrated camera (2592x1944, MATLAB), scaled to width x height."""
        full = cls(np.array(_PAPER_K), np.array(_PAPER_DIST), *_PAPER_SIZE)
        return full.scaled_to(width, height)

    # ----------------------------------------------------------------- files
    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> CameraModel:
        """Read an OpenCV FileStorage file (YAML/XML/JSON) as OpenCV's tools write it."""
        p = Path(path)
        if not p.is_file():
            what = "is a directory" if p.is_dir() else "does not exist"
            raise CameraModelError(
                f"camera file {p} {what}; make one with `obstacle-fusion calibrate`"
            )
        if p.stat().st_size == 0:
            raise CameraModelError(
                f"camera file {p} is empty; make one with `obstacle-fusion calibrate`"
            )
        try:
            fs = cv2.FileStorage(str(p), cv2.FILE_STORAGE_READ)
        except (cv2.error, SystemError) as exc:
            raise CameraModelError(
                f"camera file {p} is not a readable OpenCV FileStorage file "
                f"(YAML/XML/JSON): {_opencv_detail(exc)}"
            ) from None
        try:
            return cls._read(fs, p)
        except (cv2.error, SystemError) as exc:
            # Well-formed YAML with a malformed matrix (rows x cols != data) lands here.
            raise CameraModelError(
                f"camera file {p} is damaged: {_opencv_detail(exc)}; write it again with "
                "`obstacle-fusion calibrate`"
            ) from None
        finally:
            fs.release()

    @classmethod
    def _read(cls, fs: cv2.FileStorage, p: Path) -> CameraModel:
        """The model from an open FileStorage; CameraModelError naming what is missing."""
        if not fs.isOpened():
            raise CameraModelError(f"camera file {p} could not be opened by OpenCV")

        def need(key: str) -> Any:
            node = fs.getNode(key)
            if node.empty() or node.isNone():
                raise CameraModelError(
                    f"camera file {p} has no '{key}' (needs camera_matrix, "
                    "distortion_coefficients, image_width, image_height)"
                )
            return node

        k = need("camera_matrix").mat()
        d = need("distortion_coefficients").mat()
        width = need("image_width").real()
        height = need("image_height").real()
        if k is None or d is None:
            bad = "camera_matrix" if k is None else "distortion_coefficients"
            raise CameraModelError(f"camera file {p}: '{bad}' is not an OpenCV matrix")
        rms: float | None = None
        for key in ("rms", "avg_reprojection_error"):
            node = fs.getNode(key)
            if not node.empty() and node.isReal():
                rms = float(node.real())
                break
        if not (math.isfinite(width) and math.isfinite(height)):
            raise CameraModelError(f"camera file {p}: image size must be finite numbers")
        try:
            return cls(np.asarray(k), np.asarray(d).reshape(-1), int(width), int(height), rms)
        except CameraModelError as exc:
            raise CameraModelError(f"camera file {p}: {exc}") from None

    def save(
        self,
        path: str | os.PathLike[str],
        extra: Mapping[str, int | float | str] | None = None,
    ) -> None:
        """Write the FileStorage file that cv2.FileStorage and OpenCV's samples read.

        YAML unless the name ends in .xml or .json. Written beside the target and then
        renamed, so a failed write never destroys an existing calibration.
        """
        p = Path(path)
        suffix = p.suffix.lower()
        fmt = {
            ".xml": cv2.FILE_STORAGE_FORMAT_XML,
            ".json": cv2.FILE_STORAGE_FORMAT_JSON,
        }.get(suffix, cv2.FILE_STORAGE_FORMAT_YAML)
        if not p.parent.is_dir():
            raise CameraModelError(
                f"cannot write camera file {p}: folder {p.parent} does not exist"
            )
        if p.is_dir():
            raise CameraModelError(f"cannot write camera file {p}: it is a directory")
        part = p.with_name(f".{p.name}.part")
        try:
            fs = cv2.FileStorage(str(part), cv2.FILE_STORAGE_WRITE | fmt)
        except (cv2.error, SystemError) as exc:
            raise CameraModelError(f"cannot write camera file {p}: {exc}") from None
        if not fs.isOpened():
            raise CameraModelError(f"cannot write camera file {p}: check folder permissions")
        try:
            fs.write("image_width", self.width)
            fs.write("image_height", self.height)
            fs.write("camera_matrix", np.ascontiguousarray(self.camera_matrix))
            fs.write(
                "distortion_coefficients",
                np.ascontiguousarray(self.dist_coeffs.reshape(-1, 1)),
            )
            if self.rms_px is not None:
                fs.write("rms", float(self.rms_px))
                fs.write("avg_reprojection_error", float(self.rms_px))
            for key, value in (extra or {}).items():
                fs.write(key, value)
            fs.release()
            os.replace(part, p)
        except BaseException:
            fs.release()
            part.unlink(missing_ok=True)
            raise

    # ----------------------------------------------------------------- undistortion
    @cached_property
    def _maps(self) -> tuple[npt.NDArray[Any], npt.NDArray[Any]]:
        map1, map2 = cv2.initUndistortRectifyMap(
            self.camera_matrix,
            self.dist_coeffs,
            None,
            self.camera_matrix,
            self.size,
            cv2.CV_16SC2,
        )
        return map1, map2

    def undistort_maps(self) -> tuple[npt.NDArray[Any], npt.NDArray[Any]]:
        """Fixed-point remap tables, built once per model.

        The undistorted image keeps this model's camera matrix and size, so the pinhole
        formulas (H = L h / fy) apply to it with the same fx, fy, cx, cy.
        """
        return self._maps

    def undistort(
        self, image: npt.NDArray[Any], out: npt.NDArray[Any] | None = None
    ) -> npt.NDArray[Any]:
        """Remove lens distortion; ``out`` lets a stream reuse one buffer."""
        h, w = image.shape[:2]
        if (w, h) != self.size:
            raise CameraModelError(
                f"image is {w}x{h} but the camera model is for {self.width}x{self.height}; "
                "use camera.scaled_to(width, height) (or for_image) first"
            )
        map1, map2 = self._maps
        if out is None:
            return cv2.remap(image, map1, map2, cv2.INTER_LINEAR)
        return cv2.remap(image, map1, map2, cv2.INTER_LINEAR, dst=out)

    # ----------------------------------------------------------------- geometry
    def project(self, points_cam: npt.ArrayLike) -> FloatArray:
        """Camera-frame 3-D points (N x 3, z forward) to distorted pixel coordinates."""
        pts = np.asarray(points_cam, dtype=np.float64).reshape(-1, 1, 3)
        zero = np.zeros(3)
        pix, _ = cv2.projectPoints(pts, zero, zero, self.camera_matrix, self.dist_coeffs)
        out: FloatArray = np.asarray(pix, dtype=np.float64).reshape(-1, 2)
        return out

    def unproject(self, pixels: npt.ArrayLike) -> FloatArray:
        """Distorted pixels (N x 2) to rays (N x 3) with z = 1 in the camera frame."""
        pts = np.asarray(pixels, dtype=np.float64).reshape(-1, 1, 2)
        criteria = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 50, 1e-10)
        iterative = getattr(cv2, "undistortPointsIter", None)  # OpenCV 4.x spelling
        if iterative is not None:
            norm = iterative(pts, self.camera_matrix, self.dist_coeffs, None, None, criteria)
        else:
            norm = cv2.undistortPoints(pts, self.camera_matrix, self.dist_coeffs, criteria=criteria)
        norm = norm.reshape(-1, 2)
        rays: FloatArray = np.hstack([norm, np.ones((norm.shape[0], 1))])
        return rays

    def undistort_points(self, pixels: npt.ArrayLike) -> FloatArray:
        """Distorted pixels (N x 2) to where they land in the undistorted image."""
        rays = self.unproject(pixels)
        out: FloatArray = rays[:, :2] * [self.fx, self.fy] + [self.cx, self.cy]
        out[:, 0] += self.camera_matrix[0, 1] * rays[:, 1]
        return out

    def __repr__(self) -> str:
        rms = "None" if self.rms_px is None else f"{self.rms_px:.3f}"
        return (
            f"CameraModel({self.width}x{self.height}, fx={self.fx:.2f}, fy={self.fy:.2f}, "
            f"cx={self.cx:.2f}, cy={self.cy:.2f}, dist={np.round(self.dist_coeffs, 6).tolist()}, "
            f"rms_px={rms})"
        )
