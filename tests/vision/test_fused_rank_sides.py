"""search._rank_sides in C (``_cmiddle.rank_sides``) gives the numpy path's lists, bit for
bit: random gradients and profiles, runs from the floor and late ones, ties, empty groups,
one column, the frame's border columns, a few rows, strided arrays."""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import search
from obstacle_fusion.vision.fused.tuning import MAX_SIDE_CANDIDATES, PRESENCE_CAP

pytestmark = pytest.mark.skipif(search._c_rank_sides is None, reason="no C accelerator")


def _c(
    ax3: Any, prof_v: Any, prof_short: Any, groups: Any, rb: int, noise: float, late: int
) -> list[list[int]] | None:
    assert search._c_rank_sides is not None
    return search._c_rank_sides(
        ax3,
        prof_v,
        prof_short,
        groups,
        rb,
        PRESENCE_CAP * noise,
        2.5 * noise,
        late,
        MAX_SIDE_CANDIDATES,
    )


def _case(seed: int, h: int, w: int, strided: bool = False, whole: bool = False) -> tuple[Any, ...]:
    """Gradients of a few strong columns whose edge runs up from the bottom, starts higher
    up (a late run) or breaks, over noise near the presence threshold. ``whole``: profiles
    of whole-number means (many ties, as the method's column means of a few rows)."""
    rng = np.random.default_rng(seed)
    noise = float(rng.uniform(0.5, 12.0))
    ax3 = rng.integers(0, int(4 * noise) + 2, (h, w)).astype(np.int16)
    for c in rng.integers(0, w, max(2, w // 6)):
        lo = int(rng.integers(0, h))
        hi = int(rng.integers(lo, h + 1))
        ax3[lo:hi, c] += rng.integers(20, 600, hi - lo).astype(np.int16)
    ax3[rng.random((h, w)) < 0.05] = 0  # gaps in the runs
    if whole:
        prof_v = rng.integers(0, 40, w).astype(np.float32)
    else:
        prof_v = (ax3.astype(np.float32).mean(axis=0) + rng.normal(0, 3, w)).astype(np.float32)
    prof_short = np.minimum(prof_v, rng.uniform(0, 200, w).astype(np.float32))
    peaks = np.sort(rng.choice(w, int(rng.integers(0, w + 1)), replace=False)).astype(np.intp)
    mid = int(rng.integers(0, w))
    groups = [peaks[peaks <= mid], peaks[peaks >= mid // 2]]
    rb = int(rng.integers(2, h + 2))
    late = int(rng.integers(0, h + 1))
    if strided:
        wide = np.zeros((h, 2 * w), np.int16)
        wide[:, ::2] = ax3
        ax3 = wide[:, ::2]
        wide_v = np.zeros(2 * w, np.float32)
        wide_v[::2] = prof_v
        prof_v = wide_v[::2]
    return ax3, prof_v, prof_short, groups, rb, noise, late


@pytest.mark.parametrize("strided", [False, True])
@pytest.mark.parametrize("whole", [False, True])
def test_rank_sides_matches_numpy(strided: bool, whole: bool) -> None:
    ranked = 0
    for seed in range(400):
        h = 2 + seed % 40
        w = 1 + (seed * 7) % 60
        args = _case(seed, h, w, strided, whole)
        got = _c(*args)
        want = search._rank_sides_numpy(*args)
        if got is not None:
            ranked += 1
            assert got == want, seed
        assert search._rank_sides(*args) == want, seed
    # the C path ranks most cases (it leaves only ties to numpy)
    assert ranked >= (120 if whole else 300)


def test_rank_sides_edges() -> None:
    ax3 = np.zeros((10, 5), np.int16)
    ax3[:, 0] = 100
    ax3[:, 4] = 90
    prof_v = np.array([10, 0, 0, 0, 9], np.float32)
    prof_short = prof_v.copy()
    empty = np.zeros(0, np.intp)
    border = np.array([0, 4], np.intp)
    one = np.array([4], np.intp)
    for groups in ([empty, empty], [border, empty], [one, border], [empty], [one]):
        for rb in (2, 3, 6, 11):
            args = (ax3, prof_v, prof_short, groups, rb, 1.0, 3)
            assert _c(*args) == search._rank_sides_numpy(*args), (groups, rb)
    got = _c(ax3, prof_v, prof_short, [border, one], 11, 1.0, 3)
    assert got == [[0, 4], [4]]


def test_rank_sides_late_runs_rank_below() -> None:
    """A column whose edge starts a few rows up ranks below one from the floor, though
    stronger: the same in C."""
    ax3 = np.zeros((30, 8), np.int16)
    ax3[:29, 2] = 50  # from the floor (row 28 up)
    ax3[10:25, 5] = 500  # starts 4 rows up
    prof_v = np.array([0, 0, 5, 0, 0, 80, 0, 0], np.float32)
    args = (ax3, prof_v, prof_v.copy(), [np.array([2, 5], np.intp)], 30, 1.0, 8)
    assert _c(*args) == search._rank_sides_numpy(*args) == [[2, 5]]
    assert _c(*args[:-1], 2) == search._rank_sides_numpy(*args[:-1], 2) == [[2]]


def test_rank_sides_leaves_ties_to_numpy() -> None:
    ax3 = np.full((12, 6), 100, np.int16)
    prof_v = np.array([0, 7, 7, 3, 0, 0], np.float32)
    g = [np.array([1, 2, 3], np.intp)]
    assert _c(ax3, prof_v, prof_v, g, 12, 1.0, 0) is None
    prof_v[2] = 6.5
    assert _c(ax3, prof_v, prof_v, g, 12, 1.0, 0) == [[1, 2, 3]]
    # equal strengths with runs of different lengths: distinct ranks, ranked in C
    prof_v[2] = 7.0
    ax3[5, 2] = ax3[4, 2] = ax3[3, 2] = 0
    got = _c(ax3, prof_v, prof_v, g, 12, 1.0, 0)
    assert got == search._rank_sides_numpy(ax3, prof_v, prof_v, g, 12, 1.0, 0) == [[1, 2, 3]]
    # equal strengths across the last of the 3 * MAX_SIDE_CANDIDATES places: numpy's
    many = 3 * MAX_SIDE_CANDIDATES
    wide = np.full((12, many + 2), 100, np.int16)
    prof = np.arange(many + 2, 0, -1).astype(np.float32)
    prof[many] = prof[many - 1]
    cols = [np.arange(many + 2, dtype=np.intp)]
    assert _c(wide, prof, prof, cols, 12, 1.0, 0) is None
    prof[many] -= 0.5
    assert _c(wide, prof, prof, cols, 12, 1.0, 0) == [[0, 1, 2][:MAX_SIDE_CANDIDATES]]


def test_rank_sides_outside_is_numpy() -> None:
    """Columns outside the arrays, or more rows than the gradients hold: None (numpy's)."""
    ax3 = np.full((12, 6), 100, np.int16)
    prof_v = np.arange(6, dtype=np.float32)
    for g in (np.array([-1, 2], np.intp), np.array([2, 6], np.intp)):
        assert _c(ax3, prof_v, prof_v, [g], 12, 1.0, 0) is None
    assert _c(ax3, prof_v, prof_v, [np.array([2], np.intp)], 14, 1.0, 0) is None
    assert _c(ax3, prof_v, prof_v, [np.array([2], np.intp)], 0, 1.0, 0) is None


def test_rank_sides_types() -> None:
    ax3 = np.zeros((4, 4), np.int16)
    prof: npt.NDArray[np.float32] = np.zeros(4, np.float32)
    with pytest.raises(TypeError):
        _c(ax3.astype(np.int32), prof, prof, [], 3, 1.0, 0)
    with pytest.raises(TypeError):
        _c(ax3, prof.astype(np.float64), prof, [], 3, 1.0, 0)
    with pytest.raises(TypeError):
        _c(ax3, prof, prof, [np.zeros(2, np.int32)], 3, 1.0, 0)


@pytest.mark.filterwarnings("ignore:invalid value encountered in cast")  # numpy's, on NaN
@pytest.mark.parametrize("profile", [1, 2])  # prof_v, prof_short
def test_a_nan_in_a_profile_is_left_to_numpy(profile: int) -> None:
    """A NaN never compares less, so C would order it unlike numpy's sort: it declines."""
    ax3 = np.zeros((12, 6), np.int16)
    ax3[:, [1, 2, 4]] = 300
    prof_v = np.array([5, 9, 7, 3, 8, 2], np.float32)
    prof_short = prof_v.copy()
    args: list[Any] = [ax3, prof_v, prof_short, [np.arange(6, dtype=np.intp)], 12, 2.0, 0]
    assert _c(*args) is not None  # finite: C ranks it
    args[profile] = args[profile].copy()
    args[profile][0] = np.nan
    assert _c(*args) is None
    assert search._rank_sides(*args) == search._rank_sides_numpy(*args)
