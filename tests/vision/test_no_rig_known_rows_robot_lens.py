"""With no rig, the rows read as with a rig (``measure.Measurer._known_rig_rows``) give a
face only from a reading taken under a lens a robot carries
(``measure.KNOWN_ROWS_ROBOT_LENS``: at most ``measure.KNOWN_ROWS_MAX_LENS_M`` up):
readings that agree on one face only under lenses higher than that stand for no robot.

The rooms are diagnosis rooms (new9), measured with no rig. Photo 3414 (hard): a textured
box standing near the horizon on a paved floor; the search finds no face, and the rows
read lowest first stood the paving near the image's foot (row 332, lenses 0.87-1.22 m up
at the guessed pitches) as a face 0.81 m high, +108 %. With the rule that row gives
nothing and the box's own row (197) agrees, +0.5 %. Photo 3411 (hard): a low box under a
lens looking up 4.7 degrees, whose row's readings agree under lenses 0.50-0.82 m up, one
of them a robot's: its answer is kept.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.fused.method import FusedMethod
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.types import Measurement, Timer

from tests.vision.test_rig_source_and_clipping import CAM
from tests.vision_fixtures import measured_room

BOX = (200.0, 100.0, 300.0, 200.0)  # the face every reading finds, 100 x 100 px
PITCHES = (-2.0, 0.0, 2.0, 4.0)


def _errors(res: Measurement, truth: dict[str, float]) -> tuple[float, float]:
    assert res.detected and res.height_m is not None and res.width_m is not None, res.reason
    return abs(res.height_m / truth["height_m"] - 1), abs(res.width_m / truth["width_m"] - 1)


def test_the_paved_floor_stands_no_face() -> None:
    res, truth = measured_room("photo", 3414, True, False)
    assert max(_errors(res, truth)) < 0.05
    assert res.camera_height_m is not None
    assert res.camera_height_m <= measure.KNOWN_ROWS_MAX_LENS_M


def test_without_the_rule_the_paving_is_the_face(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "KNOWN_ROWS_ROBOT_LENS", False)
    res, truth = measured_room("photo", 3414, True, False)
    height_err, _ = _errors(res, truth)
    assert height_err > 1.0
    assert (res.camera_height_m or 0.0) > measure.KNOWN_ROWS_MAX_LENS_M


def test_a_row_with_a_robots_lens_among_its_readings_keeps_its_face() -> None:
    res, truth = measured_room("photo", 3411, True, False)
    assert max(_errors(res, truth)) < 0.1


def _row_read(
    monkeypatch: pytest.MonkeyPatch,
    lenses: dict[float, tuple[float, float]],
    slack: bool = False,
    depth: float = 2.0,
) -> Measurement | None:
    """One row read as with a rig (:meth:`Measurer._known_rig_row`) at PITCHES, the lens
    each pitch stands for and the confidence of the face (BOX, standing on its foot) read
    there given by ``lenses`` (pitch: (camera height, confidence)), the face ``depth`` off.
    ``slack``: whether the limit keeps KNOWN_ROWS_UP_SLACK_DEG (off: the lens limit alone)."""

    def fake_rig(
        self: Measurer,
        fused: FusedMethod,
        image: np.ndarray,
        range_m: float,
        timer: Timer,
        height: float,
        pitch: float,
    ) -> Measurement:
        return Measurement(
            detected=True,
            method="fused",
            range_m=range_m,
            height_m=0.3,
            width_m=0.3,
            box_px=BOX,
            height_px=100.0,
            width_px=100.0,
            confidence=lenses[pitch][1],
        )

    monkeypatch.setattr(Measurer, "_run_guessed_rig", fake_rig)
    if not slack:
        monkeypatch.setattr(measure, "KNOWN_ROWS_UP_SLACK_DEG", 0.0)
    monkeypatch.setattr(measure, "camera_height_for_row", lambda r, d, p, fy, cy: lenses[p][0])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    monkeypatch.setattr(measure, "_outside_beam", lambda *a: False)
    measurer = Measurer(CAM, None)
    fused = measurer._method_for(500, 375)
    image = np.zeros((375, 500, 3), np.uint8)
    return measurer._known_rig_row(fused, image, depth, Timer(), 300, PITCHES)  # type: ignore[arg-type]


HIGH = {-2.0: (0.87, 0.3), 0.0: (0.99, 0.4), 2.0: (1.10, 0.5), 4.0: (1.22, 0.2)}


def test_readings_agreeing_only_under_high_lenses_give_no_face(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    assert _row_read(monkeypatch, HIGH) is None


def test_without_the_rule_high_lenses_give_the_face(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "KNOWN_ROWS_ROBOT_LENS", False)
    face = _row_read(monkeypatch, HIGH)
    assert face is not None and face.camera_height_m == pytest.approx(1.10)


# the surest reading 0.62 m up, the one at the limit 0.58 m: the face given is the surest
# of the readings under a robot's lens (a step of 0.05 m either way moves it)
EDGE = {-2.0: (0.58, 0.3), 0.0: (0.62, 0.5), 2.0: (0.70, 0.4), 4.0: (0.80, 0.2)}


def test_the_face_given_is_the_surest_under_a_robots_lens(monkeypatch: pytest.MonkeyPatch) -> None:
    face = _row_read(monkeypatch, EDGE)
    assert face is not None and face.camera_height_m == pytest.approx(0.58)


@pytest.mark.parametrize("step", [-0.05, 0.05])
def test_the_lens_limit_is_the_robots(monkeypatch: pytest.MonkeyPatch, step: float) -> None:
    monkeypatch.setattr(measure, "KNOWN_ROWS_MAX_LENS_M", measure.KNOWN_ROWS_MAX_LENS_M + step)
    face = _row_read(monkeypatch, EDGE)
    assert face is None or face.camera_height_m != pytest.approx(0.58)


def test_a_reading_at_the_limit_is_a_robots(monkeypatch: pytest.MonkeyPatch) -> None:
    # the surest reading exactly KNOWN_ROWS_MAX_LENS_M up (read when the test runs), the
    # others over it: the limit is a robot's lens, that reading the face given
    limit = measure.KNOWN_ROWS_MAX_LENS_M
    at = {-2.0: (limit, 0.5), 0.0: (0.9, 0.4), 2.0: (1.0, 0.3), 4.0: (1.1, 0.2)}
    face = _row_read(monkeypatch, at)
    assert face is not None and face.camera_height_m == pytest.approx(limit)


FAR = 3.0  # the depth at which a lens looking up reads higher than KNOWN_ROWS_MAX_LENS_M


def _looking_up_limit() -> float:
    """The lens limit at FAR for a lens looking up past the steepest reading (a robot's
    highest lens plus FAR times the tangent of KNOWN_ROWS_UP_SLACK_DEG, read when the test
    runs)."""
    slack = FAR * math.tan(math.radians(measure.KNOWN_ROWS_UP_SLACK_DEG))
    return measure.KNOWN_ROWS_ROBOT_MAX_M + slack


def _lenses(at: float) -> dict[float, tuple[float, float]]:
    return {-2.0: (at, 0.5), 0.0: (1.0, 0.4), 2.0: (1.1, 0.3), 4.0: (1.2, 0.2)}


def test_far_off_the_limit_is_a_lens_looking_up() -> None:
    # the allowance is what sets the limit at FAR (else this file's edges test nothing)
    assert _looking_up_limit() > measure.KNOWN_ROWS_MAX_LENS_M + 0.02


@pytest.mark.parametrize(("over", "taken"), [(-0.005, True), (0.005, False)])
def test_the_limit_grows_with_the_depth_for_a_lens_looking_up(
    monkeypatch: pytest.MonkeyPatch, over: float, taken: bool
) -> None:
    at = _looking_up_limit() + over
    face = _row_read(monkeypatch, _lenses(at), slack=True, depth=FAR)
    assert (face is not None and face.camera_height_m == pytest.approx(at)) is taken


@pytest.mark.parametrize(
    "name, step", [("KNOWN_ROWS_UP_SLACK_DEG", 0.5), ("KNOWN_ROWS_ROBOT_MAX_M", 0.01)]
)
@pytest.mark.parametrize("sign", [-1.0, 1.0])
def test_the_allowance_moves_with_its_constants(
    monkeypatch: pytest.MonkeyPatch, name: str, step: float, sign: float
) -> None:
    # a reading 0.003 m inside the limit at FAR: the constant a step lower refuses it; one
    # 0.003 m outside is taken with it a step higher
    inside = _looking_up_limit() - 0.003
    outside = inside + 0.006
    monkeypatch.setattr(measure, name, getattr(measure, name) + sign * step)
    inside_face = _row_read(monkeypatch, _lenses(inside), slack=True, depth=FAR)
    outside_face = _row_read(monkeypatch, _lenses(outside), slack=True, depth=FAR)
    assert (inside_face is not None) is (sign > 0)
    assert (outside_face is not None) is (sign > 0)


# The issue's robots: a lens at most 0.5 m up, looking at most 5 degrees up or down; the
# readings' steepest pitch up is KNOWN_RIG_PITCHES_DEG's least (down positive).
ISSUE_LENS_MAX_M = 0.5
ISSUE_PITCH_MAX_DEG = 5.0


@pytest.mark.parametrize(("over", "taken"), [(-0.003, True), (0.003, False)])
def test_the_allowance_is_the_issues_robots(
    monkeypatch: pytest.MonkeyPatch, over: float, taken: bool
) -> None:
    steepest_up = -min(measure.KNOWN_RIG_PITCHES_DEG)
    limit = ISSUE_LENS_MAX_M + FAR * math.tan(math.radians(ISSUE_PITCH_MAX_DEG - steepest_up))
    face = _row_read(monkeypatch, _lenses(limit + over), slack=True, depth=FAR)
    assert (face is not None) is taken


def test_near_the_lens_limit_holds(monkeypatch: pytest.MonkeyPatch) -> None:
    # at 2 m the allowance is under KNOWN_ROWS_MAX_LENS_M, which holds: a reading just
    # under it is taken, one just over it not
    for over, taken in ((-0.005, True), (0.005, False)):
        at = measure.KNOWN_ROWS_MAX_LENS_M + over
        face = _row_read(monkeypatch, _lenses(at), slack=True)
        assert (face is not None) is taken


def test_a_lens_looking_up_past_the_readings_keeps_the_box(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # photo 1190 ordinary (a tuning room): a lens 0.49 m up looking up 4.2 degrees, the box
    # 3.1 m off read at 0.61 m under the steepest reading; with no allowance the can on
    # the box is taken (test_fused_stands_on_top holds the answer with the allowance)
    monkeypatch.setattr(measure, "KNOWN_ROWS_UP_SLACK_DEG", 0.0)
    res, truth = measured_room("photo", 1190, False, False)
    assert max(_errors(res, truth)) > 0.25
