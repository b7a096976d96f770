"""The fused method: the sonar's range tells the image where to look and what to expect.

Working view: undistorted and levelled (see :class:`View`), so the face square to the robot
is an exact scaled copy, its vertical edges are image columns, and a point on the floor at
depth z sits on row cy + fy * camera_height / z. From the range L (face depth D):

1. the floor-contact edge must lie near row cy + fy h / D (band from the range's error);
2. the beam (about 15 degrees) bounds where the face is horizontally: it must reach into
   the beam's columns at depth D;
3. the face's vertical edges stand on that floor-contact edge and run straight up to the
   front top edge, where they stop (top-face edges slant away, background lines do not
   stop at the box's sides, a stripe on the face does not end the vertical edges), and
   the face keeps its own shade between them (books on a shelf behind it do not).

Candidates for each edge come from gradient profiles; every (bottom, left, right) triple
is scored with its best top; the winner's four edges are refined to sub-pixel lines, and
height/width follow from the pinhole model at depth D (per-edge depths from the floor
geometry correct a few degrees of yaw).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.types import Line, Measurement, Timer, View

log = logging.getLogger(__name__)

F32 = npt.NDArray[Any]  # float32 gradient images (OpenCV returns loosely typed arrays)
I16 = npt.NDArray[np.int16]  # int16 gradient images

_MAX_SIDE_CANDIDATES = 3
_MAX_BOTTOM_CANDIDATES = 3
MIN_SIZE_M = 0.03  # smallest face side the method looks for
# a side's edge rows count from a quarter of its contrast near the floor, but never need
# more than this many noise levels (see _presence)
_PRESENCE_CAP = 5.0
_HOLE_SHARE = 0.2  # a gap in the sides longer than this share of the face is no top face
_TAIL_SHARE = 0.1  # a top edge's blur tail, as a share of the edge, within _TAIL_ROWS
_TAIL_ROWS = 2
# a stripe of another shade across the face (a label) at most this share of its height
_LABEL_SHARE = 0.35
_LABEL_BLUR_ROWS = 3  # a top edge's blur: rows from the top to the face's own shade
_MAX_VERIFIED = 4  # best candidates checked for world-vertical sides
_RADIAL_MIN = 0.08  # a floor line's lean (du/dv) from which it is told from a vertical
_LEAN_MIN = 0.05  # a fitted side's lean below this is vertical whatever the floor's
_BANDS = 4  # column bands of a face candidate, each to keep the face's shade
_BAND_SHARE = 0.8
_FRONT_TOP_SIGMAS = 3.0  # a top face's front edge: this many noise levels of a row mean
# below this confidence the fused method reports no detection rather than a likely wrong
# size (chosen on generated hard scenes: it turns most gross errors into misses)
DEFAULT_MIN_CONFIDENCE = 0.05
_WIN7 = np.arange(-3, 4)[:, None]  # row offsets of a 7-row window around an edge
_T5 = np.linspace(0.0, 1.0, 5)[:, None]  # outline samples along each face edge


def _face_term(face: Any, bands: Any) -> Any:
    """The face-shade share's weight: squared, and cut where one column band's share
    falls under _BAND_SHARE of the whole face's (that band covers floor or wall)."""
    return face**2 * np.minimum(1.0, bands / np.maximum(_BAND_SHARE * face, 1e-6)) ** 2


def _clamp(x: float, lo: float, hi: float) -> float:
    return lo if x < lo else hi if x > hi else x


def _median(a: npt.NDArray[Any]) -> float:
    """Median by partition: np.median's wrapper costs more than the work on small arrays."""
    flat = a.ravel()
    if flat.size == 0:
        return 0.0
    k = flat.size // 2
    return float(np.partition(flat, k)[k])


def _mean(a: npt.NDArray[Any], axis: int | None = None) -> Any:
    """Mean via sum (np.mean's Python-level wrapper dominates on small arrays)."""
    n = a.size if axis is None else a.shape[axis]
    return a.sum(axis=axis) * (1.0 / max(n, 1))


def _col_means(a: npt.NDArray[Any]) -> F32:
    """Float32 column means of an integer-valued gradient block (cv2.reduce: ~2x faster
    than numpy's casting sum; float32 sums of integers under 2**24 are exact)."""
    sums = cv2.reduce(a, 0, cv2.REDUCE_SUM, dtype=cv2.CV_32F)[0]
    sums *= 1.0 / max(a.shape[0], 1)
    return sums


def _row_means(a: I16) -> F32:
    """Row means of an int16 gradient block in float32 (sums exact: integers < 2**24)."""
    return a.sum(axis=1, dtype=np.float32) * (1.0 / max(a.shape[1], 1))


def _local_maxima(p: F32, threshold: float) -> npt.NDArray[np.intp]:
    if p.size < 3:
        return np.zeros(0, np.intp)
    mid = p[1:-1]
    idx = np.nonzero((mid >= p[:-2]) & (mid > p[2:]) & (mid > threshold))[0] + 1
    return idx


def _subpixel(profile: F32, centre: npt.NDArray[np.intp]) -> npt.NDArray[np.float64]:
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


def _range_sums(img: npt.NDArray[Any], ranges: list[tuple[int, int]]) -> F32:
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


def _grey_range_sums(grey: npt.NDArray[np.uint8], ranges: list[tuple[int, int]]) -> F32:
    """Row sums of an 8-bit image over many column ranges [c0, c1), from one integral.

    Equal to :func:`_range_sums` (integer sums, exact in int32 and then in float32: a row
    sum is at most 255 * width) for many ranges at the cost of a few of its calls.
    """
    lo = min(c0 for c0, _ in ranges)
    hi = max(c1 for _, c1 in ranges)
    integral = cv2.integral(grey[:, lo:hi])  # int32, (rows + 1) x (width + 1)
    idx = np.array(ranges, np.intp).ravel() - lo  # c0, c1, c0, c1, ...
    at = integral[:, idx]
    per_row = at[1:] - at[:-1]
    return (per_row[:, 1::2] - per_row[:, 0::2]).astype(np.float32)


def _face_shade(means: F32, rb: int, kf: int) -> F32:
    """Per column, the face's own shade: the median of the kf row means starting 3 rows
    above the floor-contact row (clear of the bottom edge's blur)."""
    return np.partition(means[rb - 3 - kf : rb - 3], kf // 2, axis=0)[kf // 2]


def _first_match(match: npt.NDArray[np.bool_], rb: int) -> npt.NDArray[np.intp]:
    """Per column, the first row at or below each row in the face's shade (rb if none)."""
    row_idx = np.arange(rb)[:, None]
    return np.minimum.accumulate(np.where(match, row_idx, rb)[::-1], axis=0)[::-1]


def _shade_share(
    upto: npt.NDArray[np.int32],
    first: npt.NDArray[np.intp],
    tops: npt.NDArray[np.intp],
    cols: npt.NDArray[np.intp],
    rb: int,
    h_t: npt.NDArray[np.intp],
) -> npt.NDArray[np.float64]:
    """Share of a candidate's rows (top to bottom) in the face's shade, a label counted in.

    A stripe (label) across the face: rows of another shade with the face's own above and
    below them, inside a top that starts in the face's shade (within a blurred edge's
    rows), are face. ``upto`` are running counts of the shade matches, ``first`` from
    :func:`_first_match`, ``cols`` each candidate's column in them.
    """
    share = (upto[rb, cols] - upto[tops, cols]) / h_t
    ft = first[tops, cols]
    inner = (rb - ft) - (upto[rb, cols] - upto[ft, cols])
    label = (ft - tops <= _LABEL_BLUR_ROWS) & (inner <= _LABEL_SHARE * h_t)
    return np.where(label, share + inner / h_t, share)


def _presence(strength: Any, noise: float) -> Any:
    """Threshold for a side's edge rows: a quarter of its strength near the floor, capped.

    The cap matters where the background changes along the side (floor, then another box,
    then the wall): the side's contrast there can be a fraction of that near the floor.
    """
    return np.maximum(np.minimum(0.25 * strength, _PRESENCE_CAP * noise), 2.5 * noise)


class _Sides:
    """Candidate vertical edge columns at one floor-contact row: per-row presence tables.

    One column of each table per candidate column, built in one pass for all of them
    (per-column arrays cost more in numpy call overhead than in work). Counts are exact
    integers, so they are the per-column values whatever the summation order.
    """

    __slots__ = ("index", "below", "upto", "nxt", "run_top", "out", "out_left", "out_right", "csum")

    def __init__(
        self, ax3: I16, cols: list[int], thresholds: npt.NDArray[np.float64], rb: int
    ) -> None:
        k = len(cols)
        w = ax3.shape[1]
        c = np.array(cols, np.intp)
        self.index = {col: i for i, col in enumerate(cols)}
        # the side columns, then the columns just outside (4 px) as the left or right
        # side, at the side's threshold: background texture there says the edges above
        # a top are not the side's own
        vals = ax3[:rb, np.concatenate([c, np.maximum(c - 4, 0), np.minimum(c + 4, w - 1)])]
        on_all = vals > _int_threshold(thresholds, 3)
        on = on_all[:, :k]
        # edge rows in 0..r-1 for all 3k columns; a last column of zeros for a side with
        # no column outside it
        counts = _running_counts(on_all, extra=1)
        self.upto = counts[:, :k]
        self.below = self.upto[rb] - self.upto[:rb]  # edge rows in r..rb-1
        self.out = counts  # columns k..2k-1 outside left, 2k..3k-1 outside right
        self.out_left = [k + i if cols[i] >= 4 else -1 for i in range(k)]
        self.out_right = [2 * k + i if cols[i] + 4 < w else -1 for i in range(k)]
        # first edge row at or below r (rb if none): the hole under a top candidate
        idx = np.where(on, np.arange(rb)[:, None], rb)
        self.nxt = np.minimum.accumulate(idx[::-1], axis=0)[::-1]
        # top row of the edge run from the floor-contact row (gaps under 3 rows)
        if rb - 1 < 3:
            self.run_top = [rb - 1] * k
        else:
            self.run_top = (rb - 1 - _first_gap(on[: rb - 1][::-1])).tolist()
        # exact column sums from the top (side strength over a face's rows)
        integral = cv2.integral(np.ascontiguousarray(vals[:, :k]), sdepth=cv2.CV_64F)
        self.csum = integral[:, 1:] - integral[:, :-1]

    def background(self, il: int, ir: int) -> tuple[int, int]:
        """Table columns of the outside counts for a pair; one side's twice if only it exists."""
        a, b = self.out_left[il], self.out_right[ir]
        zero = self.out.shape[1] - 1
        if a < 0 and b < 0:
            return zero, zero
        return (a if a >= 0 else b), (b if b >= 0 else a)


def _first_gap(on: npt.NDArray[np.bool_]) -> npt.NDArray[np.intp]:
    """Per column, the first row starting 3 consecutive misses (the row count if none).

    Worked on a transposed copy: numpy's any/argmax down the rows of a narrow array
    cost several times as much as along contiguous rows.
    """
    miss = ~np.ascontiguousarray(on.T)
    gap = miss[:, :-2] & miss[:, 1:-1] & miss[:, 2:] if miss.shape[1] > 2 else miss
    return np.where(gap.any(axis=1), np.argmax(gap, axis=1), miss.shape[1])


def _late_run(on: npt.NDArray[np.bool_], late_rows: int) -> npt.NDArray[np.intp]:
    """Per column, the length of an edge run that starts within ``late_rows`` of the
    bottom (3 hits in a row) and goes on to its first gap of 3 misses; 0 if none."""
    t = np.ascontiguousarray(on.T)
    n = t.shape[1]
    if n < 6 or late_rows < 1:
        return np.zeros(t.shape[0], np.intp)
    hit = t[:, :-2] & t[:, 1:-1] & t[:, 2:]
    hit[:, min(late_rows, hit.shape[1]) :] = False
    has = hit.any(axis=1)
    start = np.argmax(hit, axis=1)
    miss = ~t
    gap = miss[:, :-2] & miss[:, 1:-1] & miss[:, 2:]
    gap &= np.arange(n - 2)[None, :] >= start[:, None]
    end = np.where(gap.any(axis=1), np.argmax(gap, axis=1), n)
    return np.where(has, end - start, 0)


def _int_threshold(thresholds: npt.NDArray[Any], repeat: int = 1) -> npt.NDArray[np.int16]:
    """For the int16 gradients, x > t exactly when x > floor(t): a compare without casts.

    (Thresholds stay far below the int16 range: |gradient| <= 1020, noise likewise.)
    """
    floor = np.floor(thresholds).astype(np.int16)
    return np.concatenate([floor] * repeat) if repeat > 1 else floor


def _running_counts(flags: npt.NDArray[np.bool_], extra: int = 0) -> npt.NDArray[np.int32]:
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
        peak = np.argmax(win[lo : lo + 3], axis=0) + lo
        np.minimum(peak, 5, out=peak)
        peaks.append(peak)
    stacked = np.concatenate([win for win, _, _ in windows], axis=1, dtype=np.float32)
    off = _subpixel(stacked, np.concatenate(peaks))
    n = x.size
    return [
        _fit_line(x, start + peaks[i] + off[i * n : (i + 1) * n])
        for i, (_, start, _) in enumerate(windows)
    ]


def _fit_line(x: npt.NDArray[np.float64], y: npt.NDArray[np.float64]) -> tuple[float, float]:
    """y = a + b x, least squares with one round of outlier rejection."""
    if x.size < 2:
        return (_median(y) if y.size else 0.0, 0.0)
    a, b = _lsq(x, y)
    res = np.abs(y - (a + b * x))
    keep = res <= max(0.75, 2.5 * _median(res))
    if 2 <= np.count_nonzero(keep) < x.size:
        a, b = _lsq(x[keep], y[keep])
    return a, b


def _lsq(x: npt.NDArray[np.float64], y: npt.NDArray[np.float64]) -> tuple[float, float]:
    # sum / n is exactly what .mean() computes, without its Python-level wrapper
    xm, ym = float(np.add.reduce(x)) / x.size, float(np.add.reduce(y)) / y.size
    dx = x - xm
    sxx = float(dx @ dx)
    b = float(dx @ (y - ym)) / sxx if sxx > 1e-12 else 0.0
    return ym - b * xm, b


class _BottomProfile(NamedTuple):
    """Per-column bottom-edge peaks near the fitted bottom line (for the side-face test)."""

    cols: npt.NDArray[np.intp]
    strength: F32
    pos: npt.NDArray[np.float64]  # sub-pixel peak row
    dev: npt.NDArray[np.float64]  # peak row minus the fitted line
    ref: float  # median strength over the centre columns
    on: list[bool]  # on the line and strong


@dataclass(frozen=True)
class _Candidate:
    """A face hypothesis: floor-contact row, side columns, top row, and its scores."""

    score: float  # for choosing among candidates
    rb: int
    ul: int
    ur: int
    vt: int
    evidence: float  # 0..1: shape fit and edge strength, before ambiguity

    def overlap(self, other: _Candidate) -> float:
        """Intersection over union of the two face rectangles."""
        iw = min(self.ur, other.ur) - max(self.ul, other.ul)
        ih = min(self.rb, other.rb) - max(self.vt, other.vt)
        if iw <= 0 or ih <= 0:
            return 0.0
        inter = float(iw * ih)
        union = (self.ur - self.ul) * (self.rb - self.vt) + (other.ur - other.ul) * (
            other.rb - other.vt
        )
        return inter / max(union - inter, 1.0)


class FusedMethod:
    name = "fused"

    def __init__(self, view: View, min_confidence: float = DEFAULT_MIN_CONFIDENCE) -> None:
        self.view = view
        self.min_confidence = min_confidence
        h, w = view.camera.height, view.camera.width
        self._kernel3 = np.ones((1, 3), np.uint8)
        self._h, self._w = h, w
        self._depth = 1.0
        self._grey: npt.NDArray[Any] = np.zeros((1, 1), np.uint8)
        # gradient buffers reused every frame: fresh large arrays cost more in page faults
        # than the filters themselves
        self._buf = np.empty((2, h, w), np.float32)  # |dy|, top edge
        self._adx = np.empty((2, h, w), np.int16)  # |dx| and its 1x3 dilation
        self._dx = np.empty((h, w), np.int16)
        self._dy = np.empty((h, w), np.int16)

    # ------------------------------------------------------------------ per frame
    def run(self, image: npt.NDArray[Any], range_m: float, timer: Timer) -> Measurement:
        v = self.view
        rig = v.rig
        fail = Measurement(detected=False, method=self.name, range_m=range_m, distance_m=range_m)
        depth = rig.face_depth(range_m)
        self._depth = depth
        if depth <= 0.05:
            fail.reason = "the face depth from this range and the rig is not in front of the lens"
            return fail
        h_img, w_img = self._h, self._w
        vb0 = v.cy + v.fy * rig.camera_height_m / depth
        tol = 3.0 + (vb0 - v.cy) * (0.03 + 0.01 / depth)
        r0b, r1b = int(math.floor(vb0 - tol)), int(math.ceil(vb0 + tol))
        r0b, r1b = max(r0b, 4), min(r1b, h_img - 4)
        if r0b > r1b:
            fail.reason = (
                f"the floor-contact row predicted from the range ({vb0:.0f}) is outside the "
                "image; check the rig's camera height and pitch"
            )
            return fail
        roi_end = min(h_img, r1b + 4)
        roi = v.warp(image, roi_end)  # only the rows above the floor-contact band
        self._grey = roi
        timer.lap("undistort")
        n = roi.shape[0]
        ay = self._buf[0, :n]
        # both 3x3 Sobels in one pass, exact in int16 (|g| <= 1020); |d/dy| as float32,
        # the same values the float Sobels give, for less than one of them costs; the
        # signed d/dy and |d/dx| stay int16 (their sums are taken in float32 where
        # needed: integers under 2**24, exact)
        dx, dy = self._dx[:n], self._dy[:n]
        cv2.spatialGradient(roi, dx, dy)
        ax, ax3 = self._adx[0, :n], self._adx[1, :n]
        np.abs(dx, out=ax)
        np.abs(dy, out=ay)
        # tolerate a column of drift on vertical edges (int16: exact, and the dilation
        # and the reads cost less than in float32)
        cv2.dilate(ax, self._kernel3, dst=ax3)
        noise = _median(ay[::4, ::4]) / 0.6745 + 1.0
        timer.lap("gradients")

        xb0, xb1 = rig.beam_x_bounds(range_m)
        u_lo = int(_clamp(math.floor(v.cx + v.fx * xb0 / depth), 2, w_img - 3))
        u_hi = int(_clamp(math.ceil(v.cx + v.fx * xb1 / depth), 2, w_img - 3))
        if u_hi - u_lo < 4:
            mid = (u_lo + u_hi) // 2
            u_lo, u_hi = max(2, mid - 2), min(w_img - 3, mid + 2)

        prof_b = _mean(ay[r0b : r1b + 1, u_lo : u_hi + 1], 1)
        rows_b = np.arange(r0b, r1b + 1)
        prior_b = 0.5 + 0.5 * np.exp(-0.5 * ((rows_b - vb0) / max(tol / 2.0, 1.0)) ** 2)
        padded = np.zeros(prof_b.size + 2, prof_b.dtype)  # np.pad costs more than the work
        padded[1:-1] = prof_b
        pk = _local_maxima(padded, 0.0) - 1
        pk = pk[(pk >= 0) & (pk < prof_b.size)]
        if pk.size == 0:
            pk = np.array([int(np.argmax(prof_b))])
        order = np.argsort(-(prof_b[pk] * prior_b[pk]))[:_MAX_BOTTOM_CANDIDATES]
        bottoms = [(int(rows_b[pk[i]]), float(prior_b[pk[i]])) for i in order]
        # the row the range predicts is always a candidate: a dark box on a dark floor
        # can leave its floor-contact edge too faint to peak
        predicted = int(round(vb0))
        if r0b <= predicted <= r1b and all(abs(rb - predicted) > 1 for rb, _ in bottoms):
            bottoms.append((predicted, 1.0))

        best: _Candidate | None = None
        cands: list[_Candidate] = []
        min_w = max(4.0, v.fx * MIN_SIZE_M / depth)
        for rb, pb in bottoms:
            k = int(_clamp(round(v.fy * 0.05 / depth), 3, 25))
            top_strip = max(0, rb - 1 - k)
            if rb - 2 <= top_strip:
                continue
            # vertical-edge profiles over a short (5 cm) and a tall (25 cm) strip above the
            # bottom: a side may lack contrast against the floor yet not against the wall
            prof_short = _col_means(ax[top_strip : rb - 1])
            prof_v = prof_short
            tall = max(0, rb - 1 - int(_clamp(round(v.fy * 0.25 / depth), k, 4 * k + 8)))
            if tall < top_strip:
                prof_v = np.maximum(prof_short, _col_means(ax[tall : rb - 1]))
            base = _median(prof_v) + 0.5
            peaks = _local_maxima(prof_v, max(2.5 * base, 1.5 * noise))
            if peaks.size < 2:
                log.debug("bottom %d: fewer than two vertical-edge peaks", rb)
                continue
            # presence thresholds from the strip nearest the floor, where the side may be
            # faint (a dark box on a dark floor) while its upper part is not
            left, right = self._rank_sides(
                ax3,
                prof_v,
                prof_short,
                [peaks[peaks <= u_hi], peaks[peaks >= u_lo]],
                rb,
                noise,
                rb - 1 - tall,
            )
            log.debug("bottom %d: peaks %s, left %s, right %s", rb, peaks.tolist(), left, right)
            cols = sorted({*left, *right})
            if not cols:
                continue
            sides = _Sides(ax3, cols, _presence(prof_short[cols].astype(np.float64), noise), rb)
            pairs = [(ul, ur) for ul in left for ur in right if ur - ul >= min_w]
            for cand in self._score_pairs(ax3, ay, sides, pairs, noise, rb, pb):
                cands.append(cand)
                if best is None or cand.score > best.score:
                    best = cand
            if best is not None and best.evidence > 0.8:
                break  # a clear face at the most likely floor-contact row
        # the best candidates whose sides are not vertical in the world (the seams of a
        # floor patch run towards the vanishing point) are no face and no rival either
        cands.sort(key=lambda c: -c.score)
        best = None
        rivals = cands
        for i, cand in enumerate(cands[:_MAX_VERIFIED]):
            if self._sides_vertical(ax, cand):
                best = cand
                rivals = cands[i:]
                break
            log.debug(
                "face %d-%d x %d-%d: sides lean to the vanishing point",
                cand.ul,
                cand.ur,
                cand.vt,
                cand.rb,
            )
        timer.lap("search")
        if best is None:
            fail.reason = "no face with a floor-contact edge and two vertical sides near the range"
            return fail
        rb, ul, ur, vt = best.rb, best.ul, best.ur, best.vt
        # a different face (little overlap) scoring nearly as well makes the choice a guess
        rival = max((c.score for c in rivals if c.overlap(best) < 0.5), default=0.0)
        ambiguity = min(1.0, rival / best.score) if best.score > 0.0 else 1.0
        conf = best.evidence * (1.0 - ambiguity)
        log.debug(
            "face %d-%d x %d-%d: evidence %.3f, ambiguity %.2f",
            ul,
            ur,
            vt,
            rb,
            best.evidence,
            ambiguity,
        )
        if conf < self.min_confidence:
            fail.confidence = round(conf, 3)
            fail.reason = (
                f"no clear face: the best candidate's confidence {conf:.3f} is under "
                f"{self.min_confidence:g} (weak edges, or another face almost as likely)"
            )
            return fail
        vt, sign = self._front_top(dy, rb, ul, ur, vt, noise)
        top_row: float | None = None  # a sub-pixel front top row that needs no refining
        front = self._front_from_back(ay, dy, rb, ul, ur, vt)
        if front is not None:
            vt, sign, top_row = front
        # the top edge's signed gradient, only in the 7-row window its refinement reads
        top_edge = self._buf[1, :n]
        r0 = int(_clamp(vt - 3, 0, n - 7))
        win = top_edge[r0 : r0 + 7]
        np.multiply(dy[r0 : r0 + 7], np.float32(sign), out=win)
        np.maximum(win, 0.0, out=win)
        return self._refine(
            ax, ay, ax3, top_edge, rb, ul, ur, vt, top_row, conf, depth, range_m, timer
        )

    def _sides_vertical(self, ax: I16, cand: _Candidate) -> bool:
        """False when a side leans the way a floor line through its foot would.

        In the levelled view every vertical world edge is an image column; a seam or
        plank edge on the floor through (u, v) runs towards the vanishing point, at
        du/dv = (u - cx) / (v - cy). Near the centre column the two look alike: then true.
        """
        v = self.view
        below = cand.rb - v.cy
        if below <= 5.0:
            return True
        mv = max(1, (cand.rb - cand.vt) // 10)
        rows = np.arange(cand.vt + mv, cand.rb - mv + 1)
        if rows.size < 5:
            return True
        for a, b in self._fit_vertical(ax, rows, [cand.ul, cand.ur], ax.shape[1]):
            radial = (a + b * cand.rb - v.cx) / below
            if (
                abs(radial) >= _RADIAL_MIN
                and abs(b) >= _LEAN_MIN
                and abs(b - radial) < 0.5 * abs(radial)
            ):
                return False
        return True

    @staticmethod
    def _rank_sides(
        ax3: I16,
        prof_v: F32,
        prof_short: F32,
        groups: list[npt.NDArray[np.intp]],
        rb: int,
        noise: float,
        late_rows: int = 0,
    ) -> list[list[int]]:
        """Strongest columns whose edge runs straight up from the floor-contact row.

        One ranking per group of peak columns (the left side's, the right side's); the
        run lengths of all groups' strongest columns are found in one pass.
        """
        chosen = [g[np.argsort(-prof_v[g])][: 3 * _MAX_SIDE_CANDIDATES] for g in groups]
        cols_all = np.concatenate(chosen)
        if cols_all.size == 0:
            return [[] for _ in groups]
        col_vals = ax3[: rb - 1, cols_all][::-1]  # rows going up from the bottom
        on = col_vals > _int_threshold(_presence(prof_short[cols_all], noise))
        # run length: rows up to the first gap of 3 consecutive misses
        first_gap = _first_gap(on)
        rank_all = prof_v[cols_all] * np.sqrt(np.maximum(first_gap, 1))
        # A box in the floor's own shade shows its sides only against the wall: an edge
        # run that starts higher up (within the tall strip) counts too, but ranks below
        # every run from the floor, so it only fills the places those leave free.
        late = _late_run(on, late_rows)
        only_late = (first_gap < 3) & (late >= 3)
        if only_late.any():
            late_rank = prof_v[cols_all] * np.sqrt(np.maximum(late, 1))
            below_all = float(late_rank.max()) + 1.0  # every late rank ends up negative
            rank_all = np.where(only_late, late_rank - below_all, rank_all)
            first_gap = np.where(only_late, late, first_gap)
        ranked = []
        start = 0
        for cols in chosen:
            end = start + cols.size
            keep = first_gap[start:end] >= 3
            order = np.argsort(-rank_all[start:end][keep])[:_MAX_SIDE_CANDIDATES]
            ranked.append([int(c) for c in cols[keep][order]])
            start = end
        return ranked

    def _score_pairs(
        self,
        ax3: I16,
        ay: F32,
        sides: _Sides,
        pairs: list[tuple[int, int]],
        noise: float,
        rb: int,
        prior_b: float,
    ) -> list[_Candidate]:
        """Score every (left, right) pair at one floor-contact row, each with its best top.

        All pairs' top candidates are scored in one flat pass (pair-major, rows ascending:
        the order a per-pair loop would see them in); the candidates come back in the order
        of ``pairs``. Row sums of integer gradients are exact in float32, so they are the
        per-pair values bit for bit.
        """
        min_h = max(3, int(self.view.fy * MIN_SIZE_M / self._depth))
        top_limit = rb - min_h
        if top_limit < 3:
            return []
        ps = []
        for ul, ur in pairs:
            m = max(1, (ur - ul) // 8)
            if ur - ul - 2 * m >= 2:
                ps.append((ul, ur, ul + m, ur - m))
        if not ps:
            return []
        n_p = len(ps)
        h_ay, w_ay = ay.shape
        grey = self._grey
        il = np.array([sides.index[p[0]] for p in ps], np.intp)
        ir = np.array([sides.index[p[1]] for p in ps], np.intp)
        inv_n = np.array([1.0 / (p[3] - p[2]) for p in ps], np.float32)
        # mean |d/dy| between the sides for every row above the smallest face (row sums of
        # integers: exact, the per-pair values bit for bit)
        ranges = [(c0, c1) for _, _, c0, c1 in ps]
        prof = _range_sums(ay[:top_limit], ranges) * inv_n
        row_sum = _grey_range_sums(grey[:rb], ranges)
        snr = prof / noise
        mask = np.zeros((top_limit, n_p), bool)
        mid = snr[1:-1]
        mask[1:-1] = (mid >= snr[:-2]) & (mid > snr[2:]) & (mid > 1.2)
        # where each vertical edge ends is a top candidate too: the front top edge of a
        # box can be nearly invisible (front and top faces alike) while its sides are not
        run_top = sides.run_top
        for j in range(n_p):
            for e in (run_top[il[j]], run_top[ir[j]]):
                for r in (e - 1, e):
                    if 0 < r < top_limit:
                        mask[r, j] = True
        pp, tops = np.nonzero(mask.T)  # pair-major, rows ascending within a pair
        if tops.size == 0:
            return []
        tl, tr = il[pp], ir[pp]
        # coverage of each side from each top candidate down to the bottom, and above it
        # (tops < top_limit: the face height rb - tops is >= min_h + 1, never 0)
        h_t = rb - tops
        span = h_t.astype(np.float64)
        below, upto = sides.below, sides.upto
        cov = 0.5 * (below[tops, tl] + below[tops, tr]) / span
        # vertical edges above the top (half as high again as the face): a stripe across
        # the face leaves them there
        above_start = np.maximum(tops - np.maximum(3, h_t // 2), 0)
        n_above = np.maximum(tops - above_start, 1)
        ext_t = upto[tops, tl] + upto[tops, tr]
        ext_a = upto[above_start, tl] + upto[above_start, tr]
        above = 0.5 * (ext_t - ext_a) / n_above
        # ...but textured background (books, posters) gives vertical edges everywhere: only
        # what the side columns have beyond the columns just outside them counts
        bg = np.array([sides.background(il[j], ir[j]) for j in range(n_p)], np.intp)
        ba, bb = bg[pp, 0], bg[pp, 1]
        out = sides.out
        bg_t = out[tops, ba] + out[tops, bb]
        bg_a = out[above_start, ba] + out[above_start, bb]
        above = np.maximum(above - 0.5 * (bg_t - bg_a) / n_above, 0.0)
        stop = 1.0 - above
        # rows just below a top candidate with no vertical edge: the top face of a low box
        start = np.minimum(tops + 1, rb - 1)
        nxt = sides.nxt
        hole = 0.5 * (nxt[start, tl] + nxt[start, tr] - 2 * start).astype(np.float64)
        # the box's top edge stops at its sides; a shelf or skirting line runs on
        # (means over the columns just outside each side, at the top rows)
        o_cols = []  # per pair: left range start, end, right range start, end
        for ul, ur, _, _ in ps:
            wo = max(3, (ur - ul) // 5)
            o_cols.append(
                (max(0, ul - 1 - wo), max(1, ul - 1), min(w_ay - 1, ur + 2), min(w_ay, ur + 2 + wo))
            )
        o_lo, o_hi = min(o[0] for o in o_cols), max(o[3] for o in o_cols)
        o_at = np.array(o_cols, np.intp) - o_lo  # range ends within the block
        o_inv = np.array([(1.0 / (o[1] - o[0]), 1.0 / (o[3] - o[2])) for o in o_cols], np.float32)
        # running row sums at the top rows (exact in float32: integers under 2**24)
        run = np.zeros((tops.size, o_hi - o_lo + 1), np.float32)
        np.cumsum(ay[tops, o_lo:o_hi], axis=1, out=run[:, 1:])
        ends = run[np.arange(tops.size)[:, None], o_at[pp]]  # T x 4
        inv_t = o_inv[pp]
        o_l = (ends[:, 1] - ends[:, 0]) * inv_t[:, 0]
        o_r = (ends[:, 3] - ends[:, 2]) * inv_t[:, 1]
        prof_tops = prof[tops, pp]
        inside = np.maximum(prof_tops, 1e-3)
        contained = np.minimum(np.maximum(1.0 - np.maximum(o_l, o_r) / inside, 0.0), 1.0)
        # texture inside the face (books on a shelf behind a box's top) is not the face
        # (rows from the highest top candidate down: counts are exact whatever the start)
        t0 = int(tops.min())
        tex = _range_sums(ax3[t0:rb], ranges) * inv_n
        flags = np.zeros((rb, 2 * n_p), bool)  # face shade (below) and texture per row
        flags[t0:, n_p:] = tex > 3.0 * noise
        # A hole is a top face only if one fits there: a top face shows below the horizon
        # and spans at most (t - cy) * 2 m / D rows (a box up to 2 m long). A longer hole is
        # a side losing contrast against the background, a milder fault.
        hole_max = np.maximum(0.0, (tops - self.view.cy) * 2.0 / self._depth) + 1.0
        soft = np.exp(-hole / np.maximum(4.0, _HOLE_SHARE * h_t))
        hole_fit = np.where(hole <= hole_max, np.exp(-hole / 2.0), soft)
        # rows whose inside has the face's own shade (measured just above the floor): a
        # shelf of books or a poster over the box does not, a box's face does (but for a
        # stripe across it, or its top face)
        row_sum *= inv_n
        kf = max(2, min(8, min_h // 2))  # within the smallest face the method looks for
        face = _face_shade(row_sum, rb, kf)
        tol = np.maximum(np.float32(8.0), (0.08 * face.astype(np.float64)).astype(np.float32))
        match_b = np.abs(row_sum - face) <= tol
        flags[:, :n_p] = match_b
        counts = _running_counts(flags)  # rows in 0..r-1 (exact counts)
        match_upto, tex_upto = counts[:, :n_p], counts[:, n_p:]
        textured = (tex_upto[rb, pp] - tex_upto[tops, pp]) / h_t
        match_t = match_upto[tops, pp]
        face_frac = _shade_share(match_upto, _first_match(match_b, rb), tops, pp, rb, h_t)
        # ...and the face's shade coming back above a band of another shade right above
        # a top means the top was a stripe across the face (a top face of the same shade
        # as the front starts right at the top, with no band)
        a0 = np.maximum(tops - np.maximum(3, h_t), 0)
        face_above = (match_t - match_upto[a0, pp]) / np.maximum(tops - a0, 1)
        # (tops >= 1: row 0 is never a candidate)
        band = ~(match_b[tops - 1, pp] | match_b[np.maximum(tops - 2, 0), pp])
        face_above = np.where(band, face_above, 0.0)
        face_bands = self._band_face_share(grey, ps, tops, pp, rb, kf, noise)
        snr_tops = snr[tops, pp]
        feats = {
            "face_bands": face_bands,
            "snr": snr_tops,
            "hole": hole,
            "hole_fit": hole_fit,
            "cov": cov,
            "stop": stop,
            "contained": contained,
            "textured": textured,
            "face": face_frac,
            "face_above": face_above,
        }
        score_t, fit = self._top_score(feats)
        # the bottom edge's strength between the sides (max over +-1 row), per pair
        m3 = np.zeros(w_ay + 1, np.float32)  # exact: integers under 2**24
        np.cumsum(ay[rb - 1 : rb + 2].max(axis=0), out=m3[1:])
        bounds = np.searchsorted(pp, np.arange(n_p + 1)).tolist()
        debug = log.isEnabledFor(logging.DEBUG)
        csum_s = sides.csum
        cands: list[_Candidate] = []
        for j, (ul, ur, c0, c1) in enumerate(ps):
            s0, s1 = bounds[j], bounds[j + 1]
            if s1 == s0:
                continue
            if debug:
                for k in np.argsort(-score_t[s0:s1])[:5] + s0:
                    log.debug(
                        "  pair %d-%d rb %d top %d: score %.3f snr %.1f hole %.1f cov %.2f "
                        "stop %.2f contained %.2f textured %.2f face %.2f above %.2f",
                        ul,
                        ur,
                        rb,
                        tops[k],
                        score_t[k],
                        snr_tops[k],
                        hole[k],
                        cov[k],
                        stop[k],
                        contained[k],
                        textured[k],
                        face_frac[k],
                        face_above[k],
                    )
            i = s0 + int(np.argmax(score_t[s0:s1]))
            vt = int(tops[i])
            snr_b = float(np.float32(m3[c1] - m3[c0]) * (1.0 / (c1 - c0))) / noise
            inv_h = 1.0 / (rb - vt)
            a, b = int(il[j]), int(ir[j])
            snr_l = float(np.float32(csum_s[rb, a] - csum_s[vt, a]) * inv_h) / noise
            snr_r = float(np.float32(csum_s[rb, b] - csum_s[vt, b]) * inv_h) / noise
            side = min(snr_l, snr_r, 30.0)
            horiz = min(max(float(snr_tops[i]), 2.0 * float(stop[i])), snr_b, 30.0)
            if side < 2.0 or horiz < 1.0 or side * horiz < 6.0:
                log.debug(
                    "pair %d-%d at %d: weak sides %.1f or top/bottom %.1f", ul, ur, rb, side, horiz
                )
                continue
            fit_i = float(fit[i])
            score = math.sqrt(side * horiz) * fit_i * prior_b
            # evidence: how well the edges fit a face (shape) times how clearly they stand out
            evidence = (
                math.sqrt(min(1.0, 2.0 * fit_i))
                * (1.0 - math.exp(-min(side, horiz) / 4.0))
                * (0.5 + 0.5 * prior_b)
            )
            cands.append(_Candidate(score, rb, ul, ur, vt, _clamp(evidence, 0.0, 1.0)))
        return cands

    @staticmethod
    def _band_face_share(
        grey: npt.NDArray[np.uint8],
        ps: list[tuple[int, int, int, int]],
        tops: npt.NDArray[np.intp],
        pp: npt.NDArray[np.intp],
        rb: int,
        kf: int,
        noise: float,
    ) -> npt.NDArray[np.float64]:
        """Per top candidate, the worst column band's share of rows in its own face shade.

        The whole-width row means can match the face's shade while one side of the pair
        covers floor and wall beside the face (a weak true side and a strong background
        edge beyond it): each band of a real face keeps its own shade from bottom to top.
        """
        ranges = []
        for _, _, c0, c1 in ps:
            # band edges across [c0, c1); a band is at least one column wide
            cuts = [c0 + round(b * (c1 - c0) / _BANDS) for b in range(_BANDS + 1)]
            ranges += [(cuts[b], max(cuts[b + 1], cuts[b] + 1)) for b in range(_BANDS)]
        widths = np.array([c1 - c0 for c0, c1 in ranges], np.float32)
        means = _grey_range_sums(grey[:rb], ranges) / widths
        face = _face_shade(means, rb, kf)
        grey_noise = max(noise - 1.0, 0.0) / 3.46
        tol = np.maximum(
            np.maximum(np.float32(8.0), 0.08 * face),
            (3.0 * grey_noise / np.sqrt(widths)).astype(np.float32),
        )
        match = np.abs(means - face) <= tol
        upto = _running_counts(match)
        first = _first_match(match, rb)
        h_t = rb - tops
        shares = [
            _shade_share(upto, first, tops, pp * _BANDS + b, rb, h_t) for b in range(_BANDS)
        ]
        return np.min(shares, axis=0)

    @staticmethod
    def _top_score(
        f: dict[str, npt.NDArray[Any]],
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """Score of each top candidate and its shape fit (0..1) from the edge evidence."""
        fit = (
            f["hole_fit"]
            * f["cov"] ** 2
            * f["stop"] ** 2
            * (0.3 + 0.7 * f["contained"])
            * (1.0 - f["textured"])
            * _face_term(f["face"], f["face_bands"])
            * (1.0 - f["face_above"])
        )
        score = np.minimum(np.maximum(f["snr"], 0.5), 20.0) ** 0.25 * fit
        return score, fit

    def _front_top(
        self, dy: I16, rb: int, ul: int, ur: int, vt: int, noise: float
    ) -> tuple[int, float]:
        """A box lower than the lens shows its top face: prefer the face's front edge.

        The top face's back edge sits above the front one by at most
        (vt - cy) * (1 - D / (D + 2 m)) rows (a box up to 2 m long). In the signed vertical
        gradient the two edges stay apart even when only a pixel or two apart (the top
        face is lit differently from the wall and from the front face); the lowest
        significant extremum in that reach, within the upper 30 % of the face, is the
        front top edge. Returns the row and the sign of its gradient.
        """
        v = self.view
        m = max(1, (ur - ul) // 8)
        below_horizon = vt - v.cy
        reach = int(min(below_horizon * 2.0 / (self._depth + 2.0), 0.3 * (rb - vt)))
        if below_horizon <= 1.0 or reach < 1:
            return vt, (1.0 if int(dy[vt, ul + m : ur - m].sum()) >= 0 else -1.0)
        # the row means only where the scan reads them (rows vt..last), as Python floats;
        # prof[r - vt] is row r
        last = max(vt, min(vt + reach, rb - 3) + 1)
        prof = _row_means(dy[vt : last + 1, ul + m : ur - m]).tolist()
        # noise of a mean over the face's columns (Sobel smooths ~3 columns together); next
        # to the top edge also its own blur tail, further up only noise
        thr_noise = _FRONT_TOP_SIGMAS * noise * math.sqrt(3.0 / max(1, ur - ul - 2 * m))
        thr_near = thr_noise + _TAIL_SHARE * abs(prof[0])
        best = vt
        for r in range(vt + 1, min(vt + reach, rb - 3) + 1):
            p_prev, p, p_next = prof[r - 1 - vt], prof[r - vt], prof[r + 1 - vt]
            a = abs(p)
            thr = thr_near if r - vt <= _TAIL_ROWS else thr_noise
            if a >= thr and a >= abs(p_prev) and a >= abs(p_next):
                best = r
            elif a >= thr and p * p_prev < 0 and a > abs(p_next):
                best = r
        return best, (1.0 if prof[best - vt] >= 0 else -1.0)

    def _front_from_back(
        self, ay: F32, dy: I16, rb: int, ul: int, ur: int, vt: int
    ) -> tuple[int, float, float | None] | None:
        """A top edge narrower than the face, shrunk towards the centre: the top face's back.

        A top face recedes: its back edge at depth D + l spans the face's columns scaled
        by s = D / (D + l) about the principal point, and lies on row cy + s (vf - cy) for
        a front top edge on row vf. So a top edge that ends inside both vertical edges,
        by the amounts that one scale s explains, is the back edge, and the front edge is
        on row cy + (vt - cy) / s: taken there, or at the signed-gradient extremum within
        a pixel or two of it (the front edge itself may be too faint to be picked).
        Returns the row, its gradient's sign, and the sub-pixel row when it was taken
        from the prediction alone (then not to be refined), or None: no top face here.
        """
        v = self.view
        if vt - v.cy < 3.0 or ur - ul < 12:
            return None
        h, w = ay.shape
        c0, c1 = max(1, ul - 4), min(w - 1, ur + 5)
        prof = ay[max(0, vt - 1) : vt + 2, c0:c1].max(axis=0)
        m = max(2, (ur - ul) // 4)
        level = _median(ay[max(0, vt - 1) : vt + 2, ul + m : ur - m].max(axis=0))
        if level <= 0.0:
            return None
        half = 0.5 * level
        on = np.nonzero(prof >= half)[0]
        if on.size < 4:
            return None
        a, b = float(c0 + on[0]), float(c0 + on[-1])
        # the front top edge spans the face (the edge ends within a pixel of each side)
        if a - ul < 2.0 and ur - b < 2.0:
            return None
        scale = (b - a) / float(ur - ul)
        if not 0.4 <= scale <= 0.97:
            return None
        pred_a = v.cx + scale * (ul - v.cx)
        pred_b = v.cx + scale * (ur - v.cx)
        if abs(pred_a - a) > 1.5 or abs(pred_b - b) > 1.5:
            return None  # not a shrink about the principal point: not a receding top face
        vf = v.cy + (vt - v.cy) / scale
        min_h = max(3, int(v.fy * MIN_SIZE_M / self._depth))
        if vf <= vt + 1.0 or vf >= rb - min_h:
            return None
        mc = max(1, (ur - ul) // 8)
        r0, r1 = max(vt + 1, int(math.floor(vf)) - 2), min(rb - min_h, int(math.ceil(vf)) + 2)
        if r1 < r0:
            return None
        col = _row_means(dy[vt : r1 + 2, ul + mc : ur - mc])  # col[r - vt] is row r
        # a local extremum of the signed gradient nearest the predicted row: the largest
        # value in the window may be the back edge's own blur tail right below it
        mag = np.abs(col)
        weakest = 0.15 * float(mag[0])
        peaks = [
            i
            for i in range(r0, r1 + 1)
            if mag[i - vt] >= weakest
            and mag[i - vt] >= mag[i - vt - 1]
            and mag[i - vt] >= mag[i - vt + 1]
        ]
        r = min(peaks, key=lambda i: abs(i - vf)) if peaks else int(round(vf))
        log.debug(
            "top %d is a back edge (scale %.3f): front top edge at %d (pred %.1f)", vt, scale, r, vf
        )
        # with no extremum of its own, the predicted row itself, sub-pixel: refining near
        # it would slide onto the back edge's blur tail
        return r, (1.0 if col[r - vt] >= 0 else -1.0), (None if peaks else vf)

    # ------------------------------------------------------------------ refinement
    def _refine(
        self,
        ax: I16,
        ay: F32,
        ax3: I16,
        top_edge: F32,
        rb: int,
        ul: int,
        ur: int,
        vt: int,
        top_row: float | None,
        conf: float,
        depth: float,
        range_m: float,
        timer: Timer,
    ) -> Measurement:
        v = self.view
        h_roi, w_img = ay.shape
        # horizontal edges: per-column sub-pixel peaks near rb and vt
        m = max(1, (ur - ul) // 10)
        cols = np.arange(ul + m, ur - m + 1)
        (bottom_a, bottom_b), (top_a, top_b) = self._fit_horizontal(
            [(ay, rb), (top_edge, vt)], cols, h_roi
        )
        if top_row is not None:  # predicted by _front_from_back, not refined
            top_a = top_row - top_b * 0.5 * float(cols[0] + cols[-1])
        # vertical edges: per-row sub-pixel peaks near ul and ur
        mv = max(1, (rb - vt) // 10)
        rows = np.arange(vt + mv, rb - mv + 1)
        (left_a, left_b), (right_a, right_b) = self._fit_vertical(ax, rows, [ul, ur], w_img)

        # A side face (yaw, or a box off the axis) shows beside the front face: the front
        # face's bottom edge is straight, the side face's rises towards the horizon.
        # Where the straight part ends is the front corner.
        bottom = self._bottom_profile(ay, bottom_a, bottom_b, ul, ur)
        if bottom is not None:
            left_a, left_b = self._side_face(
                ax, bottom, bottom_a, bottom_b, ul, ur, vt, rb, -1, left_a, left_b
            )
            right_a, right_b = self._side_face(
                ax, bottom, bottom_a, bottom_b, ul, ur, vt, rb, 1, right_a, right_b
            )

        def corner(
            ha: float, hb: float, va: float, vb: float
        ) -> tuple[float, float]:  # v = ha + hb u ; u = va + vb v
            u = va + vb * ha
            for _ in range(3):
                u = va + vb * (ha + hb * u)
            return (u, ha + hb * u)

        bl = corner(bottom_a, bottom_b, left_a, left_b)
        br = corner(bottom_a, bottom_b, right_a, right_b)
        tr = corner(top_a, top_b, right_a, right_b)
        tl = corner(top_a, top_b, left_a, left_b)
        # Where the vertical edges end is the front top corner even when the top face
        # (a pixel or three tall) merges with the front top edge in the gradient.
        if tl[1] - v.cy > 1.0:
            end_l = self._edge_end(ax3, left_a, left_b, vt, rb)
            end_r = self._edge_end(ax3, right_a, right_b, vt, rb)
            if end_l is not None and end_r is not None:
                d_l, d_r = end_l - tl[1], end_r - tr[1]
                lower = 0.5 * (d_l + d_r)
                # only a thin top face (thicker ones are separate edges, handled above),
                # seen alike on both sides
                if 0.75 < lower <= 4.0 and abs(d_l - d_r) < 1.0:
                    tl = (left_a + left_b * end_l, end_l)
                    tr = (right_a + right_b * end_r, end_r)
        h_left = bl[1] - tl[1]
        h_right = br[1] - tr[1]
        h_px = 0.5 * (h_left + h_right)
        # depths of the two vertical edges from the floor geometry, anchored at D (yaw)
        vb_mid = 0.5 * (bl[1] + br[1]) - v.cy
        z_l = z_r = depth
        if vb_mid > 5.0:
            rl = vb_mid / max(bl[1] - v.cy, 1e-6)
            rr = vb_mid / max(br[1] - v.cy, 1e-6)
            # only a difference the bottom line resolves (over a pixel between the two
            # corners): on a far box a sub-pixel slope from noise would add a depth
            # difference of several cm to the width
            if abs(bl[1] - br[1]) > 1.0 and (abs(rl - 1.0) > 0.01 or abs(rr - 1.0) > 0.01):
                z_l = depth * _clamp(rl, 0.8, 1.25)
                z_r = depth * _clamp(rr, 0.8, 1.25)
        ul_f = 0.5 * (bl[0] + tl[0])
        ur_f = 0.5 * (br[0] + tr[0])
        x_l = (ul_f - v.cx) * z_l / v.fx
        x_r = (ur_f - v.cx) * z_r / v.fx
        width_m = math.hypot(x_r - x_l, z_r - z_l)
        height_m = h_px * depth / v.fy
        timer.lap("refine")
        corners = np.array([bl, br, tr, tl])
        step = corners[[1, 2, 3, 0]] - corners
        outline = (corners[:, None, :] + _T5[None] * step[:, None, :]).reshape(-1, 2)
        # one projection for both: each edge's first sample (t = 0) is its corner
        pix = v.to_input(outline)
        lo_px, hi_px = pix.min(axis=0), pix.max(axis=0)
        box = (float(lo_px[0]), float(lo_px[1]), float(hi_px[0]), float(hi_px[1]))
        ends = pix[::5]
        lines: list[Line] = [
            (float(ends[a, 0]), float(ends[a, 1]), float(ends[b, 0]), float(ends[b, 1]))
            for a, b in ((0, 1), (3, 2), (0, 3), (1, 2))
        ]
        return Measurement(
            detected=True,
            method=self.name,
            range_m=range_m,
            distance_m=range_m,
            height_m=float(height_m),
            width_m=float(width_m),
            box_px=box,
            confidence=round(conf, 3),
            lines=lines,
            height_px=float(h_px),
            width_px=float(ur_f - ul_f),
        )

    @staticmethod
    def _bottom_profile(ay: F32, ba: float, bb: float, ul: int, ur: int) -> _BottomProfile | None:
        """The bottom edge's per-column peaks near its fitted line (v = ba + bb u).

        Both sides' side-face tests read the same profile: computed once for the two.
        """
        h, w = ay.shape
        c_lo, c_hi = max(ul - 2, 2), min(ur + 3, w - 2)
        cols = np.arange(c_lo, c_hi)
        if cols.size < 8:
            return None
        pred = ba + bb * cols
        r0 = np.round(pred).astype(np.intp)
        np.maximum(r0, 3, out=r0)
        np.minimum(r0, h - 4, out=r0)
        win = ay[r0[None, :] + _WIN7, cols[None, :]]  # 7 x n
        peak = np.argmax(win[1:-1], axis=0) + 1  # 1..5
        strength = win.ravel()[peak * cols.size + np.arange(cols.size)]
        pos = r0 - 3 + peak + _subpixel(win, peak)
        dev = pos - pred
        m = max(1, (ur - ul) // 4)
        # cols is consecutive: the centre columns are a slice
        centre = slice(max(0, ul + m - c_lo), max(0, ur - m - c_lo + 1))
        if strength[centre].size < 3:
            return None
        ref = _median(strength[centre])
        on = ((np.abs(dev) <= 0.8) & (strength >= 0.4 * ref)).tolist()
        return _BottomProfile(cols, strength, pos, dev, ref, on)

    def _side_face(
        self,
        ax: I16,
        bottom: _BottomProfile,
        ba: float,
        bb: float,
        ul: int,
        ur: int,
        vt: int,
        rb: int,
        direction: int,
        va: float,
        vb: float,
    ) -> tuple[float, float]:
        """The front face's vertical edge on one side, moved inwards past a side face.

        ``direction`` -1 for the left side, +1 for the right; (va, vb) is the fitted edge
        u = va + vb v, returned unchanged when no side face is seen.
        """
        w = ax.shape[1]
        cols, strength, pos, dev, ref, on = bottom
        mid = int(np.searchsorted(cols, (ul + ur) // 2))
        order = range(mid, -1, -1) if direction < 0 else range(mid, cols.size)
        end = mid
        off_run = 0
        for i in order:
            if on[i]:
                end, off_run = i, 0
            else:
                off_run += 1
                if off_run >= 2:
                    break
        edge_u = va + vb * rb
        end_u = float(cols[end])
        if (end_u - edge_u) * -direction < 1.5:  # the straight bottom reaches the edge
            return va, vb
        # the side face's bottom: strong, above the line, between the end and the edge
        if direction < 0:
            seg = (cols < end_u) & (cols >= edge_u - 0.5)
        else:
            seg = (cols > end_u) & (cols <= edge_u + 0.5)
        seg &= (strength >= 0.3 * ref) & (dev < -0.5)
        # the two columns just past the end must rise, and the rise must be a slope
        nxt = [end + direction, end + 2 * direction]
        if not all(0 <= i < cols.size and seg[i] for i in nxt):
            return va, vb
        # a side face's bottom runs on unbroken to the outer edge and ends clearly above
        # the front bottom line; noise on a low-contrast bottom edge does neither
        between = (cols - end_u) * direction > 0
        between &= (cols - edge_u) * direction <= 0.5
        n_between = np.count_nonzero(between)  # seg[between].mean() without the wrapper
        if n_between and np.count_nonzero(seg & between) / n_between < 0.6:
            return va, vb
        on_seg = np.nonzero(seg)[0]
        outer = on_seg[-3:] if direction > 0 else on_seg[:3]
        clear_rise = float(np.add.reduce(dev[outer])) / outer.size <= -1.5
        sa, sb = _lsq(cols[seg].astype(np.float64), pos[seg])
        if (sb - bb) * direction <= -0.15:  # rising outwards: meets the front bottom there
            corner_u = (sa - ba) / (bb - sb)
        elif float(dev[nxt[0]] + dev[nxt[1]]) / 2 < -1.0:  # a step up (blur merges the slope)
            corner_u = end_u + 0.5 * direction
        else:
            return va, vb
        if not (min(end_u, edge_u) - 1.0 <= corner_u <= max(end_u, edge_u) + 1.0):
            return va, vb
        # a vertical edge (front/side shading) near the corner gives the slope; else vertical
        mv = max(1, (rb - vt) // 10)
        rows = np.arange(vt + mv, rb - mv + 1)
        c = int(round(corner_u))
        if rows.size >= 3 and 3 <= c < w - 3:
            # .mean(axis=0) in float32, without the wrapper
            strip = np.add.reduce(ax[rows, c - 1 : c + 2], 0, dtype=np.float32) / rows.size
            edge_mean = np.add.reduce(ax[rows, int(round(edge_u))], dtype=np.float32) / rows.size
            if float(strip.max()) >= 0.25 * float(edge_mean):
                a2, b2 = self._fit_vertical(ax, rows, [c], w)[0]
                if abs((a2 + b2 * rb) - corner_u) <= 1.0:
                    return a2, b2
        if not clear_rise:  # no shading edge at the corner and only a slight rise
            return va, vb
        return corner_u - vb * rb, vb

    @staticmethod
    def _edge_end(ax3: I16, a: float, b: float, vt: int, rb: int) -> float | None:
        """Sub-pixel row where a vertical edge (u = a + b v) fades out going up.

        ``ax3`` is |d/dx| dilated over +-1 column (the edge's strength within a column).
        """
        h, w = ax3.shape
        lo = max(1, vt - 6)
        hi = min(rb - 2, vt + max(4, (rb - vt) // 2))
        if hi - lo < 6:
            return None
        rows = np.arange(lo, hi + 1)
        cols = np.round(a + b * rows).astype(np.intp)
        np.maximum(cols, 1, out=cols)  # np.clip's wrapper costs more than the work here
        np.minimum(cols, w - 2, out=cols)
        strength = ax3[rows, cols].astype(np.float32)  # cols are within 1..w-2: exact
        mid0 = vt + max(2, (rb - vt) // 4)
        ref_rows = strength[rows >= mid0]
        if ref_rows.size < 3:
            return None
        half = 0.5 * _median(ref_rows)
        # going up from the reference part, the first row below half strength that stays
        # below for two more rows (a dip where the background behind the side changes, from
        # floor to wall, is not the end); the scan in Python bools
        weak = (strength < half).tolist()
        for i in range(int(np.searchsorted(rows, mid0)) - 1, 0, -1):
            if weak[i] and not weak[i + 1] and all(weak[max(0, i - 2) : i]):
                frac = (half - strength[i]) / max(float(strength[i + 1] - strength[i]), 1e-6)
                return float(rows[i] + frac)
        return None

    @staticmethod
    def _fit_horizontal(
        edges: list[tuple[F32, int]], cols: npt.NDArray[np.intp], h: int
    ) -> list[tuple[float, float]]:
        """Lines v = a + b u through each (gradient image, row) edge's per-column peaks."""
        # 7 rows around each edge; the peak within +-1 row (cols are consecutive: a slice)
        u0 = int(cols[0]) if cols.size else 0
        windows = []
        for img, row in edges:
            r0 = int(_clamp(row - 3, 0, h - 7))
            windows.append((img[r0 : r0 + 7, u0 : u0 + cols.size], r0, max(1, row - 1 - r0)))
        return _fit_edges(windows, cols.astype(np.float64))

    @staticmethod
    def _fit_vertical(
        ax: I16, rows: npt.NDArray[np.intp], edge_cols: list[int], w: int
    ) -> list[tuple[float, float]]:
        """Lines u = a + b v through each vertical edge's per-row peaks near its column."""
        # rows are consecutive: a slice, not a gather
        v0 = int(rows[0]) if rows.size else 0
        windows = []
        for col in edge_cols:
            c0 = int(_clamp(col - 3, 0, w - 7))
            windows.append((ax[v0 : v0 + rows.size, c0 : c0 + 7].T, c0, max(1, col - 1 - c0)))
        return _fit_edges(windows, rows.astype(np.float64))
