"""With the rig, a side moves out along the face's foot line past a seam to where the line
ends at an edge standing the face's whole height (``extent.FOOT_LINE_TO_SIDE``,
``FOOT_WALK_REACH``, ``FOOT_MIN_MOVE``, ``FOOT_SIDE_SNR``).

The room is a tuning room (photo 100-159): photo 153 (hard, with the rig) is a face of
light planks with a dark one at its left end, whose top against the grey wall is no line;
the seam between them (col 63) was taken for the side (w -11 %, confidence 0.61). Its foot
line runs on past the seam (with a gap of 7 columns) to the real side at col 25, 36 columns
out of a 320-column pair, whose edge stands 3.51 noise levels from the foot to the top.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import extent

from tests.vision_fixtures import room_size_errors


def _dark_plank() -> float:
    eh, ew = room_size_errors("photo", 153, True)
    assert eh < 0.05
    return ew


def test_the_foot_line_carries_the_side_past_the_seam() -> None:
    assert _dark_plank() < 0.03


def test_without_the_rule_the_seam_is_the_side(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(extent, "FOOT_LINE_TO_SIDE", False)
    assert _dark_plank() > 0.08


@pytest.mark.parametrize(("snr", "moved"), [(3.5, True), (3.6, False)])
def test_the_side_must_stand_out(monkeypatch: pytest.MonkeyPatch, snr: float, moved: bool) -> None:
    monkeypatch.setattr(extent, "FOOT_SIDE_SNR", snr)
    assert (_dark_plank() < 0.03) is moved


@pytest.mark.parametrize(("reach", "moved"), [(0.115, True), (0.11, False)])
def test_the_walk_s_reach(monkeypatch: pytest.MonkeyPatch, reach: float, moved: bool) -> None:
    # the line ends 36 columns out of a 320-column pair
    monkeypatch.setattr(extent, "FOOT_WALK_REACH", reach)
    assert (_dark_plank() < 0.03) is moved


@pytest.mark.parametrize(("least", "moved"), [(6, True), (38, True), (40, False)])
def test_the_least_move(monkeypatch: pytest.MonkeyPatch, least: int, moved: bool) -> None:
    # the real side stands 38 columns past the seam
    monkeypatch.setattr(extent, "FOOT_MIN_MOVE", least)
    assert (_dark_plank() < 0.03) is moved
