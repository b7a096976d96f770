"""search.line_columns in C (``_cmiddle.line_columns``) finds the numpy path's columns:
random strips with thin lines and steps, one row and many, strided views, columns at and
past the borders, duplicates, numpy integers, other widths beside the line."""

from __future__ import annotations

import numpy as np
import pytest
from obstacle_fusion.vision.fused import search

pytestmark = pytest.mark.skipif(search._c_line_columns is None, reason="no C accelerator")


def _numpy(monkeypatch: pytest.MonkeyPatch, strip: np.ndarray, cols: list[int]) -> set[int]:
    with monkeypatch.context() as m:
        m.setattr(search, "_c_line_columns", None)
        return search.line_columns(strip, cols)


@pytest.mark.parametrize("beside", [2, 3, 4, 5])
@pytest.mark.parametrize("strided", [False, True])
def test_line_columns_in_c_match_numpy(
    monkeypatch: pytest.MonkeyPatch, beside: int, strided: bool
) -> None:
    monkeypatch.setattr(search, "LINE_BESIDE", beside)
    rng = np.random.default_rng(beside)
    found = 0
    for _ in range(300):
        w = int(rng.integers(1, 80))
        rows = int(rng.integers(1, 30))
        base = rng.integers(0, 256, w)
        for c in rng.integers(0, w, 3):
            base[c : c + int(rng.integers(1, 4))] = rng.integers(0, 256)
        strip = np.clip(base + rng.integers(-6, 7, (rows, w)), 0, 255).astype(np.uint8)
        if strided:
            wide = np.zeros((rows, 2 * w), np.uint8)
            wide[:, ::2] = strip
            strip = wide[:, ::2]
        cols = rng.integers(-3, w + 3, int(rng.integers(1, 12))).tolist()
        cols += cols[:2]  # duplicates
        got = search.line_columns(strip, cols)
        assert got == _numpy(monkeypatch, strip, cols)
        found += len(got)
    assert found > 20  # the random strips do hold lines


def test_line_columns_in_c_edges(monkeypatch: pytest.MonkeyPatch) -> None:
    prof = np.full(20, 120, np.uint8)
    prof[9:11] = 60  # a dark seam at 9-10 on one shade
    strip = np.tile(prof, (1, 1))
    cols = [0, 9, 10, 19, 6, 13]
    assert search.line_columns(strip, cols) == _numpy(monkeypatch, strip, cols) == {9, 10}
    as_numpy = [np.int64(c) for c in cols]
    assert search.line_columns(strip, as_numpy) == {9, 10}  # type: ignore[arg-type]
    assert search.line_columns(strip[:0], cols) == set()
    assert search.line_columns(strip, []) == set()
    assert search.line_columns(strip[:, :5], [2]) == set()
