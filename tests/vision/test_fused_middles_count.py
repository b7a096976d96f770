"""The C accelerator's medians (``_cmiddle.median_f32`` and ``middle_u8``) against numpy's.

Session 37 reworked two inner parts of its ``middles``: the lanes' offsets (the innermost
of the other axes in a plain loop) and the counting path's search for the 16-value block
holding the middles (SSE2 sums of the two count tables). These tests compare both with
numpy's float32 median (and sort) on random arrays of 1 to 4 dimensions along every axis,
strided, transposed and reversed views, lanes of one column, and values packed at the
blocks' borders (0, 15/16, 239/240, 255) and at the count tables' 16-bit limit."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused.profiles import _NETWORK_BYTES, NETWORK_LANES

_cmiddle = pytest.importorskip("obstacle_fusion.vision.fused._cmiddle")


def _c_median(a: npt.NDArray[np.uint8], axis: int, network: bytes) -> npt.NDArray[np.float32]:
    out = np.empty(a.shape[:axis] + a.shape[axis + 1 :], np.float32)
    _cmiddle.median_f32(a, axis, network, out)
    return out


def _views(rng: np.random.Generator, shape: tuple[int, ...]) -> list[npt.NDArray[np.uint8]]:
    a = rng.integers(0, 256, shape, np.uint8)
    views = [a, a[::-1], a.T, np.ascontiguousarray(a.T)]
    if a.ndim >= 2:
        views += [a[:, ::2], a[:, :1], a[::2, ::-1]]
    if a.ndim == 3:  # the two outer axes continue each other across the middle one
        views += [a.transpose(0, 2, 1), a.transpose(2, 0, 1)]
    return views


@pytest.mark.parametrize(
    "shape",
    [(2,), (17,), (300,), (2, 1), (1, 40), (40, 1), (33, 7), (5, 120, 3), (40, 6, 3),
     (3, 4, 5, 6), (18, 1, 3), (1, 19, 1), (4, 6, 5), (30, 20, 3)],
)  # fmt: skip
def test_counted_and_network_medians_are_numpy_s(shape: tuple[int, ...]) -> None:
    rng = np.random.default_rng(sum(shape) * 31 + len(shape))
    for a in _views(rng, shape):
        for axis in range(a.ndim):
            n = a.shape[axis]
            if n < 2 or 0 in a.shape:
                continue
            want = np.median(a.astype(np.float32), axis=axis)
            got = _c_median(a, axis, b"")  # counted
            assert np.array_equal(got, want), (a.shape, a.strides, axis)
            if n <= NETWORK_LANES:  # by the network
                got = _c_median(a, axis, _NETWORK_BYTES[n])
                assert np.array_equal(got, want), (a.shape, a.strides, axis)
            # middle_u8 along the last axis: the two middles of numpy's sort
            lanes = np.moveaxis(a, axis, -1)
            lo = np.empty(lanes.shape[:-1], np.uint8)
            hi = np.empty(lanes.shape[:-1], np.uint8)
            _cmiddle.middle_u8(lanes, b"", lo, hi)
            s = np.sort(lanes, axis=-1)
            assert np.array_equal(lo, s[..., n // 2 - 1]) and np.array_equal(hi, s[..., n // 2])


@pytest.mark.parametrize("centre", [0, 1, 15, 16, 17, 127, 128, 239, 240, 241, 254, 255])
def test_counted_medians_at_the_blocks_borders(centre: int) -> None:
    """Values gathered round a 16-value block's border: the block search stops in the
    right block (or runs on to the last, value by value)."""
    rng = np.random.default_rng(centre)
    for n in (18, 19, 64, 65, 501):
        a = np.clip(centre + rng.integers(-2, 3, (n, 9)), 0, 255).astype(np.uint8)
        a[:, 0] = centre  # one value all along
        a[: n // 2, 1] = 0  # half the lane at each end
        a[n // 2 :, 1] = 255
        want = np.median(a.astype(np.float32), axis=0)
        assert np.array_equal(_c_median(a, 0, b""), want), (centre, n)


@pytest.mark.parametrize("value", [0, 200, 255])
def test_counted_medians_at_the_16_bit_limit(value: int) -> None:
    """65535 values in one lane fill a 16-bit count (the longest lane the two tables
    take: their block sums must not wrap); 65536 take the other path."""
    for n in (65535, 65536):
        a = np.full((n, 2), value, np.uint8)
        a[: n // 3, 1] = 255 - value
        want = np.median(a.astype(np.float32), axis=0)
        assert np.array_equal(_c_median(a, 0, b""), want), (value, n)
        assert np.array_equal(_c_median(np.ascontiguousarray(a.T), 1, b""), want)


def _partitioned_kth(a: npt.NDArray[np.float32], k: int) -> float:
    flat = a.flatten()
    flat.partition(k)
    return float(flat[k])


@pytest.mark.parametrize(
    "shape", [(1,), (2,), (1023,), (4096,), (1, 1), (1, 300), (300, 1), (94, 125), (375, 500)]
)
def test_kth_counted_is_the_partition_s_value(shape: tuple[int, ...]) -> None:
    """Whole float32 values 0..1023 (the frame's |d/dy|): the value a partition leaves
    at k, for every k at the ends and the middle, on the array and strided, reversed and
    transposed views of it, one row or column too."""
    rng = np.random.default_rng(sum(shape))
    a = rng.integers(0, 1024, shape).astype(np.float32)
    if a.size > 4:
        a.flat[:3] = (0.0, 1023.0, 1022.0)  # the table's ends
    views = [a, a[::-1]]
    if a.ndim == 2:
        views += [a[::4, ::4], a.T, a[:, :1], a[:1], a[::-3, 1::2]]
    for v in views:
        if v.size == 0:
            continue
        for k in {0, 1 % v.size, v.size // 2, v.size - 1}:
            assert _cmiddle.kth_counted(v, k) == _partitioned_kth(v, k), (v.shape, k)


def test_kth_counted_leaves_what_it_cannot_count_to_the_partition() -> None:
    """None (the caller partitions) for a value past 1023, a fraction, a negative value,
    negative zero and NaN, and for a k outside the array (an empty one too); a type error
    for other types and 3-D arrays."""
    a = np.arange(64, dtype=np.float32).reshape(8, 8)
    assert _cmiddle.kth_counted(a, 32) == 32.0
    for bad in (1024.0, 0.5, -1.0, -0.0, np.nan, np.inf):
        b = a.copy()
        b[5, 6] = bad
        assert _cmiddle.kth_counted(b, 32) is None, bad
    assert _cmiddle.kth_counted(a, 64) is None and _cmiddle.kth_counted(a, -1) is None
    assert _cmiddle.kth_counted(np.empty(0, np.float32), 0) is None
    with pytest.raises(TypeError):
        _cmiddle.kth_counted(a.astype(np.float64), 3)
    with pytest.raises(TypeError):
        _cmiddle.kth_counted(a.reshape(4, 4, 4), 3)


def test_median_counts_large_whole_arrays_and_partitions_the_rest(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """profiles.median offers arrays of COUNTED_MEDIAN_MIN values and more to the count
    (just at the limit: counted; one value fewer: partitioned), and takes the partition's
    value where the count refuses (fractions): the same medians either way."""
    from obstacle_fusion.vision.fused import profiles

    counted = profiles._c_kth_counted
    assert counted is not None, "the C accelerator is not built (make setup)"
    calls: list[int] = []

    def spied(src: object, k: int) -> float | None:
        calls.append(k)
        return counted(src, k)

    monkeypatch.setattr(profiles, "_c_kth_counted", spied)
    rng = np.random.default_rng(5)
    n = profiles.COUNTED_MEDIAN_MIN
    whole = rng.integers(0, 1021, (3, n)).astype(np.float32)
    for arr, offered in [
        (whole[0], True),  # just at the limit
        (whole[0, 1:], False),  # just under it
        (whole[:, ::2], True),  # strided, 2-D
        (whole + 0.5, True),  # fractions: refused, partitioned
        (whole.astype(np.float64), False),
    ]:
        calls.clear()
        got = profiles.median(arr)
        assert bool(calls) is offered, arr.shape
        assert got == _partitioned_kth(arr, arr.size // 2)
