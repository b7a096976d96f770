"""A face's top is where its sides end (``method.SIDES_END_TOP``,
``region.lower_top_where_sides_end``).

The rooms are tuning rooms (photo and procedural, seeds 100-159 and 2000-2099): photo 135
(hard, no rig) is a teal plank face before a photographed rocket in line above it; the
texture rescue walked the top up the rocket (+78 %). Its left side parts it from the
background beside it up to its top; above it the photograph runs on level across the side
line. Photo 2016 (hard, no rig) is a low box before the rocket's platform: the texture
rescue's top was put on the platform's top (+172 %), a band of the platform standing out
beside one side on the way. Procedural 141 (ordinary, no rig) is a large glossy face whose
sides the pitch-0 trial leaves a little inside it at its foot: the contrast across them
changes at the wall's skirting behind, where the face has no edge of its own.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import method, region

from tests.vision_fixtures import room_size_errors


def _rocket_face() -> float:
    eh, ew = room_size_errors("photo", 135, True, with_rig=False)
    assert ew < 0.1
    return eh


def test_a_top_up_the_background_in_line_comes_down_to_where_the_sides_end() -> None:
    assert _rocket_face() < 0.05


def test_without_the_rule_the_top_stays_on_the_rocket(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method, "SIDES_END_TOP", False)
    assert _rocket_face() > 0.25


@pytest.mark.parametrize("level", [2.0, 20.0])
def test_the_level_limit_decides(monkeypatch: pytest.MonkeyPatch, level: float) -> None:
    # 2: the photograph's own grain across the side line is no longer level; 20: the
    # face's upper rows count as past its top, the walk ends under its real top edge
    monkeypatch.setattr(region, "SIDES_END_LEVEL", level)
    assert _rocket_face() > 0.25


def test_the_keep_share_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "SIDES_END_KEEP", 0.05)
    assert _rocket_face() > 0.25


def test_a_side_must_stand_out_at_the_foot(monkeypatch: pytest.MonkeyPatch) -> None:
    # the left side parts the face from the background by about 30 Lab at its foot
    monkeypatch.setattr(region, "SIDES_END_STAND", 45.0)
    assert _rocket_face() > 0.25


def test_the_face_must_end_at_an_edge(monkeypatch: pytest.MonkeyPatch) -> None:
    # the rocket face's top edge is 8.8 times its face's median row
    monkeypatch.setattr(region, "SIDES_END_EDGE", 10.0)
    assert _rocket_face() > 0.25


def _glossy_face() -> float:
    eh, _ = room_size_errors("procedural", 141, False, with_rig=False)
    return eh


def test_a_line_behind_the_face_with_no_edge_on_it_is_no_top() -> None:
    assert _glossy_face() < 0.05


def test_without_the_edge_the_skirting_is_taken(monkeypatch: pytest.MonkeyPatch) -> None:
    # the face's own rows at the skirting: 1.5-1.9 times its median row
    monkeypatch.setattr(region, "SIDES_END_EDGE", 1.0)
    assert _glossy_face() > 0.25


def _platform_face() -> float:
    eh, _ = room_size_errors("photo", 2016, True, with_rig=False)
    return eh


def test_a_band_beside_one_side_on_the_way_is_crossed() -> None:
    assert _platform_face() < 0.1


def test_the_share_past_the_sides_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "SIDES_END_SHARE", 0.97)
    assert _platform_face() > 0.25
