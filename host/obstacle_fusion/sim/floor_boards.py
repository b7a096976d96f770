"""Photos of a chessboard lying on the floor, seen by a camera of a known rig.

What `obstacle-fusion calibrate-rig` is proven against: the board is ray-cast through the
calibrated lens (its distortion included) by :class:`~obstacle_fusion.vision.chessboard.
BoardRenderer`, placed on the floor by :func:`~obstacle_fusion.vision.rig_calibration.
floor_board_pose` for a camera at a given height, pitch and roll.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.chessboard import BoardPose, BoardRenderer, BoardSpec, RenderedBoard
from obstacle_fusion.vision.rig_calibration import floor_board_pose

#: Where a user is told to lay the board: near enough to be seen large, in front.
NEAREST_M = 0.4
FARTHEST_M = 1.0


@dataclass(frozen=True)
class FloorRig:
    """The truth a floor photo is rendered for."""

    height_m: float
    pitch_deg: float
    roll_deg: float = 0.0


def board_in_view(
    camera: CameraModel, board: BoardSpec, pose: tuple[np.ndarray, np.ndarray], margin: float = 0.03
) -> bool:
    """True when the whole board, its white border included, lies inside the image."""
    q = board.square_m
    outline = np.array(
        [
            [-2 * q, -2 * q, 0.0],
            [(board.cols + 1) * q, -2 * q, 0.0],
            [(board.cols + 1) * q, (board.rows + 1) * q, 0.0],
            [-2 * q, (board.rows + 1) * q, 0.0],
        ]
    )
    r, _ = cv2.Rodrigues(np.asarray(pose[0], np.float64))
    cam_pts = outline @ np.asarray(r).T + np.asarray(pose[1], np.float64)
    if (cam_pts[:, 2] <= 0.05).any():
        return False
    px = camera.project(cam_pts)
    mx, my = margin * camera.width, margin * camera.height
    return bool(
        (px[:, 0] >= mx).all()
        and (px[:, 0] <= camera.width - 1 - mx).all()
        and (px[:, 1] >= my).all()
        and (px[:, 1] <= camera.height - 1 - my).all()
    )


def nearest_placement(
    camera: CameraModel,
    board: BoardSpec,
    rig: FloorRig,
    *,
    right_m: float = 0.0,
    yaw_deg: float = 0.0,
    start_m: float = NEAREST_M,
    stop_m: float = FARTHEST_M,
) -> float | None:
    """The nearest distance (board centre ahead of the lens, 1 cm steps from ``start_m``)
    at which the whole board is in view: where it is seen largest. None: nowhere in range."""
    for dist in np.arange(start_m, stop_m + 1e-9, 0.01):
        pose = floor_board_pose(
            board,
            rig.height_m,
            rig.pitch_deg,
            rig.roll_deg,
            distance_m=float(dist),
            right_m=right_m,
            yaw_deg=yaw_deg,
        )
        if board_in_view(camera, board, pose):
            return float(dist)
    return None


def render_floor_board(
    renderer: BoardRenderer,
    rig: FloorRig,
    distance_m: float,
    *,
    right_m: float = 0.0,
    yaw_deg: float = 0.0,
    noise_sigma: float = 2.0,
    blur_sigma: float = 0.7,
    rng: np.random.Generator | None = None,
) -> RenderedBoard:
    """One photo of the renderer's board on the floor, ``distance_m`` ahead of the lens."""
    rvec, tvec = floor_board_pose(
        renderer.board,
        rig.height_m,
        rig.pitch_deg,
        rig.roll_deg,
        distance_m=distance_m,
        right_m=right_m,
        yaw_deg=yaw_deg,
    )
    pose = BoardPose(
        (float(rvec[0]), float(rvec[1]), float(rvec[2])),
        (float(tvec[0]), float(tvec[1]), float(tvec[2])),
    )
    return renderer.render(
        pose,
        background=95,
        noise_sigma=noise_sigma,
        blur_sigma=blur_sigma,
        rng=rng if rng is not None else np.random.default_rng(0),
    )
