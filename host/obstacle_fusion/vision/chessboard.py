"""Chessboard geometry, and a renderer of boards seen through a known camera.

Calibration can only be proven against a camera whose answer is known, so the renderer
ray-casts each (supersampled) pixel of a distorted camera onto the board plane: the
distortion is the model's own, not an approximation of it.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.errors import UserError
from obstacle_fusion.vision.camera import CameraModel, FloatArray


@dataclass(frozen=True)
class BoardSpec:
    """A chessboard by its inner corners (OpenCV's pattern size) and square size."""

    cols: int
    rows: int
    square_m: float = 0.025

    #: OpenCV's detector needs more than 2 inner corners a side; past 50 no printed board
    #: is seen whole by a camera, and the grid arrays would only eat memory.
    MIN_CORNERS = 3
    MAX_CORNERS = 50

    def __post_init__(self) -> None:
        lo, hi = self.MIN_CORNERS, self.MAX_CORNERS
        if not (lo <= self.cols <= hi and lo <= self.rows <= hi):
            raise UserError(
                f"a board needs {lo} to {hi} inner corners a side, got {self.cols}x{self.rows} "
                "(count the INNER corners: a board of 10x7 squares is 9x6)"
            )
        if not (math.isfinite(self.square_m) and self.square_m > 0):
            raise UserError(f"square size must be positive, got {self.square_m} m")

    @classmethod
    def parse(cls, text: str, square_m: float = 0.025) -> BoardSpec:
        """'9x6' (inner corners per row x per column, as OpenCV counts them)."""
        match = re.fullmatch(r"\s*(\d+)\s*[xX*,]\s*(\d+)\s*", text)
        if match is None:
            raise UserError(
                f"bad board size {text!r}: give inner corners as COLSxROWS, e.g. 9x6 "
                "(a board of 10x7 squares has 9x6 inner corners)"
            )
        return cls(int(match.group(1)), int(match.group(2)), square_m)

    @property
    def pattern_size(self) -> tuple[int, int]:
        return (self.cols, self.rows)

    @property
    def n_corners(self) -> int:
        return self.cols * self.rows

    def object_points(self) -> npt.NDArray[np.float32]:
        """Inner corners on the board plane (z = 0), in OpenCV's detection order."""
        grid = np.zeros((self.n_corners, 3), np.float32)
        grid[:, :2] = np.mgrid[0 : self.cols, 0 : self.rows].T.reshape(-1, 2) * self.square_m
        return grid

    def __str__(self) -> str:
        return f"{self.cols}x{self.rows} inner corners, {self.square_m * 1000:g} mm squares"


@dataclass(frozen=True)
class BoardPose:
    """Board-to-camera rotation (Rodrigues vector) and translation in metres."""

    rvec: tuple[float, float, float]
    tvec: tuple[float, float, float]

    def rotation(self) -> FloatArray:
        r, _ = cv2.Rodrigues(np.asarray(self.rvec, np.float64))
        out: FloatArray = np.asarray(r, np.float64)
        return out


@dataclass(frozen=True)
class RenderedBoard:
    image: npt.NDArray[np.uint8]  # grey, uint8
    pose: BoardPose
    true_corners: FloatArray  # N x 2, distorted pixel coordinates, detection order


def _euler_rvec(ax: float, ay: float, az: float) -> tuple[float, float, float]:
    cx_, sx_ = math.cos(ax), math.sin(ax)
    cy_, sy_ = math.cos(ay), math.sin(ay)
    cz_, sz_ = math.cos(az), math.sin(az)
    rx = np.array([[1, 0, 0], [0, cx_, -sx_], [0, sx_, cx_]])
    ry = np.array([[cy_, 0, sy_], [0, 1, 0], [-sy_, 0, cy_]])
    rz = np.array([[cz_, -sz_, 0], [sz_, cz_, 0], [0, 0, 1]])
    rvec, _ = cv2.Rodrigues(rz @ ry @ rx)
    flat = rvec.reshape(3)
    return (float(flat[0]), float(flat[1]), float(flat[2]))


def default_poses(camera: CameraModel, board: BoardSpec, count: int = 9) -> list[BoardPose]:
    """Varied, well-conditioned views: tilts of 15-35 degrees, board over most of the image.

    Deterministic, so a test calibrates the same views at two resolutions.
    """
    board_w = (board.cols + 1) * board.square_m
    board_h = (board.rows + 1) * board.square_m
    # Distance at which the board (with its margin) spans about 55 % of the narrower FOV.
    fill = 0.55
    dist = max(
        camera.fx * board_w / (fill * camera.width),
        camera.fy * board_h / (fill * camera.height),
    )
    tilts = [
        (25, 0, 0),
        (-25, 0, 5),
        (0, 30, -5),
        (0, -30, 3),
        (20, 20, 10),
        (-20, -25, -8),
        (15, -20, 180 - 4),
        (-15, 25, 180 + 6),
        (30, 10, 90 - 3),
        (-30, -10, 90 + 3),
        (10, 35, 2),
        (-35, 5, -2),
    ]
    q = board.square_m
    outline = np.array(
        [
            [-2 * q, -2 * q, 0],
            [(board.cols + 1) * q, -2 * q, 0],
            [(board.cols + 1) * q, (board.rows + 1) * q, 0],
            [-2 * q, (board.rows + 1) * q, 0],
        ]
    )
    margin_x, margin_y = 0.02 * camera.width, 0.02 * camera.height
    shifts = [(0.0, 0.0), (-0.17, -0.15), (0.17, 0.15), (-0.17, 0.15), (0.17, -0.15)]
    poses: list[BoardPose] = []
    for i in range(count):
        ax, ay, az = (math.radians(a) for a in tilts[i % len(tilts)])
        rvec = _euler_rvec(ax, ay, az)
        r, _ = cv2.Rodrigues(np.asarray(rvec))
        centre_board = np.array(
            [(board.cols - 1) * board.square_m / 2, (board.rows - 1) * board.square_m / 2, 0]
        )
        sx, sy = shifts[i % len(shifts)]
        z = dist * (1.0 + 0.08 * ((i * 7) % 3 - 1))
        target = np.array(
            [sx * z * camera.width / camera.fx, sy * z * camera.height / camera.fy, z]
        )
        target[0] += (camera.width / 2 - camera.cx) * z / camera.fx
        target[1] += (camera.height / 2 - camera.cy) * z / camera.fy
        # Step back until the whole board, margin included, is inside the image.
        for _ in range(30):
            t = target - r @ centre_board
            seen = camera.project(outline @ r.T + t)
            inside = (
                (seen[:, 0] >= margin_x)
                & (seen[:, 0] <= camera.width - 1 - margin_x)
                & (seen[:, 1] >= margin_y)
                & (seen[:, 1] <= camera.height - 1 - margin_y)
            )
            if inside.all():
                break
            target = target * 1.08
        poses.append(BoardPose(rvec, (float(t[0]), float(t[1]), float(t[2]))))
    return poses


class BoardRenderer:
    """Renders boards through one camera; the per-pixel ray table is built once."""

    def __init__(self, camera: CameraModel, board: BoardSpec, supersample: int = 3) -> None:
        if supersample < 1:
            raise ValueError("supersample must be >= 1")
        self.camera = camera
        self.board = board
        self.supersample = supersample
        s = supersample
        # Sample points at the centres of s x s sub-pixels of each output pixel.
        offs = (np.arange(s) + 0.5) / s - 0.5
        us = (np.arange(camera.width)[:, None] + offs[None, :]).reshape(-1)
        vs = (np.arange(camera.height)[:, None] + offs[None, :]).reshape(-1)
        uu, vv = np.meshgrid(us, vs)
        rays = camera.unproject(np.stack([uu.ravel(), vv.ravel()], axis=1))
        # Normalised image coordinates of every sample; float32 is ample (1e-4 px).
        shape = (camera.height * s, camera.width * s)
        self._x = rays[:, 0].astype(np.float32).reshape(shape)
        self._y = rays[:, 1].astype(np.float32).reshape(shape)

    def render(
        self,
        pose: BoardPose,
        *,
        background: int = 110,
        dark: int = 25,
        light: int = 230,
        noise_sigma: float = 0.0,
        blur_sigma: float = 0.0,
        rng: np.random.Generator | None = None,
    ) -> RenderedBoard:
        cam, board, s = self.camera, self.board, self.supersample
        # Board plane z = 0 maps to normalised image coordinates by H = [r1 r2 t];
        # H^-1 takes each sample back to board coordinates, w > 0 means in front.
        r = pose.rotation()
        h = np.column_stack([r[:, 0], r[:, 1], np.asarray(pose.tvec, np.float64)])
        hi = np.linalg.inv(h).astype(np.float32)
        x, y = self._x, self._y
        w = hi[2, 0] * x + hi[2, 1] * y + hi[2, 2]
        front = w > 1e-9
        w = np.where(front, w, np.float32(1.0))
        q = np.float32(board.square_m)
        bx = (hi[0, 0] * x + hi[0, 1] * y + hi[0, 2]) / (w * q)
        by = (hi[1, 0] * x + hi[1, 1] * y + hi[1, 2]) / (w * q)
        # Squares span [-1, cols] x [-1, rows] in square units; a 1-square white margin.
        on_squares = (bx >= -1) & (bx < board.cols) & (by >= -1) & (by < board.rows)
        on_margin = (bx >= -2) & (bx < board.cols + 1) & (by >= -2) & (by < board.rows + 1)
        black = ((np.floor(bx) + np.floor(by)) % 2 == 0) & on_squares
        value = np.full(bx.shape, float(background), np.float32)
        value[on_margin & front] = light
        value[black & front] = dark
        img = value.reshape(cam.height, s, cam.width, s).mean(axis=(1, 3))
        if blur_sigma > 0:
            img = cv2.GaussianBlur(img, (0, 0), blur_sigma)
        if noise_sigma > 0:
            gen = rng if rng is not None else np.random.default_rng(0)
            img = img + gen.normal(0.0, noise_sigma, img.shape)
        out = np.clip(np.rint(img), 0, 255).astype(np.uint8)
        true_corners = self.true_corners(pose)
        return RenderedBoard(out, pose, true_corners)

    def true_corners(self, pose: BoardPose) -> FloatArray:
        """Where the inner corners truly are (distorted pixels), in detection order."""
        r = pose.rotation()
        pts = self.board.object_points().astype(np.float64) @ r.T + np.asarray(pose.tvec)
        return self.camera.project(pts)


def render_boards(
    camera: CameraModel,
    board: BoardSpec,
    poses: Sequence[BoardPose] | None = None,
    count: int = 9,
    **render_kwargs: Any,
) -> list[RenderedBoard]:
    """Boards through ``camera`` at ``poses`` (or :func:`default_poses`)."""
    renderer = BoardRenderer(camera, board)
    chosen = list(poses) if poses is not None else default_poses(camera, board, count)
    return [renderer.render(p, **render_kwargs) for p in chosen]
