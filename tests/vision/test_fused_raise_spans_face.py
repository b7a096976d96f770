"""A raise past the inner edges must end on a line across the face
(``extent.RAISE_SPANS_FACE``, ``extent.raise_spans_face``, with the rig; session 41).

Photo 3020 (ordinary, with the rig; the set ``new``) is a seam face 0.25 m high with a
rocket of the face's grey photographed behind it in line with it. The search's seam pair
had the right top (row 228, its line over the whole pair); the seams and the rocket's
edges run on above it, and ``raise_top_past_inner_edges`` took the top to row 196, where
the rocket's edge stands over 48 % of the pair only (+43 % high before the rule): a raise
of 32 rows over a found face of 104. Procedural 108 (hard, with the rig; own) is a face
found as an 11-row piece (10 columns wide) whose sides run on 88 rows up: a raise eight
times the piece's height, left to the sides (``method.RAISE_SPAN_MAX_RAISE``; refused, the
answer went from 33 % to 85 % short).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import extent, foot_outline, method, region

from tests.vision_fixtures import room_size_errors


def _rocket_behind() -> float:
    eh, ew = room_size_errors("photo", 3020, False)
    assert ew < 0.05
    return eh


def test_the_raise_up_the_rocket_behind_is_refused() -> None:
    assert _rocket_behind() < 0.1


def test_without_the_rule_the_top_goes_up_the_rocket(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(extent, "RAISE_SPANS_FACE", False)
    assert _rocket_behind() > 0.25


@pytest.mark.parametrize(("short", "refused"), [(0.49, True), (0.47, False)])
def test_the_raised_line_short_of_the_face(
    monkeypatch: pytest.MonkeyPatch, short: float, refused: bool
) -> None:
    # the rocket's edge at the raised top stands over 0.48 of the pair
    monkeypatch.setattr(extent, "RAISE_SPAN_SHORT", short)
    assert (_rocket_behind() < 0.1) is refused


@pytest.mark.parametrize(("limit", "refused"), [(0.31, True), (0.30, False)])
def test_a_raise_under_the_found_height_is_judged(
    monkeypatch: pytest.MonkeyPatch, limit: float, refused: bool
) -> None:
    # photo 3020 o: a raise of 32 rows over a face of 104 (0.31 of its height)
    monkeypatch.setattr(method, "RAISE_SPAN_MAX_RAISE", limit)
    assert (_rocket_behind() < 0.1) is refused


def _small_piece() -> float:
    eh, _ = room_size_errors("procedural", 108, True)
    return eh


@pytest.mark.parametrize(("limit", "raised"), [(7.9, True), (8.0, False)])
def test_a_raise_past_a_small_piece_is_the_sides(
    monkeypatch: pytest.MonkeyPatch, limit: float, raised: bool
) -> None:
    # procedural 108 h: a raise of 88 rows over a piece of 11 (8.0 times its height)
    monkeypatch.setattr(method, "RAISE_SPAN_MAX_RAISE", limit)
    assert (_small_piece() < 0.5) is raised


def test_the_rule_alone_keeps_a_top_under_a_pole_in_line(monkeypatch: pytest.MonkeyPatch) -> None:
    # procedural 316 (own): a low box seen from above, a pole behind in line with its left
    # side; with the colour's guards off (test_fused_method.py), this rule keeps its top
    monkeypatch.setattr(region, "SHORT_RAISE", 0.0)
    monkeypatch.setattr(method, "lower_top_to_background", lambda *a: int(a[3]))
    monkeypatch.setattr(method, "lower_top_past_top_face", lambda *a: int(a[3]))
    assert room_size_errors("procedural", 316, False)[0] < 0.05
    monkeypatch.setattr(extent, "RAISE_SPANS_FACE", False)
    # (where the sides read from the foot end lowers it too: TOP_WHERE_SIDES_END, a backstop)
    monkeypatch.setattr(foot_outline, "TOP_WHERE_SIDES_END", False)
    assert room_size_errors("procedural", 316, False)[0] > 0.15


# a drawn |d/dy|: the found top's line at row 60 and a raised top's at row 30, the face's
# columns 20-120 (the rule reads the columns between, 21-119: 99 of them)
NOISE = 1.0
LEFT, RIGHT, TOP, RAISED = 20, 120, 60, 30


def _edges(top_cols: int, raised_cols: int) -> npt.NDArray[np.float32]:
    ay = np.zeros((100, 140), np.float32)
    ay[TOP, LEFT + 1 : LEFT + 1 + top_cols] = 20.0
    ay[RAISED, LEFT + 1 : LEFT + 1 + raised_cols] = 20.0
    return ay


def test_the_share_of_a_line() -> None:
    ay = _edges(99, 33)
    assert extent.top_line_share(ay, TOP, LEFT, RIGHT, NOISE) == pytest.approx(1.0)
    assert extent.top_line_share(ay, RAISED, LEFT, RIGHT, NOISE) == pytest.approx(1 / 3)
    # read within RAISE_SPAN_ROWS of the row (each row's line within EDGE_ROWS): the
    # snap's row may lie a row or two off
    reach = extent.RAISE_SPAN_ROWS + extent.EDGE_ROWS
    assert extent.top_line_share(ay, TOP + reach, LEFT, RIGHT, NOISE) == 1.0
    assert extent.top_line_share(ay, TOP + reach + 1, LEFT, RIGHT, NOISE) == 0.0


@pytest.mark.parametrize(("raised_cols", "stands"), [(49, False), (50, True)])
def test_the_raised_top_short_of_half_the_face(raised_cols: int, stands: bool) -> None:
    # RAISE_SPAN_SHORT 0.5: 49 of 99 columns is short of it, 50 is not
    ay = _edges(99, raised_cols)
    assert extent.raise_spans_face(ay, TOP, RAISED, LEFT, RIGHT, NOISE) is stands


@pytest.mark.parametrize(("top_cols", "stands"), [(80, False), (79, True)])
def test_the_found_top_must_span_the_face(top_cols: int, stands: bool) -> None:
    # RAISE_SPAN_HELD 0.8: 80 of 99 columns spans the face, 79 does not (a label's top:
    # the raise past it stands)
    ay = _edges(top_cols, 20)
    assert extent.raise_spans_face(ay, TOP, RAISED, LEFT, RIGHT, NOISE) is stands


def test_switched_off_every_raise_stands(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(extent, "RAISE_SPANS_FACE", False)
    assert extent.raise_spans_face(_edges(99, 20), TOP, RAISED, LEFT, RIGHT, NOISE)


def test_no_raise_stands() -> None:
    assert extent.raise_spans_face(_edges(99, 20), TOP, TOP, LEFT, RIGHT, NOISE)
