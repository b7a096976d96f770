"""A face's end that is the floor in its shadow is trimmed off (``region.SHADOW_ENDS_TRIMMED``,
``region.trim_shadow_ends``, called at the start of ``FusedMethod._refine``).

new4 photo 3183 ordinary: a lilac panelled box on a grey gravel floor, its cast shadow on
the floor to its right (the floor's grey, 10-20 darker); the colour walk along the foot took
the shadow in up to a green post, +35 % wide with the rig and without. The drawn faces
below try each limit: how much darker, how far off the floor's chroma, how wide a run,
how far in from the side it may start, and a face of the floor's own shade.
"""

from __future__ import annotations

from typing import Any

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.sim.room_scene import RoomSpec, render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import region
from obstacle_fusion.vision.fused.region import _shade_run, floor_shade_columns, trim_shadow_ends
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import View

CAM = CameraModel.paper(500, 375)

STEP = 0.25  # just inside or just outside a limit (Lab units)


@pytest.fixture(scope="module")
def room_3183() -> tuple[npt.NDArray[np.uint8], dict[str, Any], RoomSpec]:
    """new4 photo 3183 ordinary, rendered once for the module."""
    return render_room("photo", 3183, False, CAM)


@pytest.mark.parametrize("on", [True, False])
def test_a_box_s_cast_shadow_is_no_part_of_its_width(
    monkeypatch: pytest.MonkeyPatch,
    on: bool,
    room_3183: tuple[npt.NDArray[np.uint8], dict[str, Any], RoomSpec],
) -> None:
    monkeypatch.setattr(region, "SHADOW_ENDS_TRIMMED", on)
    image, truth, spec = room_3183
    res = Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    assert res.detected and res.width_m is not None
    ew = abs(res.width_m / truth["width_m"] - 1)
    assert (ew < 0.05) is on, ew


def test_the_figures() -> None:
    assert region.SHADOW_END_DARKER == 6.0 and region.SHADOW_END_CHROMA == 6.0
    assert (region.SHADOW_END_MIN_M, region.SHADOW_END_LEAD_PX) == (0.03, 3)
    assert (region.SHADOW_END_KEEP_SHARE, region.SHADOW_END_FACE_SHARE) == (0.5, 0.2)


def _lab(*entries: tuple[float, float, float]) -> npt.NDArray[np.float32]:
    return np.array(entries, np.float32)


def test_the_shadow_is_darker_by_the_limit() -> None:
    floor = _lab((100.0, 128.0, 128.0), (100.0, 128.0, 128.0))
    d = region.SHADOW_END_DARKER
    colour = _lab((100.0 - d - STEP, 128.0, 128.0), (100.0 - d + STEP, 128.0, 128.0))
    assert floor_shade_columns(colour, floor).tolist() == [True, False]


def test_the_shadow_keeps_the_floor_s_chroma_scaled_by_its_light() -> None:
    # a floor of a, b offsets (20, -10) at L 100; at L 50 its shadow's are (10, -5)
    floor = _lab((100.0, 148.0, 118.0), (100.0, 148.0, 118.0), (100.0, 148.0, 118.0))
    c = region.SHADOW_END_CHROMA
    colour = _lab(
        (50.0, 138.0, 123.0),
        (50.0, 138.0 + c - STEP, 123.0),
        (50.0, 138.0 + c + STEP, 123.0),
    )
    assert floor_shade_columns(colour, floor).tolist() == [True, True, False]


def test_a_grey_floor_counts() -> None:
    """Unlike the frame test's shadow (SHADOW_FLOOR_CHROMA), a grey floor's shade is one."""
    assert floor_shade_columns(_lab((60.0, 128.0, 128.0)), _lab((80.0, 128.0, 128.0)))[0]


@pytest.mark.parametrize("start", [0, region.SHADOW_END_LEAD_PX, region.SHADOW_END_LEAD_PX + 1])
@pytest.mark.parametrize("run", [9, 10])
def test_a_run_from_the_side_is_cut_from_its_least_width_and_lead(start: int, run: int) -> None:
    shade = np.zeros(40, bool)
    shade[start : start + run] = True
    cut = _shade_run(shade, 10)
    inside = run >= 10 and start <= region.SHADOW_END_LEAD_PX
    assert cut == (start + run if inside else 0)


# A drawn grey-floor room (a distortion-free level camera): a lilac face on columns
# LEFT..RIGHT standing on row BOTTOM, its shadow to the right (SHADOW_W columns of the
# floor's grey, darker), a grey wall above the floor.
H, W = 240, 320
TOP, BOTTOM, LEFT, RIGHT = 120, 190, 100, 200
DEPTH = 2.0  # SHADOW_END_MIN_M at 300 px focal length: 4.5 -> 4 columns (then 3)
FACE_LAB = (160.0, 137.0, 122.0)
FLOOR_LAB = (80.0, 128.0, 128.0)
WALL_LAB = (120.0, 128.0, 140.0)


def level_view() -> View:
    k = np.array([[300.0, 0.0, W / 2], [0.0, 300.0, H / 2], [0.0, 0.0, 1.0]])
    return View(CameraModel(k, np.zeros(5), W, H), Rig(), "level")


def shadow_scene(
    shadow_w: int, darker: float, face: tuple[float, float, float] = FACE_LAB
) -> npt.NDArray[np.uint8]:
    lab = np.empty((H, W, 3), np.float64)
    lab[:] = WALL_LAB
    lab[H // 2 :] = FLOOR_LAB
    lab[H // 2 : BOTTOM, RIGHT : RIGHT + shadow_w] = FLOOR_LAB
    lab[H // 2 : BOTTOM, RIGHT : RIGHT + shadow_w, 0] -= darker
    lab[TOP:BOTTOM, LEFT:RIGHT] = face
    lab += np.random.default_rng(5).normal(0, 1.0, lab.shape)
    return cv2.cvtColor(np.clip(lab, 0, 255).astype(np.uint8), cv2.COLOR_LAB2BGR)


def test_a_drawn_shadow_is_cut_back_to_the_face_s_side() -> None:
    img = shadow_scene(30, 20.0)
    left, right = trim_shadow_ends(img, level_view(), BOTTOM, LEFT, RIGHT + 30, DEPTH)
    assert left == LEFT and abs(right - RIGHT) <= 2


def test_a_faint_shade_is_no_shadow() -> None:
    img = shadow_scene(30, 3.0)
    assert trim_shadow_ends(img, level_view(), BOTTOM, LEFT, RIGHT + 30, DEPTH) == (
        LEFT,
        RIGHT + 30,
    )


def test_switched_off_nothing_is_cut(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "SHADOW_ENDS_TRIMMED", False)
    img = shadow_scene(30, 20.0)
    assert trim_shadow_ends(img, level_view(), BOTTOM, LEFT, RIGHT + 30, DEPTH) == (
        LEFT,
        RIGHT + 30,
    )


def test_a_face_of_the_floor_s_shade_is_left_whole() -> None:
    """A grey face darker than the grey floor reads as shade itself: nothing is cut."""
    dark = (FLOOR_LAB[0] - 20.0, 128.0, 128.0)
    img = shadow_scene(30, 20.0, face=dark)
    assert trim_shadow_ends(img, level_view(), BOTTOM, LEFT, RIGHT + 30, DEPTH) == (
        LEFT,
        RIGHT + 30,
    )


def test_a_shadow_wider_than_the_face_is_left() -> None:
    """The trim leaves at least SHADOW_END_KEEP_SHARE of the width: a 'shadow' wider than
    the face is more likely the face's own dark part than its shadow."""
    img = shadow_scene(120, 20.0)
    assert trim_shadow_ends(img, level_view(), BOTTOM, LEFT, RIGHT + 120, DEPTH) == (
        LEFT,
        RIGHT + 120,
    )
