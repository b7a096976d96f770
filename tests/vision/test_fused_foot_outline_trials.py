"""With no rig, a no-rig trial's face standing on the trial's row is grown to the outline
read from its foot as with the rig (``method.FOOT_OUTLINE_TRIALS``, ``method._foot_read``).

The rooms are tuning rooms (procedural and photo, seeds 2000-2099), measured with no rig.
Procedural 2029 (ordinary) is a print over the face: the trials found a piece of it, its
foot on the trial's row, 56 % too low; its outline from the foot is the face (1.0 %).
Procedural 2046 (hard) goes the same way (85 -> 1.5 %). Procedural 2162 (hard, a fresh
room) is a box found weakly (0.08-0.10) before a drum whose foot is a few rows above its
own: grown, it took the drum (2.6 -> 102 %); FOOT_TRIAL_MIN_CONFIDENCE keeps it.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.fused import method

from tests.vision_fixtures import room_size_errors


def test_a_print_s_piece_on_the_trial_s_row_is_grown_to_the_face() -> None:
    eh, ew = room_size_errors("procedural", 2029, False, with_rig=False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_rule_the_piece_is_the_answer(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method, "FOOT_OUTLINE_TRIALS", False)
    # the estimated rig taken as known reads the outline too (measure.ESTIMATED_RIG_AGAIN)
    monkeypatch.setattr(measure, "ESTIMATED_RIG_AGAIN", False)
    # ... and so do the rows read as with a rig over a small unsure face (SMALL_FACE_GROWN)
    monkeypatch.setattr(measure, "SMALL_FACE_GROWN", False)
    eh, _ = room_size_errors("procedural", 2029, False, with_rig=False)
    assert eh > 0.25


def test_a_second_room_goes_the_same_way(monkeypatch: pytest.MonkeyPatch) -> None:
    eh, ew = room_size_errors("procedural", 2046, True, with_rig=False)
    assert eh < 0.05 and ew < 0.05
    monkeypatch.setattr(method, "FOOT_OUTLINE_TRIALS", False)
    monkeypatch.setattr(measure, "ESTIMATED_RIG_AGAIN", False)
    eh, _ = room_size_errors("procedural", 2046, True, with_rig=False)
    assert eh > 0.25


def test_the_foot_must_be_near_the_trial_s_row(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method, "FOOT_TRIAL_ROWS", 0)
    # (the estimated rig taken as known reads the outline from the foot as well)
    monkeypatch.setattr(measure, "ESTIMATED_RIG_AGAIN", False)
    eh, _ = room_size_errors("procedural", 2046, True, with_rig=False)
    assert eh > 0.25


def test_a_weak_face_before_another_thing_is_not_grown() -> None:
    eh, ew = room_size_errors("procedural", 2162, True, with_rig=False)
    assert eh < 0.05 and ew < 0.05


def test_the_confidence_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # (the estimated rig taken as known reads the outline from the foot as well)
    monkeypatch.setattr(measure, "ESTIMATED_RIG_AGAIN", False)
    monkeypatch.setattr(method, "FOOT_TRIAL_MIN_CONFIDENCE", 0.0)
    eh, _ = room_size_errors("procedural", 2162, True, with_rig=False)
    assert eh > 0.25
    monkeypatch.setattr(method, "FOOT_TRIAL_MIN_CONFIDENCE", 0.6)
    eh, _ = room_size_errors("procedural", 2046, True, with_rig=False)
    assert eh > 0.25
