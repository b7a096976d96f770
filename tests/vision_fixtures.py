"""Shared helpers for the vision tests: data locations and cameras with a known answer."""

from __future__ import annotations

import os
from functools import lru_cache
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.sim.room_scene import RoomSpec, render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.chessboard import BoardRenderer, BoardSpec, default_poses
from obstacle_fusion.vision.fused import top
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import Measurement, View

REPO = Path(__file__).resolve().parents[1]
# The project's shared data sits beside the checkout (as CI lays it out); a clone elsewhere
# points at it with OBSTACLE_FUSION_SHARED_DATA.
SHARED_DATA = Path(os.environ.get("OBSTACLE_FUSION_SHARED_DATA", REPO.parent / "shared" / "data"))
CHESSBOARD_DIR = SHARED_DATA / "opencv-chessboard"

BOARD = BoardSpec(9, 6, 0.025)


def real_chessboard_photos() -> list[Path]:
    """The six real OpenCV sample photos; skip only when the shared data is truly absent."""
    if not SHARED_DATA.is_dir():
        pytest.skip(
            f"shared data folder {SHARED_DATA} is absent "
            "(set OBSTACLE_FUSION_SHARED_DATA to the folder holding opencv-chessboard/)"
        )
    photos = sorted(CHESSBOARD_DIR.glob("*.jpg"))
    assert len(photos) == 6, f"expected six photos in {CHESSBOARD_DIR}, found {len(photos)}"
    return photos


def known_camera(width: int = 640, height: int = 480) -> CameraModel:
    """A camera with marked barrel distortion and an off-centre principal point."""
    k = np.array([[610.0, 0.0, 327.3], [0.0, 603.5, 231.8], [0.0, 0.0, 1.0]])
    dist = np.array([-0.21, 0.11, 0.0012, -0.0009, -0.02])
    return CameraModel(k, dist, 640, 480).scaled_to(width, height)


@lru_cache(maxsize=4)
def rendered_boards(
    width: int, height: int, count: int = 9, noise: float = 1.5
) -> tuple[np.ndarray, ...]:
    """Boards through known_camera at this size; identical poses at every size."""
    cam = known_camera(width, height)
    renderer = BoardRenderer(cam, BOARD, supersample=3 if width <= 640 else 2)
    rng = np.random.default_rng(1234)
    poses = default_poses(cam, BOARD, count)
    return tuple(
        renderer.render(p, noise_sigma=noise, blur_sigma=0.5, rng=rng).image for p in poses
    )


@lru_cache(maxsize=64)
def _paper_room(
    family: str, seed: int, hard: bool
) -> tuple[npt.NDArray[np.uint8], dict[str, Any], RoomSpec]:
    """A room rendered once per test process: most room tests measure the same room with a
    rule on and off, and the render costs more than the measurement."""
    image, truth, spec = render_room(family, seed, hard, CameraModel.paper(500, 375))
    image.setflags(write=False)
    return image, truth, spec


def measured_room(
    family: str, seed: int, hard: bool, with_rig: bool = True
) -> tuple[Measurement, dict[str, Any]]:
    """A generated room (rendered once per process) measured at the paper's 500x375, with
    its rig (``with_rig``) or none: the measurement and the room's truth."""
    cam = CameraModel.paper(500, 375)
    image, truth, spec = _paper_room(family, seed, hard)
    return Measurer(cam, spec.rig if with_rig else None).measure(image, truth["range_m"]), truth


def room_size_errors(
    family: str, seed: int, hard: bool, with_rig: bool = True
) -> tuple[float, float]:
    """A generated room measured at the paper's 500x375, with its rig (``with_rig``) or
    none: (height, width) relative errors, the face found."""
    res, truth = measured_room(family, seed, hard, with_rig)
    assert res.detected and res.height_m is not None and res.width_m is not None, res.reason
    return (
        abs(res.height_m / truth["height_m"] - 1),
        abs(res.width_m / truth["width_m"] - 1),
    )


def gradients(
    img: npt.NDArray[np.uint8],
) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.int16], float]:
    """|d/dy|, |d/dx| dilated by one column, and the noise level, as the method takes them
    (one place for the drawn-face tests of the extent stage)."""
    dx = np.empty(img.shape, np.int16)
    dy = np.empty(img.shape, np.int16)
    cv2.spatialGradient(img, dx, dy)
    ay = np.abs(dy).astype(np.float32)
    ax3 = cv2.dilate(np.abs(dx), np.ones((1, 3), np.uint8))
    noise = float(np.median(ay[::4, ::4])) / 0.6745 + 1.0
    return ay, ax3, noise


#: A synthetic front face seen from above, as on a low box (for :func:`.top.front_top`'s
#: tests): the image size, the horizon row, the face's top, foot and sides, its depth.
#: The face (cx = 160) is narrow enough that no top face's back edge could be told from
#: its front one a few rows under it (``top._no_back_edge`` does not judge).
LOW_H, LOW_W = 240, 320
LOW_CY = 20.0
LOW_TOP, LOW_BOTTOM, LOW_LEFT, LOW_RIGHT = 80, 200, 100, 220
LOW_DEPTH = 1.0


def low_box_view() -> View:
    """The level view of a lens looking down on the face (horizon at row LOW_CY)."""
    k = np.array([[300.0, 0.0, LOW_W / 2], [0.0, 300.0, LOW_CY], [0.0, 0.0, 1.0]])
    return View(CameraModel(k, np.zeros(5), LOW_W, LOW_H), Rig(), "level")


def low_box_front_row(
    img: npt.NDArray[np.uint8], horizon_known: bool = False, top_row: int = LOW_TOP
) -> int:
    """The front top edge :func:`.top.front_top` finds under the face's top (``top_row``)
    in ``img`` (``horizon_known``: as with the rig given, see ``top.STAIRS_CHAINED``)."""
    dy = np.empty(img.shape, np.int16)
    dx = np.empty(img.shape, np.int16)
    cv2.spatialGradient(img, dx, dy)
    noise = float(np.median(np.abs(dy[::4, ::4]))) / 0.6745 + 1.0
    row, _ = top.front_top(
        low_box_view(),
        LOW_DEPTH,
        dy,
        LOW_BOTTOM,
        LOW_LEFT,
        LOW_RIGHT,
        top_row,
        noise,
        horizon_known=horizon_known,
    )
    return row


def face_found(
    box: tuple[float, float, float, float], confidence: float, pitch: float | None = None
) -> Measurement:
    """A detection of ``box`` (pixels) at ``confidence``, as a trial of the no-rig search
    returns it (``pitch``: the camera pitch it was levelled for), for the rules that
    compare trials by their boxes."""
    return Measurement(
        detected=True,
        method="fused",
        range_m=2.0,
        height_m=0.3,
        width_m=0.3,
        confidence=confidence,
        box_px=box,
        height_px=box[3] - box[1],
        width_px=box[2] - box[0],
        camera_pitch_deg=pitch,
    )
