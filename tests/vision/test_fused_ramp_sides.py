"""A shading ramp of one colour (a shadow's penumbra on the floor) is no side."""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import search
from obstacle_fusion.vision.fused.search import ramp_columns
from obstacle_fusion.vision.measure import Measurer

W, ROWS, EDGE = 120, 12, 60


def strip(
    left: tuple[int, int, int], right: tuple[int, int, int], width: int
) -> npt.NDArray[np.uint8]:
    """A BGR strip going from colour ``left`` to ``right`` linearly over ``width`` columns
    centred on EDGE, with a little noise."""
    t = np.clip((np.arange(W) - (EDGE - width / 2)) / max(width, 1), 0.0, 1.0)
    row = (1 - t)[:, None] * np.array(left, float) + t[:, None] * np.array(right, float)
    img = np.repeat(row[None], ROWS, axis=0)
    img += np.random.default_rng(5).normal(0, 1.5, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def ramps(img: npt.NDArray[np.uint8]) -> set[int]:
    grey = cv2.cvtColor(img, cv2.COLOR_BGR2GRAY)
    lab = cv2.cvtColor(img, cv2.COLOR_BGR2LAB)
    return ramp_columns(grey, lab, [EDGE])


FLOOR = (95, 110, 125)  # a greyish brown floor (BGR)
SHADOW = (71, 82, 94)  # the same floor in shadow (3/4 of its light)
GREEN = (60, 150, 60)


def test_a_penumbra_of_the_floors_colour_is_a_ramp() -> None:
    assert ramps(strip(SHADOW, FLOOR, 14)) == {EDGE}


def test_a_sharp_edge_between_two_shades_is_a_side() -> None:
    assert ramps(strip(SHADOW, FLOOR, 2)) == set()


def test_a_ramp_between_two_colours_is_a_side() -> None:
    # a face's side blurred by shading at its foot still parts two colours
    assert ramps(strip(GREEN, FLOOR, 14)) == set()


def _error(monkeypatch: pytest.MonkeyPatch | None = None) -> float:
    cam = CameraModel.paper(500, 375)
    image, truth, spec = render_room("procedural", 146, False, cam)
    res = Measurer(cam, spec.rig).measure(image, truth["range_m"])
    assert res.detected and res.height_m is not None and res.width_m is not None
    return max(abs(res.height_m / truth["height_m"] - 1), abs(res.width_m / truth["width_m"] - 1))


def test_the_contact_shadow_beside_a_box_is_not_measured() -> None:
    # the shadow left of the box, its penumbra taken for a side, was the face (-84 %)
    assert _error() < 0.12


def test_without_the_rule_the_shadow_is_measured(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(search, "RAMP_SIDES", False)
    assert _error() > 0.25
