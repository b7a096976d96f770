"""With no rig, a trial's face wholly beside the sonar's beam is refused
(:func:`obstacle_fusion.vision.measure._outside_beam`, BEAM_HOLDS_FACE): the echo the range
comes from is inside the beam."""

from __future__ import annotations

import math

import numpy as np
import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import FusedMethod
from obstacle_fusion.vision.measure import Measurer, _outside_beam, beam_columns_px
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import Measurement, View

CAM = CameraModel.paper(500, 375)
RANGE_M = 2.8
STEP_PX = 0.5  # just inside or just outside the limit


def _view() -> View:
    return View(CAM, Rig(), "level")


def test_the_beam_s_columns_follow_the_cone_at_the_range() -> None:
    """15 degrees about the lens's axis at 2.8 m: +-2.8 tan(7.5 deg) m, fx / D px per m."""
    rig = Rig()
    assert rig.beam_width_deg == 15.0
    u_lo, u_hi = beam_columns_px(_view(), rig, RANGE_M, RANGE_M)
    half = CAM.fx * math.tan(math.radians(7.5))
    assert u_lo == pytest.approx(CAM.cx - half)
    assert u_hi == pytest.approx(CAM.cx + half)


def test_a_face_is_beside_the_beam_only_past_its_edge_and_the_slack() -> None:
    rig = Rig()
    view = _view()
    u_lo, u_hi = beam_columns_px(view, rig, RANGE_M, RANGE_M)
    slack = measure.BEAM_EDGE_SLACK_PX
    assert slack == 2.0
    left_inside = (u_lo - 60.0, 150.0, u_lo - slack + STEP_PX, 200.0)
    left_outside = (u_lo - 60.0, 150.0, u_lo - slack - STEP_PX, 200.0)
    right_inside = (u_hi + slack - STEP_PX, 150.0, u_hi + 60.0, 200.0)
    right_outside = (u_hi + slack + STEP_PX, 150.0, u_hi + 60.0, 200.0)
    assert not _outside_beam(left_inside, view, rig, RANGE_M, RANGE_M)
    assert _outside_beam(left_outside, view, rig, RANGE_M, RANGE_M)
    assert not _outside_beam(right_inside, view, rig, RANGE_M, RANGE_M)
    assert _outside_beam(right_outside, view, rig, RANGE_M, RANGE_M)
    # a face wider than the beam, or unknown, is not beside it
    wide = (u_lo - 60.0, 150.0, u_hi + 60.0, 200.0)
    assert not _outside_beam(wide, view, rig, RANGE_M, RANGE_M)
    assert not _outside_beam(None, view, rig, RANGE_M, RANGE_M)


def test_the_sonar_s_offset_moves_the_beam() -> None:
    """A sonar 0.3 m right of the lens: a face just right of the lens's beam is in its."""
    view = _view()
    u_lo, u_hi = beam_columns_px(view, Rig(), RANGE_M, RANGE_M)
    box = (u_hi + 10.0, 150.0, u_hi + 40.0, 200.0)
    assert _outside_beam(box, view, Rig(), RANGE_M, RANGE_M)
    assert not _outside_beam(box, view, Rig(sonar_right_m=0.3), RANGE_M, RANGE_M)


@pytest.mark.parametrize("on", [True, False])
def test_no_rig_search_refuses_a_face_beside_the_beam(
    monkeypatch: pytest.MonkeyPatch, on: bool
) -> None:
    """Every trial finds a sure face far right of the beam (as new4 procedural 3183 hard's
    bigger box): the search reports it only with the rule off."""
    monkeypatch.setattr(measure, "BEAM_HOLDS_FACE", on)
    _, u_hi = beam_columns_px(_view(), Rig(), RANGE_M, RANGE_M)
    box = (u_hi + 100.0, 120.0, u_hi + 170.0, 205.0)

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        return Measurement(
            detected=True,
            method="fused",
            range_m=RANGE_M,
            distance_m=RANGE_M,
            height_m=0.5,
            width_m=0.45,
            box_px=box,
            confidence=0.9,
            height_px=box[3] - box[1],
            width_px=box[2] - box[0],
        )

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [205])
    monkeypatch.setattr(measure, "weak_contact_rows", lambda *a: [])
    image = np.full((375, 500, 3), 120, np.uint8)
    image[205:] = 60  # a darker floor below the contact row
    found = Measurer(CAM, None).measure(image, RANGE_M)
    assert (found.detected and found.box_px == box) is (not on), found
