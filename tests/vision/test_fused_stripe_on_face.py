"""A stripe down the face (a tape) is a marking on it, not a gap between two faces
(``region.BRIDGE_STRIPES``, ``region.bridge_stripe``, ``method._across_stripe``): its two
edges parallel a few centimetres apart, the face's colour the same on both sides and its
foot line running on across it on the same row.

Procedural 3080 (hard, a diagnosis room of new2): a purple face 0.93 m wide at 2.89 m with
a beige tape 15 columns (0.095 m) wide down it; the tape's top shows no line against the
wall, so the widening across seams stopped at its near edge and the answer was the left
half (-57 %, with the rig and with none). At the tape: foot line on 14 of its 15 columns,
the face's colour either side (8-bit Lab) 1.4 apart.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.fused import extent, method, region

from tests.vision_fixtures import room_size_errors


@pytest.mark.parametrize("with_rig", [True, False])
def test_the_face_is_crossed_past_its_tape(with_rig: bool) -> None:
    eh, ew = room_size_errors("procedural", 3080, True, with_rig=with_rig)
    assert eh < 0.02 and ew < 0.02


def test_without_the_rule_the_half_stands(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "BRIDGE_STRIPES", False)
    # (the walk over a plank whose top faded, session 48, crosses the tape too: off here)
    monkeypatch.setattr(extent, "FADED_PLANK_WALK", False)
    _, ew = room_size_errors("procedural", 3080, True)
    assert ew > 0.5


@pytest.mark.parametrize(
    ("name", "value", "crossed"),
    [
        # the tape's far edge 15 columns past the side (0.0945 m at 2.89 m), its blur
        # from 13 (0.0819 m): a window of 13 columns reaches it, 12 do not
        ("STRIPE_MAX_M", 0.083, True),
        ("STRIPE_MAX_M", 0.081, False),
        ("STRIPE_SAME_SURFACE", 1.5, True),  # the two halves' colours 1.41 apart
        ("STRIPE_SAME_SURFACE", 1.3, False),
        ("STRIPE_FOOT_SHARE", 0.93, True),  # the foot line on 14 of the tape's 15 columns
        ("STRIPE_FOOT_SHARE", 0.94, False),
    ],
)
def test_each_limit(
    monkeypatch: pytest.MonkeyPatch, name: str, value: float, crossed: bool
) -> None:
    monkeypatch.setattr(region, name, value)
    monkeypatch.setattr(extent, "FADED_PLANK_WALK", False)  # (crosses the tape too)
    _, ew = room_size_errors("procedural", 3080, True)
    assert (ew < 0.02) if crossed else (ew > 0.5)


@pytest.mark.parametrize(
    ("widened", "kept"),
    [
        ((100, 230), (100, 230)),  # the face runs on 15 columns past the 15-column stripe
        ((100, 229), (100, 200)),  # 14: the stripe stands at the face's real side
    ],
)
def test_the_face_must_run_on_past_the_stripe(
    monkeypatch: pytest.MonkeyPatch, widened: tuple[int, int], kept: tuple[int, int]
) -> None:
    monkeypatch.setattr(method, "bridge_stripe", lambda *a: (100, 215))
    monkeypatch.setattr(method, "widen_across_seams", lambda *a: widened)
    got = method._across_stripe(*([None] * 6), 100, 200, 1.0, 1.0, True)  # type: ignore[arg-type]
    assert got == kept


def test_a_seam_wide_as_a_stripe_is_crossed_on_the_luminance(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # photo 1278 (ordinary), a face in the wall's lightness with a seam: before the rule
    # only the background channel (measure.BACKGROUND_TURN) found it
    monkeypatch.setattr(measure, "BACKGROUND_TURN", False)
    eh, ew = room_size_errors("photo", 1278, False)
    assert eh < 0.05 and ew < 0.05
