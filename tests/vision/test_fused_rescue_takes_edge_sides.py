"""A face found by its colour in place of the edges' face standing above the contact band,
lying between that face's sides and reaching as high, takes those sides as far as they
rise as its own (``method.RESCUE_TAKES_EDGE_SIDES``, ``RESCUE_SIDES_SLACK``,
``RESCUE_SAME_TOP_ROWS``).

Procedural 2003 (hard, a tuning room of seeds 2000-2099) is a low gloss face; the edges
found its sides (158-315, top row 247) with a foot 4 rows above the contact band and no
outline round it, so the colour's face standing in the band was taken: its colour run
along the foot ended at the highlight, 227-316 (w -43 %), its top row 243. Its right side
lies a column past the edges'. Procedural 312 (hard) is a box in front of a chair and a
can whose outline the edges took (137-394, top row 230): the box's colour face, 236-269
high, lies between those sides but lower, and keeps its own.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import foot_outline, method

from tests.vision_fixtures import room_size_errors


def test_the_colour_face_takes_the_edges_sides() -> None:
    eh, ew = room_size_errors("procedural", 2003, True)
    assert eh < 0.08 and ew < 0.05


def test_without_the_edges_sides_the_highlight_cuts_the_face(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # the width read from the foot's sides (session 37) finds this face by itself
    monkeypatch.setattr(foot_outline, "WIDTH_FROM_FOOT", False)
    monkeypatch.setattr(method, "RESCUE_TAKES_EDGE_SIDES", False)
    _, ew = room_size_errors("procedural", 2003, True)
    assert ew > 0.4


def test_the_slack_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # the width read from the foot's sides (session 37) finds this face by itself
    monkeypatch.setattr(foot_outline, "WIDTH_FROM_FOOT", False)
    # the colour face's right side is a column past the edges': no slack, not between
    monkeypatch.setattr(method, "RESCUE_SIDES_SLACK", 0)
    _, ew = room_size_errors("procedural", 2003, True)
    assert ew > 0.4


def test_a_colour_face_lower_than_the_outline_keeps_its_sides() -> None:
    eh, ew = room_size_errors("procedural", 312, True)
    assert eh < 0.05 and ew < 0.05


def test_the_top_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # 312's colour top lies 6 rows under the outline's: a limit of 6 takes its sides
    monkeypatch.setattr(method, "RESCUE_SAME_TOP_ROWS", 6)
    _, ew = room_size_errors("procedural", 312, True)
    assert ew > 0.25
