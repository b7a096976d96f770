"""With no rig, a floor-contact row is tried only where a robot's lens can see the contact
on it (:func:`obstacle_fusion.vision.measure._robot_row`, ROW_FITS_ROBOT)."""

from __future__ import annotations

import math

import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import FusedMethod
from obstacle_fusion.vision.measure import Measurer, _robot_row
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import Measurement

from tests.vision.test_rig_source_and_clipping import no_rig_room

CAM = CameraModel.paper(500, 375)
STEP_M = 0.005  # just inside or just outside the limit


#: The highest level lens whose row a robot's lens (at most 0.6 m up, looking up by at
#: most 8 degrees) still sees the contact on, at each depth, worked out by hand: the row's
#: angle below a level axis, atan(0.6 / D), plus 8 degrees, back to a level lens's height
#: D tan(that):
#:   1.0 m: atan 0.6  = 30.964 deg, + 8 = 38.964, tan 0.8087 -> 0.809 m
#:   1.5 m: atan 0.4  = 21.801 deg, + 8 = 29.801, tan 0.5727 -> 0.859 m
#:   2.0 m: atan 0.3  = 16.699 deg, + 8 = 24.699, tan 0.4599 -> 0.920 m
#:   3.0 m: atan 0.2  = 11.310 deg, + 8 = 19.310, tan 0.3504 -> 1.051 m
#:   5.0 m: atan 0.12 =  6.843 deg, + 8 = 14.843, tan 0.2650 -> 1.325 m
LEVEL_LIMIT_M = {1.0: 0.809, 1.5: 0.859, 2.0: 0.920, 3.0: 1.051, 5.0: 1.325}


def test_the_figures_are_for_the_robot_s_lens() -> None:
    assert (measure.UNDER_MAX_CAMERA_HEIGHT_M, measure.MAX_ESTIMATED_PITCH_DEG) == (0.6, 8.0)


@pytest.mark.parametrize("depth", sorted(LEVEL_LIMIT_M))
def test_a_level_row_fits_a_robot_up_to_the_most_pitch_looking_up(depth: float) -> None:
    limit = LEVEL_LIMIT_M[depth]
    assert limit < measure.MAX_ESTIMATED_CAMERA_HEIGHT_M  # tighter than the fixed cap
    assert _robot_row(limit - STEP_M, 0.0, depth)
    assert not _robot_row(limit + STEP_M, 0.0, depth)


def test_a_pitched_trial_is_judged_by_its_row_not_its_lens() -> None:
    """A lens looking up by the most pitch stands lowest for its row: at the robot's
    highest lens it is just inside, a little higher just outside; the same lens looking
    down images a row far higher, well inside."""
    top = measure.UNDER_MAX_CAMERA_HEIGHT_M
    up = -measure.MAX_ESTIMATED_PITCH_DEG
    assert _robot_row(top - STEP_M, up, 3.0)
    assert not _robot_row(top + STEP_M, up, 3.0)
    assert _robot_row(top + STEP_M, -up, 3.0)


def test_switched_off_every_row_fits(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "ROW_FITS_ROBOT", False)
    assert _robot_row(LEVEL_LIMIT_M[3.0] + 0.3, 0.0, 3.0)


@pytest.mark.parametrize("on", [True, False])
def test_no_trial_runs_on_a_row_no_robot_sees(monkeypatch: pytest.MonkeyPatch, on: bool) -> None:
    """At the longest range a row for a level lens between the range's limit and the fixed
    cap (MAX_ESTIMATED_CAMERA_HEIGHT_M) lies in the image: it stands no trial, at any
    pitch, while the rule is on; a row inside the limit does."""
    monkeypatch.setattr(measure, "ROW_FITS_ROBOT", on)
    image, _, view, _ = no_rig_room(4001)
    far = 5.0
    depth = Rig().face_depth(far)
    assert depth == far  # the sonar on the lens's axis
    limit = LEVEL_LIMIT_M[far]
    outside = (limit + measure.MAX_ESTIMATED_CAMERA_HEIGHT_M) / 2
    inside = limit - 0.1
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (inside, outside)}
    assert row_at[outside] < image.shape[0]
    rows: list[float] = []

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        # the level lens of the row tried: the pinhole's projection of the contact for the
        # trial's lens (the camera's geometry); the limit it is held to is the table's
        rig = self.view.rig
        angle = math.atan2(rig.camera_height_m, depth) - math.radians(rig.camera_pitch_deg)
        rows.append(depth * math.tan(angle))
        return Measurement(detected=False, method="fused", range_m=far)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[outside], row_at[inside]])
    monkeypatch.setattr(measure, "weak_contact_rows", lambda *a: [row_at[outside]])
    Measurer(CAM, None).measure(image, far)
    assert any(abs(h - inside) < 0.02 for h in rows), rows
    assert any(h > limit + 0.02 for h in rows) is (not on), rows
