"""With no rig, a trial's face wholly beside the sonar's beam is refused
(:func:`obstacle_fusion.vision.measure._outside_beam`, BEAM_HOLDS_FACE): the echo the range
comes from is inside the beam."""

from __future__ import annotations

import numpy as np
import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import FusedMethod
from obstacle_fusion.vision.measure import Measurer, _outside_beam, beam_columns_px
from obstacle_fusion.vision.rig import Rig, SonarMount
from obstacle_fusion.vision.types import Measurement, View

CAM = CameraModel.paper(500, 375)
RANGE_M = 2.8
STEP_PX = 0.5  # just inside or just outside the limit


# Hand-worked for the paper lens at 500x375 (fx 458.72, cx 248.63), tan 7.5 deg = 0.131653:
# at 2.8 m the cone's half is 2.8 * 0.131653 = 0.36863 m, 458.72 * 0.36863 / 2.8 = 60.39 px
BEAM_2_8 = (188.24, 309.02)
# ... with the sonar 0.2 m ahead of the lens the face is at D = 3.0 m: 458.72 * 0.36863 / 3.0
# = 56.37 px about cx
BEAM_AHEAD = (192.27, 305.00)
# ... with the sonar 0.3 m right of the lens: shifted 458.72 * 0.3 / 2.8 = 49.15 px
BEAM_RIGHT = (237.39, 358.17)
# ... with no rig, widened by the mounting allowance 458.72 * 0.10 / 2.8 = 16.38 px each side
BEAM_ALLOWED = (171.86, 325.40)
SLACK = 2.0


def _view() -> View:
    return View(CAM, Rig(), "level")


def _left(x1: float) -> tuple[float, float, float, float]:
    """A face ending at column ``x1``."""
    return (x1 - 60.0, 150.0, x1, 200.0)


def _right(x0: float) -> tuple[float, float, float, float]:
    """A face starting at column ``x0``."""
    return (x0, 150.0, x0 + 60.0, 200.0)


def _assert_edges(
    lo: float, hi: float, view: View, rig: Rig, depth: float, allow: float = 0.0
) -> None:
    """A face ending STEP_PX inside columns lo..hi reaches the beam; STEP_PX outside, not."""
    assert not _outside_beam(_left(lo + STEP_PX), view, rig, RANGE_M, depth, allow)
    assert _outside_beam(_left(lo - STEP_PX), view, rig, RANGE_M, depth, allow)
    assert not _outside_beam(_right(hi - STEP_PX), view, rig, RANGE_M, depth, allow)
    assert _outside_beam(_right(hi + STEP_PX), view, rig, RANGE_M, depth, allow)


def _sure_face(box: tuple[float, float, float, float]) -> Measurement:
    """What a faked FusedMethod.run finds on every trial: a sure face of box ``box``."""
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


def test_the_beam_s_columns_are_the_cone_s_at_the_range() -> None:
    assert CAM.fx == pytest.approx(458.72, abs=0.01)
    assert CAM.cx == pytest.approx(248.63, abs=0.01)
    assert Rig().beam_width_deg == 15.0
    cols = beam_columns_px(_view(), Rig(), RANGE_M, RANGE_M)
    assert cols == pytest.approx(BEAM_2_8, abs=0.01)
    # the cone's half at the range (not at the depth), seen at the face's depth
    ahead = Rig(sonar_ahead_m=0.2)
    assert ahead.face_depth(RANGE_M) == pytest.approx(3.0)
    cols = beam_columns_px(_view(), ahead, RANGE_M, ahead.face_depth(RANGE_M))
    assert cols == pytest.approx(BEAM_AHEAD, abs=0.01)


def test_a_face_is_beside_the_beam_only_past_its_edge_and_the_slack() -> None:
    rig = Rig()
    view = _view()
    assert measure.BEAM_EDGE_SLACK_PX == SLACK
    lo, hi = BEAM_2_8[0] - SLACK, BEAM_2_8[1] + SLACK
    _assert_edges(lo, hi, view, rig, RANGE_M)
    # a face wider than the beam, or unknown, is not beside it
    wide = (lo - 60.0, 150.0, hi + 60.0, 200.0)
    assert not _outside_beam(wide, view, rig, RANGE_M, RANGE_M)
    assert not _outside_beam(None, view, rig, RANGE_M, RANGE_M)


def test_the_sonar_ahead_narrows_the_beam_at_the_face() -> None:
    rig = Rig(sonar_ahead_m=0.2)
    view, depth = _view(), 3.0
    lo, hi = BEAM_AHEAD[0] - SLACK, BEAM_AHEAD[1] + SLACK
    _assert_edges(lo, hi, view, rig, depth)


def test_the_sonar_s_offset_moves_the_beam() -> None:
    """A sonar 0.3 m right of the lens: the beam's columns shift 49.15 px right."""
    rig = Rig(sonar_right_m=0.3)
    view = _view()
    assert beam_columns_px(view, rig, RANGE_M, RANGE_M) == pytest.approx(BEAM_RIGHT, abs=0.01)
    lo, hi = BEAM_RIGHT[0] - SLACK, BEAM_RIGHT[1] + SLACK
    _assert_edges(lo, hi, view, rig, RANGE_M)


def test_with_no_rig_the_bound_allows_for_the_sonar_s_mounting() -> None:
    """Rig()'s mounting is a guess: the bound is widened 0.10 m each side, fx * 0.10 / D px."""
    assert measure.BEAM_MOUNT_ALLOWANCE_M == 0.10
    allow = Measurer(CAM, None)._allowance()
    assert allow == 0.10
    rig, view = Rig(), _view()
    cols = beam_columns_px(view, rig, RANGE_M, RANGE_M, allow)
    assert cols == pytest.approx(BEAM_ALLOWED, abs=0.01)
    lo, hi = BEAM_ALLOWED[0] - SLACK, BEAM_ALLOWED[1] + SLACK
    _assert_edges(lo, hi, view, rig, RANGE_M, allow)
    # the review's case: a sonar 0.1 m right of the lens, a 4 cm pole on its axis at 0.5 m
    # (cx + 458.72 * 0.1 / 0.5 = cx + 91.74, +-18.35 px: columns 322.0-358.7) is kept,
    # though Rig()'s assumed beam ends at cx + 60.39 + 2 = 311.0
    pole = (322.0, 150.0, 358.7, 200.0)
    assert _outside_beam(pole, view, rig, 0.5, 0.5)
    assert not _outside_beam(pole, view, rig, 0.5, 0.5, allow)


def test_a_known_mounting_takes_no_allowance() -> None:
    """A rig given, and the rig check's searcher (the rig's mounting kept): none."""
    with_rig = Measurer(CAM, Rig(sonar_right_m=0.3))
    assert with_rig._allowance() == 0.0
    assert with_rig._rig_searcher()._allowance() == 0.0


def test_a_yawed_sonar_s_beam_is_not_checked() -> None:
    """Sensor 0 yawed: its beam is not about the lens's axis, the rule stands aside."""
    view, box = _view(), _right(BEAM_2_8[1] + SLACK + 30.0)
    straight = Rig(sonars=(SonarMount(0, yaw_deg=0.0),))
    yawed = Rig(sonars=(SonarMount(0, yaw_deg=10.0),))
    other_yawed = Rig(sonars=(SonarMount(0), SonarMount(1, yaw_deg=30.0)))
    assert _outside_beam(box, view, straight, RANGE_M, RANGE_M)
    assert not _outside_beam(box, view, yawed, RANGE_M, RANGE_M)
    assert _outside_beam(box, view, other_yawed, RANGE_M, RANGE_M)


def test_a_beam_beside_the_image_refuses_nothing() -> None:
    """A sonar 0.35 m right at 0.5 m: its beam (cx + 321.1 +- 60.4 px, from 507.3 with the
    slack) misses the 500-px image; 0.3 m right (cx + 275.2, from 461.5) reaches into it."""
    view, box, near = _view(), _left(100.0), 0.5
    assert not _outside_beam(box, view, Rig(sonar_right_m=0.35), near, near)
    assert _outside_beam(box, view, Rig(sonar_right_m=0.3), near, near)
    # ... and on the left: 0.35 m left, ending at cx - 321.1 + 60.4 + 2 = -10.1
    assert not _outside_beam(_right(100.0), view, Rig(sonar_right_m=-0.35), near, near)
    assert _outside_beam(_right(100.0), view, Rig(sonar_right_m=-0.3), near, near)


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
        return _sure_face(box)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [205])
    monkeypatch.setattr(measure, "weak_contact_rows", lambda *a: [])
    image = np.full((375, 500, 3), 120, np.uint8)
    image[205:] = 60  # a darker floor below the contact row
    found = Measurer(CAM, None).measure(image, RANGE_M)
    assert (found.detected and found.box_px == box) is (not on), found


def test_with_a_rig_its_own_reading_beside_the_beam_is_unchanged(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A rig given: the rig path's own sure reading of a face far right of the beam
    (columns 409-479, the beam's 188-309) is the answer, the rule on or off."""
    box = (BEAM_2_8[1] + 100.0, 120.0, BEAM_2_8[1] + 170.0, 205.0)

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        return _sure_face(box)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    image = np.full((375, 500, 3), 120, np.uint8)
    found = {}
    for on in (True, False):
        monkeypatch.setattr(measure, "BEAM_HOLDS_FACE", on)
        found[on] = Measurer(CAM, Rig()).measure(image, RANGE_M)
    assert found[True].detected and found[True].box_px == box, found[True]
    assert found[True].height_m == found[False].height_m
    assert found[True].confidence == found[False].confidence
