"""With no rig and the pitch guessed, the face measured allowing the lens to look down
UNREAD_PITCH_DOWN_DEG more is taken with its top lowered (``UNREAD_TOP_FACE_LOWERS``) only
where the two tops can be a top face's edges: at the steepest pitch allowed (the guess
plus UNREAD_PITCH_DOWN_DEG, no steeper than stands the lens UNDER_MAX_CAMERA_HEIGHT_M up
over the foot's row) the guessed top, the back edge, lies under the horizon and at most
MAX_TOP_FACE_DEPTH_M behind the front (``measure.TOP_FACE_DEPTH_BOUND``,
``measure._top_face_too_deep``).

The room is a diagnosis room (new7), measured with no rig. Procedural 3327 (hard): a
brick face 0.55 m tall, taller than the lens (0.44 m); the level guess reads it whole
(0.97), the allowance lowers its top 12.6 rows to a brick course, -12.7 %: that top face
would reach 3.8 m behind the front. With the rule the top stays, +0.3 %.
"""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import cast

import numpy as np
import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.measure import _top_face_too_deep
from obstacle_fusion.vision.pitch import camera_height_for_row
from obstacle_fusion.vision.types import Measurement, View

from tests.vision_fixtures import room_size_errors

FY, CY = 500.0, 200.0
#: a lens without distortion: input pixels are the pitch-0 view's
PINHOLE = CameraModel(
    np.array([[FY, 0.0, 250.0], [0.0, FY, CY], [0.0, 0.0, 1.0]]), np.zeros(4), 500, 400
)
VIEW = cast(View, SimpleNamespace(fy=FY, cy=CY, camera=PINHOLE))
RANGE_M = 2.0
FRONT_M = 0.3  # the face's front height


def _row(height_below_lens: float, distance: float, pitch_deg: float) -> float:
    return CY + FY * math.tan(math.atan(height_below_lens / distance) - math.radians(pitch_deg))


def _pair(
    lens: float, pitch_deg: float, top_depth: float, guess_deg: float = 0.0
) -> tuple[Measurement, Measurement]:
    """The guessed face (its top the back edge of a top face ``top_depth`` deep) and the
    allowance's face (its top the front edge), seen by a lens ``lens`` up pitched
    ``pitch_deg`` down; the guessed pitch ``guess_deg``."""
    foot = _row(lens, RANGE_M, pitch_deg)
    front = _row(lens - FRONT_M, RANGE_M, pitch_deg)
    back = _row(lens - FRONT_M, RANGE_M + top_depth, pitch_deg)
    guessed = Measurement(
        True, "fused", RANGE_M, box_px=(100.0, back, 200.0, foot), camera_pitch_deg=guess_deg
    )
    lowered = Measurement(True, "fused", RANGE_M, box_px=(100.0, front, 200.0, foot))
    return guessed, lowered


def _too_deep(lens: float, pitch_deg: float, top_depth: float, guess_deg: float = 0.0) -> bool:
    return _top_face_too_deep(*_pair(lens, pitch_deg, top_depth, guess_deg), VIEW, RANGE_M)


def test_the_brick_face_keeps_its_top() -> None:
    eh, ew = room_size_errors("procedural", 3327, True, with_rig=False)
    assert eh < 0.03 and ew < 0.03


def test_without_the_rule_a_brick_course_is_the_top(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "TOP_FACE_DEPTH_BOUND", False)
    eh, _ = room_size_errors("procedural", 3327, True, with_rig=False)
    assert eh > 0.1


def test_a_top_face_of_an_obstacles_depth_is_allowed() -> None:
    # seen at the steepest pitch the allowance gives (5 degrees, the lens 0.4 m up)
    assert not _too_deep(0.4, 5.0, 0.3)
    assert not _too_deep(0.4, 5.0, 1.49)
    assert _too_deep(0.4, 5.0, 1.51)
    # seen at a shallower pitch the same rows stand a deeper face at the steepest: allowed
    assert not _too_deep(0.4, 3.0, 0.3)


def test_max_top_face_depth(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "MAX_TOP_FACE_DEPTH_M", 1.4)
    assert _too_deep(0.4, 5.0, 1.45)
    monkeypatch.setattr(measure, "MAX_TOP_FACE_DEPTH_M", 1.6)
    assert not _too_deep(0.4, 5.0, 1.55)


def test_the_pitch_allowed(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "UNREAD_PITCH_DOWN_DEG", 4.0)
    assert _too_deep(0.4, 5.0, 1.49)  # a shallower steepest pitch: deeper


def test_the_guessed_pitch_adds_to_the_allowance() -> None:
    assert not _too_deep(0.4, 7.0, 1.49, guess_deg=2.0)
    assert _too_deep(0.4, 7.0, 1.49, guess_deg=0.0)


def test_the_lens_height_bounds_the_pitch(monkeypatch: pytest.MonkeyPatch) -> None:
    # the lens 0.6 m up at 3 degrees: no steeper pitch though 5 are allowed
    assert not _too_deep(0.6, 3.0, 1.49)
    assert _too_deep(0.6, 3.0, 1.51)
    monkeypatch.setattr(measure, "UNDER_MAX_CAMERA_HEIGHT_M", 0.55)
    assert _too_deep(0.6, 3.0, 1.49)
    monkeypatch.setattr(measure, "UNDER_MAX_CAMERA_HEIGHT_M", 0.65)
    assert not _too_deep(0.6, 3.0, 1.51)


def test_a_back_edge_above_the_horizon_is_no_top_face(monkeypatch: pytest.MonkeyPatch) -> None:
    # however deep a top face is allowed, its back edge lies under the horizon
    monkeypatch.setattr(measure, "MAX_TOP_FACE_DEPTH_M", 1e9)
    foot = _row(0.4, RANGE_M, 5.0)
    front = _row(0.1, RANGE_M, 5.0)
    horizon = CY - FY * math.tan(math.radians(5.0))
    lowered = Measurement(True, "fused", RANGE_M, box_px=(100.0, front, 200.0, foot))
    for back, deep in ((horizon - 0.01, True), (horizon + 0.01, False)):
        guessed = Measurement(True, "fused", RANGE_M, box_px=(100.0, back, 200.0, foot))
        assert _top_face_too_deep(guessed, lowered, VIEW, RANGE_M) is deep


def test_no_box_no_bound() -> None:
    guessed, lowered = _pair(0.4, 5.0, 3.0)
    assert not _top_face_too_deep(Measurement(True, "fused", RANGE_M), lowered, VIEW, RANGE_M)
    assert not _top_face_too_deep(guessed, Measurement(True, "fused", RANGE_M), VIEW, RANGE_M)


def test_the_rows_are_undistorted() -> None:
    # the paper's lens (barrel distortion): the boxes are input pixels, the pitch and the
    # lens's height reckoned in the undistorted view. A face near the image's left edge,
    # seen at the steepest pitch (5 degrees, the lens 0.4 m up): read as view rows, its
    # distorted rows stand a top face 1.55 m deep as 1.43 m
    cam = CameraModel.paper(500, 375)
    view = cast(View, SimpleNamespace(fy=cam.fy, cy=cam.cy, camera=cam))

    def seen(height_below_lens: float, distance: float) -> float:
        level = math.atan(height_below_lens / distance) - math.radians(5.0)
        ray = [(40.0 - cam.cx) / cam.fx, math.tan(level), 1.0]
        return float(cam.project([ray])[0, 1])

    foot, front = seen(0.4, RANGE_M), seen(0.4 - FRONT_M, RANGE_M)
    lowered = Measurement(True, "fused", RANGE_M, box_px=(20.0, front, 60.0, foot))
    for top_depth, deep in ((1.45, False), (1.55, True)):
        back = seen(0.4 - FRONT_M, RANGE_M + top_depth)
        guessed = Measurement(
            True, "fused", RANGE_M, box_px=(20.0, back, 60.0, foot), camera_pitch_deg=0.0
        )
        assert _top_face_too_deep(guessed, lowered, view, RANGE_M) is deep


def _level_pair(back: float, front: float) -> tuple[Measurement, Measurement]:
    """The guessed face (top ``back``) and the lowered one (top ``front``) with the
    guessed pitch 5 degrees up: the steepest pitch allowed is level (0 degrees, the
    lens 0.4 m up, under the bound)."""
    foot = CY + FY * 0.4 / RANGE_M
    guessed = Measurement(
        True, "fused", RANGE_M, box_px=(100.0, back, 200.0, foot), camera_pitch_deg=-5.0
    )
    lowered = Measurement(True, "fused", RANGE_M, box_px=(100.0, front, 200.0, foot))
    return guessed, lowered


def test_a_back_edge_on_the_horizon_is_no_top_face() -> None:
    # the steepest pitch level: the horizon is the row cy, and a back edge on it no
    # top face's (a top face lies under the lens)
    assert _top_face_too_deep(*_level_pair(CY, CY + 30.0), VIEW, RANGE_M)
    assert not _top_face_too_deep(*_level_pair(CY + 10.0, CY + 12.0), VIEW, RANGE_M)  # 0.4 m


def test_a_top_face_exactly_max_deep_is_allowed(monkeypatch: pytest.MonkeyPatch) -> None:
    # the steepest pitch level: the back edge as many times farther than the front as
    # its row's drop under the horizon is under the front's
    back, front = CY + 10.0, CY + 30.0
    deep = RANGE_M * (
        camera_height_for_row(front, RANGE_M, 0.0, FY, CY)
        / camera_height_for_row(back, RANGE_M, 0.0, FY, CY)
        - 1.0
    )
    assert deep == pytest.approx(4.0)
    monkeypatch.setattr(measure, "MAX_TOP_FACE_DEPTH_M", deep)
    assert not _top_face_too_deep(*_level_pair(back, front), VIEW, RANGE_M)
    monkeypatch.setattr(measure, "MAX_TOP_FACE_DEPTH_M", math.nextafter(deep, 0.0))
    assert _top_face_too_deep(*_level_pair(back, front), VIEW, RANGE_M)
