"""With no rig, an unsure answer (reported under CHECK_CONFIDENCE, unfloored) is checked
against readings as with a rig (``measure.FOOT_ROW_CHECK``, ``Measurer._foot_row_check``):
first the floor-contact rows below its foot, lowest first, where those readings agree on
another face (not the found outline with a lower foot, :func:`measure._same_outline`)
standing more than CHECK_NEARER_ROWS lower and at most CHECK_NEARER_WIDER times as wide;
else its own foot row, where they agree on a face on that foot (within CHECK_FOOT_ROWS)
whose height or width differs by over CHECK_RATIO times.

Photo 2046 (hard, a tuning room): the search took a face beside the box, its foot 19.3 rows
above the box's (reported sure 0.041, the agreed face 0.83 times as wide); the row below
reads the box (28.8 -> 1.4 % off). Photo 2060 (hard): the search read a piece 61 px wide on
the box's foot row; that row's readings agree on the box 2.69 times as wide, its foot 3.8
rows up (70.6 -> 19.6 % off). Photo 122 (hard) stays right: the rows below it stand a band
across the floor ten times as wide. Photo 2071 (hard) stays right: its foot row's readings
are 1.21 times as tall. Procedural 130 (ordinary) stays right: the row below reads its own
outline with its foot 12 rows lower (3.3 -> 10.6 % off if taken).
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision import measure

from tests.vision_fixtures import room_size_errors


def _off(family: str, seed: int, hard: bool) -> float:
    return max(room_size_errors(family, seed, hard, with_rig=False))


@pytest.fixture
def below(monkeypatch: pytest.MonkeyPatch) -> pytest.MonkeyPatch:
    """The rows below the answer's foot read too (CHECK_ROWS_BELOW, off by default: it
    moved a fresh answer from 8.5 to 45 % off)."""
    monkeypatch.setattr(measure, "CHECK_ROWS_BELOW", True)
    return monkeypatch


def test_a_face_beside_the_box_gives_way_to_the_box_on_a_lower_row(
    below: pytest.MonkeyPatch,
) -> None:
    assert _off("photo", 2046, True) < 0.05


def test_without_the_rows_below_the_face_beside_it_stays() -> None:
    assert _off("photo", 2046, True) > 0.25


@pytest.mark.parametrize(("limit", "fixed"), [(0.045, True), (0.04, False)])
def test_the_confidence_limit_decides(below: pytest.MonkeyPatch, limit: float, fixed: bool) -> None:
    # the found face's reported confidence, unfloored: 0.041
    below.setattr(measure, "CHECK_CONFIDENCE", limit)
    assert (_off("photo", 2046, True) < 0.05) is fixed


@pytest.mark.parametrize(("rows", "fixed"), [(19.0, True), (19.5, False)])
def test_the_nearer_rows_limit_decides(below: pytest.MonkeyPatch, rows: float, fixed: bool) -> None:
    # the box's foot stands 19.3 rows below the found face's
    below.setattr(measure, "CHECK_NEARER_ROWS", rows)
    assert (_off("photo", 2046, True) < 0.05) is fixed


@pytest.mark.parametrize(("wider", "fixed"), [(0.85, True), (0.8, False)])
def test_the_nearer_width_limit_decides(
    below: pytest.MonkeyPatch, wider: float, fixed: bool
) -> None:
    # the box is 0.83 times as wide as the found face
    below.setattr(measure, "CHECK_NEARER_WIDER", wider)
    assert (_off("photo", 2046, True) < 0.05) is fixed


def test_a_band_across_the_floor_below_is_not_taken(below: pytest.MonkeyPatch) -> None:
    assert _off("photo", 122, True) < 0.15


def test_without_the_width_limit_the_band_is_taken(below: pytest.MonkeyPatch) -> None:
    below.setattr(measure, "CHECK_NEARER_WIDER", 20.0)
    assert _off("photo", 122, True) > 1.0


def test_the_found_outline_with_a_lower_foot_is_not_taken(below: pytest.MonkeyPatch) -> None:
    assert _off("procedural", 130, False) < 0.05


def test_without_the_outline_check_the_lower_foot_is_taken(
    below: pytest.MonkeyPatch,
) -> None:
    below.setattr(measure, "_same_outline", lambda upper, lower: False)
    assert _off("procedural", 130, False) > 0.08


def test_a_piece_on_the_foot_row_gives_way_to_the_box() -> None:
    assert _off("photo", 2060, True) < 0.25


def test_without_the_rule_the_piece_stays(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "FOOT_ROW_CHECK", False)
    assert _off("photo", 2060, True) > 0.5


@pytest.mark.parametrize(("rows", "fixed"), [(4.0, True), (3.5, False)])
def test_the_foot_rows_limit_decides(
    monkeypatch: pytest.MonkeyPatch, rows: float, fixed: bool
) -> None:
    # the box's foot on that row stands 3.8 rows above the piece's
    monkeypatch.setattr(measure, "CHECK_FOOT_ROWS", rows)
    assert (_off("photo", 2060, True) < 0.25) is fixed


@pytest.mark.parametrize(("ratio", "fixed"), [(2.6, True), (2.75, False)])
def test_the_ratio_limit_decides(
    monkeypatch: pytest.MonkeyPatch, ratio: float, fixed: bool
) -> None:
    # the box reads 2.69 times as wide as the piece
    monkeypatch.setattr(measure, "CHECK_RATIO", ratio)
    assert (_off("photo", 2060, True) < 0.25) is fixed


@pytest.mark.parametrize(("ratio", "kept"), [(1.25, True), (1.2, False)])
def test_a_reading_a_little_taller_is_not_taken(
    monkeypatch: pytest.MonkeyPatch, ratio: float, kept: bool
) -> None:
    # photo 2071 hard: its foot row's readings agree on a face 1.21 times as tall
    monkeypatch.setattr(measure, "CHECK_RATIO", ratio)
    assert (_off("photo", 2071, True) < 0.05) is kept
