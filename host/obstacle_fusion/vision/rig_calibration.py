"""The rig from photos of a chessboard lying flat on the floor in front of the robot.

The board's pose (``cv2.solvePnP`` with the calibrated lens) gives the floor plane in the
camera frame: its distance from the lens is the camera's height, and the direction of the
floor's normal, seen from the camera, gives the pitch and the roll. With the rig's axes
(:mod:`obstacle_fusion.vision.rig`: x right, y down, z forward) and the camera pitched down
by p and rolled by r about its optical axis (right side down positive), the floor's "down"
direction in camera coordinates is g = (sin r cos p, cos r cos p, sin p), so
pitch = asin(g_z) and roll = atan2(g_x, g_y). The board's own yaw and place on the floor do
not matter. Several photos are combined by the median, so one bad fit does not move it.
"""

from __future__ import annotations

import logging
import math
import os
import statistics
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.errors import UserError
from obstacle_fusion.vision.calibration import find_corners, read_image
from obstacle_fusion.vision.camera import CameraModel, CameraModelError, FloatArray
from obstacle_fusion.vision.chessboard import BoardSpec
from obstacle_fusion.vision.rig import Rig

log = logging.getLogger(__name__)

#: Roll the rig has no place for: above this the heights and widths suffer; warn.
ROLL_WARN_DEG = 1.0
#: A photo whose fit differs from the median by more than this is flagged (not dropped).
OUTLIER_HEIGHT_M = 0.02
OUTLIER_PITCH_DEG = 1.0


@dataclass(frozen=True)
class FloorFit:
    """One photo's board pose, read as the camera's mounting above the floor."""

    name: str
    found: bool
    height_m: float | None = None  # lens above the floor (board thickness added)
    pitch_deg: float | None = None  # down positive
    roll_deg: float | None = None  # right side down positive
    rms_px: float | None = None  # reprojection error of the board's corners
    board_distance_m: float | None = None  # forward distance of the board's centre
    problem: str | None = None  # why the photo was set aside
    corners: FloatArray | None = field(default=None, repr=False, compare=False)


@dataclass(frozen=True)
class RigCalibration:
    """Every photo's fit and their median."""

    fits: tuple[FloorFit, ...]
    height_m: float
    pitch_deg: float
    roll_deg: float
    board: BoardSpec

    @property
    def used(self) -> tuple[FloorFit, ...]:
        return tuple(f for f in self.fits if f.found)

    @property
    def roll_warning(self) -> str | None:
        if abs(self.roll_deg) <= ROLL_WARN_DEG:
            return None
        return (
            f"the camera is rolled {self.roll_deg:+.2f} degrees about its axis (more than "
            f"{ROLL_WARN_DEG:g}); the rig cannot hold roll, so heights and widths will lean: "
            "level the camera on its mount and take the photos again"
        )

    def outliers(self) -> list[FloorFit]:
        """Photos whose fit disagrees with the median (a moved robot, a lifted board)."""
        return [
            f
            for f in self.used
            if f.height_m is not None
            and f.pitch_deg is not None
            and (
                abs(f.height_m - self.height_m) > OUTLIER_HEIGHT_M
                or abs(f.pitch_deg - self.pitch_deg) > OUTLIER_PITCH_DEG
            )
        ]

    def rig(
        self,
        *,
        sonar_right_m: float = 0.0,
        sonar_below_m: float = 0.05,
        sonar_ahead_m: float = 0.0,
        beam_width_deg: float = 15.0,
    ) -> Rig:
        return Rig(
            camera_height_m=round(self.height_m, 5),
            camera_pitch_deg=round(self.pitch_deg, 4),
            sonar_right_m=sonar_right_m,
            sonar_below_m=sonar_below_m,
            sonar_ahead_m=sonar_ahead_m,
            beam_width_deg=beam_width_deg,
        )


def mounting_from_pose(rvec: npt.ArrayLike, tvec: npt.ArrayLike) -> tuple[float, float, float]:
    """(height_m, pitch_deg, roll_deg) of a camera that sees a floor plane at this pose.

    ``rvec``/``tvec`` take the board's plane (its z = 0) into the camera frame.
    """
    r, _ = cv2.Rodrigues(np.asarray(rvec, np.float64).reshape(3, 1))
    n = np.asarray(r, np.float64)[:, 2]  # the plane's normal in the camera frame
    d = float(n @ np.asarray(tvec, np.float64).reshape(3))  # signed distance lens -> plane
    g = n if d > 0 else -n  # from the lens towards the plane: "down"
    pitch = math.degrees(math.asin(max(-1.0, min(1.0, float(g[2])))))
    roll = math.degrees(math.atan2(float(g[0]), float(g[1])))
    return abs(d), pitch, roll


def fit_board(
    name: str,
    corners: FloatArray,
    board: BoardSpec,
    camera: CameraModel,
    board_thickness_m: float = 0.0,
) -> FloorFit:
    """The floor pose from one board's detected corners (distorted pixels, OpenCV order)."""
    obj = board.object_points().astype(np.float64)
    img = np.asarray(corners, np.float64).reshape(-1, 1, 2)
    k, d = camera.camera_matrix, camera.dist_coeffs
    solve: Any = cv2.solvePnPGeneric  # IPPE: the planar solver, both of its solutions
    n_sol, rvecs, tvecs, _errs = solve(obj, img, k, d, flags=cv2.SOLVEPNP_IPPE)
    best: tuple[float, Any, Any] | None = None
    for i in range(int(n_sol)):
        rv, tv = cv2.solvePnPRefineLM(obj, img, k, d, rvecs[i].copy(), tvecs[i].copy())
        proj, _ = cv2.projectPoints(obj, rv, tv, k, d)
        err = float(np.sqrt(np.mean(np.sum((proj.reshape(-1, 2) - img.reshape(-1, 2)) ** 2, 1))))
        if float(np.asarray(tv).reshape(3)[2]) > 0 and (best is None or err < best[0]):
            best = (err, rv, tv)
    if best is None:
        return FloorFit(name, False, problem="no pose of the board in front of the camera")
    err, rv, tv = best
    height, pitch, roll = mounting_from_pose(rv, tv)
    r, _ = cv2.Rodrigues(rv)
    centre_b = np.array(
        [(board.cols - 1) * board.square_m / 2, (board.rows - 1) * board.square_m / 2, 0.0]
    )
    centre_c = np.asarray(r, np.float64) @ centre_b + np.asarray(tv, np.float64).reshape(3)
    # the centre's forward distance on the floor (robot z): along the camera's axis levelled
    p = math.radians(pitch)
    forward = float(centre_c[2] * math.cos(p) - centre_c[1] * math.sin(p))
    return FloorFit(
        name,
        True,
        height_m=height + board_thickness_m,
        pitch_deg=pitch,
        roll_deg=roll,
        rms_px=err,
        board_distance_m=forward,
        corners=np.asarray(corners, np.float64),
    )


ImageLoader = Callable[[], npt.NDArray[np.uint8]]


def _grey(image: npt.NDArray[np.uint8]) -> npt.NDArray[np.uint8]:
    if image.ndim == 2:
        return image
    return np.asarray(cv2.cvtColor(image, cv2.COLOR_BGR2GRAY), np.uint8)


def calibrate_rig(
    items: Sequence[tuple[str, ImageLoader]],
    board: BoardSpec,
    camera: CameraModel,
    *,
    board_thickness_m: float = 0.0,
    camera_name: str = "the calibration",
) -> RigCalibration:
    """Fit every photo (one in memory at a time); the median of those with a board.

    A photo with no board is named and skipped; none usable is a UserError (exit 2). The
    camera is scaled to each photo's size; a photo of another aspect ratio is an error.
    """
    if not items:
        raise UserError("no photos given")
    fits: list[FloorFit] = []
    for name, load in items:
        try:
            image = load()
        except UserError as exc:
            log.warning("skipping %s: %s", name, exc)
            fits.append(FloorFit(name, False, problem="unreadable image"))
            continue
        h, w = image.shape[:2]
        try:
            cam = camera.scaled_to(w, h)
        except CameraModelError:
            raise UserError(
                f"{name} is {w}x{h} but {camera_name} is for {camera.width}x{camera.height} "
                "(another aspect ratio): take the rig photos with the camera at the "
                "calibrated aspect, or calibrate it at this size"
            ) from None
        corners, _detector = find_corners(_grey(image), board)
        if corners is None:
            log.warning("no %dx%d board found in %s; skipping it", *board.pattern_size, name)
            fits.append(FloorFit(name, False, problem="no board found"))
            continue
        fit = fit_board(name, corners, board, cam, board_thickness_m)
        if not fit.found:
            log.warning("%s: %s; skipping it", name, fit.problem)
        fits.append(fit)
    used = [f for f in fits if f.found]
    if not used:
        named = ", ".join(f"{f.name} ({f.problem})" for f in fits)
        raise UserError(
            f"no photo is usable: {named}. Lay the board ({board}) flat on the floor in "
            "front of the robot, wholly in view (0.4-1 m ahead suits most rigs), and check "
            "that --board counts INNER corners (a board of 10x7 squares is 9x6)"
        )
    return RigCalibration(
        tuple(fits),
        float(statistics.median(f.height_m for f in used if f.height_m is not None)),
        float(statistics.median(f.pitch_deg for f in used if f.pitch_deg is not None)),
        float(statistics.median(f.roll_deg for f in used if f.roll_deg is not None)),
        board,
    )


def calibrate_rig_files(
    paths: Sequence[str | os.PathLike[str]],
    board: BoardSpec,
    camera: CameraModel,
    *,
    board_thickness_m: float = 0.0,
    camera_name: str = "the calibration",
) -> RigCalibration:
    """As :func:`calibrate_rig`, reading the photos from disk; a missing path fails first."""
    for p in paths:
        if not Path(p).exists():
            raise UserError(f"photo {p} does not exist")
        if Path(p).is_dir():
            raise UserError(f"{p} is a directory; give image files (a shell glob works)")
    items = [(str(p), _loader(p)) for p in paths]
    return calibrate_rig(
        items, board, camera, board_thickness_m=board_thickness_m, camera_name=camera_name
    )


def _loader(path: str | os.PathLike[str]) -> ImageLoader:
    return lambda: read_image(path)


# --------------------------------------------------------------------------- the inverse


def camera_to_robot(pitch_deg: float, roll_deg: float = 0.0) -> FloatArray:
    """Rotation p_robot = R p_camera for a camera rolled by ``roll_deg`` about its optical
    axis (right side down positive), then pitched down by ``pitch_deg``."""
    p, r = math.radians(pitch_deg), math.radians(roll_deg)
    rx = np.array(
        [[1.0, 0.0, 0.0], [0.0, math.cos(p), math.sin(p)], [0.0, -math.sin(p), math.cos(p)]]
    )
    rz = np.array(
        [[math.cos(r), -math.sin(r), 0.0], [math.sin(r), math.cos(r), 0.0], [0.0, 0.0, 1.0]]
    )
    out: FloatArray = rx @ rz
    return out


def floor_board_pose(
    board: BoardSpec,
    height_m: float,
    pitch_deg: float,
    roll_deg: float = 0.0,
    *,
    distance_m: float = 0.6,
    right_m: float = 0.0,
    yaw_deg: float = 0.0,
) -> tuple[FloatArray, FloatArray]:
    """(rvec, tvec) of a board lying on the floor, its centre ``distance_m`` ahead of the
    lens and ``right_m`` to the right, turned by ``yaw_deg``, for a camera at ``height_m``
    with that pitch and roll: what :func:`fit_board` must read back."""
    y = math.radians(yaw_deg)
    bx = np.array([math.cos(y), 0.0, math.sin(y)])  # along the board's rows, on the floor
    by = np.array([-math.sin(y), 0.0, math.cos(y)])  # away from the robot
    bz = np.cross(bx, by)  # up
    board_to_robot = np.column_stack([bx, by, bz])
    centre_b = np.array(
        [(board.cols - 1) * board.square_m / 2, (board.rows - 1) * board.square_m / 2, 0.0]
    )
    origin_r = np.array([right_m, height_m, distance_m]) - board_to_robot @ centre_b
    r_rc = camera_to_robot(pitch_deg, roll_deg).T  # robot -> camera
    rvec, _ = cv2.Rodrigues(r_rc @ board_to_robot)
    tvec = r_rc @ origin_r
    return np.asarray(rvec, np.float64).reshape(3), np.asarray(tvec, np.float64).reshape(3)
