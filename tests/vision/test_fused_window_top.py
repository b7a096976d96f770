"""The colour rescue's top walked on up while windows of rows keep the face's mean colour
(``method.WINDOW_RESCUE_TOP``, ``region.raise_top_by_windows``).

The rooms are tuning rooms with the rig: photo 710 hard is a grey-green textured face with a
white tape across it, photo 156 ordinary a brick print on a gravel floor. In both the edges
gave no clear face and the colour rescue put the top on a texture line of the face just
above its foot (710: 82 % short, 156: 81 %): the row walks compare each row's colour with
the face's, and a print changes that row by row. Over windows of 5 cm of rows the face's
mean colour holds, across the tape too, up to its top, where the background follows. The
drawn faces below try each limit of the walk.
"""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import method, region
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import View

from tests.vision_fixtures import room_size_errors

ROOMS = [("photo", 710, True), ("photo", 156, False)]


@pytest.mark.parametrize(("family", "seed", "hard"), ROOMS)
def test_a_textured_face_is_walked_up_to_its_top(family: str, seed: int, hard: bool) -> None:
    eh, _ = room_size_errors(family, seed, hard)
    assert eh < 0.05


@pytest.mark.parametrize(("family", "seed", "hard"), ROOMS)
def test_without_the_window_walk_a_texture_line_is_the_top(
    monkeypatch: pytest.MonkeyPatch, family: str, seed: int, hard: bool
) -> None:
    monkeypatch.setattr(method, "WINDOW_RESCUE_TOP", False)
    eh, _ = room_size_errors(family, seed, hard)
    assert eh > 0.25


def test_a_rig_only_guessed_is_not_walked(monkeypatch: pytest.MonkeyPatch) -> None:
    # every run of the method taken as on a guessed rig: photo/710 keeps its texture line
    monkeypatch.setattr(
        method.FusedMethod,
        "rig_guessed",
        property(lambda _: True, lambda _, __: None),
        raising=False,
    )
    eh, _ = room_size_errors("photo", 710, True)
    assert eh > 0.25


# A drawn face (rows FACE_TOP..BOTTOM, columns LEFT..RIGHT) of stripes STRIPE rows apart
# (a brick course's joints), before a light wall, the walk started at row START inside it.
# At DEPTH with fy 300 a window is 15 rows.
H, W = 240, 320
FACE_TOP, BOTTOM, LEFT, RIGHT = 30, 200, 60, 260
START = 150
STRIPE = 3
DEPTH = 1.0
DARK, LIGHT = 80.0, 120.0
WALL_L = 170.0
FLOOR_LAB = (140.0, 110.0, 140.0)
TAPE = (80, 100)


def view(cy: float = H / 2) -> View:
    """A distortion-free camera with no pitch, its horizon at row ``cy``."""
    k = np.array([[300.0, 0.0, W / 2], [0.0, 300.0, cy], [0.0, 0.0, 1.0]])
    return View(CameraModel(k, np.zeros(5), W, H), Rig(), "level")


def striped_scene(
    tape: bool = False, wall_l: float = WALL_L, light: float = LIGHT, stripe: int = STRIPE
) -> npt.NDArray[np.uint8]:
    """The striped face (dark and ``light`` stripes ``stripe`` rows tall, the top one dark) before a wall of
    lightness ``wall_l``; ``tape``: a white band across the face (rows TAPE)."""
    lab = np.empty((H, W, 3), np.float64)
    lab[:] = (wall_l, 128.0, 128.0)
    lab[BOTTOM:] = FLOOR_LAB
    rows = np.arange(FACE_TOP, BOTTOM)
    shade = np.where(((rows - FACE_TOP) // stripe) % 2 == 0, DARK, light)
    lab[FACE_TOP:BOTTOM, LEFT:RIGHT] = (0.0, 128.0, 128.0)
    lab[FACE_TOP:BOTTOM, LEFT:RIGHT, 0] = shade[:, None]
    if tape:
        lab[TAPE[0] : TAPE[1], LEFT:RIGHT] = (235.0, 128.0, 128.0)
    lab += np.random.default_rng(5).normal(0, 1.5, lab.shape)
    lab[..., 0] *= 100.0 / 255.0  # float Lab: L in 0..100, a and b about 0
    lab[..., 1:] -= 128.0
    bgr = cv2.cvtColor(lab.astype(np.float32), cv2.COLOR_LAB2BGR)
    return np.asarray(np.clip(bgr * 255.0, 0, 255).astype(np.uint8))


def raise_by_windows(img: npt.NDArray[np.uint8], cy: float = H / 2) -> int:
    grey = img.mean(axis=2)
    ay = np.zeros(grey.shape, np.float32)
    ay[1:-1] = np.abs(grey[2:] - grey[:-2])
    return region.raise_top_by_windows(img, view(cy), ay, BOTTOM, START, LEFT, RIGHT, DEPTH)


def test_a_drawn_striped_face_is_walked_up_to_its_top() -> None:
    assert abs(raise_by_windows(striped_scene()) - FACE_TOP) <= 2


def test_a_tape_across_the_face_is_crossed() -> None:
    assert abs(raise_by_windows(striped_scene(tape=True)) - FACE_TOP) <= 2


@pytest.mark.parametrize(("gap_share", "crossed"), [(0.25, True), (0.05, False)])
def test_the_gap_share_decides(
    monkeypatch: pytest.MonkeyPatch, gap_share: float, crossed: bool
) -> None:
    # the tape's 20 rows stop the 30-row windows over about 45 rows: a window's 30 and
    # the share of the 100 rows walked under it (0.15 needed)
    monkeypatch.setattr(region, "WINDOW_GAP_SHARE", gap_share)
    assert (raise_by_windows(striped_scene(tape=True)) < TAPE[0]) is crossed


def test_a_wall_of_the_face_mean_running_on_beside_it_stops_the_walk() -> None:
    # the wall is the stripes' mean lightness: above the start nothing parts the face
    assert raise_by_windows(striped_scene(wall_l=(DARK + LIGHT) / 2)) == START


def test_the_beside_step_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "WINDOW_BESIDE_STEP", 0.0)
    assert raise_by_windows(striped_scene(wall_l=(DARK + LIGHT) / 2)) < START


def test_a_top_below_the_horizon_is_not_raised() -> None:
    # the horizon above the face: a box's top face of the front's colour could show
    assert raise_by_windows(striped_scene(), cy=FACE_TOP - 10) == START
    assert abs(raise_by_windows(striped_scene(), cy=FACE_TOP + 10) - FACE_TOP) <= 2


@pytest.mark.parametrize(("least", "moves"), [(2.2, True), (2.7, False)])
def test_the_least_raise_decides(
    monkeypatch: pytest.MonkeyPatch, least: float, moves: bool
) -> None:
    # the raise is 120 rows, 2.4 times the 50 rows found
    monkeypatch.setattr(region, "WINDOW_MIN_RAISE", least)
    assert (raise_by_windows(striped_scene()) < START) is moves


def coarse_scene() -> npt.NDArray[np.uint8]:
    """Stripes of 15 rows: a 15-row window strays by up to 20 from the face's mean, a
    30-row one (a whole period) by the 4.4 the face found (3 stripes) is off it."""
    return striped_scene(stripe=15)


@pytest.mark.parametrize(("limit", "moves"), [(5.0, True), (4.0, False)])
def test_the_spread_limit_decides(
    monkeypatch: pytest.MonkeyPatch, limit: float, moves: bool
) -> None:
    monkeypatch.setattr(region, "WINDOW_MAX_SPREAD", limit)
    assert (raise_by_windows(coarse_scene()) < START) is moves


def test_coarse_stripes_are_read_over_wider_windows(monkeypatch: pytest.MonkeyPatch) -> None:
    assert abs(raise_by_windows(coarse_scene()) - FACE_TOP) <= 2
    monkeypatch.setattr(region, "WINDOW_WIDER", 1)
    assert raise_by_windows(coarse_scene()) == START


@pytest.mark.parametrize(("tol", "moves"), [(1.5, True), (0.5, False)])
def test_the_face_tolerance_decides(
    monkeypatch: pytest.MonkeyPatch, tol: float, moves: bool
) -> None:
    # the fine stripes' 30-row windows stray by 0.9 from the face's mean
    monkeypatch.setattr(region, "WINDOW_FACE_TOL", tol)
    assert (raise_by_windows(striped_scene()) < START) is moves


@pytest.mark.parametrize(("resume", "crossed"), [(0.5, True), (1.0, False)])
def test_the_resume_share_decides(
    monkeypatch: pytest.MonkeyPatch, resume: float, crossed: bool
) -> None:
    # above the tape the face's 30-row windows hold over about 20 rows: under a whole
    # window, over half of one
    monkeypatch.setattr(region, "WINDOW_RESUME_SHARE", resume)
    assert (raise_by_windows(striped_scene(tape=True)) < TAPE[0]) is crossed
