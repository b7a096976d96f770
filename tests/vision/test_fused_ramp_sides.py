"""A shading ramp of one colour (a shadow's penumbra on the floor) is no side."""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import method, search
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
    # the shadow lies in the cone's outer part: the far share (method.FAR_OFF_AXIS) alone
    # passes it over too
    monkeypatch.setattr(method, "FAR_OFF_AXIS", False)
    assert _error() > 0.25


def test_the_ramp_walks_in_c_are_numpy_s(monkeypatch: pytest.MonkeyPatch) -> None:
    """The accelerator's walks (ramp_spans) give the numpy walks' spans and so the same
    ramps: random strips, strips with ramps, two-level strips (ties, even row counts: a
    median half-way), rows from 1 to past the C sort's 64 (counted there), strips of 1-3
    columns, candidate columns at both ends and repeated, none; strided and reversed
    views. A column outside the strip stays numpy's."""
    from obstacle_fusion.vision.fused import _cmiddle

    assert search._c_ramp_spans is not None, "the C accelerator is not built (make setup)"
    rng = np.random.default_rng(31)
    for it in range(1500):
        rows, w = int(rng.integers(1, 90)), int(rng.integers(1, 45))
        if it % 3 == 0:
            s = rng.integers(0, 256, (rows, w)).astype(np.uint8)
        elif it % 3 == 1:
            base = np.cumsum(rng.integers(-3, 12, w)).clip(0, 255)
            s = (base[None, :] + rng.integers(-2, 3, (rows, w))).clip(0, 255).astype(np.uint8)
        else:
            s = rng.choice(np.array([0, 128, 255], np.uint8), (rows, w))
        views = (s, s[:, ::-1], s[::-1], np.asfortranarray(s))
        cols = [int(c) for c in rng.integers(0, w, int(rng.integers(0, 8)))] + [0, w - 1]
        min_cols, beside = int(rng.integers(1, 9)), int(rng.integers(0, 5))
        monkeypatch.setattr(search, "RAMP_COLUMNS", min_cols)
        monkeypatch.setattr(search, "RAMP_BESIDE", beside)
        for v in views:
            want = search._ramp_spans(v, cols)
            assert _cmiddle.ramp_spans(v, cols, min_cols, beside) == want
            assert _cmiddle.ramp_spans(v, [], min_cols, beside) == []
    monkeypatch.setattr(search, "RAMP_COLUMNS", 7)
    monkeypatch.setattr(search, "RAMP_BESIDE", 4)
    img = strip(FLOOR, SHADOW, 20)
    grey = cv2.cvtColor(img, cv2.COLOR_BGR2GRAY)
    lab = cv2.cvtColor(img, cv2.COLOR_BGR2LAB)
    got = ramp_columns(grey, lab, [EDGE, 3, EDGE])
    outside = ramp_columns(grey, lab, [EDGE, W])  # a column outside: numpy's walk
    monkeypatch.setattr(search, "_c_ramp_spans", None)
    assert got == ramp_columns(grey, lab, [EDGE, 3, EDGE]) == {EDGE}
    assert outside == ramp_columns(grey, lab, [EDGE, W]) == {EDGE}
    with pytest.raises(ValueError):
        _cmiddle.ramp_spans(grey, [W], 7, 4)
    with pytest.raises(TypeError):
        _cmiddle.ramp_spans(grey.astype(np.int16), [EDGE], 7, 4)
    with pytest.raises(TypeError):
        _cmiddle.ramp_spans(grey[:0], [EDGE], 7, 4)  # no rows: ramp_columns returns first
    with pytest.raises(TypeError):
        _cmiddle.ramp_spans(img, [EDGE], 7, 4)  # 3-D
