"""score_pairs' top candidates and their features in C (``_cmiddle.score_tops``) are the
numpy path's, bit for bit: random gradients, grey rows and pairs, edge sizes included."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import scoring
from obstacle_fusion.vision.fused.search import Sides


def _frame(
    rng: np.random.Generator, h: int, w: int, strided: bool
) -> tuple[npt.NDArray[np.uint8], npt.NDArray[np.int16], npt.NDArray[np.float32]]:
    """A grey frame of a few shades (face, wall, floor rows) with noise, and integer
    gradients as the method's: |d/dx| int16 with a few strong columns, |d/dy| float32
    with a few strong rows. ``strided``: views every other column of wider arrays."""
    grey = np.clip(
        rng.choice([40.0, 90.0, 150.0], size=(h, 1)) + rng.normal(0, 6, (h, w)), 0, 255
    ).astype(np.uint8)
    ax3 = rng.integers(0, 60, (h, w)).astype(np.int16)
    ax3[:, rng.integers(0, w, 4)] += rng.integers(100, 900, (h, 4)).astype(np.int16)
    ay = rng.integers(0, 40, (h, w)).astype(np.float32)
    ay[rng.integers(0, h, 6)] += rng.integers(50, 1000, (6, w)).astype(np.float32)
    if strided:
        wide_grey = np.zeros((h, 2 * w), np.uint8)
        wide_grey[:, ::2] = grey
        grey = wide_grey[:, ::2]
        wide_ay = np.zeros((h, 2 * w), np.float32)
        wide_ay[:, ::2] = ay
        wide_ax = np.zeros((h, 2 * w), np.int16)
        wide_ax[:, ::2] = ax3
        return grey, wide_ax[:, ::2], wide_ay[:, ::2]
    return grey, ax3, ay


def _case(seed: int, h: int, w: int, n_cols: int, strided: bool = False) -> tuple[Any, ...]:
    rng = np.random.default_rng(seed)
    grey, ax3, ay = _frame(rng, h, w, strided)
    rb = int(rng.integers(max(8, h // 2), h - 1))
    cols = sorted({int(c) for c in rng.integers(0, w, n_cols)} | {0, w - 1})
    thresholds = rng.uniform(5.0, 200.0, len(cols))
    sides = Sides(ax3, cols, thresholds, rb)
    pairs = [(a, b) for a in cols for b in cols if b - a >= 4][:12]
    noise = float(rng.uniform(0.5, 12.0))
    return grey, ax3, ay, sides, pairs, noise, rb


def _both(
    grey: Any, ax3: Any, ay: Any, sides: Any, pairs: Any, noise: float, rb: int, min_h: int
) -> tuple[Any, Any]:
    top_limit = rb - min_h
    ps = []
    for ul, ur in pairs:
        m = max(1, (ur - ul) // 8)
        if ur - ul - 2 * m >= 2:
            ps.append((ul, ur, ul + m, ur - m))
    at = [(sides.index[p[0]], sides.index[p[1]]) for p in ps]
    args = (grey, ax3, ay, sides, ps, at, noise, rb, top_limit, min_h)
    return scoring._tops_in_c(*args), scoring._tops_in_numpy(*args)


def _same(c: Any, n: Any) -> None:
    if n is None:
        assert c is None
        return
    assert c is not None
    assert np.array_equal(c[0], n[0]) and np.array_equal(c[1], n[1])
    assert set(c[2]) == set(n[2])
    for key, want in n[2].items():
        got = c[2][key]
        assert got.dtype == want.dtype, key
        assert np.array_equal(got, want), key
        assert np.array_equal(np.signbit(got), np.signbit(want)), key


needs_c = pytest.mark.skipif(
    scoring._c_score_tops is None, reason="the C accelerator is not built (make setup)"
)


@needs_c
@pytest.mark.parametrize("seed", range(40))
def test_score_tops_in_c_is_the_numpy_path(seed: int) -> None:
    rng = np.random.default_rng(1000 + seed)
    h, w = int(rng.integers(20, 160)), int(rng.integers(8, 220))
    case = _case(seed, h, w, int(rng.integers(1, 10)), strided=seed % 3 == 0)
    grey, ax3, ay, sides, pairs, noise, rb = case
    for min_h in (3, 4, 7, max(3, rb - 3), 16):
        if rb - min_h >= 3:
            _same(*_both(grey, ax3, ay, sides, pairs, noise, rb, min_h))


@needs_c
@pytest.mark.parametrize("w", [5, 6, 9])
def test_score_tops_in_c_on_the_narrowest_pairs(w: int) -> None:
    """Pairs of the fewest columns (two inner ones), at both image borders, and the
    fewest rows a top is looked for in (top_limit 3)."""
    rng = np.random.default_rng(w)
    grey, ax3, ay = _frame(rng, 12, w, False)
    rb = 10
    sides = Sides(ax3, list(range(w)), rng.uniform(5.0, 50.0, w), rb)
    pairs = [(0, 4), (w - 5, w - 1), (0, w - 1)]
    for min_h in (3, 4, 7):
        _same(*_both(grey, ax3, ay, sides, pairs, 2.0, rb, min_h))


@needs_c
def test_score_pairs_with_and_without_c(monkeypatch: pytest.MonkeyPatch) -> None:
    view = SimpleNamespace(fy=400.0, cy=60.0, cx=100.0)
    for seed in range(12):
        grey, ax3, ay, sides, pairs, noise, rb = _case(seed, 140, 200, 8)
        args = (view, 1.0, grey, ax3, ay, sides, pairs, noise, rb, 0.9)
        with_c = scoring.score_pairs(*args)  # type: ignore[arg-type]
        with monkeypatch.context() as m:
            m.setattr(scoring, "_c_score_tops", None)
            without_c = scoring.score_pairs(*args)  # type: ignore[arg-type]
        assert with_c == without_c


@needs_c
def test_score_tops_refuses_what_it_cannot_take() -> None:
    from obstacle_fusion.vision.fused import _cmiddle

    grey, ax3, ay, sides, pairs, noise, rb = _case(3, 60, 80, 6)
    pair = np.array([[0, 40, 5, 35, 0, 1, 10, 10, 0, 0]], np.intp)
    cap = 2 * rb

    def call(**change: Any) -> Any:
        a: dict[str, Any] = dict(
            ay=ay,
            ax3=ax3,
            counts=sides.out,
            nxt=sides.nxt,
            grey=grey,
            pairs=pair,
            bands=4,
            noise=noise,
            rb=rb,
            top_limit=rb - 5,
            kf=2,
            label_rows=3,
            label_share=0.35,
            tops=np.empty(cap, np.intp),
            pp=np.empty(cap, np.intp),
            f64=np.empty((8, cap)),
            f32=np.empty((2, cap), np.float32),
            i32=np.empty((2, cap), np.int32),
        )
        a.update(change)
        return _cmiddle.score_tops(*a.values())

    assert call() >= 0
    with pytest.raises(TypeError):
        call(ay=ay.astype(np.float64))
    with pytest.raises(TypeError):
        call(ax3=ax3.astype(np.int32))
    with pytest.raises(TypeError):
        call(grey=grey.astype(np.int16))
    with pytest.raises(ValueError):
        call(grey=grey[: rb - 1])  # rows short of rb
    with pytest.raises(ValueError):
        call(bands=0)
    with pytest.raises(ValueError):
        call(tops=np.empty(3, np.intp), pp=np.empty(3, np.intp))  # no room for the tops
    with pytest.raises(ValueError):
        call(pairs=np.array([[0, 400, 5, 35, 0, 1, 10, 10, 0, 0]], np.intp))  # past the image
    with pytest.raises(ValueError):
        call(pairs=np.array([[0, 40, 5, 35, 0, 99, 10, 10, 0, 0]], np.intp))  # no such side
    with pytest.raises(ValueError):
        call(top_limit=2)
    with pytest.raises(ValueError):
        call(pairs=pair[:0])  # no pair
