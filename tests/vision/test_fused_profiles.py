"""The fused method's fast array helpers give exactly what the numpy calls they replace give."""

from __future__ import annotations

import numpy as np
import pytest
from obstacle_fusion.vision.fused.profiles import (
    NETWORK_LANES,
    NETWORK_MIN_VALUES,
    VerticalFits,
    column_means,
    fit_vertical,
    grey_range_sums,
    median_of,
    median_u8,
    norm,
    range_sums,
    row_norms,
    share,
)
from obstacle_fusion.vision.fused.scoring import band_ranges


@pytest.mark.parametrize(
    ("shape", "axis"),
    [
        ((7,), None),
        ((8,), None),
        ((4, 50, 3), 0),
        ((9, 50, 3), 0),
        ((31, 12, 3), 1),
        ((30, 6, 3), 1),
        ((10, 3), 0),
        ((5, 6), None),
    ],
)
def test_median_of_is_numpys_median(shape: tuple[int, ...], axis: int | None) -> None:
    rng = np.random.default_rng(len(shape) * 10 + (axis or 0) + shape[0])
    a = (rng.random(shape) * 255).astype(np.float32)
    a.flat[::5] = np.round(a.flat[::5])  # ties too
    before = a.copy()
    got, want = median_of(a, axis), np.median(a, axis=axis)
    assert np.asarray(got).dtype == np.asarray(want).dtype
    assert np.array_equal(got, want)
    assert np.array_equal(a, before)  # the input is not sorted in place


def test_band_ranges_round_half_to_even_as_python() -> None:
    ps = [(0, 0, 10, 12), (0, 0, 3, 9), (0, 0, 20, 41), (0, 0, 5, 7)]
    want = []
    for _, _, c0, c1 in ps:
        cuts = [c0 + round(b * (c1 - c0) / 4) for b in range(5)]
        want += [(cuts[b], max(cuts[b + 1], cuts[b] + 1)) for b in range(4)]
    assert band_ranges(ps).tolist() == [list(r) for r in want]


def test_grey_range_sums_match_plain_sums() -> None:
    rng = np.random.default_rng(3)
    grey = rng.integers(0, 256, (40, 60), np.uint8)
    ranges = [(3, 9), (10, 11), (0, 60), (25, 41)]
    want = range_sums(grey.astype(np.float32), ranges)
    assert np.array_equal(grey_range_sums(grey, ranges), want)
    assert np.array_equal(grey_range_sums(grey, np.array(ranges)), want)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_norms_are_numpys(dtype: type) -> None:
    rng = np.random.default_rng(4)
    x = ((rng.random((200, 3)) - 0.5) * 300).astype(dtype)
    want = np.linalg.norm(x, axis=1)
    assert row_norms(x).dtype == want.dtype
    assert np.array_equal(row_norms(x), want)
    assert all(norm(v) == float(np.linalg.norm(v)) for v in x)


def test_column_means_and_share_are_numpys() -> None:
    rng = np.random.default_rng(5)
    for rows in (1, 7, 130):
        a = rng.integers(0, 1021, (rows, 97)).astype(np.int16)
        want = np.asarray(a.mean(axis=0), np.float32)
        assert np.array_equal(column_means(a), want)
        assert np.array_equal(column_means(a[:, 10:17]), want[10:17])
        flags = a[:, 0] > 500
        assert share(flags) == float(flags.mean())


@pytest.mark.parametrize(
    ("shape", "axis"),
    [((9,), None), ((1, 40, 3), 0), ((4, 40, 3), 0), ((5, 40, 3), 0), ((9, 40, 3), 0),
     ((33, 10, 3), 1), ((12, 3), 0), ((3, 7), 0)],
)
def test_median_u8_is_the_float_median(shape: tuple[int, ...], axis: int | None) -> None:
    rng = np.random.default_rng(shape[0])
    a = rng.integers(0, 256, shape, np.uint8)
    want = np.median(a.astype(np.float32), axis=axis)
    got = median_u8(a, axis)
    assert np.asarray(got).dtype == np.float32
    assert np.array_equal(got, want)


def test_empty_blocks_give_numpy_s_answers_not_a_crash() -> None:
    """OpenCV's reduce and sort crash on empty blocks; a face at a tiny frame's top edge
    asked for the column means of no rows (seen as a segfault on a 40x30 frame)."""
    from obstacle_fusion.vision.fused.profiles import column_means, median_u8

    assert column_means(np.zeros((0, 7), np.int16)).tolist() == [0.0] * 7
    assert column_means(np.zeros((3, 0), np.int16)).shape == (0,)
    empty = np.zeros((3, 0, 3), np.uint8)
    assert median_u8(empty, axis=0).shape == (0, 3)


@pytest.mark.parametrize("n", range(2, NETWORK_LANES + 1))
def test_median_u8_by_network_is_the_float_median(n: int) -> None:
    """Many short lanes take the selection network: every lane's middle exactly, odd and
    even counts, along the first axis and along a middle one (strided lanes), ties too."""
    rng = np.random.default_rng(n)
    lanes = NETWORK_MIN_VALUES + 7
    a = rng.integers(0, 256, (n, lanes, 3), np.uint8)
    a[:, :40] = rng.integers(100, 103, (n, 40, 3))  # many ties
    b = np.ascontiguousarray(a.transpose(1, 0, 2))  # lanes along axis 1
    for arr, axis in ((a, 0), (b, 1), (a[:, ::2], 0)):
        want = np.median(arr.astype(np.float32), axis=axis)
        got = median_u8(arr, axis)
        assert got.dtype == np.float32
        assert np.array_equal(got, want)


def test_vertical_fits_are_fit_vertical_once_per_rows_and_columns() -> None:
    rng = np.random.default_rng(9)
    ax = rng.integers(0, 60, (120, 200)).astype(np.int16)
    ax[:, 50] += 400  # two vertical edges, one leaning
    ax[np.arange(120), 140 + np.arange(120) // 40] += 400
    fits = VerticalFits(ax)
    rows = np.arange(10, 110)
    first = fits(rows, [50, 140], 200)
    assert first == fit_vertical(ax, rows, [50, 140], 200)
    ax[:, 140:150] = 0  # a second call with the same rows and columns is the first fit
    assert fits(rows, [50, 140], 200) == first
    # other rows, columns or width are fitted anew (on the changed image)
    for args in ((np.arange(10, 109), [50, 140], 200), (np.arange(11, 110), [50, 140], 200),
                 (rows, [50, 141], 200), (rows, [50], 200), (rows, [50, 140], 199)):
        assert fits(*args) == fit_vertical(ax, *args)
        assert fits(*args) != first
