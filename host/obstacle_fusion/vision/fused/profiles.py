"""Small array helpers shared by the stages: means, medians, sub-pixel peaks, running
counts and line fits.

Each receives numpy arrays (int16 / float32 gradient images, uint8 grey, bool flags) and
returns arrays or floats; none keeps state. They are written for speed on the small
blocks the method reads (per-call overhead dominates there) and stay exact where noted:
sums of integer-valued images are exact in float32 below 2**24.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

_c_middle_u8: Callable[[Any, bytes, Any, Any], None] | None
_c_walk_on: Callable[[Any, int, int, int], int | None] | None
_c_first_gap: Callable[[Any, Any], None] | None
_c_next_true: Callable[[Any, int, Any], None] | None
_c_median_f32: Callable[[Any, int, bytes, Any], None] | None
try:  # the optional C accelerator (setup.py); without it numpy selects the middles
    import obstacle_fusion.vision.fused._cmiddle as _cmiddle

    _c_middle_u8, _c_walk_on = _cmiddle.middle_u8, _cmiddle.walk_on
    _c_first_gap, _c_next_true = _cmiddle.first_gap, _cmiddle.next_true
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_middle_u8 = _c_walk_on = _c_first_gap = _c_next_true = None
try:  # (apart: an accelerator built before it still takes the middles)
    from obstacle_fusion.vision.fused._cmiddle import median_f32 as _c_median_f32
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_median_f32 = None
_c_kth_counted: Callable[[Any, int], float | None] | None
try:  # (apart, as median_f32)
    from obstacle_fusion.vision.fused._cmiddle import kth_counted as _c_kth_counted
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_kth_counted = None
_c_row_norms: Callable[[Any, Any], None] | None
try:  # (apart, as median_f32)
    from obstacle_fusion.vision.fused._cmiddle import row_norms as _c_row_norms
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_row_norms = None
_c_median_float32: Callable[[Any, int, Any], bool] | None
try:  # (apart, as median_f32)
    from obstacle_fusion.vision.fused._cmiddle import median_float32 as _c_median_float32
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_median_float32 = None

F32 = npt.NDArray[Any]  # float32 gradient images (OpenCV returns loosely typed arrays)
I16 = npt.NDArray[np.int16]  # int16 gradient images


def clamp(x: float, lo: float, hi: float) -> float:
    """x within [lo, hi] (a Python float: np.clip's wrapper costs more than the work)."""
    return lo if x < lo else hi if x > hi else x


#: Fewest values :func:`median` first offers the C accelerator's count (the frame's noise
#: level: |d/dy| at every 4th row and column, whole numbers; a partition of a flat copy
#: costs ~30 instructions a value, the count ~7). Below it the call costs more than it saves.
COUNTED_MEDIAN_MIN = 1024


def median(a: npt.NDArray[Any]) -> float:
    """Median by partition: np.median's wrapper costs more than the work on small arrays.
    (The upper middle, a value of ``a``; large float32 arrays of whole numbers 0..1023
    counted in C: the same value.)"""
    if a.size == 0:
        return 0.0
    if (
        _c_kth_counted is not None
        and a.size >= COUNTED_MEDIAN_MIN
        and a.dtype == np.float32
        and a.ndim <= 2
    ):
        counted = _c_kth_counted(a, a.size // 2)
        if counted is not None:
            return counted
    flat = a.flatten()  # one copy (np.partition of a.ravel() copied a strided block twice)
    k = flat.size // 2
    flat.partition(k)
    return float(flat[k])


def partitioned(a: npt.NDArray[Any], kth: int, axis: int = -1) -> npt.NDArray[Any]:
    """``np.partition(a, kth, axis)``: a copy, partitioned in place (the same call numpy's
    Python-level wrapper makes, without the wrapper)."""
    s = a.copy(order="K")
    s.partition(kth, axis=axis)
    return s


def lanes_last(a: npt.NDArray[Any], axis: int) -> npt.NDArray[Any]:
    """``np.moveaxis(a, axis, -1)``: the same view, without the wrapper's axis checks
    (they cost more than the sorts that follow on the small blocks the stages read)."""
    nd = a.ndim
    axis = axis + nd if axis < 0 else axis
    if not 0 <= axis < nd:
        return np.moveaxis(a, axis, -1)  # its error
    if axis == nd - 1:
        return a.view()
    return a.transpose([i for i in range(nd) if i != axis] + [axis])


def upper_middles_u8(sample: npt.NDArray[np.uint8]) -> npt.NDArray[np.float32]:
    """Each column's upper middle (sorted position n // 2) of 8-bit samples (n rows, at
    least 2): counted in C where the accelerator built (np.partition's wrapper costs more
    than the work on a few hundred values), else by numpy."""
    mid = sample.shape[0] // 2
    if _c_middle_u8 is not None and sample.dtype == np.uint8 and sample.shape[0] >= 2:
        lo = np.empty(sample.shape[1], np.uint8)
        hi = np.empty(sample.shape[1], np.uint8)
        _c_middle_u8(sample.T, b"", lo, hi)
        return hi.astype(np.float32)
    return np.partition(sample, mid, axis=0)[mid].astype(np.float32)


def median_of(a: npt.NDArray[Any], axis: int | None = None) -> Any:
    """``np.median(a, axis)`` of a NaN-free float array, by one sort: the same values.

    numpy's vectorised sort beats the partition np.median uses on these short lanes
    several times over (a 150 x 120 x 3 colour block by columns: 0.06 against 0.6 ms,
    a few rows of a 500-column band by rows: 0.09 against 0.2-0.3 ms). The middle element,
    or the mean of the two middle ones computed as np.median does ((a + b) / 2 in the
    array's own float type).

    A float32 array of one or two dimensions is done in C where the accelerator built (one
    call for the copy, the sort and the picks; a lane with a NaN or a negative zero, whose
    place numpy's sort decides, is left to it): the same values, the same types.
    """
    if _c_median_float32 is not None and a.dtype == np.float32 and 0 < a.ndim <= 2:
        c = _c_median_float32_of(a, axis)
        if c is not None:
            return c
    if axis is None:
        s = a.flatten()  # np.sort(a, axis=None): a flat copy, sorted
        s.sort()
    else:
        s = lanes_last(a, axis).copy(order="C")  # the lanes contiguous, then sorted
        s.sort(axis=-1)
    n = s.shape[-1]
    if n == 0:
        return np.median(a, axis=axis)  # its warning and NaN for an empty lane
    k = n // 2
    if n % 2:
        return s[..., k]
    return (s[..., k - 1] + s[..., k]) / 2


def _c_median_float32_of(a: npt.NDArray[np.float32], axis: int | None) -> Any:
    """:func:`median_of` of a 1-D or 2-D float32 array by the C selection: an array of the
    lanes' medians, or None where it does not take
    the lanes (empty ones, a NaN, a negative zero: numpy's answer stands)."""
    if _c_median_float32 is None or a.size == 0:
        return None
    if axis is None:
        src, ax, shape = (a if a.ndim == 1 else a.reshape(-1)), 0, ()
    else:
        if not -a.ndim <= axis < a.ndim:
            return None  # numpy's error
        ax = axis % a.ndim
        src, shape = a, a.shape[:ax] + a.shape[ax + 1 :]
    out = np.empty(shape, np.float32)
    if not _c_median_float32(src, ax, out):
        return None
    # (the sorting path's types: a 0-d array, or for an even count its mean, a scalar)
    return out[()] if not shape and src.shape[ax] % 2 == 0 else out


def median_u8(a: npt.NDArray[np.uint8], axis: int | None = None) -> Any:
    """``median_of(a.astype(np.float32), axis)`` of an 8-bit array, without the float copy:
    the middle values of each lane (by a selection network, in C when the optional
    accelerator is built, or by sorting the lanes; lanes longer than a network, in C, by
    counting their values), taken
    to float32, the two middle ones averaged there (8-bit values are exact in float32: the
    same result)."""
    n = a.size if axis is None else a.shape[axis]
    if a.size == 0:  # numpy's answer for empty lanes (OpenCV's sort would crash on them)
        return np.median(a.astype(np.float32), axis=axis)
    k = n // 2
    if (
        n >= 2
        and _c_median_f32 is not None
        and _c_middle_u8 is not None  # (the tests take it away to compare numpy's paths)
        and a.dtype == np.uint8
        and (axis is None or -a.ndim <= axis < a.ndim)
    ):
        # the middles and their float32 median in one C call (the network for short
        # lanes, counts for longer ones): the values of the two-step path below
        if axis is None:
            src, ax, shape = a.reshape(-1), 0, ()
        else:
            src, ax = a, axis % a.ndim
            shape = a.shape[:ax] + a.shape[ax + 1 :]
        network = _NETWORK_BYTES[n] if n <= NETWORK_LANES and axis is not None else b""
        out = np.empty(shape, np.float32)
        _c_median_f32(src, ax, network, out)
        # (the two-step path's types: a 0-d array, or for an even count its mean, a scalar)
        return out[()] if not shape and n % 2 == 0 else out
    lo: npt.NDArray[Any]
    hi: npt.NDArray[Any]
    if (
        axis is not None
        and 2 <= n <= NETWORK_LANES
        and _c_middle_u8 is not None
        and a.dtype == np.uint8  # (some callers pass a median's float32 colours on)
    ):
        # the selection network over all lanes in one C call (:mod:`._cmiddle`)
        lanes = lanes_last(a, axis)
        lo = np.empty(lanes.shape[:-1], np.uint8)
        hi = np.empty(lanes.shape[:-1], np.uint8)
        _c_middle_u8(lanes, _NETWORK_BYTES[n], lo, hi)
    elif axis is not None and 2 <= n <= NETWORK_LANES and a.size >= NETWORK_MIN_VALUES * n:
        lo, hi = _middle_by_network(a, axis, n)
    elif n >= 2 and _c_middle_u8 is not None and a.dtype == np.uint8:
        # longer lanes: their values counted in C (an empty network),
        # not sorted as 16-bit copies
        lanes = a.reshape(-1) if axis is None else lanes_last(a, axis)
        lo = np.empty(lanes.shape[:-1], np.uint8)  # (0-d for one lane: as the sort's)
        hi = np.empty(lanes.shape[:-1], np.uint8)
        _c_middle_u8(lanes, b"", lo, hi)
    else:
        # numpy's vectorised sort has no 8-bit kind, and sorts 16-bit lanes faster than
        # float32 ones; a median's float32 colours passed on are sorted as they are (a
        # 16-bit copy would drop their halves)
        kind = np.uint16 if a.dtype == np.uint8 else np.float32
        if axis is None:
            s = a.astype(kind).ravel()
        else:
            s = lanes_last(a, axis).astype(kind, order="C")
        s.sort(axis=-1)
        lo, hi = s[..., k - 1] if k else s[..., k], s[..., k]
    mid = hi.astype(np.float32)
    if n % 2:
        return mid
    return (lo.astype(np.float32) + mid) / 2


#: Lanes of up to this many values are reduced to their middle by a selection network ...
NETWORK_LANES = 16
#: ... when there are at least this many lanes: many short lanes (a few rows of a band,
#: per column and channel) cost numpy's sort a call per lane, the network a few
#: whole-array minima and maxima (3-6x less on 1500 lanes of 4-12 values).
NETWORK_MIN_VALUES = 256


def _merge_exchange(n: int) -> list[tuple[int, int]]:
    """Batcher's merge-exchange sorting network for n inputs (Knuth's Algorithm 5.2.2M):
    comparators (i, j), i < j, each putting the smaller value at i."""
    pairs: list[tuple[int, int]] = []
    t = (n - 1).bit_length()
    p = 1 << (t - 1)
    while p > 0:
        q, r, d = 1 << (t - 1), 0, p
        while d > 0:
            pairs += [(i, i + d) for i in range(n - d) if i & p == r]
            d, q, r = q - p, q >> 1, p
        p >>= 1
    return pairs


def _middle_network(n: int) -> list[tuple[int, int, bool, bool]]:
    """The comparators of :func:`_merge_exchange` that the middle outputs (n // 2, and
    n // 2 - 1 for an even n) depend on: (i, j, whether the minimum is needed, whether
    the maximum is)."""
    need = {n // 2} if n % 2 else {n // 2 - 1, n // 2}
    ops = []
    for i, j in reversed(_merge_exchange(n)):
        lo, hi = i in need, j in need
        if lo or hi:
            ops.append((i, j, lo, hi))
            need |= {i, j}
    return ops[::-1]


_MIDDLE_NETWORKS = {n: _middle_network(n) for n in range(2, NETWORK_LANES + 1)}
#: The same networks for the C accelerator: (i, j, 1 if the minimum is needed + 2 if the
#: maximum is) per comparator.
_NETWORK_BYTES = {
    n: bytes(x for i, j, lo, hi in ops for x in (i, j, int(lo) + 2 * int(hi)))
    for n, ops in _MIDDLE_NETWORKS.items()
}


def _middle_by_network(
    a: npt.NDArray[np.uint8], axis: int, n: int
) -> tuple[npt.NDArray[np.uint8], npt.NDArray[np.uint8]]:
    """The two middle order statistics (sorted positions n // 2 - 1 and n // 2; the
    first is the second's for n = 1) of every lane along ``axis``: exact, by elementwise
    minima and maxima of the n slices."""
    v = list(lanes_first(a, axis))
    for i, j, lo, hi in _MIDDLE_NETWORKS[n]:
        x, y = v[i], v[j]
        if lo:
            v[i] = np.minimum(x, y)
        if hi:
            v[j] = np.maximum(x, y)
    k = n // 2
    return v[k - 1], v[k]


def lanes_first(a: npt.NDArray[Any], axis: int) -> npt.NDArray[Any]:
    """``np.moveaxis(a, axis, 0)``: the same view, without the wrapper's checks."""
    nd = a.ndim
    axis = axis + nd if axis < 0 else axis
    if not 0 <= axis < nd:
        return np.moveaxis(a, axis, 0)  # its error
    if axis == 0:
        return a
    return a.transpose([axis] + [i for i in range(nd) if i != axis])


#: The widest rows :func:`narrow_max` takes column by column.
NARROW_MAX_COLUMNS = 4


def narrow_max(a: npt.NDArray[Any]) -> npt.NDArray[Any]:
    """``a.max(axis=1)`` of a 2-D integer array (the |d/dx| of a side's 3 columns): over 1
    to NARROW_MAX_COLUMNS columns, np.maximum of the columns in turn (numpy's reduction
    over so short a last axis costs several times more; a maximum is exact, in any order,
    so the same values and type)."""
    if a.ndim == 2 and 1 <= a.shape[1] <= NARROW_MAX_COLUMNS and a.dtype.kind in "iu":
        out = a[:, 0].copy()
        for j in range(1, a.shape[1]):
            np.maximum(out, a[:, j], out=out)
        return out
    return np.asarray(a.max(axis=1))


def column_means(a: npt.NDArray[np.int16]) -> npt.NDArray[np.float32]:
    """``np.asarray(a.mean(axis=0), np.float32)`` of an int16 block: the column sums by
    cv2.reduce in float64 (integers: exact, whatever the order), then divided by the row
    count as numpy's mean does; several times faster than numpy's cast-and-add."""
    if a.shape[0] == 0 or a.shape[1] == 0:  # OpenCV's reduce crashes on an empty block
        return np.zeros(a.shape[1], np.float32)
    sums = cv2.reduce(a, 0, cv2.REDUCE_SUM, dtype=cv2.CV_64F)[0]
    return np.asarray(sums / a.shape[0], np.float32)


def share(flags: npt.NDArray[np.bool_]) -> float:
    """``float(flags.mean())`` of a non-empty bool array (count / size: the same float)."""
    return np.count_nonzero(flags) / flags.size


def row_norms(x: npt.NDArray[Any]) -> npt.NDArray[Any]:
    """``np.linalg.norm(x, axis=1)`` of a real float array: the same sums and roots,
    without the wrapper (which costs more than the work on a few hundred colours). In C
    where the accelerator built, for 2-D float32 or float64 rows of 1-7 values (the colours
    and chromas the stages compare): one call for numpy's three, the same values."""
    if (
        _c_row_norms is not None
        and x.ndim == 2
        and 1 <= x.shape[1] <= 7
        and (x.dtype == np.float32 or x.dtype == np.float64)
    ):
        out = np.empty(x.shape[0], x.dtype)
        _c_row_norms(x, out)
        return out
    return np.sqrt(np.add.reduce(x * x, axis=1))


def norm(x: npt.NDArray[Any]) -> float:
    """``float(np.linalg.norm(x))`` of a real 1-D float vector (its dot, then its root in
    the vector's own float type, as np.linalg.norm takes them)."""
    return float(np.sqrt(x.dot(x)))


def mean(a: npt.NDArray[Any], axis: int | None = None) -> Any:
    """Mean via sum (np.mean's Python-level wrapper dominates on small arrays)."""
    n = a.size if axis is None else a.shape[axis]
    return a.sum(axis=axis) * (1.0 / max(n, 1))


def walk_on(on: Sequence[bool] | npt.NDArray[np.bool_], start: int, step: int, max_gap: int) -> int:
    """Last ``on`` column from ``start`` towards ``step``, over gaps of up to max_gap.

    ``on`` as a Python list: a step reads one flag, which a numpy array's scalar
    indexing makes several times dearer over a walk of hundreds of columns. With the C
    accelerator the walk is its (lists, and 1-D bool arrays read in place)."""
    if _c_walk_on is not None:
        end = _c_walk_on(on, start, step, max_gap)
        if end is not None:
            return end
    u, v, gap, n = start, start, 0, len(on)
    while 0 <= v + step < n and gap <= max_gap:
        v += step
        if on[v]:
            u, gap = v, 0
        else:
            gap += 1
    return u


def col_means(a: npt.NDArray[Any]) -> F32:
    """Float32 column means of an integer-valued gradient block (cv2.reduce: ~2x faster
    than numpy's casting sum; float32 sums of integers under 2**24 are exact)."""
    sums = cv2.reduce(a, 0, cv2.REDUCE_SUM, dtype=cv2.CV_32F)[0]
    sums *= 1.0 / max(a.shape[0], 1)
    return sums


def row_means(a: I16) -> F32:
    """Row means of an int16 gradient block in float32 (sums exact: integers < 2**24)."""
    return a.sum(axis=1, dtype=np.float32) * (1.0 / max(a.shape[1], 1))


def local_maxima(p: F32, threshold: float) -> npt.NDArray[np.intp]:
    if p.size < 3:
        return np.zeros(0, np.intp)
    mid = p[1:-1]
    idx = ((mid >= p[:-2]) & (mid > p[2:]) & (mid > threshold)).nonzero()[0] + 1
    return idx


def subpixel(profile: F32, centre: npt.NDArray[np.intp]) -> npt.NDArray[np.float64]:
    """Parabolic peak offsets at integer peaks (vectorised); profile rows are samples.

    Flat indexing and a masked divide: on these few-dozen-sample windows the per-call
    overhead of fancy 2-D indexing and np.errstate is most of the cost.
    """
    n = profile.shape[1]
    flat = profile.ravel()
    idx = centre * n + np.arange(n)
    y0, y1, y2 = flat[idx - n], flat[idx], flat[idx + n]
    den = y0 - 2.0 * y1 + y2
    off = np.zeros(n, den.dtype)
    np.divide(0.5 * (y0 - y2), den, out=off, where=den < 0)
    np.maximum(off, -0.5, out=off)
    np.minimum(off, 0.5, out=off)
    return off.astype(np.float64)


def range_sums(img: npt.NDArray[Any], ranges: list[tuple[int, int]]) -> F32:
    """Float32 row sums of ``img`` over each column range [c0, c1): one column per range.

    cv2.reduce costs about half of numpy's sum on these strided blocks and keeps to one
    thread (a matrix product would go through a multi-threaded BLAS); the sums are exact
    for integer-valued images (every partial sum stays under 2**24).
    """
    rows = img.shape[0]
    out = np.empty((len(ranges), rows), np.float32)
    for j, (c0, c1) in enumerate(ranges):
        cv2.reduce(img[:, c0:c1], 1, cv2.REDUCE_SUM, dst=out[j].reshape(rows, 1), dtype=cv2.CV_32F)
    return out.T


def grey_range_sums(
    grey: npt.NDArray[np.uint8], ranges: list[tuple[int, int]] | npt.NDArray[np.intp]
) -> F32:
    """Row sums of an 8-bit image over many column ranges [c0, c1), from one integral.

    Equal to :func:`range_sums` (integer sums, exact in int32 and then in float32: a row
    sum is at most 255 * width) for many ranges at the cost of a few of its calls.
    ``ranges``: (c0, c1) pairs, or an array of them (one row each).
    """
    r = np.asarray(ranges, np.intp).reshape(-1, 2)
    lo, hi = int(r[:, 0].min()), int(r[:, 1].max())
    integral = cv2.integral(grey[:, lo:hi])  # int32, (rows + 1) x (width + 1)
    idx = r.ravel() - lo  # c0, c1, c0, c1, ...
    at = integral[:, idx]
    per_row = at[1:] - at[:-1]
    return (per_row[:, 1::2] - per_row[:, 0::2]).astype(np.float32)


def first_gap(on: npt.NDArray[np.bool_]) -> npt.NDArray[np.intp]:
    """Per column, the first row starting 3 consecutive misses (the row count if none).

    Worked on a transposed copy: numpy's any/argmax down the rows of a narrow array
    cost several times as much as along contiguous rows. With the C accelerator, its
    search down each column of ``on`` in place (2-D bool arrays with rows; numpy's error
    for none).
    """
    if _c_first_gap is not None and on.dtype == np.bool_ and on.ndim == 2 and on.shape[0]:
        found = np.empty(on.shape[1], np.intp)
        _c_first_gap(on, found)
        return found
    miss = ~np.ascontiguousarray(on.T)
    gap = miss[:, :-2] & miss[:, 1:-1] & miss[:, 2:] if miss.shape[1] > 2 else miss
    return np.where(gap.any(axis=1), gap.argmax(axis=1), miss.shape[1])


def next_true(flags: npt.NDArray[np.bool_], rb: int) -> npt.NDArray[np.intp]:
    """Per column of ``flags`` (rows 0..rb-1), for each row the first row at or below it
    where the flag holds, rb if none: ``np.minimum.accumulate(np.where(flags, rows, rb)
    [::-1], axis=0)[::-1]`` (in C with the accelerator: integers, the same values)."""
    if (
        _c_next_true is not None
        and flags.dtype == np.bool_
        and flags.ndim == 2
        and 0 < flags.shape[0] == rb
    ):
        found = np.empty(flags.shape, np.intp)
        _c_next_true(flags, rb, found)
        return found
    idx = np.where(flags, np.arange(rb)[:, None], rb)
    out: npt.NDArray[np.intp] = np.minimum.accumulate(idx[::-1], axis=0)[::-1]
    return out


def late_run(on: npt.NDArray[np.bool_], late_rows: int) -> npt.NDArray[np.intp]:
    """Per column, the length of an edge run that starts within ``late_rows`` of the
    bottom (3 hits in a row) and goes on to its first gap of 3 misses; 0 if none."""
    t = np.ascontiguousarray(on.T)
    n = t.shape[1]
    if n < 6 or late_rows < 1:
        return np.zeros(t.shape[0], np.intp)
    hit = t[:, :-2] & t[:, 1:-1] & t[:, 2:]
    hit[:, min(late_rows, hit.shape[1]) :] = False
    has = hit.any(axis=1)
    start = hit.argmax(axis=1)
    miss = ~t
    gap = miss[:, :-2] & miss[:, 1:-1] & miss[:, 2:]
    gap &= np.arange(n - 2)[None, :] >= start[:, None]
    end = np.where(gap.any(axis=1), gap.argmax(axis=1), n)
    return np.where(has, end - start, 0)


def int_threshold(thresholds: npt.NDArray[Any], repeat: int = 1) -> npt.NDArray[np.int16]:
    """For the int16 gradients, x > t exactly when x > floor(t): a compare without casts.

    (Thresholds stay far below the int16 range: |gradient| <= 1020, noise likewise.)
    """
    floor = np.floor(thresholds).astype(np.int16)
    return np.concatenate([floor] * repeat) if repeat > 1 else floor


def running_counts(flags: npt.NDArray[np.bool_], extra: int = 0) -> npt.NDArray[np.int32]:
    """Per column, the true rows above each row: out[r, j] = flags[:r, j].sum() (int32).

    One cv2.integral and a difference of its columns: numpy's cumsum down the rows of a
    narrow array makes one inner-loop call per row. ``extra`` zero columns are appended.
    """
    rows, cols = flags.shape
    integral = cv2.integral(flags.view(np.uint8))
    out = np.zeros((rows + 1, cols + extra), np.int32)
    np.subtract(integral[:, 1:], integral[:, :-1], out=out[:, :cols])
    return out


def _fit_edges(
    windows: list[tuple[F32, int, int]], x: npt.NDArray[np.float64]
) -> list[tuple[float, float]]:
    """Line fits through the sub-pixel gradient peaks of several 7-sample edge windows.

    Each window is 7 x n (7 samples across the edge at each position ``x`` along it), with the
    coordinate of its first sample and the first sample the peak may be at (the peak is
    within +-1 of the window's middle). The parabolic offsets of all windows are found
    in one pass: on these small windows the per-call overhead is most of the cost.
    """
    peaks = []
    for win, _, lo in windows:
        peak = win[lo : lo + 3].argmax(axis=0) + lo
        np.minimum(peak, 5, out=peak)
        peaks.append(peak)
    stacked = np.concatenate([win for win, _, _ in windows], axis=1, dtype=np.float32)
    off = subpixel(stacked, np.concatenate(peaks))
    n = x.size
    return [
        _fit_line(x, start + peaks[i] + off[i * n : (i + 1) * n])
        for i, (_, start, _) in enumerate(windows)
    ]


def _fit_line(x: npt.NDArray[np.float64], y: npt.NDArray[np.float64]) -> tuple[float, float]:
    """y = a + b x, least squares with one round of outlier rejection."""
    if x.size < 2:
        return (median(y) if y.size else 0.0, 0.0)
    a, b = lsq(x, y)
    res = np.abs(y - (a + b * x))
    keep = res <= max(0.75, 2.5 * median(res))
    if 2 <= np.count_nonzero(keep) < x.size:
        a, b = lsq(x[keep], y[keep])
    return a, b


def lsq(x: npt.NDArray[np.float64], y: npt.NDArray[np.float64]) -> tuple[float, float]:
    """y = a + b x, plain least squares: (a, b); b = 0 for a degenerate x."""
    # sum / n is exactly what .mean() computes, without its Python-level wrapper
    xm, ym = float(np.add.reduce(x)) / x.size, float(np.add.reduce(y)) / y.size
    dx = x - xm
    sxx = float(dx @ dx)
    b = float(dx @ (y - ym)) / sxx if sxx > 1e-12 else 0.0
    return ym - b * xm, b


def fit_horizontal(
    edges: list[tuple[F32, int]], cols: npt.NDArray[np.intp], h: int
) -> list[tuple[float, float]]:
    """Lines v = a + b u through each (gradient image, row) edge's per-column peaks."""
    # 7 rows around each edge; the peak within +-1 row (cols are consecutive: a slice)
    u0 = int(cols[0]) if cols.size else 0
    windows = []
    for img, row in edges:
        r0 = int(clamp(row - 3, 0, h - 7))
        windows.append((img[r0 : r0 + 7, u0 : u0 + cols.size], r0, max(1, row - 1 - r0)))
    return _fit_edges(windows, cols.astype(np.float64))


def fit_vertical(
    ax: I16, rows: npt.NDArray[np.intp], edge_cols: list[int], w: int
) -> list[tuple[float, float]]:
    """Lines u = a + b v through each vertical edge's per-row peaks near its column."""
    # rows are consecutive: a slice, not a gather
    v0 = int(rows[0]) if rows.size else 0
    windows = []
    for col in edge_cols:
        c0 = int(clamp(col - 3, 0, w - 7))
        windows.append((ax[v0 : v0 + rows.size, c0 : c0 + 7].T, c0, max(1, col - 1 - c0)))
    return _fit_edges(windows, rows.astype(np.float64))


class VerticalFits:
    """:func:`fit_vertical` over one frame's |d/dx|, each (rows, columns) fitted once.

    The face the search verifies (its sides' lean) is, more often than not, the face the
    refinement measures with the same rows and columns: the second fit is the first's.
    Keyed by the first row, the row count and the edge columns (the rows are consecutive).
    """

    __slots__ = ("ax", "_fits")

    def __init__(self, ax: I16) -> None:
        self.ax = ax
        self._fits: dict[tuple[int, int, tuple[int, ...], int], list[tuple[float, float]]] = {}

    def __call__(
        self, rows: npt.NDArray[np.intp], edge_cols: list[int], w: int
    ) -> list[tuple[float, float]]:
        key = (int(rows[0]) if rows.size else 0, int(rows.size), tuple(edge_cols), w)
        fits = self._fits.get(key)
        if fits is None:
            fits = fit_vertical(self.ax, rows, edge_cols, w)
            self._fits[key] = fits
        return list(fits)
