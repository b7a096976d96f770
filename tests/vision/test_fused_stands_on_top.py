"""With no rig, a sure face standing on the top of a wider, unsure face found on a lower
row (an object on a box, or behind it) gives way to that lower face
(``measure._stands_on_top``, ``floor_contact.face_apart_from_floor``)."""

from __future__ import annotations

import numpy as np
import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.fused import FusedMethod
from obstacle_fusion.vision.fused.confidence import FLOOR_IN_FACE
from obstacle_fusion.vision.fused.floor_contact import FACE_FLOOR_APART, face_apart_from_floor
from obstacle_fusion.vision.measure import Measurer, _stands_on_top
from obstacle_fusion.vision.types import Measurement

from tests.vision.test_rig_source_and_clipping import CAM, fake_face, no_rig_room

LOWER = (100.0, 200.0, 300.0, 280.0)  # a box 200 px wide, 80 tall, its top on row 200
UPPER = (170.0, 100.0, 230.0, 195.0)  # a can 60 px wide set back on its top


@pytest.mark.parametrize(
    "upper",
    [
        UPPER,
        (170.0, 100.0, 230.0, 202.0),  # its foot 2 px down the box's top (ON_TOP_BELOW_PX 3)
        (170.0, 100.0, 230.0, 162.0),  # its foot 38 px above it (ON_TOP_ABOVE: 40 px)
        (125.0, 100.0, 275.0, 195.0),  # the box 1.33 times as wide (ON_TOP_WIDER 1.3)
    ],
)
def test_a_narrow_face_set_back_on_a_wider_box_stands_on_it(
    upper: tuple[float, float, float, float],
) -> None:
    assert _stands_on_top(upper, LOWER)


@pytest.mark.parametrize(
    "upper, lower",
    [
        ((170.0, 100.0, 230.0, 210.0), LOWER),  # its foot 10 px down the lower face
        ((170.0, 100.0, 230.0, 205.0), LOWER),  # its foot 5 px down it
        ((170.0, 100.0, 230.0, 150.0), LOWER),  # its foot over half the box's height above
        ((170.0, 100.0, 230.0, 155.0), LOWER),  # its foot 45 px above (half the box: 40)
        ((80.0, 100.0, 140.0, 195.0), LOWER),  # it overhangs the box's left side
        ((260.0, 100.0, 320.0, 195.0), LOWER),  # it overhangs the box's right side
        ((120.0, 100.0, 280.0, 195.0), LOWER),  # nearly as wide (a reflection, a shadow)
        (UPPER, (100.0, 200.0, 300.0, 230.0)),  # the lower face a strip (a floor mark)
        (UPPER, None),
    ],
)
def test_a_face_not_on_the_lower_ones_top_does_not(
    upper: tuple[float, float, float, float],
    lower: tuple[float, float, float, float] | None,
) -> None:
    assert not _stands_on_top(upper, lower)


def boxed(face: tuple[int, int, int], floor: tuple[int, int, int]) -> np.ndarray:
    img = np.full((300, 400, 3), 200, np.uint8)  # wall
    img[150:] = floor
    img[200:280, 100:300] = face
    return img


def test_a_face_of_its_own_colour_is_apart_from_the_floor() -> None:
    assert face_apart_from_floor(boxed((150, 60, 60), (90, 90, 90)), LOWER)


def test_a_face_just_over_the_limit_is_apart() -> None:
    # grey 108 on grey 90: 18 apart in 8-bit Lab (FACE_FLOOR_APART 15)
    assert face_apart_from_floor(boxed((108, 108, 108), (90, 90, 90)), LOWER)


def test_a_patch_of_the_floor_is_not() -> None:
    # a patch a shade off the floor (a stretch of gravel read as a face): under the limit
    assert FACE_FLOOR_APART > 6.0
    assert not face_apart_from_floor(boxed((94, 94, 94), (90, 90, 90)), LOWER)
    # grey 102 on grey 90: 12 apart, under FACE_FLOOR_APART still
    assert not face_apart_from_floor(boxed((102, 102, 102), (90, 90, 90)), LOWER)
    assert not face_apart_from_floor(boxed((150, 60, 60), (90, 90, 90))[:, :, 0], LOWER)


def fake_two_readings(
    monkeypatch: pytest.MonkeyPatch,
    truth: dict[str, float],
    row_at: dict[float, int],
    sure: dict[float, float],
    boxes: dict[float, tuple[float, float, float, float]],
    low_fields: dict[str, object],
) -> None:
    """Fakes the no-rig search to find two faces only, one on each floor-contact row
    ``row_at`` (lower row 0.30 m, higher 0.20 m: confidence ``sure``, box ``boxes``, the
    lower one with ``low_fields``), both standing on their rows: the measure's choice
    between them is all that is left (here and in test_fused_same_outline)."""

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        height = round(self.view.rig.camera_height_m, 2)
        if self.view.rig.camera_pitch_deg or height not in row_at:  # other pitches, rows
            return Measurement(detected=False, method="fused", range_m=truth["range_m"])
        fields = low_fields if height == 0.30 else {}
        return fake_face(truth, True, sure[height], height_m=height, box_px=boxes[height], **fields)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[0.30], row_at[0.20]])
    monkeypatch.setattr(measure, "weak_contact_rows", lambda *a: [])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    monkeypatch.setattr(measure, "face_runs_below", lambda *a: False)


@pytest.mark.parametrize(
    "apart, low_fields, expected",
    [
        (True, {}, 0.30),
        (False, {}, 0.20),
        # a lower face that took floor in settles no row; a small one is no box
        (True, {"doubts": [FLOOR_IN_FACE]}, 0.20),
        (True, {"height_px": 10.0, "width_px": 10.0}, 0.20),
    ],
)
def test_with_no_rig_a_face_on_a_lower_boxs_top_gives_way_to_the_box(
    apart: bool, low_fields: dict[str, object], expected: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The box is found, unsure, on the lower row; a narrower sure face stands on its top
    edge on the row above: the box is taken when it has a colour of its own (and neither
    took floor in nor is small)."""

    image, truth, view, depth = no_rig_room(4005)
    # faked faces beside the axis: that rule apart
    monkeypatch.setattr(measure, "AXIS_UNSURE_TRIAL", False)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (0.20, 0.30)}
    sure = {0.30: 0.1, 0.20: 0.9}
    height_px = row_at[0.30] - row_at[0.20] + 40.0
    boxes = {
        0.30: (100.0, row_at[0.30] - height_px, 300.0, float(row_at[0.30])),
        0.20: (170.0, row_at[0.30] - height_px - 80.0, 230.0, row_at[0.30] - height_px - 4.0),
    }

    fake_two_readings(monkeypatch, truth, row_at, sure, boxes, low_fields)
    monkeypatch.setattr(measure, "face_apart_from_floor", lambda *a: apart)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.camera_height_m == pytest.approx(expected, abs=0.01)


@pytest.mark.parametrize("seed", [1154, 1190, 1165])
def test_with_no_rig_a_can_on_a_box_is_not_the_face(seed: int) -> None:
    """photo 1154 / 1190 ordinary: a cylinder stands on a wider box, sure on the box's top
    edge; the box, unsure on the floor's row below, is what the sonar ranges (h +58 % and
    w -54 / -72 % before the rule). photo 1165 ordinary: a patch of gravel before the box,
    read as a face on a line nearer the lens, is no box under it (face_apart_from_floor;
    +126 % without it)."""
    image, truth, _ = render_room("photo", seed, False, CAM)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.height_m == pytest.approx(truth["height_m"], rel=0.1)
    assert res.width_m == pytest.approx(truth["width_m"], rel=0.1)
