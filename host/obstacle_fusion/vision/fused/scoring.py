"""Pair and face scoring: which (floor-contact row, left, right, top) is the face.

Receives, per floor-contact row, the gradients, the working view's grey image, the side
columns' presence tables (:class:`~obstacle_fusion.vision.fused.search.Sides`) and the
(left, right) pairs to score. Returns one :class:`Candidate` per pair with its best top
row (:func:`score_pairs`: edge strength, side coverage and stop, the face's own shade
whole and band by band, texture inside); then :func:`verified` drops the best candidates
whose sides lean towards the vanishing point (floor seams) and returns the face and its
rivals for the confidence figure.
"""

from __future__ import annotations

import dataclasses
import logging
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.fused.profiles import (
    F32,
    I16,
    VerticalFits,
    clamp,
    grey_range_sums,
    next_true,
    partitioned,
    range_sums,
    running_counts,
)
from obstacle_fusion.vision.fused.search import Sides
from obstacle_fusion.vision.fused.tuning import (
    BAND_SHARE,
    BANDS,
    HOLE_SHARE,
    LABEL_BLUR_ROWS,
    LABEL_SHARE,
    LEAN_MIN,
    MAX_VERIFIED,
    MIN_SIZE_M,
    RADIAL_MIN,
)
from obstacle_fusion.vision.types import View

log = logging.getLogger(__name__)

#: With the rig given, the floor-contact row is predicted from the range: a face of the
#: floor's own shade (a pink board on a pink floor) stands there with no foot edge to see,
#: and the pair gate (sides times the weaker of top and foot) refused it. Where the sides
#: are clear (FOOT_FROM_RIG_SIDE noise levels, down to the predicted row) and the face
#: stands at least FOOT_FROM_RIG_MIN_M tall (a short pair with no foot is a mark on a
#: print, not a face), the top edge read at FOOT_FROM_RIG_SHARE of its strength stands in
#: for the foot (its best among the pair's tops scoring FOOT_FROM_RIG_NEAR of the best).
FOOT_FROM_RIG = True
FOOT_FROM_RIG_SIDE = 4.0
FOOT_FROM_RIG_MIN_M = 0.1
FOOT_FROM_RIG_SHARE = 0.5
FOOT_FROM_RIG_NEAR = 0.5
#: ... and only on a row within FOOT_FROM_RIG_ROW of the band's half-height of the row the
#: rig predicts (the bottoms' prior >= 0.8; a row next to the predicted one is always
#: tried): a row further off stands in for a foot the rig does not predict. Own photo 741
#: hard (rig, panels on gravel): its faint foot at 239-240, the rig's at 239.1; the pair
#: let in on row 235 (4.1 rows off, 5.4 the half-height), 4 rows up inside the face, went
#: h -0.2 -> +5.6 % at 0.273 -> 0.083; new3 photo 3113 hard (rig): row 232 for 236.0,
#: h -0.8 -> -16.7 % (review j, session 50).
FOOT_FROM_RIG_ROW = 0.5
#: The pair gate: each side PAIR_SIDE_MIN noise levels, the weaker of top and foot
#: PAIR_HORIZ_MIN, their product PAIR_PRODUCT_MIN.
PAIR_SIDE_MIN = 2.0
PAIR_HORIZ_MIN = 1.0
PAIR_PRODUCT_MIN = 6.0

_c_score_tops: Callable[..., int] | None
try:  # the optional C accelerator (setup.py): score_pairs' top candidates in one call
    from obstacle_fusion.vision.fused._cmiddle import score_tops as _c_score_tops
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_score_tops = None

#: Features of the top candidates the C accelerator returns, as rows of its float64,
#: float32 and int32 outputs (``score_tops``).
_C_F64 = ("cov", "stop", "hole", "textured", "tex_above", "face", "face_above", "face_bands")
_C_F32 = ("snr", "contained")
_C_I32 = ("up_l", "up_r")


def _face_term(face: Any, bands: Any) -> Any:
    """The face-shade share's weight: squared, and cut where one column band's share
    falls under BAND_SHARE of the whole face's (that band covers floor or wall)."""
    return face**2 * np.minimum(1.0, bands / np.maximum(BAND_SHARE * face, 1e-6)) ** 2


def _face_shade(means: F32, rb: int, kf: int) -> F32:
    """Per column, the face's own shade: the median of the kf row means starting 3 rows
    above the floor-contact row (clear of the bottom edge's blur)."""
    return partitioned(means[rb - 3 - kf : rb - 3], kf // 2, axis=0)[kf // 2]


def _first_match(match: npt.NDArray[np.bool_], rb: int) -> npt.NDArray[np.intp]:
    """Per column, the first row at or below each row in the face's shade (rb if none)."""
    return next_true(match, rb)


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
    label = (ft - tops <= LABEL_BLUR_ROWS) & (inner <= LABEL_SHARE * h_t)
    return np.where(label, share + inner / h_t, share)


@dataclass(frozen=True)
class Candidate:
    """A face hypothesis: floor-contact row, side columns, top row, and its scores."""

    score: float  # for choosing among candidates
    rb: int
    ul: int
    ur: int
    vt: int
    evidence: float  # 0..1: shape fit and edge strength, before ambiguity
    #: a higher top where the sides end (see :func:`closing_top`), or None
    closing: int | None = None
    #: the top of a clean outline of this pair (see :func:`outline_tops`), or None,
    #: with the evidence of that outline alone
    outline: int | None = None
    outline_evidence: float = 0.0
    #: the closing top passed the texture condition only because the texture ends at it
    #: (PRINT_ENDS_TEXTURE: a print over the face up to its top)
    print_top: bool = False
    #: the evidence of the face closed at ``closing`` alone (its shape fit without the
    #: face-shade terms, as an outline's)
    closing_evidence: float = 0.0
    #: the evidence with the face's texture left out, for a face textured from its foot
    #: up over PRINT_COVERS_FACE of its rows (a print of its own); else the evidence
    print_evidence: float = 0.0
    #: the pair passed the gate only with the rig's predicted contact row standing in for
    #: a foot edge too faint to see (FOOT_FROM_RIG)
    foot_unseen: bool = False

    def overlap(self, other: Candidate) -> float:
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


def sides_vertical(view: View, ax: I16, cand: Candidate, fits: VerticalFits | None = None) -> bool:
    """False when a side leans the way a floor line through its foot would.

    In the levelled view every vertical world edge is an image column; a seam or
    plank edge on the floor through (u, v) runs towards the vanishing point, at
    du/dv = (u - cx) / (v - cy). Near the centre column the two look alike: then true.
    ``fits``: the frame's side fits over ``ax``, kept for the refinement.
    """
    v = view
    below = cand.rb - v.cy
    if below <= 5.0:
        return True
    mv = max(1, (cand.rb - cand.vt) // 10)
    rows = np.arange(cand.vt + mv, cand.rb - mv + 1)
    if rows.size < 5:
        return True
    fit = fits if fits is not None else VerticalFits(ax)
    for a, b in fit(rows, [cand.ul, cand.ur], ax.shape[1]):
        radial = (a + b * cand.rb - v.cx) / below
        if abs(radial) >= RADIAL_MIN and abs(b) >= LEAN_MIN and abs(b - radial) < 0.5 * abs(radial):
            return False
    return True


#: A face textured over at least this share of its rows (so down to its foot) bears a
#: print of its own, a brick or tile pattern (:attr:`Candidate.print_evidence`).
PRINT_COVERS_FACE = 0.8


def pair_passes(side: float, horiz: float) -> bool:
    """The pair gate: clear sides, and a top and foot clear enough beside them."""
    return side >= PAIR_SIDE_MIN and horiz >= PAIR_HORIZ_MIN and side * horiz >= PAIR_PRODUCT_MIN


def foot_from_rig(side: float, horiz: float, top_snr: float, height_m: float) -> float:
    """The weaker of top and foot for the pair gate where the rig predicts the foot's row
    (FOOT_FROM_RIG): the top at FOOT_FROM_RIG_SHARE of its strength when the foot edge is
    too faint but the sides are clear and the face is tall enough; else ``horiz``."""
    if not FOOT_FROM_RIG or side < FOOT_FROM_RIG_SIDE or height_m < FOOT_FROM_RIG_MIN_M:
        return horiz
    return max(horiz, min(top_snr, 30.0) * FOOT_FROM_RIG_SHARE)


def foot_stand_in(
    side: float, top_term: float, foot: float, near: float, height_m: float
) -> tuple[float, bool]:
    """The weaker of top and foot for the pair gate, the foot from the rig where only the
    foot fails the gate (FOOT_FROM_RIG: :func:`foot_from_rig` with the top ``near``), and
    whether it stood in. Where the top term (``top_term``) fails the gate on its own, the
    pair is no clear face whatever its foot: nothing stands in (review j, session 50:
    before, a faint top on a seen foot was let in on another top's strength, its doubt
    ``foot_unseen``)."""
    horiz = min(top_term, foot)
    if pair_passes(side, horiz) or not pair_passes(side, top_term):
        return horiz, False
    read = foot_from_rig(side, horiz, near, height_m)
    return read, read != horiz


def near_top_snr(scores: npt.NDArray[Any], snrs: npt.NDArray[Any]) -> float:
    """The strongest of a pair's tops (``snrs``) among those scoring at least
    FOOT_FROM_RIG_NEAR of its best score (``scores``): the top the score chose may be a
    faint line above the face (FOOT_FROM_RIG); 0 when none (no tops)."""
    if scores.size == 0:
        return 0.0
    near = scores >= FOOT_FROM_RIG_NEAR * scores.max()
    return float(snrs[near].max()) if near.any() else 0.0


def on_rigs_row(rb: int, vb0: float, tol: float) -> bool:
    """Whether the floor-contact row ``rb`` is the rig's for FOOT_FROM_RIG: within
    FOOT_FROM_RIG_ROW of the band's half-height ``tol`` of the predicted row ``vb0``."""
    return abs(rb - vb0) <= FOOT_FROM_RIG_ROW * tol


def score_pairs(
    view: View,
    depth: float,
    grey: npt.NDArray[np.uint8],
    ax3: I16,
    ay: F32,
    sides: Sides,
    pairs: list[tuple[int, int]],
    noise: float,
    rb: int,
    prior_b: float,
    foot_known: bool = False,
) -> list[Candidate]:
    """Score every (left, right) pair at one floor-contact row, each with its best top.

    All pairs' top candidates are scored in one flat pass (pair-major, rows ascending:
    the order a per-pair loop would see them in); the candidates come back in the order
    of ``pairs``. Row sums of integer gradients are exact in float32, so they are the
    per-pair values bit for bit. ``foot_known``: ``rb`` is the contact row the given rig
    predicts from the range (FOOT_FROM_RIG may then excuse a faint foot edge).
    """
    min_h = max(3, int(view.fy * MIN_SIZE_M / depth))
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
    sides_at = [(sides.index[p[0]], sides.index[p[1]]) for p in ps]
    h_t: npt.NDArray[np.intp]
    if _c_score_tops is not None:
        found = _tops_in_c(grey, ax3, ay, sides, ps, sides_at, noise, rb, top_limit, min_h)
    else:
        found = _tops_in_numpy(grey, ax3, ay, sides, ps, sides_at, noise, rb, top_limit, min_h)
    if found is None:
        return []
    tops, pp, feats = found
    h_t = rb - tops
    # A hole is a top face only if one fits there: a top face shows below the horizon
    # and spans at most (t - cy) * 2 m / D rows (a box up to 2 m long). A longer hole is
    # a side losing contrast against the background, a milder fault.
    hole = feats["hole"]
    hole_max = np.maximum(0.0, (tops - view.cy) * 2.0 / depth) + 1.0
    soft = np.exp(-hole / np.maximum(4.0, HOLE_SHARE * h_t))
    feats["hole_fit"] = np.where(hole <= hole_max, np.exp(-hole / 2.0), soft)
    snr_tops, stop, textured = feats["snr"], feats["stop"], feats["textured"]
    cov, contained, face_frac, face_above = (
        feats["cov"],
        feats["contained"],
        feats["face"],
        feats["face_above"],
    )
    w_ay = ay.shape[1]
    score_t, fit = _top_score(feats)
    o_ok, o_fit = outline_tops(feats)
    # the bottom edge's strength between the sides (max over +-1 row), per pair
    m3 = np.zeros(w_ay + 1, np.float32)  # exact: integers under 2**24
    np.maximum.reduce(ay[rb - 1 : rb + 2], axis=0).cumsum(out=m3[1:])
    bounds = pp.searchsorted(np.arange(n_p + 1)).tolist()
    debug = log.isEnabledFor(logging.DEBUG)
    csum_s = sides.csum
    cands: list[Candidate] = []
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
        i = s0 + int(score_t[s0:s1].argmax())
        vt = int(tops[i])
        snr_b = float(np.float32(m3[c1] - m3[c0]) * (1.0 / (c1 - c0))) / noise
        inv_h = 1.0 / (rb - vt)
        a, b = sides_at[j]
        snr_l = float(np.float32(csum_s[rb, a] - csum_s[vt, a]) * inv_h) / noise
        snr_r = float(np.float32(csum_s[rb, b] - csum_s[vt, b]) * inv_h) / noise
        side = min(snr_l, snr_r, 30.0)
        top_term = min(max(float(snr_tops[i]), 2.0 * float(stop[i])), 30.0)
        horiz = min(top_term, snr_b)
        unseen = False
        if foot_known and not pair_passes(side, horiz):
            # the rig's contact row stands in for a foot edge the face's shade hides
            read, unseen = foot_stand_in(
                side,
                top_term,
                snr_b,
                near_top_snr(score_t[s0:s1], snr_tops[s0:s1]),
                (rb - vt) * depth / view.fy,
            )
            if unseen:
                log.debug(
                    "pair %d-%d at %d: foot from the rig, %.1f for %.1f", ul, ur, rb, read, horiz
                )
                horiz = read
        if not pair_passes(side, horiz):
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
        print_ev = evidence
        if float(textured[i]) >= PRINT_COVERS_FACE:
            # a print over the whole face down to its foot (a brick or tile pattern): the
            # evidence its shape fit gives without the texture term
            fit_p = fit_i / max(1e-6, 1.0 - float(textured[i]))
            print_ev = evidence * math.sqrt(
                min(1.0, 2.0 * fit_p) / max(1e-12, min(1.0, 2.0 * fit_i))
            )
        closing = closing_top(feats, tops, s0, s1, i, view.cy)
        print_top = False
        c_ev = 0.0
        if closing is not None:
            kc = s0 + int(np.flatnonzero(tops[s0:s1] == closing)[0])
            print_top = bool(textured[kc] > textured[i] + TEXTURE_MARGIN)
            c_ev = _edge_evidence(csum_s, rb, closing, a, b, noise, float(snr_tops[kc]), snr_b)
            c_ev *= math.sqrt(min(1.0, 2.0 * float(o_fit[kc]))) * (0.5 + 0.5 * prior_b)
        if debug and closing is not None:
            log.debug("  pair %d-%d rb %d top %d: closing top %d", ul, ur, rb, vt, closing)
        outline, o_ev = None, 0.0
        ok = o_ok[s0:s1].nonzero()[0]
        if ok.size:
            k = s0 + int(ok[o_fit[s0 + ok].argmax()])
            kt = int(tops[k])
            inv_k = 1.0 / (rb - kt)
            sl = float(np.float32(csum_s[rb, a] - csum_s[kt, a]) * inv_k) / noise
            sr = float(np.float32(csum_s[rb, b] - csum_s[kt, b]) * inv_k) / noise
            hk = min(float(snr_tops[k]), snr_b, 30.0)
            sk = min(sl, sr, 30.0)
            if sk >= OUTLINE_SNR and hk >= OUTLINE_SNR:
                outline = kt
                o_ev = (
                    math.sqrt(min(1.0, 2.0 * float(o_fit[k])))
                    * (1.0 - math.exp(-min(sk, hk) / 4.0))
                    * (0.5 + 0.5 * prior_b)
                )
                if debug:
                    log.debug(
                        "  pair %d-%d rb %d: outline top %d (fit %.2f)",
                        ul,
                        ur,
                        rb,
                        kt,
                        float(o_fit[k]),
                    )
        cands.append(
            Candidate(
                score,
                rb,
                ul,
                ur,
                vt,
                clamp(evidence, 0.0, 1.0),
                closing,
                outline,
                clamp(o_ev, 0.0, 1.0),
                print_top,
                clamp(c_ev, 0.0, 1.0),
                clamp(print_ev, 0.0, 1.0),
                unseen,
            )
        )
    return cands


def _tops_in_numpy(
    grey: npt.NDArray[np.uint8],
    ax3: I16,
    ay: F32,
    sides: Sides,
    ps: list[tuple[int, int, int, int]],
    sides_at: list[tuple[int, int]],
    noise: float,
    rb: int,
    top_limit: int,
    min_h: int,
) -> tuple[npt.NDArray[np.intp], npt.NDArray[np.intp], dict[str, npt.NDArray[Any]]] | None:
    """score_pairs' top candidates (pair-major, rows ascending: rows and pair indices) and
    their features in numpy (all but ``hole_fit``); None when there are none."""
    n_p = len(ps)
    w_ay = ay.shape[1]
    il = np.array([a for a, _ in sides_at], np.intp)
    ir = np.array([b for _, b in sides_at], np.intp)
    inv_n = np.array([1.0 / (p[3] - p[2]) for p in ps], np.float32)
    # mean |d/dy| between the sides for every row above the smallest face (row sums of
    # integers: exact, the per-pair values bit for bit)
    ranges = [(c0, c1) for _, _, c0, c1 in ps]
    prof = range_sums(ay[:top_limit], ranges) * inv_n
    # the grey row sums between the sides and over each side's column bands, from one
    # integral (exact integer sums: the same values as one integral per call)
    bands = band_ranges(ps)
    grey_sums = grey_range_sums(grey[:rb], np.concatenate([np.array(ranges, np.intp), bands]))
    row_sum = grey_sums[:, :n_p]
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
    pp, tops = mask.T.nonzero()  # pair-major, rows ascending within a pair
    if tops.size == 0:
        return None
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
    o_inv = np.array([(1.0 / (o[1] - o[0]), 1.0 / (o[3] - o[2])) for o in o_cols], np.float32)
    # row sums over each pair's two outside ranges at the top rows (exact in float32:
    # integers under 2**24), both ranges of every pair in one pass (each range is at
    # least one column wide)
    o_ranges = [(o[k] - o_lo, o[k + 1] - o_lo) for o in o_cols for k in (0, 2)]
    o_sums = range_sums(ay[tops, o_lo:o_hi], o_ranges)  # T x 2 pairs
    at_top = np.arange(tops.size)
    inv_t = o_inv[pp]
    o_l = o_sums[at_top, 2 * pp] * inv_t[:, 0]
    o_r = o_sums[at_top, 2 * pp + 1] * inv_t[:, 1]
    prof_tops = prof[tops, pp]
    inside = np.maximum(prof_tops, 1e-3)
    contained = np.minimum(np.maximum(1.0 - np.maximum(o_l, o_r) / inside, 0.0), 1.0)
    # texture inside the face (books on a shelf behind a box's top) is not the face
    # (rows from the highest top candidate down: counts are exact whatever the start)
    t0 = int(above_start.min())
    tex = range_sums(ax3[t0:rb], ranges) * inv_n
    flags = np.zeros((rb, 2 * n_p), bool)  # face shade (below) and texture per row
    flags[t0:, n_p:] = tex > 3.0 * noise
    # rows whose inside has the face's own shade (measured just above the floor): a
    # shelf of books or a poster over the box does not, a box's face does (but for a
    # stripe across it, or its top face)
    row_sum *= inv_n
    kf = max(2, min(8, min_h // 2))  # within the smallest face the method looks for
    face = _face_shade(row_sum, rb, kf)
    tol = np.maximum(np.float32(8.0), (0.08 * face.astype(np.float64)).astype(np.float32))
    match_b = np.abs(row_sum - face) <= tol
    flags[:, :n_p] = match_b
    counts = running_counts(flags)  # rows in 0..r-1 (exact counts)
    match_upto, tex_upto = counts[:, :n_p], counts[:, n_p:]
    textured = (tex_upto[rb, pp] - tex_upto[tops, pp]) / h_t
    # the same share over the rows just above each top (as many as ``above`` reads)
    tex_above = (tex_upto[tops, pp] - tex_upto[above_start, pp]) / n_above
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
    face_bands = band_face_share(grey, ps, tops, pp, rb, kf, noise, grey_sums[:, n_p:], bands)
    snr_tops = snr[tops, pp]
    feats = {
        "face_bands": face_bands,
        "snr": snr_tops,
        "hole": hole,
        "cov": cov,
        "stop": stop,
        "contained": contained,
        "textured": textured,
        "tex_above": tex_above,
        "face": face_frac,
        "face_above": face_above,
        # each side's edge rows above each top candidate (rows 0..top-1): the rows a side
        # runs on between two tops (closing_top)
        "up_l": upto[tops, tl],
        "up_r": upto[tops, tr],
    }
    return tops, pp, feats


def _tops_in_c(
    grey: npt.NDArray[np.uint8],
    ax3: I16,
    ay: F32,
    sides: Sides,
    ps: list[tuple[int, int, int, int]],
    sides_at: list[tuple[int, int]],
    noise: float,
    rb: int,
    top_limit: int,
    min_h: int,
) -> tuple[npt.NDArray[np.intp], npt.NDArray[np.intp], dict[str, npt.NDArray[Any]]] | None:
    """:func:`_tops_in_numpy` in one call of the C accelerator (``score_tops``): the same
    candidates and the same values, bit for bit (its float32 and float64 operations are
    numpy's, in numpy's order)."""
    assert _c_score_tops is not None
    n_p = len(ps)
    run_top = sides.run_top
    pairs = np.array(
        [
            (ul, ur, c0, c1, a, b, run_top[a], run_top[b], *sides.background(a, b))
            for (ul, ur, c0, c1), (a, b) in zip(ps, sides_at, strict=True)
        ],
        np.intp,
    )
    cap = top_limit * n_p
    tops, pp = np.empty(cap, np.intp), np.empty(cap, np.intp)
    f64 = np.empty((len(_C_F64), cap))
    f32 = np.empty((len(_C_F32), cap), np.float32)
    i32 = np.empty((len(_C_I32), cap), np.int32)
    kf = max(2, min(8, min_h // 2))
    n = _c_score_tops(
        ay,
        ax3,
        sides.out,
        sides.nxt,
        grey,
        pairs,
        BANDS,
        noise,
        rb,
        top_limit,
        kf,
        LABEL_BLUR_ROWS,
        LABEL_SHARE,
        tops,
        pp,
        f64,
        f32,
        i32,
    )
    if n == 0:
        return None
    feats: dict[str, npt.NDArray[Any]] = {k: f64[i, :n] for i, k in enumerate(_C_F64)}
    feats.update({k: f32[i, :n] for i, k in enumerate(_C_F32)})
    feats.update({k: i32[i, :n] for i, k in enumerate(_C_I32)})
    return tops[:n], pp[:n], feats


def _edge_evidence(
    csum_s: Any, rb: int, top: int, a: int, b: int, noise: float, snr_top: float, snr_b: float
) -> float:
    """How clearly a face's edges from ``top`` down to ``rb`` stand out (0..1): its weaker
    side and its weaker horizontal edge, in noise levels (side columns a and b of the
    side tables' running sums ``csum_s``)."""
    inv = 1.0 / (rb - top)
    sl = float(np.float32(csum_s[rb, a] - csum_s[top, a]) * inv) / noise
    sr = float(np.float32(csum_s[rb, b] - csum_s[top, b]) * inv) / noise
    return 1.0 - math.exp(-min(sl, sr, snr_top, snr_b, 30.0) / 4.0)


#: A higher top candidate closes the face (:func:`closing_top`) where the sides stop:
#: its stop (1 - the share of the rows above it where the sides run on) is at least this ...
CLOSED_STOP = 0.9
#: ... and the chosen top's stop this much lower (the sides run on above the chosen top) ...
STOP_MARGIN = 0.1
#: ... both sides present over at least this share of its rows down to the floor ...
CLOSING_COVERAGE = 0.75
#: ... its edge at least this many noise levels strong ...
CLOSING_SNR = 3.0
#: ... and at least this share of the chosen top edge's strength ...
CLOSING_SNR_SHARE = 0.4
#: ... ending at the sides at most this much less clearly than the chosen top edge ...
CONTAINED_MARGIN = 0.1
#: ... with the sides present under it (a hole's fit at least this) ...
CLOSING_HOLE_FIT = 0.5
#: ... its rows at most this much more textured than the chosen face's (unless the
#: texture ends at it: PRINT_ENDS_TEXTURE) ...
TEXTURE_MARGIN = 0.3
#: ... or the rows just above it at most this share textured: a print over the face
#: (texture inside) ends at the face's top, the background above it is plain (a brick
#: pattern's joint or a shelf's books have the same texture above it as below) ...
PRINT_ENDS_TEXTURE = 0.1
#: ... and the face's shade coming back above it over at most this share of the rows.
CLOSING_FACE_ABOVE = 0.2
#: Each side on its own runs on over at least this share of the rows between the chosen
#: top and the closing one (the weaker side, not the two sides' mean): a print across the
#: face leaves both of the face's sides standing above it (a gloss band may fade one of
#: them over a third of those rows), an object behind the face in line with one side
#: carries that side's edge only, the other side against the background beside it.
CLOSING_SIDE_RUN = 0.5


def _sides_run_on(f: dict[str, npt.NDArray[Any]], k: int, i: int, rows: int) -> bool:
    """Both sides run on over CLOSING_SIDE_RUN of the ``rows`` rows between top candidate
    ``k`` (higher) and ``i``: each side's own edge rows, not their mean."""
    least = min(int(f["up_l"][i]) - int(f["up_l"][k]), int(f["up_r"][i]) - int(f["up_r"][k]))
    return least >= CLOSING_SIDE_RUN * rows


def closing_top(
    f: dict[str, npt.NDArray[Any]],
    tops: npt.NDArray[np.intp],
    s0: int,
    s1: int,
    i: int,
    horizon: float,
) -> int | None:
    """A higher top row where the pair's sides end, when the chosen top ``tops[i]`` has
    them running on above it; None when there is none.

    A print, a gloss band, a label or a panel joint across a face is a horizontal edge
    between its sides; a print's colour, not the face's margin at its foot, fills the
    rows above it, so the face-shade factor scores the face's real top down. The sides
    still run on above such an edge, up to the face's top, an edge that stops there and
    ends at the sides at least as clearly. Only above the horizon: below it a box's top
    face shows, its edges nearly columns near the image's centre, and its back edge is
    such a line too. (``f``: the top candidates' features, ``s0:s1`` the pair's.)"""
    best, best_fit = None, 0.0
    # (the rows as Python ints: one call, not two numpy scalars a candidate)
    rows = tops[s0:s1].tolist()
    top_i = int(tops[i])
    for k, row in enumerate(rows, s0):
        if row >= top_i or row > horizon:
            continue
        if (
            f["stop"][k] >= CLOSED_STOP
            and f["stop"][i] <= f["stop"][k] - STOP_MARGIN
            and f["cov"][k] >= CLOSING_COVERAGE
            and f["snr"][k] >= max(CLOSING_SNR, CLOSING_SNR_SHARE * f["snr"][i])
            and f["contained"][k] >= f["contained"][i] - CONTAINED_MARGIN
            and f["hole_fit"][k] >= CLOSING_HOLE_FIT
            and (
                f["textured"][k] <= f["textured"][i] + TEXTURE_MARGIN
                or f["tex_above"][k] <= PRINT_ENDS_TEXTURE
            )
            and f["face_above"][k] <= CLOSING_FACE_ABOVE
            and _sides_run_on(f, k, i, top_i - row)
        ):
            # the top's own score without the face-shade terms (a print fails those)
            fit = (
                min(max(float(f["snr"][k]), 0.5), 20.0) ** 0.25
                * float(f["cov"][k]) ** 2
                * float(f["stop"][k]) ** 2
                * (0.3 + 0.7 * float(f["contained"][k]))
                * float(f["hole_fit"][k])
            )
            if fit > best_fit:
                best, best_fit = row, fit
    return best


#: A clean outline (:func:`outline_tops`): both sides present over at least this share
#: of its rows, ...
OUTLINE_COVERAGE = 0.9
#: ... the sides ending at its top (stop at least this) ...
OUTLINE_STOP = 0.9
#: ... its top edge ending at the sides (contained at least this) ...
OUTLINE_CONTAINED = 0.7
#: ... and its edges (top, bottom, both sides) at least this many noise levels strong.
OUTLINE_SNR = 5.0


def outline_tops(
    f: dict[str, npt.NDArray[Any]],
) -> tuple[npt.NDArray[np.bool_], npt.NDArray[np.float64]]:
    """Which top candidates close a clean outline, and that outline's fit (0..1).

    A box's face is one surface: its two sides run from the floor up to its top (the
    coverage; an unbroken run was too strict: a picture's edge fades where its colours
    meet the background's for a few rows), and its top edge stops at them. A print or a
    label over the face (a poster, text) fills it with edges and shades of its own,
    which the face-shade and texture terms of the score count against it, so a plain
    piece of the print (a margin, a strip along its foot) can outscore the face; the
    outline does not depend on what is inside it. (``f``: the top candidates' features,
    as :func:`score_pairs` takes them.)"""
    ok = (
        (f["cov"] >= OUTLINE_COVERAGE)
        & (f["stop"] >= OUTLINE_STOP)
        & (f["contained"] >= OUTLINE_CONTAINED)
        & (f["snr"] >= OUTLINE_SNR)
        & (f["hole_fit"] >= CLOSING_HOLE_FIT)
        & (f["face_above"] <= CLOSING_FACE_ABOVE)
    )
    fit = f["hole_fit"] * f["cov"] ** 2 * f["stop"] ** 2 * (0.3 + 0.7 * f["contained"])
    return ok, fit


def band_ranges(ps: list[tuple[int, int, int, int]]) -> npt.NDArray[np.intp]:
    """The BANDS column bands [start, end) across each pair's inner columns [c0, c1),
    pair-major, one row each; a band is at least one column wide."""
    inner = np.array([(c0, c1) for _, _, c0, c1 in ps], np.intp).reshape(-1, 2)
    c0 = inner[:, :1]
    # band edges c0 + round(b (c1 - c0) / BANDS), rounded half to even as Python's round
    cuts = c0 + (np.arange(BANDS + 1) * (inner[:, 1:] - c0) / BANDS).round().astype(np.intp)
    out = np.empty((len(ps), BANDS, 2), np.intp)
    out[:, :, 0] = cuts[:, :-1]
    out[:, :, 1] = np.maximum(cuts[:, 1:], cuts[:, :-1] + 1)
    return out.reshape(-1, 2)


def band_face_share(
    grey: npt.NDArray[np.uint8],
    ps: list[tuple[int, int, int, int]],
    tops: npt.NDArray[np.intp],
    pp: npt.NDArray[np.intp],
    rb: int,
    kf: int,
    noise: float,
    sums: F32 | None = None,
    ranges: npt.NDArray[np.intp] | None = None,
) -> npt.NDArray[np.float64]:
    """Per top candidate, the worst column band's share of rows in its own face shade.

    The whole-width row means can match the face's shade while one side of the pair
    covers floor and wall beside the face (a weak true side and a strong background
    edge beyond it): each band of a real face keeps its own shade from bottom to top.
    ``sums``: the grey row sums over :func:`band_ranges` (rows 0..rb-1) and ``ranges``
    those bands, if already taken.
    """
    if ranges is None:
        ranges = band_ranges(ps)
    widths = (ranges[:, 1] - ranges[:, 0]).astype(np.float32)
    if sums is None:
        sums = grey_range_sums(grey[:rb], ranges)
    means = sums / widths
    face = _face_shade(means, rb, kf)
    grey_noise = max(noise - 1.0, 0.0) / 3.46
    tol = np.maximum(
        np.maximum(np.float32(8.0), 0.08 * face),
        (3.0 * grey_noise / np.sqrt(widths)).astype(np.float32),
    )
    match = np.abs(means - face) <= tol
    upto = running_counts(match)
    first = _first_match(match, rb)
    # every band's share in one pass (band-major), the worst band per top candidate
    n = tops.size
    cols = (pp * BANDS)[None, :] + np.arange(BANDS)[:, None]
    shares = _shade_share(
        upto,
        first,
        np.concatenate([tops] * BANDS),
        cols.ravel(),
        rb,
        np.concatenate([rb - tops] * BANDS),
    )
    return np.minimum.reduce(shares.reshape(BANDS, n), axis=0)


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


#: An outline encloses the face chosen (:func:`enclosing_outline`) when the face lies in
#: it, their floor-contact rows at most this many rows apart (a piece of the picture
#: inside it, higher up, is no rival of it: :func:`nested`) ...
OUTLINE_ROWS = 2
#: ... its area is at least this many times the face's, one of its sides beyond the
#: face's (the face's own pair is :func:`closing_top`'s) ...
OUTLINE_AREA = 1.3
#: ... and its top and floor-contact edges each run across this share of its columns.
OUTLINE_EDGE_COVER = 0.8
#: The outline's top is its pair's own best top within this many rows.
OUTLINE_OWN_TOP_ROWS = 2
#: A pair's closing top (:func:`closing_top`) encloses the face chosen as its clean
#: outline does: the rectangle up to where that pair's sides stop round a piece of a print
#: (a switch for the tests). The method takes such an enclosure only with the pair's foot
#: at most FOOT_ABOVE_SHARE of the floor band's tolerance above the row the range predicts
#: (method.py, after :func:`enclosing_outline`).
CLOSING_ENCLOSES = True


def edge_cover(ay: F32, row: int, ul: int, ur: int) -> float:
    """Share of the columns ul..ur where a horizontal edge on ``row`` (or one next to it)
    has at least a third of its upper-quartile strength."""
    if ur - ul < 8 or row < 1:
        return 1.0
    prof = ay[row - 1 : row + 2, ul + 2 : ur - 1].max(axis=0)
    # the upper quartile (np.percentile's linear one) by a partition: percentile's own
    # overhead is most of this per-frame check
    pos = 0.75 * (prof.size - 1)
    lo = int(pos)
    hi = min(lo + 1, prof.size - 1)
    part = np.partition(prof, (lo, hi))
    ref = float(part[lo]) + (pos - lo) * (float(part[hi]) - float(part[lo]))
    return float(np.mean(prof >= 0.3 * ref)) if ref > 0.0 else 0.0


def nested(c: Candidate, outer: Candidate) -> bool:
    """Whether ``c`` lies inside ``outer`` (to a pixel; its foot to OUTLINE_ROWS): a
    piece of a print whose lower edge is one inside the picture lies higher up."""
    return (
        outer.vt < c.rb <= outer.rb + OUTLINE_ROWS
        and c.ul >= outer.ul - 1
        and c.ur <= outer.ur + 1
        and c.vt >= outer.vt - 1
    )


def enclosing_outline(
    view: View,
    ax: I16,
    ay: F32,
    best: Candidate,
    cands: list[Candidate],
    fits: VerticalFits | None = None,
    closing_foot_from: int | None = None,
) -> tuple[Candidate, bool] | None:
    """A clean outline (:func:`outline_tops`) round the face chosen, or None; and whether
    its top is its own pair's best top too (to OUTLINE_OWN_TOP_ROWS): else only the
    outline chose that row, not the top's score (a doubt).

    The face chosen lying inside a larger rectangle on the same floor-contact row, whose
    sides run from the floor to its top and whose top stops at them, is a piece
    of a print over that face (its margin, a plain strip at its foot, a panel of the
    picture): the face is one surface, and the outline is its edge, its top and foot
    running across all of it (a box's top edge and a background edge beside it, or a
    box and what stands behind it, make no such outline). Returned as a candidate with
    that top, the face's score and the outline's own evidence.

    A wider pair closed where its sides stop (its closing top, CLOSING_ENCLOSES) is such
    an outline too, its evidence that of the closed face alone: a print's edges inside
    the face make its best top an edge in the picture, while its sides run on round the
    piece chosen up to the face's top. ``closing_foot_from``: a closed pair whose foot
    lies above this row is not one (a print standing above the floor the range predicts);
    judged pair by pair, so it never hides a clean outline round the same face."""
    if best.outline is not None:
        return None  # a clean outline itself: a face, not a piece of a print
    if best.closing is not None:
        best = dataclasses.replace(best, vt=best.closing)  # the face chosen, closed
    area = (best.ur - best.ul) * (best.rb - best.vt)
    found = None
    for c in cands:
        if c.ul >= best.ul - 1 and c.ur <= best.ur + 1:
            continue
        if c.outline is not None:
            outer = dataclasses.replace(
                c,
                vt=c.outline,
                score=max(c.score, best.score),
                evidence=c.outline_evidence,
                print_evidence=c.outline_evidence,
                closing=None,
            )
        elif (
            c.closing is not None
            and CLOSING_ENCLOSES
            and (closing_foot_from is None or c.rb >= closing_foot_from)
        ):
            # its own closing kept: the top is from the sides (a doubt) as for the face
            # closed there itself
            outer = dataclasses.replace(
                c,
                vt=c.closing,
                score=max(c.score, best.score),
                evidence=c.closing_evidence,
                print_evidence=c.closing_evidence,
            )
        else:
            continue
        if abs(best.rb - outer.rb) > OUTLINE_ROWS or not nested(best, outer):
            continue
        if (outer.ur - outer.ul) * (outer.rb - outer.vt) < OUTLINE_AREA * area:
            continue
        if found is not None and c.score <= found[0]:
            continue
        if (
            edge_cover(ay, outer.vt, outer.ul, outer.ur) < OUTLINE_EDGE_COVER
            or edge_cover(ay, outer.rb, outer.ul, outer.ur) < OUTLINE_EDGE_COVER
        ):
            continue
        if not sides_vertical(view, ax, outer, fits):
            continue
        found = (c.score, outer, c)
    if found is None:
        return None
    outer = found[1]
    log.debug(
        "face %d-%d x %d-%d inside the outline %d-%d x %d-%d",
        best.ul,
        best.ur,
        best.vt,
        best.rb,
        outer.ul,
        outer.ur,
        outer.vt,
        outer.rb,
    )
    return outer, abs(found[2].vt - outer.vt) <= OUTLINE_OWN_TOP_ROWS


def verified(
    view: View, ax: I16, cands: list[Candidate], fits: VerticalFits | None = None
) -> tuple[Candidate | None, list[Candidate]]:
    """The best candidate with world-vertical sides (None if none of the first
    MAX_VERIFIED has them) and its rivals: the candidates from it on, best first.

    ``cands`` is sorted in place, best score first; ``fits`` keeps the side fits.
    """
    # the best candidates whose sides are not vertical in the world (the seams of a
    # floor patch run towards the vanishing point) are no face and no rival either
    cands.sort(key=lambda c: -c.score)
    best = None
    rivals = cands
    for i, cand in enumerate(cands[:MAX_VERIFIED]):
        if sides_vertical(view, ax, cand, fits):
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
    return best, rivals
