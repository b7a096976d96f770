"""With no rig, the pitch a face's sides read is taken only where the camera height it and
the face's floor-contact row stand for is one a robot carries (``measure.
SIDES_PITCH_LENS_BOUND``, ``measure._robot_lens``, ``UNDER_MAX_CAMERA_HEIGHT_M``).

The room is a tuning room, measured with no rig. Photo 2089 (ordinary): a seamed face, the
lens 0.49 m up looking 3.7 degrees up; the sides' lean reads 2.2 degrees down, which stands
the lens 0.71 m up and reads a line above the face as its top (+19 %); the level reading,
kept, is within 5 %.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.measure import _robot_lens

from tests.vision_fixtures import room_size_errors


def test_a_pitch_standing_the_lens_too_high_is_not_taken() -> None:
    eh, ew = room_size_errors("photo", 2089, False, with_rig=False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_rule_the_line_above_the_face_is_its_top(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(measure, "SIDES_PITCH_LENS_BOUND", False)
    # (the level trials' reading, its top lower and undoubted, stands for the face the
    # line's top left refused: measure.LOWER_TOP_READING, session 44, a backstop here)
    monkeypatch.setattr(measure, "LOWER_TOP_READING", False)
    eh, _ = room_size_errors("photo", 2089, False, with_rig=False)
    assert eh > 0.15


@pytest.mark.parametrize(("height", "robot"), [(0.6, True), (0.601, False), (0.12, True)])
def test_robot_lens_limit(height: float, robot: bool) -> None:
    assert measure.UNDER_MAX_CAMERA_HEIGHT_M == 0.6
    assert _robot_lens(height) is robot


def test_robot_lens_any_height_with_the_rule_off(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "SIDES_PITCH_LENS_BOUND", False)
    assert _robot_lens(0.9)
