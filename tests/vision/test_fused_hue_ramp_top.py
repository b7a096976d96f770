"""The hue walk's top taken where the top it left is a lightness ramp, not an edge
(``region.HUE_RAMP_TOP``, ``HUE_RAMP_STEP``, ``HUE_RAMP_ROWS``).

photo/3009 ordinary (set new, seed 3009) is a beige gloss face before a light grey
photograph: the highlight fades down the face as a ramp and the top was put on it, 40 %
short. The face's hue holds up to its true top, but its end against the grey is a fainter
edge than the ramp's gradient, so the walk's edge test (``HUE_TOP_EDGE_GAIN``) refused it.
Where nothing ends the face at the top it left (its lightness runs on across it as a ramp)
the walk's top is taken. The drawn faces try the step limit, wherever the step lies in the
window, the window itself, and the chroma limit; photo/3083 ordinary with no rig tries the
chroma limit on a grey face before a grey photograph.
"""

from __future__ import annotations

import math
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


def _ordinary_photo_room(seed: int) -> Room:
    image, truth, spec = render_room("photo", seed, False, CameraModel.paper(500, 375))
    return image, truth, spec.rig


@pytest.fixture(scope="module")
def room() -> Room:
    return _ordinary_photo_room(3009)


def height_error(room: Room) -> float:
    image, truth, rig = room
    cam = CameraModel.paper(500, 375)
    res = Measurer(cam, rig).measure(image, float(truth["range_m"]))
    assert res.detected and res.height_m is not None and res.width_m is not None
    assert abs(res.width_m / float(truth["width_m"]) - 1) < 0.05
    return res.height_m / float(truth["height_m"]) - 1


@pytest.fixture(scope="module")
def grey_room() -> Room:
    return _ordinary_photo_room(3083)


def grey_room_error(room: Room) -> float:
    image, truth, _ = room
    # with no rig
    res = Measurer(CameraModel.paper(500, 375), None).measure(image, float(truth["range_m"]))
    assert res.detected and res.height_m is not None
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
FACE_LAB = (120.0, 150.0, 140.0)  # chroma 25.1 drawn, 24.6 read back through 8-bit BGR
WALL_LAB = (153.0, 128.0, 128.0)
FLOOR_LAB = (90.0, 110.0, 140.0)
# a step past the limit wherever it lies (blurred, sigma 1 row: one change over DRIFT_ROWS
# holds 0.87 of it, and the rows' medians round to 1 L), and one well within it
OVER, WITHIN = 8.0, 3.0
# a of faces whose chroma reads back 11.0 and 13.0 (b reads 127)
CHROMA_11, CHROMA_13 = 11.0, 13.0


NOISE = np.random.default_rng(3).normal(0, 1.5, (H, W, 3))


def level_view() -> View:
    """A distortion-free camera with no pitch (the horizon at row H / 2)."""
    k = np.array([[300.0, 0.0, W / 2], [0.0, 300.0, H / 2], [0.0, 0.0, 1.0]])
    return View(CameraModel(k, np.zeros(5), W, H), Rig(), "level")


def ramp_scene(
    step: float = 0.0,
    step_row: int = LOW,
    ramp: float = RAMP,
    blur: float = 0.0,
    face: tuple[float, float, float] = FACE_LAB,
) -> npt.NDArray[np.uint8]:
    """The drawn face; ``step``: the rows above ``step_row`` that much lighter at a step
    (blurred over ``blur`` rows, a Gaussian's sigma)."""
    lab = np.empty((H, W, 3), np.float64)
    lab[:] = WALL_LAB
    lab[BOTTOM:] = FLOOR_LAB
    rows = np.arange(FACE_TOP, BOTTOM)
    light = ramp * np.clip((LOW - rows) / (LOW - FACE_TOP), 0.0, 1.0)
    if blur > 0:
        edge = 0.5 + 0.5 * np.array(
            [math.erf((step_row - 0.5 - r) / (blur * 2**0.5)) for r in rows]
        )
    else:
        edge = (rows < step_row).astype(np.float64)
    lab[FACE_TOP:BOTTOM, LEFT:RIGHT] = face
    lab[FACE_TOP:BOTTOM, LEFT:RIGHT, 0] += (light + step * edge)[:, None]
    lab += NOISE
    return cv2.cvtColor(np.clip(lab, 0, 255).astype(np.uint8), cv2.COLOR_LAB2BGR)


@pytest.fixture(autouse=True)
def no_edge_gain(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> None:
    if "room" not in request.fixturenames and "grey_room" not in request.fixturenames:
        monkeypatch.setattr(region, "HUE_TOP_EDGE_GAIN", 1000.0)


def raise_by_hue(img: npt.NDArray[np.uint8]) -> int:
    grey = img.mean(axis=2)
    ay = np.zeros(grey.shape, np.float32)
    ay[1:-1] = np.abs(grey[2:] - grey[:-2])
    return region.raise_top_by_hue(img, level_view(), ay, BOTTOM, LOW, LEFT, RIGHT, 1.0)


def walked(img: npt.NDArray[np.uint8]) -> bool:
    return abs(raise_by_hue(img) - FACE_TOP) <= 2


def test_a_drawn_ramp_is_walked_to_the_faint_top() -> None:
    assert walked(ramp_scene())


def test_the_faint_top_is_refused_without_the_rule(ramp_off: None) -> None:
    assert raise_by_hue(ramp_scene()) == LOW


def test_a_steep_ramp_starting_at_the_top_left_is_walked() -> None:
    # 1.7 L a row from LOW up, flat below: 5.1 L a change against 0 below the bend (a
    # change set against the window's mean, or read alone, refuses it); a ramp's changes
    # stand out of nothing
    assert raise_by_hue(ramp_scene(ramp=120.0)) < LOW - 30


def test_a_small_step_at_the_top_left_is_still_a_ramp() -> None:
    # 2 L at the top left: within HUE_RAMP_STEP of the ramp's own change
    assert walked(ramp_scene(step=2.0))


def test_a_step_past_the_limit_keeps_the_top() -> None:
    # 6 L at the top left: an edge across the face
    assert raise_by_hue(ramp_scene(step=6.0)) == LOW


def test_a_blurred_step_is_refused_wherever_it_lies_in_the_window() -> None:
    # the step's boundary from HUE_RAMP_ROWS above the top left to as far below it, across
    # the ramp's bend at LOW: the step is not part of its own reference (against the
    # window's mean change, 8 L 3-6 rows below the top left or 6 above it passed)
    rows = range(LOW - region.HUE_RAMP_ROWS, LOW + region.HUE_RAMP_ROWS + 1)
    for sign in (1, -1):
        kept = [r for r in rows if raise_by_hue(ramp_scene(sign * OVER, r, blur=1.0)) == LOW]
        assert kept == list(rows), sign
    assert all(walked(ramp_scene(WITHIN, r, blur=1.0)) for r in rows)


def test_the_step_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "HUE_RAMP_STEP", 10.0)
    assert walked(ramp_scene(step=6.0))
    monkeypatch.setattr(region, "HUE_RAMP_STEP", 0.5)
    assert raise_by_hue(ramp_scene()) == LOW


def test_the_window_reaches_hue_ramp_rows_either_side(monkeypatch: pytest.MonkeyPatch) -> None:
    # at the default 6 a step 6 rows above the top left or 6 below it (rows from LOW + 6
    # lighter) is in the window, 7 is not
    def kept(step_row: int) -> bool:
        return raise_by_hue(ramp_scene(OVER, step_row, 0.0, 1.0)) == LOW

    assert kept(LOW - 6) and not kept(LOW - 7)
    assert kept(LOW + 6) and not kept(LOW + 7)
    monkeypatch.setattr(region, "HUE_RAMP_ROWS", 5)
    assert not kept(LOW - 6) and not kept(LOW + 6)
    monkeypatch.setattr(region, "HUE_RAMP_ROWS", 7)
    assert kept(LOW + 7)


def test_a_grey_face_is_not_walked_past_a_faint_top(monkeypatch: pytest.MonkeyPatch) -> None:
    # the drawn face's chroma is 24.6 read back: a face less chromatic than
    # HUE_RAMP_MIN_CHROMA has no hue that a grey wall above it does not share
    monkeypatch.setattr(region, "HUE_RAMP_MIN_CHROMA", 25.0)
    assert raise_by_hue(ramp_scene()) == LOW
    monkeypatch.setattr(region, "HUE_RAMP_MIN_CHROMA", 24.0)
    assert walked(ramp_scene())


def test_the_chroma_limit_at_its_default() -> None:
    # faces of chroma 11 and 13 read back (a, b from 128) round the default 12
    assert region.HUE_RAMP_MIN_CHROMA == 2 * region.SHADED_HUE_STEP
    assert raise_by_hue(ramp_scene(face=(120.0, 128.0 + CHROMA_11, 128.0))) == LOW
    assert walked(ramp_scene(face=(120.0, 128.0 + CHROMA_13, 128.0)))


def test_a_grey_face_before_a_grey_photograph_keeps_its_top(grey_room: Room) -> None:
    # photo/3083 ordinary, no rig: a trial's face on the grey photograph is not walked up
    # it (with HUE_RAMP_MIN_CHROMA 0 it outscores the box: +110 %, not +1.2 %)
    assert abs(grey_room_error(grey_room)) < 0.05
