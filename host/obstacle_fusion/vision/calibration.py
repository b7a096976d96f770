"""Camera calibration by Zhang's method (the paper used MATLAB's toolbox of the same method).

Corners come from OpenCV's chessboard detector refined to sub-pixel accuracy; images
where no board is found are named and skipped, so one bad photo never spoils a session.
"""

from __future__ import annotations

import logging
import math
import os
import sys
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.errors import UserError
from obstacle_fusion.vision.camera import CameraModel, FloatArray
from obstacle_fusion.vision.chessboard import BoardSpec

log = logging.getLogger(__name__)

#: Zhang's method needs at least three views of the plane for all five intrinsics.
MIN_BOARDS = 3

_DETECT_FLAGS = cv2.CALIB_CB_ADAPTIVE_THRESH | cv2.CALIB_CB_NORMALIZE_IMAGE
_SUBPIX_CRITERIA = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 50, 1e-3)


@dataclass(frozen=True)
class ImageResult:
    """What one calibration image contributed."""

    name: str
    found: bool
    rms_px: float | None = None  # this view's reprojection RMS after calibration
    corners: FloatArray | None = field(default=None, repr=False, compare=False)
    detector: str | None = None  # "classic" or "sector-based"
    problem: str | None = None  # why it was set aside despite a board (or not even read)


@dataclass(frozen=True)
class CalibrationResult:
    camera: CameraModel
    board: BoardSpec
    images: tuple[ImageResult, ...]
    std_dev: dict[str, float]  # 1-sigma of fx, fy, cx, cy from OpenCV's estimate

    @property
    def used(self) -> tuple[ImageResult, ...]:
        return tuple(r for r in self.images if r.found)

    @property
    def skipped(self) -> tuple[ImageResult, ...]:
        return tuple(r for r in self.images if not r.found)


def _subpix_window(corners: FloatArray, board: BoardSpec) -> tuple[int, int]:
    """Half-window under half the smallest corner spacing, so it never sees two corners."""
    grid = corners.reshape(board.rows, board.cols, 2)
    dx = np.linalg.norm(np.diff(grid, axis=1), axis=2).min()
    dy = np.linalg.norm(np.diff(grid, axis=0), axis=2).min()
    half = int(max(2, min(11, math.floor(0.4 * min(dx, dy)))))
    return (half, half)


def find_corners(
    gray: npt.NDArray[np.uint8], board: BoardSpec
) -> tuple[FloatArray | None, str | None]:
    """Sub-pixel inner corners (N x 2, OpenCV order) and the detector used, or (None, None)."""
    found, corners = cv2.findChessboardCorners(gray, board.pattern_size, flags=_DETECT_FLAGS)
    if found:
        pts = np.asarray(corners, np.float32).reshape(-1, 1, 2)
        win = _subpix_window(pts.reshape(-1, 2).astype(np.float64), board)
        refined = cv2.cornerSubPix(gray, pts, win, (-1, -1), _SUBPIX_CRITERIA)
        return np.asarray(refined, np.float64).reshape(-1, 2), "classic"
    # The sector-based detector copes with blur and uneven light the classic one misses.
    found, corners = cv2.findChessboardCornersSB(
        gray, board.pattern_size, flags=cv2.CALIB_CB_NORMALIZE_IMAGE | cv2.CALIB_CB_EXHAUSTIVE
    )
    if found:
        return np.asarray(corners, np.float64).reshape(-1, 2), "sector-based"
    return None, None


def _to_gray(image: npt.NDArray[np.uint8]) -> npt.NDArray[np.uint8]:
    if image.ndim == 2:
        return image
    if image.ndim == 3 and image.shape[2] == 3:
        return np.asarray(cv2.cvtColor(image, cv2.COLOR_BGR2GRAY), np.uint8)
    if image.ndim == 3 and image.shape[2] == 4:
        return np.asarray(cv2.cvtColor(image, cv2.COLOR_BGRA2GRAY), np.uint8)
    raise UserError(f"unsupported image layout {image.shape}")


ProgressFn = Callable[[int, int, str], None]


@contextmanager
def progress_reporter(total: int, enabled: bool | None = None) -> Iterator[ProgressFn]:
    """A rich progress bar on a terminal, log lines otherwise.

    ``enabled=None`` decides by whether stderr is a terminal.
    """
    use_rich = sys.stderr.isatty() if enabled is None else enabled
    if not use_rich:

        def report(done: int, total_: int, name: str) -> None:
            log.info("calibration: %d/%d %s", done, total_, name)

        yield report
        return
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn

    with Progress(
        TextColumn("[bold]finding boards"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("{task.description}"),
        transient=True,
    ) as bar:
        task = bar.add_task("", total=total)

        def report_rich(done: int, total_: int, name: str) -> None:
            bar.update(task, completed=done, description=name)

        yield report_rich


ImageLoader = Callable[[], npt.NDArray[np.uint8]]


def calibrate_images(
    images: Sequence[tuple[str, npt.NDArray[np.uint8]]],
    board: BoardSpec,
    *,
    flags: int = 0,
    min_boards: int = MIN_BOARDS,
    progress: bool | None = None,
) -> CalibrationResult:
    """Calibrate from named images (BGR or grey), all of one resolution.

    ``flags`` are cv2.CALIB_* flags passed to calibrateCamera (e.g. CALIB_FIX_K3).
    """
    loaders = [(name, _constant(image)) for name, image in images]
    return _calibrate(loaders, board, flags=flags, min_boards=min_boards, progress=progress)


def _constant(image: npt.NDArray[np.uint8]) -> ImageLoader:
    return lambda: image


def _calibrate(
    items: Sequence[tuple[str, ImageLoader]],
    board: BoardSpec,
    *,
    flags: int,
    min_boards: int,
    progress: bool | None,
) -> CalibrationResult:
    """Detect board by board (one image in memory at a time), then solve once."""
    if not items:
        raise UserError("no calibration images given")
    size: tuple[int, int] | None = None
    first_name = ""
    obj = board.object_points()
    results: list[ImageResult] = []
    with progress_reporter(len(items), progress) as report:
        for i, (name, load) in enumerate(items):
            try:
                gray = _to_gray(load())
            except UserError as exc:
                # A truncated or foreign file among good photos: name it and go on.
                log.warning("skipping %s: %s", name, exc)
                results.append(ImageResult(name, False, problem="unreadable image"))
                report(i + 1, len(items), name)
                continue
            this = (int(gray.shape[1]), int(gray.shape[0]))
            if size is None:
                size, first_name = this, name
            elif this != size:
                raise UserError(
                    f"calibration images have different resolutions: {first_name} is "
                    f"{size[0]}x{size[1]} but {name} is {this[0]}x{this[1]}; intrinsics belong "
                    "to one resolution, so calibrate each resolution separately"
                )
            corners, detector = find_corners(gray, board)
            twin = None if corners is None else _same_view(corners, results)
            if corners is None:
                log.warning("no %dx%d board found in %s; skipping it", *board.pattern_size, name)
                results.append(ImageResult(name, False))
            elif twin is not None:
                # A copy adds no information but weighs the solve towards one pose.
                log.warning("%s shows the board exactly as %s does; skipping it", name, twin)
                results.append(ImageResult(name, False, problem=f"same view as {twin}"))
            else:
                results.append(ImageResult(name, True, None, corners, detector))
            report(i + 1, len(items), name)
    used = [r for r in results if r.found]
    if len(used) < min_boards or size is None:
        aside = [f"{r.name} ({r.problem})" for r in results if r.problem is not None]
        boardless = [r.name for r in results if not r.found and r.problem is None]
        parts = [
            f"a board ({board.cols}x{board.rows} inner corners) was found in only "
            f"{len(used)} of {len(items)} images; calibration needs at least {min_boards}."
        ]
        if aside:
            parts.append(f"Set aside: {', '.join(aside)}.")
        if boardless:
            parts.append(
                f"No board in: {', '.join(boardless)}. Check --board counts INNER corners "
                "(a board of 10x7 squares is 9x6) and that the whole board is in view."
            )
        if not aside and not boardless:
            parts.append(
                f"Every image had its board: give at least {min_boards} photos, the board "
                "at different angles and places in the view (10-20 is typical)."
            )
        raise UserError(" ".join(parts))
    object_points = [obj for _ in used]
    image_points = [np.asarray(r.corners, np.float32).reshape(-1, 1, 2) for r in used]
    solve: Any = cv2.calibrateCameraExtended  # the stubs reject None for the outputs
    try:
        rms, k, d, _rvecs, _tvecs, std_intr, _std_extr, per_view = solve(
            object_points, image_points, size, None, None, flags=flags
        )
    except cv2.error:
        raise UserError(_degenerate("the solver failed", len(used))) from None
    std = np.asarray(std_intr, np.float64).reshape(-1)
    _check_plausible(np.asarray(k, np.float64), np.asarray(d, np.float64), std, size, len(used))
    view = iter(np.asarray(per_view, np.float64).reshape(-1))
    final = [
        ImageResult(r.name, True, float(next(view)), r.corners, r.detector) if r.found else r
        for r in results
    ]
    camera = CameraModel(np.asarray(k), np.asarray(d).reshape(-1), size[0], size[1], float(rms))
    log.info("calibrated %s from %d views", camera, len(used))
    return CalibrationResult(
        camera,
        board,
        tuple(final),
        {"fx": float(std[0]), "fy": float(std[1]), "cx": float(std[2]), "cy": float(std[3])},
    )


def _same_view(corners: FloatArray, earlier: Sequence[ImageResult]) -> str | None:
    """The name of an earlier view with the board at the same place (a copied photo)."""
    for r in earlier:
        if r.found and r.corners is not None and np.abs(r.corners - corners).max() < 0.5:
            return r.name
    return None


def _degenerate(what: str, views: int) -> str:
    return (
        f"calibration from {views} views is not usable: {what}. The views are too alike: "
        "take 10-20 photos with the board tilted in different directions (about 20-45 "
        "degrees) and placed across the whole image, corners included"
    )


#: 1-sigma of fx or fy, relative, above which a calibration is refused (heights and widths
#: scale with 1/f) or, above the lower figure, warned about. Good sessions reach 0.1-0.3 %.
MAX_FOCAL_SIGMA = 0.05
WARN_FOCAL_SIGMA = 0.01


def _check_plausible(
    k: npt.NDArray[np.float64],
    d: npt.NDArray[np.float64],
    std: npt.NDArray[np.float64],
    size: tuple[int, int],
    views: int,
) -> None:
    """Refuse a solution no lens has rather than write it for `measure` to trust."""
    fx, fy, cx, cy = float(k[0, 0]), float(k[1, 1]), float(k[0, 2]), float(k[1, 2])
    w, h = size
    if not (np.all(np.isfinite(k)) and np.all(np.isfinite(d)) and fx > 0 and fy > 0):
        raise UserError(_degenerate("the solution is not finite", views))
    if not 0.5 <= fx / fy <= 2.0:
        raise UserError(
            _degenerate(f"fx {fx:.0f} px and fy {fy:.0f} px differ by more than 2x", views)
        )
    if not (0 < cx < w and 0 < cy < h):
        raise UserError(
            _degenerate(f"the principal point ({cx:.0f}, {cy:.0f}) lies outside the image", views)
        )
    sigma = max(float(std[0]) / fx, float(std[1]) / fy)
    if not sigma <= MAX_FOCAL_SIGMA:  # NaN included
        raise UserError(
            _degenerate(f"the focal length is uncertain to {100 * sigma:.1f} % (1 sigma)", views)
        )
    if sigma > WARN_FOCAL_SIGMA:
        log.warning(
            "the focal length is uncertain to %.1f %% (1 sigma): sizes will be as uncertain; "
            "more photos at varied tilts would pin it down",
            100 * sigma,
        )


def _check_path(p: Path) -> None:
    if not p.exists():
        raise UserError(f"image {p} does not exist")
    if p.is_dir():
        raise UserError(f"{p} is a directory; give image files (a shell glob works: dir/*.jpg)")


def read_image(path: str | os.PathLike[str]) -> npt.NDArray[np.uint8]:
    """An image from disk, or a UserError naming the file and the reason."""
    p = Path(path)
    _check_path(p)
    try:
        data = np.fromfile(p, dtype=np.uint8)
    except OSError as exc:
        raise UserError(f"cannot read image {p}: {exc.strerror or exc}") from None
    level = cv2.utils.logging.getLogLevel()
    cv2.utils.logging.setLogLevel(cv2.utils.logging.LOG_LEVEL_SILENT)  # we name the file
    try:
        image = cv2.imdecode(data, cv2.IMREAD_COLOR) if data.size else None
    finally:
        cv2.utils.logging.setLogLevel(level)
    if image is None:
        raise UserError(f"{p} is not a readable image (empty, corrupt or an unknown format)")
    return np.asarray(image, np.uint8)


def calibrate_files(
    paths: Sequence[str | os.PathLike[str]],
    board: BoardSpec,
    *,
    flags: int = 0,
    min_boards: int = MIN_BOARDS,
    progress: bool | None = None,
) -> CalibrationResult:
    """Check every path first (so a typo fails fast), then read one image at a time."""
    for p in paths:
        _check_path(Path(p))
    items = [(str(p), _file_loader(p)) for p in paths]
    return _calibrate(items, board, flags=flags, min_boards=min_boards, progress=progress)


def _file_loader(path: str | os.PathLike[str]) -> ImageLoader:
    return lambda: read_image(path)
