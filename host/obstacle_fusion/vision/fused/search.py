"""Candidate search: where the face's floor-contact edge and its two sides may be.

Receives the working view's gradients (|d/dy| as float32, |d/dx| and its 1x3 dilation as
int16), the noise level and what the range predicts (the floor-contact row and its band,
the beam's columns at the face's depth). Returns the candidate floor-contact rows, each
with its prior (:func:`bottom_candidates`), and per row the side columns' presence tables
(:class:`Sides`) with the (left, right) pairs to score (:func:`side_candidates`).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.fused.profiles import (
    F32,
    I16,
    clamp,
    col_means,
    first_gap,
    int_threshold,
    late_run,
    local_maxima,
    mean,
    median,
    median_u8,
    next_true,
    running_counts,
)
from obstacle_fusion.vision.fused.tuning import (
    MAX_BOTTOM_CANDIDATES,
    MAX_SIDE_CANDIDATES,
    MIN_SIZE_M,
    PRESENCE_CAP,
)
from obstacle_fusion.vision.types import View

log = logging.getLogger(__name__)

_c_ramp_spans: Callable[[Any, list[int], int, int], list[tuple[int, int, int]]] | None
try:  # the optional C accelerator (setup.py): ramp_columns' walks; else numpy's
    from obstacle_fusion.vision.fused._cmiddle import ramp_spans as _c_ramp_spans
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_ramp_spans = None
_c_rank_sides: Callable[..., list[list[int]] | None] | None
try:  # (apart: an accelerator built before it still walks the ramps)
    from obstacle_fusion.vision.fused._cmiddle import rank_sides as _c_rank_sides
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_rank_sides = None
_c_line_columns: Callable[..., list[int]] | None
try:  # (apart, as rank_sides)
    from obstacle_fusion.vision.fused._cmiddle import line_columns as _c_line_columns
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_line_columns = None
_c_side_tables: Callable[..., list[int] | None] | None
try:  # (apart, as rank_sides)
    from obstacle_fusion.vision.fused._cmiddle import side_tables as _c_side_tables
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_side_tables = None


def beam_columns(view: View, range_m: float, depth: float, w_img: int) -> tuple[int, int]:
    """The columns the sonar's beam covers at the face's depth (at least 4 apart)."""
    v = view
    xb0, xb1 = v.rig.beam_x_bounds(range_m)
    u_lo = int(clamp(math.floor(v.cx + v.fx * xb0 / depth), 2, w_img - 3))
    u_hi = int(clamp(math.ceil(v.cx + v.fx * xb1 / depth), 2, w_img - 3))
    if u_hi - u_lo < 4:
        mid = (u_lo + u_hi) // 2
        u_lo, u_hi = max(2, mid - 2), min(w_img - 3, mid + 2)
    return u_lo, u_hi


def bottom_candidates(
    ay: F32, vb0: float, tol: float, r0b: int, r1b: int, u_lo: int, u_hi: int
) -> list[tuple[int, float]]:
    """Floor-contact rows to try, most likely first, each with its prior from the range.

    Peaks of the mean |d/dy| over the beam's columns within the predicted band
    [r0b, r1b], ranked by strength times a Gaussian prior about the predicted row vb0;
    the predicted row itself is always added.
    """
    # (a band of a few dozen rows: Python lists cost less than numpy's per-call overhead)
    prof = mean(ay[r0b : r1b + 1, u_lo : u_hi + 1], 1).tolist()
    n = len(prof)
    # local maxima of the profile padded with zeros: >= the row above, > the row below, > 0
    pk = [
        i
        for i, x in enumerate(prof)
        if x > 0.0 and x >= (prof[i - 1] if i else 0.0) and x > (prof[i + 1] if i + 1 < n else 0.0)
    ]
    if not pk:
        pk = [prof.index(max(prof))]
    rows = np.array(pk) + r0b
    prior = (0.5 + 0.5 * np.exp(-0.5 * ((rows - vb0) / max(tol / 2.0, 1.0)) ** 2)).tolist()
    order = sorted(range(len(pk)), key=lambda i: -(prof[pk[i]] * prior[i]))
    bottoms = [(r0b + pk[i], prior[i]) for i in order[:MAX_BOTTOM_CANDIDATES]]
    # the row the range predicts is always a candidate: a dark box on a dark floor
    # can leave its floor-contact edge too faint to peak
    predicted = int(round(vb0))
    if r0b <= predicted <= r1b and all(abs(rb - predicted) > 1 for rb, _ in bottoms):
        bottoms.append((predicted, 1.0))
    return bottoms


#: The short strip just above a floor-contact row over which the side columns' vertical
#: edges are read, metres at the face (a side stands right on the floor).
SHORT_STRIP_M = 0.05


def side_candidates(
    view: View,
    ax: I16,
    ax3: I16,
    rb: int,
    depth: float,
    noise: float,
    u_lo: int,
    u_hi: int,
    min_w: float,
    grey: npt.NDArray[np.uint8] | None = None,
    lab: Callable[[int, int], npt.NDArray[np.uint8] | None] | None = None,
    rig_known: bool = True,
    beside_seam: bool = False,
    seam_sides: list[int] | None = None,
) -> tuple[Sides, list[tuple[int, int]]] | None:
    """The side columns at floor-contact row ``rb``: their presence tables and the
    (left, right) pairs at least ``min_w`` apart, or None when no side stands there.
    ``grey``: the working view the gradients were taken of, ``lab``: its rows r0..r1-1 in
    8-bit Lab; with both, a column whose edge near the floor is a shading ramp between two
    shades of one colour (:func:`ramp_columns`) is no side; with ``rig_known`` (the camera's
    height and pitch given, not tried), where thin lines (:func:`line_columns`) took every
    ranked place of a side, the strongest other columns are its candidates too (where over
    LINE_MOST peaks are lines' edges, a pattern of joints, only those beyond its outermost
    lines: JOINT_PATTERN_ENDS); with ``beside_seam`` too, where a seam's edges take two of
    a side's places, the nearest peak beyond the seam (:func:`_beside_seam`). Such peaks
    are appended to ``seam_sides`` whether or not ``beside_seam`` is on (a caller reruns
    a miss with it on only where it would add a side)."""
    v = view
    k = int(clamp(round(v.fy * SHORT_STRIP_M / depth), 3, 25))
    top_strip = max(0, rb - 1 - k)
    if rb - 2 <= top_strip:
        return None
    # vertical-edge profiles over a short (5 cm) and a tall (25 cm) strip above the
    # bottom: a side may lack contrast against the floor yet not against the wall
    prof_short = col_means(ax[top_strip : rb - 1])
    prof_v = prof_short
    tall = max(0, rb - 1 - int(clamp(round(v.fy * 0.25 / depth), k, 4 * k + 8)))
    if tall < top_strip:
        prof_v = np.maximum(prof_short, col_means(ax[tall : rb - 1]))
    base = median(prof_v) + 0.5
    peaks = local_maxima(prof_v, max(2.5 * base, 1.5 * noise))
    if peaks.size < 2:
        log.debug("bottom %d: fewer than two vertical-edge peaks", rb)
        return None
    # presence thresholds from the strip nearest the floor, where the side may be
    # faint (a dark box on a dark floor) while its upper part is not
    left, right = _rank_sides(
        ax3,
        prof_v,
        prof_short,
        [peaks[peaks <= u_hi], peaks[peaks >= u_lo]],
        rb,
        noise,
        rb - 1 - tall,
    )
    if grey is not None and LINE_SIDES and rig_known and (set(left) | set(right)):
        # seams or joints on the face may take every ranked place of a side: the strongest
        # columns that are no such line are that side's candidates too (the seams stay:
        # widen_across_seams runs a seam pair's top out to the face's sides)
        lines = line_columns(grey[top_strip : rb - 1], [*left, *right])
        all_lines = [bool(cs) and all(c in lines for c in cs) for cs in (left, right)]
        if SEAM_TAKES_TWO and not all(all_lines) and (beside_seam or seam_sides is not None):
            # a seam's two edges in two of a side's places leave one for the true side,
            # which a floor joint beside the face may outrank: the face's shade runs out
            # from the seam to the face's side, the first edge beyond the seam that runs
            # up from the floor and is no line
            more_left, more_right = _beside_seam(
                grey[top_strip : rb - 1],
                ax3,
                prof_v,
                prof_short,
                peaks,
                lines,
                (left, right),
                rb,
                noise,
                rb - 1 - tall,
            )
            added = [c for c in more_left if c not in left]
            added += [c for c in more_right if c not in right]
            if seam_sides is not None:
                seam_sides.extend(added)
            if beside_seam and added:
                log.debug("bottom %d: sides beyond a seam %s", rb, added)
                left, right = more_left, more_right
        if any(all_lines):
            seen = {*left, *right}
            lines |= line_columns(
                grey[top_strip : rb - 1], [p for p in peaks.tolist() if p not in seen]
            )
        if any(all_lines) and (len(lines) <= LINE_MOST or JOINT_PATTERN_ENDS):
            rest = peaks[~np.isin(peaks, sorted(lines))]
            if len(lines) > LINE_MOST:
                # a pattern of joints (a brick or plank print) is lines all over the
                # face: not the strongest peaks between them (a brick's own edge) but
                # those beyond its outermost lines, where the pattern ends: its sides
                rest = rest[(rest < min(lines)) | (rest > max(lines))]
            more = _rank_sides(
                ax3,
                prof_v,
                prof_short,
                [rest[rest <= u_hi], rest[rest >= u_lo]],
                rb,
                noise,
                rb - 1 - tall,
            )
            log.debug(
                "bottom %d: lines %s on one shade, sides beside them %s", rb, sorted(lines), more
            )
            if all_lines[0]:
                left = [*left, *(c for c in more[0] if c not in left)]
            if all_lines[1]:
                right = [*right, *(c for c in more[1] if c not in right)]
    if grey is not None and lab is not None and RAMP_SIDES:
        ramps = ramp_columns(
            grey[top_strip : rb - 1], lambda: lab(top_strip, rb - 1), [*left, *right]
        )
        if ramps:
            log.debug("bottom %d: shading ramps %s are no sides", rb, sorted(ramps))
            left = [c for c in left if c not in ramps]
            right = [c for c in right if c not in ramps]
    log.debug("bottom %d: peaks %s, left %s, right %s", rb, peaks.tolist(), left, right)
    cols = sorted({*left, *right})
    if not cols:
        return None
    sides = Sides(ax3, cols, _presence(prof_short[cols].astype(np.float64), noise), rb)
    pairs = [(ul, ur) for ul in left for ur in right if ur - ul >= min_w]
    return sides, pairs


#: A side column is an edge of a thin line (a seam, a panel joint, a strip of tape running
#: up the face) when the shade LINE_BESIDE columns beyond it on both sides is one shade:
#: the two sides differ by at most LINE_SAME of the line's own contrast to them (and by no
#: more than LINE_SAME_MAX grey levels), the line's contrast at least LINE_CONTRAST.
LINE_SIDES = True
LINE_BESIDE = 4
LINE_SAME = 0.25
LINE_SAME_MAX = 8.0
LINE_CONTRAST = 12.0
#: Where a seam's two edges (two lines' edges) take two of a side's ranked places but not
#: all of them (LINE_SIDES stands aside), the nearest peak beyond the seam on that side
#: that is no line's edge and runs up from the floor is that side's candidate too: the
#: face's shade runs on from the seam to its side, and the one place left goes to a floor
#: joint or a step beside the face as often as to that side, weak where the face's shade
#: is near the floor's or the wall's (session 49). Only in a rerun of a miss with the rig
#: given (method.SEAM_MISS_RERUN): on every frame, its extra pairs moved the confidence of
#: right answers both ways by up to 0.5 (own procedural/702 ordinary 0.68 -> 0.24).
SEAM_TAKES_TWO = True
#: ... the peaks walked over beyond the seam, lines' edges (another seam) skipped.
SEAM_WALK_PEAKS = 4
#: ... where at most this many of the peaks are such lines' edges (two seams) ...
LINE_MOST = 8
#: ... and, where more are (a pattern of joints: a brick or plank print), the strongest
#: peaks beyond the pattern's outermost lines (where it ends) are (session 29, `rigphoto`)
JOINT_PATTERN_ENDS = True


def _beside_seam(
    strip: npt.NDArray[np.uint8],
    ax3: I16,
    prof_v: F32,
    prof_short: F32,
    peaks: npt.NDArray[np.intp],
    lines: set[int],
    sides: tuple[list[int], list[int]],
    rb: int,
    noise: float,
    late_rows: int,
) -> tuple[list[int], list[int]]:
    """The (left, right) candidates ``sides`` with, for a side two or more of whose places
    but not all are lines' edges (a seam's two edges), the nearest peak beyond the seam on
    that side (left of its leftmost line, right of its rightmost; at most SEAM_WALK_PEAKS
    peaks walked, lines' edges in ``strip`` skipped) added, where it runs up from the
    floor (:func:`_rank_sides`): the face's shade runs on from a seam to its side."""
    out = [sides[0], sides[1]]
    for i, cs in enumerate(sides):
        seam = [c for c in cs if c in lines]
        if len(seam) < 2 or len(seam) == len(cs):
            continue
        beyond = peaks[peaks < min(seam)][::-1] if i == 0 else peaks[peaks > max(seam)]
        walk = [int(c) for c in beyond.tolist()[:SEAM_WALK_PEAKS]]
        more = line_columns(strip, [c for c in walk if c not in lines])
        near = [c for c in walk if c not in lines and c not in more][:1]
        if not near or near[0] in cs:
            continue
        ranked = _rank_sides(
            ax3, prof_v, prof_short, [np.array(near, dtype=np.intp)], rb, noise, late_rows
        )[0]
        if ranked:
            out[i] = [*cs, *ranked]
    return out[0], out[1]


def line_columns(strip: npt.NDArray[np.uint8], cols: list[int]) -> set[int]:
    """Of ``cols``, the edges of a thin vertical line on one shade in ``strip`` (the rows
    just above the floor): a face's side parts two shades (the face's and what is beside
    it), a seam or joint on the face is the same shade either side of it."""
    if strip.shape[0] == 0 or not cols:
        return set()
    if (
        _c_line_columns is not None
        and strip.dtype == np.uint8
        and strip.ndim == 2
        and LINE_BESIDE >= 2
    ):
        # in one call of the C accelerator: the same float32 means, medians and contrasts
        return set(
            _c_line_columns(strip, cols, LINE_BESIDE, LINE_CONTRAST, LINE_SAME, LINE_SAME_MAX)
        )
    prof = strip.astype(np.float32).mean(axis=0)
    d = LINE_BESIDE
    c = np.array([c for c in cols if c - d - 2 >= 0 and c + d + 3 <= prof.size], dtype=np.intp)
    if c.size == 0:
        return set()
    # every column at once (a handful of calls, not five a column), one gather of the
    # columns -d-2..d+2 round each: the medians of three are the middle of their sorted
    # values, the line's contrast is taken in float32 as before
    win = prof[c[:, None] + np.arange(-d - 2, d + 3)]
    left = np.sort(win[:, :3], axis=1)[:, 1].astype(np.float64)
    right = np.sort(win[:, -3:], axis=1)[:, 1].astype(np.float64)
    mid = (0.5 * (left + right)).astype(np.float32)
    core = win[:, 4 : 2 * d + 1]
    contrast = np.abs(core - mid[:, None]).max(axis=1).astype(np.float64)
    same = np.abs(left - right)
    keep = (contrast >= LINE_CONTRAST) & (same <= np.minimum(LINE_SAME * contrast, LINE_SAME_MAX))
    return set(c[keep].tolist())


#: A side's edge across the rows just above the floor falls to half its peak within this
#: many columns (the optics and the 3x3 Sobel blur a face's edge over 3-4 columns); one
#: holding half its peak, one sign, over RAMP_COLUMNS or more is a shading ramp: a
#: shadow's penumbra on the floor beside the face, not a side.
RAMP_COLUMNS = 7
#: Ramps are told from sides (a switch for the tests).
RAMP_SIDES = True
#: Columns read beyond each end of a ramp for the shades' chroma ...
RAMP_BESIDE = 4
#: ... which differ by less than this (8-bit Lab a, b) for one colour's two shades.
RAMP_SAME_CHROMA = 6.0


def ramp_columns(
    strip: npt.NDArray[np.uint8],
    lab: npt.NDArray[np.uint8] | Callable[[], npt.NDArray[np.uint8] | None],
    cols: list[int],
) -> set[int]:
    """Of ``cols``, those where the strip (rows just above the floor) changes as a ramp
    between two shades of one colour: the signed difference across the column (its
    strongest within one column) stays at half of it or more, with its sign, over
    RAMP_COLUMNS columns or more, and the chroma beyond its two ends differs by less than
    RAMP_SAME_CHROMA (a shadow darkens the floor it falls on; a face's side blurred on a
    ramp of shading parts two colours). ``lab``: the strip's rows in 8-bit Lab, or a
    function giving them (called only once a ramp is seen; None for a grey frame)."""
    if strip.shape[0] == 0 or not cols:
        return set()
    w = strip.shape[1]
    if (
        _c_ramp_spans is not None
        and strip.ndim == 2
        and strip.dtype == np.uint8
        and all(0 <= c < w for c in cols)
    ):
        # the gradient walks in C (only the columns walked over get their median)
        spans = _c_ramp_spans(strip, cols, RAMP_COLUMNS, RAMP_BESIDE)
    else:
        spans = _ramp_spans(strip, cols)
    chroma: npt.NDArray[np.float32] | None = None
    out: set[int] = set()
    for c, a, b in spans:
        if chroma is None:
            block = lab() if callable(lab) else lab
            if block is None or block.shape[:2] != strip.shape:
                return set()  # a grey frame: no chroma to tell a shadow by
            chroma = median_u8(block[:, :, 1:], axis=0).astype(np.float32)  # W x 2
        before = np.median(chroma[a - RAMP_BESIDE : a], axis=0)
        after = np.median(chroma[b + 1 : b + 1 + RAMP_BESIDE], axis=0)
        if float(np.hypot(*(before - after))) < RAMP_SAME_CHROMA:
            out.add(c)
    return out


def _ramp_spans(strip: npt.NDArray[np.uint8], cols: list[int]) -> list[tuple[int, int, int]]:
    """:func:`ramp_columns`' walks in numpy (the C accelerator's ``ramp_spans`` takes the
    same): (column, first, last) of each of ``cols`` (in order) whose gradient holds half
    its peak, with its sign, over RAMP_COLUMNS or more, RAMP_BESIDE columns left beyond
    both ends. ``strip``: at least one row."""
    # per row, then the median over the rows: a line slanting across the strip (a floor
    # seam) is a step in a few rows at each column, a penumbra a ramp in every row
    d = strip[:, 2:].astype(np.int16) - strip[:, :-2].astype(np.int16)
    g = np.zeros(strip.shape[1], np.float32)
    g[1:-1] = np.median(d, axis=0)
    w = g.size
    spans = []
    for c in cols:
        lo, hi = max(c - 1, 0), min(c + 2, w)
        k = lo + int(np.argmax(np.abs(g[lo:hi])))
        peak = float(g[k])
        if peak == 0.0:
            continue
        half = 0.5 * abs(peak)
        sg = 1.0 if peak > 0 else -1.0
        a = k
        while a - 1 >= 0 and sg * float(g[a - 1]) >= half:
            a -= 1
        b = k
        while b + 1 < w and sg * float(g[b + 1]) >= half:
            b += 1
        if b - a + 1 < RAMP_COLUMNS or a - RAMP_BESIDE < 0 or b + RAMP_BESIDE >= w:
            continue
        spans.append((c, a, b))
    return spans


def min_width_px(view: View, depth: float) -> float:
    """The narrowest pair of sides, in pixels, for a face of MIN_SIZE_M at this depth."""
    return max(4.0, view.fx * MIN_SIZE_M / depth)


def _presence(strength: Any, noise: float) -> Any:
    """Threshold for a side's edge rows: a quarter of its strength near the floor, capped.

    The cap matters where the background changes along the side (floor, then another box,
    then the wall): the side's contrast there can be a fraction of that near the floor.
    """
    return np.maximum(np.minimum(0.25 * strength, PRESENCE_CAP * noise), 2.5 * noise)


class Sides:
    """Candidate vertical edge columns at one floor-contact row: per-row presence tables.

    One column of each table per candidate column, built in one pass for all of them
    (per-column arrays cost more in numpy call overhead than in work). Counts are exact
    integers, so they are the per-column values whatever the summation order. With the C
    accelerator, all the tables in one call of it (``side_tables``: the same values,
    dtypes and shapes; numpy's where it declines).
    """

    __slots__ = ("index", "below", "upto", "nxt", "run_top", "out", "out_left", "out_right", "csum")

    def __init__(
        self, ax3: I16, cols: list[int], thresholds: npt.NDArray[np.float64], rb: int
    ) -> None:
        k = len(cols)
        w = ax3.shape[1]
        self.index = {col: i for i, col in enumerate(cols)}
        self.out_left = [k + i if cols[i] >= 4 else -1 for i in range(k)]
        self.out_right = [2 * k + i if cols[i] + 4 < w else -1 for i in range(k)]
        if (
            _c_side_tables is not None
            and ax3.dtype == np.int16
            and ax3.ndim == 2
            and 0 < rb <= ax3.shape[0]
            and k > 0
            and thresholds.dtype == np.float64
            and thresholds.shape == (k,)
        ):
            counts = np.empty((rb + 1, 3 * k + 1), np.int32)
            below = np.empty((rb, k), np.int32)
            nxt = np.empty((rb, k), np.intp)
            csum: npt.NDArray[Any] = np.empty((rb + 1, k), np.float64)
            run_top = _c_side_tables(ax3, cols, thresholds, rb, counts, below, nxt, csum)
            if run_top is not None:
                self.upto, self.below, self.out = counts[:, :k], below, counts
                self.nxt, self.run_top, self.csum = nxt, run_top, csum
                return
        c = np.array(cols, np.intp)
        # the side columns, then the columns just outside (4 px) as the left or right
        # side, at the side's threshold: background texture there says the edges above
        # a top are not the side's own
        vals = ax3[:rb, np.concatenate([c, np.maximum(c - 4, 0), np.minimum(c + 4, w - 1)])]
        on_all = vals > int_threshold(thresholds, 3)
        on = on_all[:, :k]
        # edge rows in 0..r-1 for all 3k columns; a last column of zeros for a side with
        # no column outside it
        counts = running_counts(on_all, extra=1)
        self.upto = counts[:, :k]
        self.below = self.upto[rb] - self.upto[:rb]  # edge rows in r..rb-1
        self.out = counts  # columns k..2k-1 outside left, 2k..3k-1 outside right
        # first edge row at or below r (rb if none): the hole under a top candidate
        self.nxt = next_true(on, rb)
        # top row of the edge run from the floor-contact row (gaps under 3 rows)
        if rb - 1 < 3:
            self.run_top = [rb - 1] * k
        else:
            self.run_top = (rb - 1 - first_gap(on[: rb - 1][::-1])).tolist()
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
    run lengths of all groups' strongest columns are found in one pass. With the C
    accelerator, in one call of it (``rank_sides``: the same lists; it leaves to numpy
    the rankings where two equal values could go either way in numpy's sort, which is
    not stable, and a Python float ``noise`` only: numpy rounds it to float32 so).
    """
    if (
        _c_rank_sides is not None
        and type(noise) is float
        and ax3.dtype == np.int16
        and ax3.ndim == 2
        and prof_v.dtype == np.float32
        and prof_short.dtype == np.float32
        and all(g.dtype == np.intp and g.ndim == 1 for g in groups)
    ):
        ranked = _c_rank_sides(
            ax3,
            prof_v,
            prof_short,
            groups,
            rb,
            PRESENCE_CAP * noise,
            2.5 * noise,
            late_rows,
            MAX_SIDE_CANDIDATES,
        )
        if ranked is not None:
            return ranked
    return _rank_sides_numpy(ax3, prof_v, prof_short, groups, rb, noise, late_rows)


def _rank_sides_numpy(
    ax3: I16,
    prof_v: F32,
    prof_short: F32,
    groups: list[npt.NDArray[np.intp]],
    rb: int,
    noise: float,
    late_rows: int = 0,
) -> list[list[int]]:
    """:func:`_rank_sides` in numpy."""
    chosen = [g[(-prof_v[g]).argsort()][: 3 * MAX_SIDE_CANDIDATES] for g in groups]
    cols_all = np.concatenate(chosen)
    if cols_all.size == 0:
        return [[] for _ in groups]
    col_vals = ax3[: rb - 1, cols_all][::-1]  # rows going up from the bottom
    on = col_vals > int_threshold(_presence(prof_short[cols_all], noise))
    # run length: rows up to the first gap of 3 consecutive misses
    run_len = first_gap(on)
    rank_all = prof_v[cols_all] * np.sqrt(np.maximum(run_len, 1))
    # A box in the floor's own shade shows its sides only against the wall: an edge
    # run that starts higher up (within the tall strip) counts too, but ranks below
    # every run from the floor, so it only fills the places those leave free.
    # (only the columns with no run from the floor need their late run: the same values)
    short = (run_len < 3).nonzero()[0]
    late = np.zeros(run_len.size, np.intp)
    if short.size:
        late[short] = late_run(on[:, short], late_rows)
    only_late = late >= 3  # late is 0 wherever a run from the floor exists
    if only_late.any():
        late_rank = prof_v[cols_all] * np.sqrt(np.maximum(late, 1))
        below_all = float(late_rank.max()) + 1.0  # every late rank ends up negative
        rank_all = np.where(only_late, late_rank - below_all, rank_all)
        run_len = np.where(only_late, late, run_len)
    ranked = []
    start = 0
    for cols in chosen:
        end = start + cols.size
        keep = run_len[start:end] >= 3
        order = (-rank_all[start:end][keep]).argsort()[:MAX_SIDE_CANDIDATES]
        ranked.append([int(c) for c in cols[keep][order]])
        start = end
    return ranked
