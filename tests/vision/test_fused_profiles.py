"""The fused method's fast array helpers give exactly what the numpy calls they replace give."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused.profiles import (
    NETWORK_LANES,
    NETWORK_MIN_VALUES,
    VerticalFits,
    column_means,
    first_gap,
    fit_vertical,
    grey_range_sums,
    median_of,
    median_u8,
    next_true,
    norm,
    range_sums,
    row_norms,
    share,
    walk_on,
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
    [
        ((9,), None),
        ((1, 40, 3), 0),
        ((4, 40, 3), 0),
        ((5, 40, 3), 0),
        ((9, 40, 3), 0),
        ((33, 10, 3), 1),
        ((12, 3), 0),
        ((3, 7), 0),
    ],
)
def test_median_u8_is_the_float_median(shape: tuple[int, ...], axis: int | None) -> None:
    rng = np.random.default_rng(shape[0])
    a = rng.integers(0, 256, shape, np.uint8)
    want = np.median(a.astype(np.float32), axis=axis)
    got = median_u8(a, axis)
    assert np.asarray(got).dtype == np.float32
    assert np.array_equal(got, want)


@pytest.mark.parametrize(("shape", "axis"), [((9,), None), ((33, 10, 3), 1), ((3, 7), 0)])
def test_median_u8_of_a_medians_half_values_keeps_the_halves(
    shape: tuple[int, ...], axis: int | None
) -> None:
    """Callers pass a median's float32 colours on (the mean of two middle 8-bit values:
    x.5 values); their median is the float median, not one of a 16-bit copy's."""
    rng = np.random.default_rng(shape[0])
    a = (rng.integers(0, 255, shape) + 0.5).astype(np.float32)
    assert np.array_equal(median_u8(a, axis), np.median(a, axis=axis))


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
    for args in (
        (np.arange(10, 109), [50, 140], 200),
        (np.arange(11, 110), [50, 140], 200),
        (rows, [50, 141], 200),
        (rows, [50], 200),
        (rows, [50, 140], 199),
    ):
        assert fits(*args) == fit_vertical(ax, *args)
        assert fits(*args) != first


def test_the_median_accelerator_is_built() -> None:
    """make setup builds the C accelerator; the tests fail (never skip) without it."""
    from obstacle_fusion.vision.fused import profiles

    assert profiles._c_middle_u8 is not None, "the C accelerator is not built (make setup)"


@pytest.mark.parametrize("n", range(2, NETWORK_LANES + 1))
@pytest.mark.parametrize("lanes", [1, 5, NETWORK_MIN_VALUES + 7])
def test_median_u8_in_c_is_numpy_s_median(
    n: int, lanes: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The accelerator's network gives the middles numpy's paths give (its selection
    network and its sort, both exact): few lanes and many, odd and even counts, ties,
    lanes along the first, a middle and the last axis, strided and reversed views."""
    from obstacle_fusion.vision.fused import profiles

    rng = np.random.default_rng(100 * n + lanes)
    a = rng.integers(0, 256, (n, lanes, 3), np.uint8)
    a[:, : lanes // 2] = rng.integers(100, 103, (n, lanes // 2, 3))  # many ties
    cases = [(a, 0), (a.transpose(1, 0, 2), 1), (np.ascontiguousarray(a.T), 2), (a[:, ::-2], 0)]
    cases += [(a[:, 0, 0], 0), (a[::-1, :, 1], 0), (a.transpose(1, 2, 0), -1), (a, -3)]
    for arr, axis in cases:
        got = median_u8(arr, axis)
        with monkeypatch.context() as m:
            m.setattr(profiles, "_c_median_f32", None)  # the C middles, then numpy's steps
            two_steps = median_u8(arr, axis)
            m.setattr(profiles, "_c_middle_u8", None)
            want = median_u8(arr, axis)
        assert type(got) is type(two_steps) and np.array_equal(got, two_steps)
        assert type(got) is type(want)
        assert np.asarray(got).dtype == np.float32
        assert np.array_equal(got, want)
        assert np.array_equal(got, np.median(arr.astype(np.float32), axis=axis))


@pytest.mark.parametrize("n", [NETWORK_LANES + 1, 18, 41, 100, 256, 257, 1500, 65535, 65536])
def test_median_u8_of_long_lanes_counted_in_c_is_numpy_s_median(
    n: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Lanes longer than a network are counted in C (an empty network): the middles
    numpy's sort gives, odd and even counts, ties, only 0s and 255s, all values alike,
    lanes along any axis, strided and reversed views, and the whole array (no axis)."""
    from obstacle_fusion.vision.fused import profiles

    calls: list[bytes] = []
    c_median = profiles._c_median_f32
    assert c_median is not None, "the C accelerator is not built (make setup)"

    def spied(src: object, axis: int, network: bytes, out: object) -> None:
        calls.append(network)
        c_median(src, axis, network, out)

    rng = np.random.default_rng(n)
    a = rng.integers(0, 256, (n, 7, 3), np.uint8)
    a[:, :2] = rng.integers(100, 103, (n, 2, 3))  # many ties
    a[:, 2, 0] = rng.choice(np.array([0, 255], np.uint8), n)  # the extremes only
    a[:, 3, 1] = 77  # one value all along
    cases: list[tuple[npt.NDArray[np.uint8], int | None]] = [
        (a, 0), (a.transpose(1, 0, 2), 1), (np.ascontiguousarray(a.T), 2), (a[::-1, ::2], 0),
        (a[:, 0, 0], 0), (a, None), (a[:, 1:5], None), (a.reshape(-1, 3), 0),
    ]  # fmt: skip
    for arr, axis in cases:
        calls.clear()
        monkeypatch.setattr(profiles, "_c_median_f32", spied)
        got = median_u8(arr, axis)
        assert calls == [b""], (arr.shape, axis)
        with monkeypatch.context() as m:
            m.setattr(profiles, "_c_median_f32", None)  # the C middles, then numpy's steps
            assert np.array_equal(median_u8(arr, axis), got), (arr.shape, axis)
            m.setattr(profiles, "_c_middle_u8", None)
            want = median_u8(arr, axis)
        assert type(got) is type(want)
        assert np.asarray(got).dtype == np.float32
        assert np.array_equal(got, want), (arr.shape, axis)
        assert np.array_equal(got, np.median(arr.astype(np.float32), axis=axis))


def test_median_u8_of_float_colours_takes_numpy_s_paths(monkeypatch: pytest.MonkeyPatch) -> None:
    """Callers pass medians on (float32 colours, enclose_by_margin): those take numpy's
    paths as without the accelerator (the sort's 16-bit lanes, the network's floats), not
    its 8-bit one."""
    from obstacle_fusion.vision.fused import profiles

    rng = np.random.default_rng(3)
    for lanes in (40, NETWORK_MIN_VALUES + 7):
        a = (rng.random((7, lanes, 3)) * 255).astype(np.float32)
        got = median_u8(a, 0)
        with monkeypatch.context() as m:
            m.setattr(profiles, "_c_middle_u8", None)
            want = median_u8(a, 0)
        assert np.array_equal(got, want)


def test_the_median_accelerator_refuses_what_it_cannot_read() -> None:
    from obstacle_fusion.vision.fused import _cmiddle
    from obstacle_fusion.vision.fused.profiles import _NETWORK_BYTES

    a = np.zeros((4, 3), np.uint8)
    lo, hi = np.empty(4, np.uint8), np.empty(4, np.uint8)
    _cmiddle.middle_u8(a, _NETWORK_BYTES[3], lo, hi)  # lanes of 3 along the last axis
    with pytest.raises(TypeError):
        _cmiddle.middle_u8(a.astype(np.int16), _NETWORK_BYTES[3], lo, hi)
    with pytest.raises(ValueError):
        _cmiddle.middle_u8(a, _NETWORK_BYTES[4], lo, hi)  # a comparator past the lane
    with pytest.raises(ValueError):
        _cmiddle.middle_u8(a, _NETWORK_BYTES[3], lo[:3], hi)  # an entry short
    with pytest.raises(ValueError):
        _cmiddle.middle_u8(a[:, :1], b"", lo, hi)  # lanes of one value
    out = np.empty(4, np.float32)
    _cmiddle.median_f32(a, 1, _NETWORK_BYTES[3], out)  # lanes of 3 along the last axis
    _cmiddle.median_f32(a.T, 0, b"", out)  # ... along the first, counted
    with pytest.raises(TypeError):
        _cmiddle.median_f32(a, 1, _NETWORK_BYTES[3], out.astype(np.float64))
    with pytest.raises(TypeError):
        _cmiddle.median_f32(a.astype(np.int16), 1, b"", out)
    with pytest.raises(ValueError):
        _cmiddle.median_f32(a, 2, b"", out)  # no such axis
    with pytest.raises(ValueError):
        _cmiddle.median_f32(a, 1, _NETWORK_BYTES[4], out)  # a comparator past the lane
    with pytest.raises(ValueError):
        _cmiddle.median_f32(a, 1, b"", out[:3])  # an entry short
    with pytest.raises(ValueError):
        _cmiddle.median_f32(a[:, :1], 1, b"", out)  # lanes of one value


def test_walk_on_in_c_is_the_python_walk(monkeypatch: pytest.MonkeyPatch) -> None:
    """The accelerator's walk ends where profiles' Python loop does: lists of bools or
    ints, bool arrays (reversed views too), uint8 and float arrays, starts outside the
    flags, steps both ways and longer than one, every gap limit."""
    from obstacle_fusion.vision.fused import profiles

    assert profiles._c_walk_on is not None, "the C accelerator is not built (make setup)"
    rng = np.random.default_rng(7)
    for _ in range(400):
        n = int(rng.integers(0, 50))
        flags = rng.random(n) < rng.random()
        start, step = int(rng.integers(-2, n + 2)), int(rng.choice([-2, -1, 1, 3]))
        gap = int(rng.integers(0, 5))
        kinds = (
            flags.tolist(),
            [int(f) for f in flags],
            flags,
            flags[::-1],
            flags.astype(np.uint8),
        )
        for on in (*kinds, flags.astype(float)):
            got = profiles.walk_on(on, start, step, gap)
            with monkeypatch.context() as m:
                m.setattr(profiles, "_c_walk_on", None)
                want = profiles.walk_on(on, start, step, gap)
            assert got == want and type(got) is int


def test_walk_on_in_c_leaves_a_standing_walk_to_python() -> None:
    """A step of 0 is walked in Python (here: stopped by the gap limit on a false flag)."""
    from obstacle_fusion.vision.fused import _cmiddle

    assert _cmiddle.walk_on([True, False, True], 1, 0, 2) is None
    assert walk_on([True, False, True], 1, 0, 2) == 1
    with pytest.raises(TypeError):
        walk_on(5, 0, 1, 2)  # type: ignore[arg-type]


def test_first_gap_in_c_is_numpy_s(monkeypatch: pytest.MonkeyPatch) -> None:
    """The accelerator's search down the columns gives numpy's rows: 1 to 2 rows (the
    first miss) and more (the first of 3 misses), none (the row count), reversed and
    strided views; no rows at all stay numpy's error."""
    from obstacle_fusion.vision.fused import profiles

    assert profiles._c_first_gap is not None, "the C accelerator is not built (make setup)"
    rng = np.random.default_rng(11)
    for _ in range(300):
        rows, cols = int(rng.integers(1, 25)), int(rng.integers(0, 9))
        on = rng.random((rows, cols)) < rng.random()
        for view in (on, on[::-1], on[:, ::-1], on[::2]):
            got = first_gap(view)
            with monkeypatch.context() as m:
                m.setattr(profiles, "_c_first_gap", None)
                want = first_gap(view)
            assert got.dtype == want.dtype and np.array_equal(got, want)
    with pytest.raises(ValueError):
        first_gap(np.zeros((0, 3), bool))


def test_next_true_in_c_is_numpy_s(monkeypatch: pytest.MonkeyPatch) -> None:
    """The accelerator's running minimum up the columns gives numpy's rows (rb where no
    flag holds at or below), on reversed and strided views; a row count other than the
    flags' stays numpy's error."""
    from obstacle_fusion.vision.fused import profiles

    assert profiles._c_next_true is not None, "the C accelerator is not built (make setup)"
    rng = np.random.default_rng(12)
    for _ in range(300):
        rows, cols = int(rng.integers(1, 25)), int(rng.integers(0, 9))
        flags = rng.random((rows, cols)) < rng.random()
        for view in (flags, flags[::-1], flags[:, ::-1], flags[::2]):
            got = next_true(view, view.shape[0])
            with monkeypatch.context() as m:
                m.setattr(profiles, "_c_next_true", None)
                want = next_true(view, view.shape[0])
            assert got.dtype == want.dtype and np.array_equal(got, want)
            idx = np.where(view, np.arange(view.shape[0])[:, None], view.shape[0])
            assert np.array_equal(got, np.minimum.accumulate(idx[::-1], axis=0)[::-1])
    with pytest.raises(ValueError):
        next_true(np.zeros((4, 3), bool), 5)


@pytest.mark.filterwarnings("ignore:overflow:RuntimeWarning")  # numpy's, on the 1e30s
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_row_norms_in_c_are_numpy_s(dtype: type, monkeypatch: pytest.MonkeyPatch) -> None:
    """The accelerator's norms are numpy's bit for bit: rows of 1 to 7 values (squares
    added from the left, as numpy's reduce under 8 values), no rows and one, strided and
    reversed views, zeros, huge and tiny values, inf and NaN; 8 values and more, other
    types and other shapes are numpy's own (the same function, another path)."""
    from obstacle_fusion.vision.fused import _cmiddle, profiles

    assert profiles._c_row_norms is not None, "the C accelerator is not built (make setup)"
    rng = np.random.default_rng(21)
    scales = [1e-30, 1e-3, 1.0, 255.0, 1e4, 1e30]
    for n in (0, 1, 2, 5, 300):
        for k in range(1, 10):
            a = rng.standard_normal((n, k + 2)) * rng.choice(scales, (n, k + 2))
            a = a.astype(dtype)
            if n:
                a[0, 1] = np.inf if k % 2 else np.nan
                a[-1] = 0.0
            for x in (a[:, 1 : 1 + k], a[::-1, :k], a[::2, -k:], np.ascontiguousarray(a[:, :k])):
                got = row_norms(x)
                with monkeypatch.context() as m:
                    m.setattr(profiles, "_c_row_norms", None)
                    want = row_norms(x)
                assert got.dtype == want.dtype and got.shape == want.shape
                assert np.array_equal(got, want, equal_nan=True)
                assert np.array_equal(got, np.linalg.norm(x, axis=1), equal_nan=True) or k >= 8
    for other in (np.ones((4, 3), np.float16), np.ones((4, 3), np.int32), np.ones((2, 4, 3))):
        with monkeypatch.context() as m:
            m.setattr(profiles, "_c_row_norms", None)
            want = row_norms(other)
        got = row_norms(other)
        assert got.dtype == want.dtype and np.array_equal(got, want)
    out = np.empty(4, np.float32)
    _cmiddle.row_norms(np.ones((4, 3), np.float32), out)
    assert np.array_equal(out, np.full(4, np.sqrt(np.float32(3.0))))
    with pytest.raises(TypeError):
        _cmiddle.row_norms(np.ones((4, 3), np.float32), np.empty(4, np.float64))  # its type
    with pytest.raises(TypeError):
        _cmiddle.row_norms(np.ones((4, 3), np.float32), out[:3])  # an entry short
    with pytest.raises(TypeError):
        _cmiddle.row_norms(np.ones((4, 8), np.float32), out)  # 8 values: numpy's pairwise sum
    with pytest.raises(TypeError):
        _cmiddle.row_norms(np.ones((4, 0), np.float32), out)  # none
    with pytest.raises(TypeError):
        _cmiddle.row_norms(np.ones(4, np.float32), out)  # 1-D
