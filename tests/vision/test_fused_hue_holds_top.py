"""The top walked on up while the face keeps its own hue (``method.HUE_HOLDS_TOP``,
``region.raise_top_by_hue``).

The rooms are tuning rooms (procedural, seeds 700-759): procedural 757 ordinary is a plain
grey-violet face with a gloss whose highlight lightens its upper half, standing before a
pink skirting band of nearly the highlight's shade; the colour walks stopped where the
highlight starts and the sides' walk where the face's left side lost the band's contrast,
so the top was put on the highlight's lower edge, 59 % too low, with the rig and without.
The face's hue holds from its foot up to its top (the highlight changes its lightness as a
ramp); above its top a lid's hue and the wall's follow at a step. The drawn faces below
try each limit of the walk.
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


@pytest.mark.parametrize("with_rig", [True, False])
def test_a_gloss_face_keeps_its_hue_up_to_its_top(with_rig: bool) -> None:
    eh, ew = room_size_errors("procedural", 757, False, with_rig)
    assert eh < 0.05 and ew < 0.05


def test_without_the_hue_walk_the_highlight_is_taken_for_the_top(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(method, "HUE_HOLDS_TOP", False)
    eh, _ = room_size_errors("procedural", 757, False)
    assert eh > 0.25


def test_the_highlight_is_a_ramp_the_drift_limit_lets_through(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # the highlight lightens the face by up to 5 units in DRIFT_ROWS rows
    monkeypatch.setattr(region, "HUE_DRIFT", 3.0)
    eh, _ = room_size_errors("procedural", 757, False)
    assert eh > 0.25


def test_the_face_ends_at_an_edge_much_stronger_than_the_highlight(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # the face's top against the lid is about 15 times the highlight's edge (the ramp test,
    # which takes the walk's top where the highlight fades as a ramp, off)
    monkeypatch.setattr(region, "HUE_TOP_EDGE_GAIN", 20.0)
    monkeypatch.setattr(region, "HUE_RAMP_TOP", False)
    eh, _ = room_size_errors("procedural", 757, False)
    assert eh > 0.25


# A drawn gloss face (rows FACE_TOP..BOTTOM, columns LEFT..RIGHT) before an olive wall with
# a pink band of nearly the highlight's lightness beside the face (rows BAND): the
# highlight lightens the face's upper part as a ramp, its lower end at row HIGHLIGHT_LOW.
H, W = 240, 320
FACE_TOP, BOTTOM, LEFT, RIGHT = 40, 200, 60, 260
HIGHLIGHT_LOW = 110
BAND = (100, 130)
DEPTH = 1.0
FACE_LAB = (92.0, 138.0, 120.0)
WALL_LAB = (110.0, 115.0, 162.0)
BAND_LAB = (108.0, 139.0, 128.0)
FLOOR_LAB = (147.0, 104.0, 130.0)


def level_view() -> View:
    """A distortion-free camera with no pitch (the horizon at row H / 2)."""
    k = np.array([[300.0, 0.0, W / 2], [0.0, 300.0, H / 2], [0.0, 0.0, 1.0]])
    return View(CameraModel(k, np.zeros(5), W, H), Rig(), "level")


def gloss_scene(
    hue_rows: float = 0.0, behind_rows: int = 0, behind_shade: float = 0.0
) -> npt.NDArray[np.uint8]:
    """The gloss face; ``hue_rows``: the face's hue moved by that much (b) on alternate
    groups of 4 rows (a face of varying hue); ``behind_rows``: a box of the face's hue
    (``behind_shade`` lighter) standing behind it in line, that many rows above its top."""
    lab = np.empty((H, W, 3), np.float64)
    lab[:] = WALL_LAB
    lab[BAND[0] : BAND[1]] = BAND_LAB
    lab[BOTTOM:] = FLOOR_LAB
    rows = np.arange(FACE_TOP, BOTTOM)
    light = np.clip((HIGHLIGHT_LOW - rows) / (HIGHLIGHT_LOW - FACE_TOP - 20), 0.0, 1.0)
    lab[FACE_TOP:BOTTOM, LEFT:RIGHT] = FACE_LAB
    lab[FACE_TOP:BOTTOM, LEFT:RIGHT, 0] += 35.0 * light[:, None]
    if hue_rows:
        lab[FACE_TOP:BOTTOM, LEFT:RIGHT, 2] += np.where((rows // 4) % 2 == 0, hue_rows, 0.0)[
            :, None
        ]
    if behind_rows:
        box = lab[FACE_TOP - behind_rows : FACE_TOP, LEFT:RIGHT]
        box[:] = FACE_LAB
        box[..., 0] += 35.0 + behind_shade
    lab += np.random.default_rng(3).normal(0, 1.5, lab.shape)
    return cv2.cvtColor(np.clip(lab, 0, 255).astype(np.uint8), cv2.COLOR_LAB2BGR)


def raise_by_hue(img: npt.NDArray[np.uint8], right: int = RIGHT) -> int:
    grey = img.mean(axis=2)
    ay = np.zeros(grey.shape, np.float32)
    ay[1:-1] = np.abs(grey[2:] - grey[:-2])
    return region.raise_top_by_hue(img, level_view(), ay, BOTTOM, HIGHLIGHT_LOW, LEFT, right, DEPTH)


def test_a_drawn_gloss_face_is_walked_up_to_its_top() -> None:
    assert abs(raise_by_hue(gloss_scene()) - FACE_TOP) <= 2


def test_a_side_out_on_the_background_walks_no_top() -> None:
    # the strip inside the right side reads the wall and the band, not the face's hue
    assert raise_by_hue(gloss_scene(), right=RIGHT + 12) == HIGHLIGHT_LOW


def test_a_face_of_varying_hue_is_not_walked() -> None:
    # its rows 4 apart in hue: within SHADED_HUE_STEP, but no plain face
    assert raise_by_hue(gloss_scene(hue_rows=4.0)) == HIGHLIGHT_LOW


def test_the_plain_hue_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "PLAIN_HUE_SPREAD", 5.0)
    assert raise_by_hue(gloss_scene(hue_rows=4.0)) < HIGHLIGHT_LOW - 20


def test_a_box_of_the_face_hue_behind_it_stops_the_walk_at_a_step() -> None:
    # 30 rows of a box of the face's hue, 15 lighter than its top rows, in line above it
    assert abs(raise_by_hue(gloss_scene(behind_rows=30, behind_shade=15.0)) - FACE_TOP) <= 2


def test_the_drift_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "HUE_DRIFT", 20.0)
    assert raise_by_hue(gloss_scene(behind_rows=30, behind_shade=15.0)) < FACE_TOP - 20


def test_the_drawn_top_edge_gain_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "HUE_TOP_EDGE_GAIN", 1000.0)
    monkeypatch.setattr(region, "HUE_RAMP_TOP", False)  # the highlight's lower end is a ramp
    assert raise_by_hue(gloss_scene()) == HIGHLIGHT_LOW


def step_scene() -> npt.NDArray[np.uint8]:
    """The drawn face with its upper part (rows FACE_TOP..HIGHLIGHT_LOW) 8 lighter at a
    step, not a ramp, before a wall of that lightness 8 apart from it in hue: the face's
    end above is a fainter edge than where the walk starts."""
    lab = np.empty((H, W, 3), np.float64)
    lab[:] = (FACE_LAB[0] + 8.0, FACE_LAB[1], FACE_LAB[2] + 8.0)
    lab[BAND[0] : BAND[1]] = BAND_LAB
    lab[BOTTOM:] = FLOOR_LAB
    lab[FACE_TOP:BOTTOM, LEFT:RIGHT] = FACE_LAB
    lab[FACE_TOP:HIGHLIGHT_LOW, LEFT:RIGHT, 0] += 8.0
    lab += np.random.default_rng(3).normal(0, 1.5, lab.shape)
    return cv2.cvtColor(np.clip(lab, 0, 255).astype(np.uint8), cv2.COLOR_LAB2BGR)


def test_a_top_on_a_clearer_edge_than_the_end_above_is_kept() -> None:
    assert raise_by_hue(step_scene()) == HIGHLIGHT_LOW


def test_the_edge_gain_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "HUE_TOP_EDGE_GAIN", 0.0)
    assert abs(raise_by_hue(step_scene()) - FACE_TOP) <= 2
