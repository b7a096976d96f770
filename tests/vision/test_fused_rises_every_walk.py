"""Every walk of the face's colour along its foot has the sides it moves out rise as the
face's up to its top (``method.RISES_EVERY_WALK``, ``region.sides_rising``): with no rig
too, and after the colour rescue's walk from the face's top.

The room is a tuning room (seeds 2000-2099): procedural 2099 (ordinary, no rig) is a brick
face with its shadow on a pink floor beside its left side. The colour rescue found the
face, then its walk along the foot from the face's top ran on over the shadow (within the
face's colour limit, stepping from the lit floor below it) and took it in: width +58 %.
The shadow's columns show the wall above it, as beyond it, so that side is brought back.
With no rig the colour face's first walk, from the beam's core, rises so too
(``region.CORE_WALK_RISES``): photo 136 (ordinary); not with the rig (photo 746 hard).
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import method, region

from tests.vision_fixtures import room_size_errors


def test_a_shadow_beside_the_face_is_not_taken_in_with_no_rig() -> None:
    eh, ew = room_size_errors("procedural", 2099, False, with_rig=False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_rule_the_rescue_walk_takes_the_shadow_in(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(method, "RISES_EVERY_WALK", False)
    _, ew = room_size_errors("procedural", 2099, False, with_rig=False)
    assert ew > 0.4


def test_the_rig_room_is_unchanged() -> None:
    # with the rig the edge search's walk rose already (region.RISES_AS_FACE): the same
    # face measured right
    eh, ew = room_size_errors("procedural", 2099, False)
    assert eh < 0.05 and ew < 0.05


# photo 136 (ordinary, no rig), a tuning room: the colour face walked from the beam's core
# ran along the foot past the face's side (region.CORE_WALK_RISES), width +46 %
def test_the_colour_face_from_the_core_rises_with_no_rig() -> None:
    eh, ew = room_size_errors("photo", 136, False, with_rig=False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_core_rule_the_colour_face_runs_on(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "CORE_WALK_RISES", False)
    eh, ew = room_size_errors("photo", 136, False, with_rig=False)
    assert max(eh, ew) > 0.25


def test_with_the_rig_a_print_piece_from_the_core_keeps_its_walk() -> None:
    # photo 746 (hard, rig), a tuning room: a print's piece walked from the core is grown
    # to the face round it; the rising check with the rig cut it to a strip (4 -> 82 %)
    eh, ew = room_size_errors("photo", 746, True)
    assert eh < 0.05 and ew < 0.05
