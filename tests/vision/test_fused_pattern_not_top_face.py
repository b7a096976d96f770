"""Rows across which the face's own pattern runs are no top face
(``region.PATTERN_NOT_TOP_FACE``, on the colour and texture rescue's face).

Photo 740 (ordinary, a tuning room) is a blue box before a photographed rocket, a brick
print on its front in a blue margin. The colour rescue finds its top (row 272); the front
top edge search under it takes a mortar joint of the print (row 285) for the edge of a
top face, and the rows between (the margin and a course of bricks) differ in colour from
the face below: the height came out 28 % short. The bricks' vertical joints run across
those rows as they run across the face below (mean step 4.3 against 5.4 between
neighbouring columns), which a top face, one surface, does not have.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import region
from obstacle_fusion.vision.fused import top as top_mod

from tests.vision_fixtures import room_size_errors


def test_a_joint_of_a_brick_print_is_no_front_top_edge() -> None:
    eh, ew = room_size_errors("photo", 740, False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_rule_the_joint_cuts_the_height(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "PATTERN_NOT_TOP_FACE", False)
    # (the joint is a dark line's lower edge as well, top.FRONT_EDGE_STEPS: without that)
    monkeypatch.setattr(top_mod, "FRONT_EDGE_STEPS", False)
    eh, _ = room_size_errors("photo", 740, False)
    assert eh > 0.25


def test_the_share_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # the rows' steps are 0.8 of the face's
    monkeypatch.setattr(region, "PATTERN_SHARE", 0.85)
    # (the joint is a dark line's lower edge as well, top.FRONT_EDGE_STEPS: without that)
    monkeypatch.setattr(top_mod, "FRONT_EDGE_STEPS", False)
    eh, _ = room_size_errors("photo", 740, False)
    assert eh > 0.25


def test_a_face_with_too_few_steps_has_no_pattern(monkeypatch: pytest.MonkeyPatch) -> None:
    # the face's mean step is 5.4
    monkeypatch.setattr(region, "PATTERN_MIN_STEP", 5.6)
    # (the joint is a dark line's lower edge as well, top.FRONT_EDGE_STEPS: without that)
    monkeypatch.setattr(top_mod, "FRONT_EDGE_STEPS", False)
    eh, _ = room_size_errors("photo", 740, False)
    assert eh > 0.25
