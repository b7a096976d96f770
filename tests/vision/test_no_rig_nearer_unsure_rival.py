"""With no rig, a sure face that keeps the answer while a face too unsure to be taken
(``measure.NEARER_AXIS_ACCEPT``) stands nearer on the beam's axis, wholly under its foot,
is doubted TRIAL_RIVAL (``measure.NEARER_UNSURE_RIVAL``): the sonar ranges the nearest
surface on its axis, and the guessed camera height that stood the sure face on the range
may have stood a surface behind the obstacle.

The room is a diagnosis room (new8), measured with no rig. Procedural 3350 (ordinary): a
low plank box (0.14 m) before a dark print on the wall; the trial that stands the box
reads it right (+2 %) at 0.08, a lower camera guess stands the print on the range, 0.74 m
tall at 0.97 (+445 %); with the rule the print is reported at 0.44, under the 0.5 of a
sure answer. Photo 3028 ordinary (new): a stretch of gravel before a box read right is
no rival, having the floor's colour (``face_apart_from_floor``).
"""

from __future__ import annotations

import math

import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.fused.confidence import (
    PITCH_UNREAD,
    SECOND_TOP,
    TOP_FROM_SIDES,
    TRIAL_RIVAL,
)
from obstacle_fusion.vision.fused.method import FusedMethod
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.types import Measurement

from tests.vision.test_rig_source_and_clipping import CAM, fake_face, no_rig_room
from tests.vision_fixtures import measured_room

FAR = (200.0, 60.0, 300.0, 150.0)  # the sure face, standing on the higher row
NEAR = (190.0, 160.0, 310.0, 230.0)  # the unsure face, wholly under its foot


def test_the_print_over_the_box_is_not_sure() -> None:
    res, _ = measured_room("procedural", 3350, False, False)
    assert res.detected and TRIAL_RIVAL in res.doubts
    assert (res.confidence or 0.0) < 0.5


def test_without_the_rule_the_print_is_sure(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "NEARER_UNSURE_RIVAL", False)
    res, _ = measured_room("procedural", 3350, False, False)
    assert res.detected and (res.confidence or 0.0) >= 0.9 and not res.doubts


def _measured(
    monkeypatch: pytest.MonkeyPatch,
    far_conf: float = 0.9,
    near_conf: float = 0.08,
    near: tuple[float, float, float, float] = NEAR,
    apart: bool = True,
    near_doubts: tuple[str, ...] = (),
) -> Measurement:
    """No rig, two contact rows: the higher (a 0.20 m level lens) stands the sure face
    FAR, the lower (0.30 m) the unsure face ``near``, at any pitch; no other trial finds
    a face. ``apart``: whether a face's colour stands apart from the floor's under it;
    ``near_doubts``: the unsure face's doubts. Faces in the sonar's beam (0.9 m: columns
    188-309). No trial reads the pitch: the answer is reported PITCH_UNREAD."""
    image, truth, view, depth = no_rig_room(4001)
    rows = [int(round(view.cy + view.fy * h / depth)) for h in (0.30, 0.20)]

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        rig = self.view.rig
        # the level lens the trial's row stands for (a pitched trial's lens is the row's
        # level one less the depth's drop at its pitch)
        level = rig.camera_height_m - depth * math.tan(math.radians(rig.camera_pitch_deg))
        if kwargs.get("floor_known") or not 0.15 < level < 0.35:
            return Measurement(detected=False, method="fused", range_m=truth["range_m"])
        if level < 0.25:
            return fake_face(truth, True, far_conf, box_px=FAR)
        return fake_face(truth, True, near_conf, box_px=near, doubts=list(near_doubts))

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: rows)
    monkeypatch.setattr(measure, "weak_contact_rows", lambda *a: [])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    # the drawn room's pixels behind the fake boxes say nothing of a print or a margin
    monkeypatch.setattr(measure, "face_runs_below", lambda *a: False)
    monkeypatch.setattr(measure, "print_runs_below", lambda *a: False)
    monkeypatch.setattr(measure, "face_apart_from_floor", lambda *a: apart)
    return Measurer(CAM, None).measure(image, truth["range_m"])


# the limits as numbers, not read from measure: a test that reads the constant moves with it
@pytest.mark.parametrize(
    ("near_conf", "doubted"),
    [
        (0.05, True),  # NEARER_RIVAL_ACCEPT, the least a trial reports
        (0.049, False),
        (0.149, True),  # still too unsure for NEARER_AXIS_ACCEPT to take it
    ],
)
def test_the_nearer_face_s_least_confidence(
    monkeypatch: pytest.MonkeyPatch, near_conf: float, doubted: bool
) -> None:
    res = _measured(monkeypatch, near_conf=near_conf)
    assert res.detected and res.box_px == FAR
    assert (TRIAL_RIVAL in res.doubts) is doubted


@pytest.mark.parametrize(("far_conf", "doubted"), [(0.5, True), (0.499, False)])
def test_only_a_sure_face_is_doubted(
    monkeypatch: pytest.MonkeyPatch, far_conf: float, doubted: bool
) -> None:
    res = _measured(monkeypatch, far_conf=far_conf)
    assert res.detected and res.box_px == FAR
    assert (TRIAL_RIVAL in res.doubts) is doubted


def test_a_stretch_of_the_floor_is_no_rival(monkeypatch: pytest.MonkeyPatch) -> None:
    # the nearer face has the floor's colour (face_apart_from_floor): gravel before the face
    res = _measured(monkeypatch, apart=False)
    assert res.detected and res.box_px == FAR and TRIAL_RIVAL not in res.doubts


def test_gravel_before_a_sure_face_leaves_it_sure() -> None:
    # photo 3028 ordinary (new): a plain box on gravel, read right at 0.75 (+1.4 / +0.4 %);
    # a trial stands a stretch of the gravel before it, 0.15 m tall at 0.08, on the axis
    # under its foot: of the floor's colour, no rival (without that check 0.75 -> 0.34)
    res, truth = measured_room("photo", 3028, False, False)
    assert res.detected and TRIAL_RIVAL not in res.doubts
    assert (res.confidence or 0.0) >= 0.5
    assert abs((res.height_m or 0.0) / truth["height_m"] - 1) < 0.05


def test_the_switch(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "NEARER_UNSURE_RIVAL", False)
    res = _measured(monkeypatch)
    assert res.detected and res.box_px == FAR and TRIAL_RIVAL not in res.doubts


@pytest.mark.parametrize(
    ("near", "doubted"),
    [
        (NEAR, True),
        ((190.0, 150.0, 310.0, 230.0), True),  # its top on the sure face's foot: in front
        ((190.0, 149.9, 310.0, 230.0), False),  # reaching into it: its lower part, a shadow
        ((260.0, 160.0, 310.0, 230.0), False),  # beside the axis
    ],
)
def test_the_nearer_face_stands_in_front_on_the_axis(
    monkeypatch: pytest.MonkeyPatch, near: tuple[float, float, float, float], doubted: bool
) -> None:
    res = _measured(monkeypatch, near=near)
    assert res.detected and res.box_px == FAR
    assert (TRIAL_RIVAL in res.doubts) is doubted


def test_a_face_sure_enough_to_be_taken_is_taken_not_a_rival(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # from NEARER_AXIS_ACCEPT (0.15) the nearer-face rule takes the face, as before the rule
    # (its first call keeps its own limit and refusal): no rival, the face swapped
    res = _measured(monkeypatch, near_conf=0.15)
    assert res.detected and res.box_px == NEAR and TRIAL_RIVAL not in res.doubts


def test_sure_before_the_search_s_pitch_doubt(monkeypatch: pytest.MonkeyPatch) -> None:
    # the face is sure by its doubts when the search ends (0.9); the PITCH_UNREAD added after
    # (its pitch a guess: 0.405 without the rival) is the pitch's doubt, not which surface
    # the guessed height stood, so it does not spare the face the rival's
    res = _measured(monkeypatch, far_conf=0.9)
    assert PITCH_UNREAD in res.doubts and TRIAL_RIVAL in res.doubts
    assert res.confidence == pytest.approx(0.9 * 0.45 * 0.45, abs=0.001)


def test_a_rival_the_refusal_would_turn_down_is_still_a_rival(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # 0.08 with two face doubts and PITCH_UNREAD: 0.007, under MIN_DOUBTED_CONFIDENCE, so
    # the nearer-face rule could not report it; as a rival it is not reported, only seen
    res = _measured(monkeypatch, near_doubts=(TOP_FROM_SIDES, SECOND_TOP))
    assert res.detected and res.box_px == FAR and TRIAL_RIVAL in res.doubts
