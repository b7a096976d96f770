"""The hue walk's top taken where the top it left is a lightness ramp, not an edge
(``region.HUE_RAMP_TOP``, ``HUE_RAMP_STEP``, ``HUE_RAMP_ROWS``).

photo/3009 ordinary (set new, seed 3009) is a beige gloss face before a light grey
photograph: the highlight fades down the face as a ramp and the top was put on it, 40 %
short. The face's hue holds up to its true top, but its end against the grey is a fainter
edge than the ramp's gradient, so the walk's edge test (``HUE_TOP_EDGE_GAIN``) refused it.
Where nothing ends the face at the top it left (its lightness runs on across it as a ramp)
the walk's top is taken. The drawn faces try the step limit and the window.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import region
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import View

Room = tuple[npt.NDArray[np.uint8], dict[str, Any], Rig]


@pytest.fixture(scope="module")
def room() -> Room:
    cam = CameraModel.paper(500, 375)
    image, truth, spec = render_room("photo", 3009, False, cam)
    return image, truth, spec.rig


def height_error(room: Room) -> float:
    image, truth, rig = room
    cam = CameraModel.paper(500, 375)
    res = Measurer(cam, rig).measure(image, float(truth["range_m"]))
    assert res.detected and res.height_m is not None and res.width_m is not None
    assert abs(res.width_m / float(truth["width_m"]) - 1) < 0.05
    return res.height_m / float(truth["height_m"]) - 1


@pytest.fixture
def ramp_off(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    monkeypatch.setattr(region, "HUE_RAMP_TOP", False)
    yield


def test_a_gloss_face_before_a_wall_of_its_lightness_is_measured_whole(room: Room) -> None:
    assert abs(height_error(room)) < 0.08


def test_without_the_rule_the_top_stays_on_the_ramp(room: Room, ramp_off: None) -> None:
    assert height_error(room) < -0.25


# A drawn face (rows FACE_TOP..BOTTOM, columns LEFT..RIGHT) whose lightness ramps up by RAMP
# from row LOW (the top the walk starts from) to its top, before a grey wall of about the
# top's lightness: the face's end is a fainter edge than the ramp's gradient at LOW. The
# walk's edge test is set out of reach in these, so the ramp test alone decides.
H, W = 240, 320
FACE_TOP, BOTTOM, LEFT, RIGHT, LOW = 40, 200, 60, 260, 110
RAMP = 30.0
FACE_LAB = (120.0, 150.0, 140.0)
WALL_LAB = (153.0, 128.0, 128.0)
FLOOR_LAB = (90.0, 110.0, 140.0)


def level_view() -> View:
    """A distortion-free camera with no pitch (the horizon at row H / 2)."""
    k = np.array([[300.0, 0.0, W / 2], [0.0, 300.0, H / 2], [0.0, 0.0, 1.0]])
    return View(CameraModel(k, np.zeros(5), W, H), Rig(), "level")


def ramp_scene(step: float = 0.0, step_row: int = LOW) -> npt.NDArray[np.uint8]:
    """The drawn face; ``step``: the rows above ``step_row`` that much lighter at a step."""
    lab = np.empty((H, W, 3), np.float64)
    lab[:] = WALL_LAB
    lab[BOTTOM:] = FLOOR_LAB
    rows = np.arange(FACE_TOP, BOTTOM)
    light = RAMP * np.clip((LOW - rows) / (LOW - FACE_TOP), 0.0, 1.0)
    lab[FACE_TOP:BOTTOM, LEFT:RIGHT] = FACE_LAB
    lab[FACE_TOP:BOTTOM, LEFT:RIGHT, 0] += (light + np.where(rows < step_row, step, 0.0))[:, None]
    lab += np.random.default_rng(3).normal(0, 1.5, lab.shape)
    return cv2.cvtColor(np.clip(lab, 0, 255).astype(np.uint8), cv2.COLOR_LAB2BGR)


@pytest.fixture(autouse=True)
def no_edge_gain(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> None:
    if "room" not in request.fixturenames:
        monkeypatch.setattr(region, "HUE_TOP_EDGE_GAIN", 1000.0)


def raise_by_hue(img: npt.NDArray[np.uint8]) -> int:
    grey = img.mean(axis=2)
    ay = np.zeros(grey.shape, np.float32)
    ay[1:-1] = np.abs(grey[2:] - grey[:-2])
    return region.raise_top_by_hue(img, level_view(), ay, BOTTOM, LOW, LEFT, RIGHT, 1.0)


def test_a_drawn_ramp_is_walked_to_the_faint_top() -> None:
    assert abs(raise_by_hue(ramp_scene()) - FACE_TOP) <= 2


def test_the_faint_top_is_refused_without_the_rule(ramp_off: None) -> None:
    assert raise_by_hue(ramp_scene()) == LOW


def test_a_small_step_at_the_top_left_is_still_a_ramp() -> None:
    # 2 L at the top left: within HUE_RAMP_STEP of the ramp's own change
    assert abs(raise_by_hue(ramp_scene(step=2.0)) - FACE_TOP) <= 2


def test_a_step_past_the_limit_keeps_the_top() -> None:
    # 6 L at the top left: an edge across the face
    assert raise_by_hue(ramp_scene(step=6.0)) == LOW


def test_the_step_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "HUE_RAMP_STEP", 10.0)
    assert abs(raise_by_hue(ramp_scene(step=6.0)) - FACE_TOP) <= 2
    monkeypatch.setattr(region, "HUE_RAMP_STEP", 0.5)
    assert raise_by_hue(ramp_scene()) == LOW


def test_the_window_reaches_a_step_near_the_top_left(monkeypatch: pytest.MonkeyPatch) -> None:
    # a step 9 rows above the top left: outside HUE_RAMP_ROWS, inside 12 rows
    scene = ramp_scene(step=6.0, step_row=LOW - 9)
    assert abs(raise_by_hue(scene) - FACE_TOP) <= 2
    monkeypatch.setattr(region, "HUE_RAMP_ROWS", 12)
    assert raise_by_hue(scene) == LOW


def test_a_grey_face_is_not_walked_past_a_faint_top(monkeypatch: pytest.MonkeyPatch) -> None:
    # the drawn face's chroma is 25: a face less chromatic than HUE_RAMP_MIN_CHROMA has no
    # hue that a grey wall above it does not share
    monkeypatch.setattr(region, "HUE_RAMP_MIN_CHROMA", 26.0)
    assert raise_by_hue(ramp_scene()) == LOW
    monkeypatch.setattr(region, "HUE_RAMP_MIN_CHROMA", 24.0)
    assert abs(raise_by_hue(ramp_scene()) - FACE_TOP) <= 2
