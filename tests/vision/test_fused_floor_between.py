"""A side with the floor seen between it and the face's foot is brought in to the foot,
even where it stands down to the contact row (``region.FLOOR_BETWEEN``,
``region.trim_to_foot``).

The rooms are tuning rooms (photo, seeds 2000-2099): photo 2062 (hard) is a brown case
beside a frame's leg standing farther back; the search took the leg's edge for the left
side, and the leg stands down to the contact row, so the trim to the foot kept it: +53 %
wide. Photo 2035 (hard) is a pink face beside a dark can, the search's left side on the
can; the wall's purple skirting above the floor between them passed for the face's colour
running on: +31 % wide. In both, the floor's own chroma fills the columns between
(0.98 and 1.0 of them, judged against the colour of the face's foot where it steps from
the floor).
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import region

from tests.vision.test_fused_region import LEFT, RIGHT, pole_scene, trim
from tests.vision_fixtures import room_size_errors


def test_a_side_on_a_leg_behind_comes_in_to_the_foot() -> None:
    eh, ew = room_size_errors("photo", 2062, True)
    assert eh < 0.05 and ew < 0.05


def test_a_side_on_a_can_beside_comes_in_to_the_foot() -> None:
    eh, ew = room_size_errors("photo", 2035, True)
    assert eh < 0.05 and ew < 0.05


def test_without_the_rule_the_leg_is_taken_for_the_side(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "FLOOR_BETWEEN", False)
    _, ew = room_size_errors("photo", 2062, True)
    assert ew > 0.25


def test_without_the_rule_the_can_is_taken_for_the_side(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "FLOOR_BETWEEN", False)
    _, ew = room_size_errors("photo", 2035, True)
    assert ew > 0.25


def test_the_floor_share_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # 0.98 of the columns between the leg and the case show the floor's chroma
    monkeypatch.setattr(region, "FLOOR_BETWEEN_SHARE", 0.99)
    _, ew = room_size_errors("photo", 2062, True)
    assert ew > 0.25


def test_a_pole_standing_on_the_contact_row_with_floor_between_comes_in() -> None:
    # the pole 40 columns right of the planks' face, standing down to the contact row at
    # its full contrast, the floor between them and on past it: the face's own sides
    img = pole_scene(1.0)
    assert trim(img, LEFT, RIGHT + 40) == (LEFT, RIGHT)


def test_without_the_rule_the_standing_pole_is_kept(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "FLOOR_BETWEEN", False)
    assert trim(pole_scene(1.0), LEFT, RIGHT + 40) == (LEFT, RIGHT + 40)


def test_a_print_margin_under_a_taken_contact_row_is_no_floor_between() -> None:
    # procedural/2080 hard with no rig: a trial contact row on the poster, its margin under
    # it; beyond the poster's side the floor band is another colour: the side stays
    eh, ew = room_size_errors("procedural", 2080, True, with_rig=False)
    assert eh < 0.05 and ew < 0.05


def test_the_floor_past_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # the poster's foot stepping from its margin is narrow too (FLOOR_BETWEEN_MIN_M): off
    monkeypatch.setattr(region, "FLOOR_BETWEEN_MIN_M", 0.0)
    eh, ew = room_size_errors("procedural", 2080, True, with_rig=False)
    assert eh < 0.05 and ew < 0.05
    monkeypatch.setattr(region, "FLOOR_PAST_CHROMA", 1000.0)
    eh, _ = room_size_errors("procedural", 2080, True, with_rig=False)
    assert eh > 0.25


def test_the_narrowest_foot_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # the case's foot is about 0.4 m wide at the sonar's depth: under a limit above that, the
    # rule is off and the leg is kept for the side
    monkeypatch.setattr(region, "FLOOR_BETWEEN_MIN_M", 0.5)
    _, ew = room_size_errors("photo", 2062, True)
    assert ew > 0.25
