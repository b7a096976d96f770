"""A gloss's ramp is read through the noise of its row means (``top.RAMP_GAPS``,
``RAMP_GAP_ROWS``, ``RAMP_RESUME_ROWS``): in :func:`.top.front_top` a peak whose
same-signed rows stay at half of it over RAMP_ROWS rows is a shading ramp, not a top face's
front edge; one row of a faint ramp falling under half of a peak that noise raised does
not end the ramp where it holds on beyond it.

Photo 2138 (ordinary, the fresh rooms), with the rig: a violet gloss box on gravel, its
highlight's upper flank a ramp of 4-7 a row over 15 rows under the top, one row at 1.2
under a bump of 7.0; the bump was taken for a top face's front edge, -19 % in height.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import top

from tests.vision_fixtures import room_size_errors


def test_the_highlight_s_flank_is_no_front_edge() -> None:
    eh, ew = room_size_errors("photo", 2138, False)
    assert eh < 0.03 and ew < 0.03


def test_without_the_rule_the_bump_on_the_ramp_is_taken(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(top, "RAMP_GAPS", False)
    eh, _ = room_size_errors("photo", 2138, False)
    assert eh > 0.15


# a peak of 8 at index 5, its own rows at half or more on either side
EDGE = [0.0, 0.0, 0.0, 1.0, 5.0, 8.0, 5.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]


def _with(i: int, values: list[float]) -> list[float]:
    prof = list(EDGE)
    prof[i : i + len(values)] = values
    return prof


def test_an_edge_s_blur_is_no_ramp() -> None:
    # three rows at half or more: an edge (RAMP_ROWS 5)
    assert not top._ramp(EDGE, 5)


def test_a_ramp_holding_on_past_one_row_under_half() -> None:
    # one row at 1.0, then two at half or more: the ramp goes on (3 + 1 + 2 rows)
    assert top._ramp(_with(7, [1.0, 4.0, 4.0]), 5)
    # ... either way up
    assert top._ramp([*reversed(_with(7, [1.0, 4.0, 4.0]))], 7)
    # ... through a row of the other sign too
    assert top._ramp(_with(7, [-1.0, 4.0, 4.0]), 5)


def test_the_switch_off_ends_the_ramp_at_the_gap(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(top, "RAMP_GAPS", False)
    assert not top._ramp(_with(7, [1.0, 4.0, 4.0]), 5)


def test_the_gap_rows_limit(monkeypatch: pytest.MonkeyPatch) -> None:
    two = _with(7, [1.0, 1.0, 4.0, 4.0])
    assert not top._ramp(two, 5)  # two rows under half: the edge ended there
    monkeypatch.setattr(top, "RAMP_GAP_ROWS", 2)
    assert top._ramp(two, 5)
    monkeypatch.setattr(top, "RAMP_GAP_ROWS", 0)
    assert not top._ramp(_with(7, [1.0, 4.0, 4.0]), 5)


def test_the_resume_rows_limit(monkeypatch: pytest.MonkeyPatch) -> None:
    once = _with(7, [1.0, 4.0, 1.0])
    assert not top._ramp(once, 5)  # one row of noise beyond the gap: no ramp resumes
    monkeypatch.setattr(top, "RAMP_RESUME_ROWS", 1)
    assert top._ramp(once, 5)
    monkeypatch.setattr(top, "RAMP_RESUME_ROWS", 3)
    assert not top._ramp(_with(7, [1.0, 4.0, 4.0]), 5)
    assert top._ramp(_with(7, [1.0, 4.0, 4.0, 4.0]), 5)


def test_half_the_peak_beyond_the_gap() -> None:
    assert top._ramp(_with(7, [1.0, 4.0, 4.0]), 5)
    assert not top._ramp(_with(7, [1.0, 3.9, 4.0]), 5)


def test_no_row_past_the_gap_stronger_than_the_peak() -> None:
    # procedural/752 hard with no rig: a front edge's run crossing one row into the top
    # edge's blur (stronger than the front edge) is no ramp
    assert not top._ramp(_with(7, [1.0, 8.1, 4.0]), 5)
    assert not top._ramp(_with(7, [1.0, 4.0, 8.1]), 5)
    assert top._ramp(_with(7, [1.0, 8.0, 4.0]), 5)
    # ... and rows further on past the gap count only up to the peak
    assert top._ramp(_with(7, [1.0, 4.0, 4.0, 4.0]), 5)
    assert not top._ramp([0.0] * 5 + [8.0, 1.0, 4.0, 4.0, 9.0] + [0.0] * 5, 5)


def test_no_gap_row_stronger_than_the_peak() -> None:
    # a row stronger than the peak ends the run: it is no gap a second crossing may use
    assert not top._ramp([0.0] * 5 + [8.0, 1.0, 4.0, 4.0, 9.0, 4.0, 4.0] + [0.0] * 5, 5)
    assert top._ramp([0.0] * 5 + [8.0, 1.0, 4.0, 4.0, 8.0, 4.0, 4.0] + [0.0] * 5, 5)


def test_the_room_whose_front_edge_run_meets_the_top_edge() -> None:
    # the top face's front edge (-62) one row of blur under the top edge (-75, -163)
    eh, _ = room_size_errors("procedural", 752, True, with_rig=False)
    assert eh < 0.06


def test_no_row_past_the_gap_on_the_top_edge_s_own() -> None:
    # new photo/3026 hard with no rig: a front edge (18.6) two rows under a top edge (18.4)
    # whose run crossed one row into the top edge's rows (prof[0] is the top's row)
    prof = [18.4, 17.5, 6.8, 11.4, 18.6, 9.5, -4.0, -6.9, -4.4, -5.6]
    assert not top._ramp(prof, 4)
    # the same rows further down are the ramp's once past the top's TAIL_ROWS (2) rows
    assert not top._ramp([0.0, 0.0, *prof], 6)
    assert top._ramp([0.0, 0.0, 0.0, *prof], 7)
    eh, _ = room_size_errors("photo", 3026, True, with_rig=False)
    assert eh < 0.02
