"""search.Sides' tables from the C accelerator (``_cmiddle.side_tables``) are the numpy
path's: values, dtypes and shapes, on random gradients, strided views, one column, the
frame's border columns (their outside columns clamped), one row and every row."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from obstacle_fusion.vision.fused import search

pytestmark = pytest.mark.skipif(search._c_side_tables is None, reason="no C accelerator")

_TABLES = ("upto", "below", "out", "nxt", "csum")


def _both(
    monkeypatch: pytest.MonkeyPatch, ax3: Any, cols: list[int], thr: Any, rb: int
) -> tuple[search.Sides, search.Sides]:
    c_tables = search._c_side_tables
    assert c_tables is not None
    answers: list[Any] = []

    def spy(*args: Any) -> Any:
        answers.append(c_tables(*args))
        return answers[-1]

    with monkeypatch.context() as m:
        m.setattr(search, "_c_side_tables", spy)
        in_c = search.Sides(ax3, cols, thr, rb)
    # the C call answered (None would mean it declined and numpy built both)
    assert len(answers) == 1 and isinstance(answers[0], list)
    with monkeypatch.context() as m:
        m.setattr(search, "_c_side_tables", None)
        in_numpy = search.Sides(ax3, cols, thr, rb)
    return in_c, in_numpy


def _same(a: search.Sides, b: search.Sides) -> None:
    for name in _TABLES:
        x, y = getattr(a, name), getattr(b, name)
        assert x.dtype == y.dtype and x.shape == y.shape, name
        assert np.array_equal(x, y), name
    assert np.array_equal(np.signbit(a.csum), np.signbit(b.csum))
    assert a.run_top == b.run_top and all(type(t) is int for t in a.run_top)
    assert (a.index, a.out_left, a.out_right) == (b.index, b.out_left, b.out_right)


@pytest.mark.parametrize("strided", [False, True])
def test_side_tables_match_numpy(monkeypatch: pytest.MonkeyPatch, strided: bool) -> None:
    for seed in range(300):
        rng = np.random.default_rng(seed)
        h, w = 1 + seed % 37, 1 + (seed * 11) % 50
        ax3 = rng.integers(0, 300, (h, w)).astype(np.int16)
        ax3[rng.random((h, w)) < 0.3] = 0
        if strided:
            wide = np.zeros((h, 2 * w), np.int16)
            wide[:, ::2] = ax3
            ax3 = wide[:, ::2]
        n = int(rng.integers(1, w + 1))
        cols = sorted({int(c) for c in rng.integers(0, w, n)} | ({0, w - 1} if seed % 3 else set()))
        thr = rng.uniform(-5.0, 250.0, len(cols))
        thr[::2] = np.round(thr[::2])  # whole thresholds: x > t exactly at the floor
        rb = int(rng.integers(1, h + 1))
        in_c, in_numpy = _both(monkeypatch, ax3, cols, thr, rb)
        _same(in_c, in_numpy)


def test_side_tables_edges(monkeypatch: pytest.MonkeyPatch) -> None:
    ax3 = np.arange(40, dtype=np.int16).reshape(8, 5)
    for cols in ([0], [4], [2], [0, 4], [0, 1, 2, 3, 4]):
        for rb in (1, 2, 3, 4, 8):
            thr = np.full(len(cols), 12.5)
            _same(*_both(monkeypatch, ax3, cols, thr, rb))


def test_side_tables_declines(monkeypatch: pytest.MonkeyPatch) -> None:
    """Outside columns and thresholds beyond int16: None, so Sides builds them in numpy."""
    ax3 = np.full((6, 5), 100, np.int16)
    assert search._c_side_tables is not None

    def call(cols: list[int], thr: Any, rb: int) -> list[int] | None:
        assert search._c_side_tables is not None
        k = len(cols)
        return search._c_side_tables(
            ax3,
            cols,
            thr,
            rb,
            np.empty((rb + 1, 3 * k + 1), np.int32),
            np.empty((rb, k), np.int32),
            np.empty((rb, k), np.intp),
            np.empty((rb + 1, k), np.float64),
        )

    assert call([5], np.array([1.0]), 6) is None
    assert call([-1], np.array([1.0]), 6) is None
    assert call([1], np.array([1e9]), 6) is None
    assert call([1], np.array([np.nan]), 6) is None
    assert call([1], np.array([1.0]), 7) is None
    assert call([1, 3], np.array([1.0, 200.0]), 6) == [0, 5]
    with pytest.raises(TypeError):
        call([1], np.array([1.0], np.float32), 6)
