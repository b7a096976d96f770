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
