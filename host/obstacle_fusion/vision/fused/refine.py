"""Sub-pixel refinement of the chosen edges, and the measurement from them.

Receives the chosen face (floor-contact row rb, side columns ul..ur, front top row vt,
or a sub-pixel top row already predicted), the gradients (|d/dx| int16 and its dilation,
|d/dy| float32, the front top edge's signed gradient), the face depth, the range and the
confidence. Fits the four edges to sub-pixel lines, moves a side inwards past a side
face (yaw, or a box off the axis), lowers the top corners to where the sides end under a
thin top face, and returns the :class:`~obstacle_fusion.vision.types.Measurement`:
height and width from the pinhole model at the face depth (per-edge depths from the floor
geometry), the box and the edges in input pixels.
"""

from __future__ import annotations

import logging
import math
from typing import NamedTuple

import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.fused.profiles import (
    F32,
    I16,
    VerticalFits,
    clamp,
    fit_horizontal,
    fit_vertical,
    lsq,
    median,
    subpixel,
)
from obstacle_fusion.vision.fused.region import MarginLine
from obstacle_fusion.vision.types import Line, Measurement, Timer, View

log = logging.getLogger(__name__)

_WIN7 = np.arange(-3, 4)[:, None]  # row offsets of a 7-row window around an edge
_T5 = np.linspace(0.0, 1.0, 5)[:, None]  # outline samples along each face edge


class _BottomProfile(NamedTuple):
    """Per-column bottom-edge peaks near the fitted bottom line (for the side-face test)."""

    cols: npt.NDArray[np.intp]
    strength: F32
    pos: npt.NDArray[np.float64]  # sub-pixel peak row
    dev: npt.NDArray[np.float64]  # peak row minus the fitted line
    ref: float  # median strength over the centre columns
    on: list[bool]  # on the line and strong


#: Top and bottom edges are fitted over the search's columns only while they span at
#: least this share of the face's width.
MIN_SPAN_SHARE = 0.3
#: The largest yaw of a face off square to the beam that the side-face test allows for.
MAX_YAW_DEG = 5.0
#: The sides' depths read from the foot's slope are kept only while the yaw they give
#: is under MAX_YAW_DEG (a switch for the tests): a narrow face's foot, a few tens of
#: pixels long, slopes a pixel or two from a shadow or a floor line at one corner, and
#: the depth difference that reads (up to a quarter of the depth) outweighs its width.
YAW_FROM_FOOT_CAPPED = True
#: A side face's bottom must rise at least this share of the least rise its width and
#: the vanishing point give (the blur and the fit's noise take some).
SIDE_FACE_RISE_SHARE = 0.5


def refine(
    view: View,
    method: str,
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
    span: tuple[int, int] | None = None,
    fits: VerticalFits | None = None,
    margin: MarginLine | None = None,
) -> Measurement:
    """The measurement of the chosen face (floor-contact row rb, sides ul..ur, top vt).

    ``span`` (default ul..ur) are the columns the top and bottom edges are fitted over:
    the side search's columns when the extent stage widened the face across seams.

    ``top_edge`` holds the front top edge's signed gradient around vt; ``top_row`` is a
    sub-pixel top row predicted by :func:`~obstacle_fusion.vision.fused.top.front_from_back`
    (used as is), else None. Height and width at the face depth ``depth``. ``fits``: the
    frame's side fits over ``ax`` (the verification's, reused when the face kept its rows
    and sides). ``margin``: a print's thin margin line's outer edges
    (:func:`~obstacle_fusion.vision.fused.region.margin_line_out`): the face's edges
    there, parallel to the print's fitted edges (never moved inwards).
    """
    v = view
    h_roi, w_img = ay.shape
    # horizontal edges: per-column sub-pixel peaks near rb and vt
    fl, fr = span if span is not None else (ul, ur)
    if fr - fl < MIN_SPAN_SHARE * (ur - ul):
        fl, fr = ul, ur  # a line fitted over a sliver of the face tilts with its noise
    m = max(1, (fr - fl) // 10)
    cols = np.arange(fl + m, fr - m + 1)
    (bottom_a, bottom_b), (top_a, top_b) = fit_horizontal([(ay, rb), (top_edge, vt)], cols, h_roi)
    if top_row is not None:  # predicted by front_from_back, not refined
        top_a = top_row - top_b * 0.5 * float(cols[0] + cols[-1])
    if margin is not None:
        # a print's thin margin line: the face's edges are its outer edges (parallel to
        # the print's: the line is read at one column, the middle of the print's)
        bottom_a = max(bottom_a, margin.foot - bottom_b * margin.col)
        if top_row is None:
            top_a = min(top_a, margin.top - top_b * margin.col)
    # vertical edges: per-row sub-pixel peaks near ul and ur
    mv = max(1, (rb - vt) // 10)
    rows = np.arange(vt + mv, rb - mv + 1)
    fit = fits if fits is not None else VerticalFits(ax)
    (left_a, left_b), (right_a, right_b) = fit(rows, [ul, ur], w_img)
    if margin is not None:  # ... and beside it (read at one row, the print's middle)
        left_a = min(left_a, margin.left - left_b * margin.row)
        right_a = max(right_a, margin.right - right_b * margin.row)

    # A side face (yaw, or a box off the axis) shows beside the front face: the front
    # face's bottom edge is straight, the side face's rises towards the horizon.
    # Where the straight part ends is the front corner.
    bottom = _bottom_profile(ay, bottom_a, bottom_b, ul, ur)
    if bottom is not None:
        # a side face recedes along the floor, its bottom edge towards the vanishing point
        # of the depth direction: (cx, cy) in the level view, moved by the box's yaw
        reach = v.fx * math.tan(math.radians(MAX_YAW_DEG))
        vp = (v.cx, v.cy, reach)
        new_left = _side_face(
            ax, bottom, bottom_a, bottom_b, ul, ur, vt, rb, -1, left_a, left_b, vp
        )
        new_right = _side_face(
            ax, bottom, bottom_a, bottom_b, ul, ur, vt, rb, 1, right_a, right_b, vp
        )
        # A camera sees at most one side face of a box (the one turned towards it): a
        # "side face" on both sides is a break in the bottom edge (a seam), not a corner.
        if new_left == (left_a, left_b) or new_right == (right_a, right_b):
            (left_a, left_b), (right_a, right_b) = new_left, new_right

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
        end_l = _edge_end(ax3, left_a, left_b, vt, rb)
        end_r = _edge_end(ax3, right_a, right_b, vt, rb)
        if end_l is not None and end_r is not None:
            d_l, d_r = end_l - tl[1], end_r - tr[1]
            lower = 0.5 * (d_l + d_r)
            # only a thin top face (thicker ones are separate edges, handled above),
            # seen alike on both sides
            if (
                0.75 < lower <= 4.0
                and abs(d_l - d_r) < 1.0
                and edge_at_ends(ay, ul, ur, vt, 0.5 * (end_l + end_r))
            ):
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
            z_l = depth * clamp(rl, 0.8, 1.25)
            z_r = depth * clamp(rr, 0.8, 1.25)
    ul_f = 0.5 * (bl[0] + tl[0])
    ur_f = 0.5 * (br[0] + tr[0])
    x_l = (ul_f - v.cx) * z_l / v.fx
    x_r = (ur_f - v.cx) * z_r / v.fx
    if YAW_FROM_FOOT_CAPPED and z_l != z_r:
        yaw = math.degrees(math.atan2(abs(z_r - z_l), abs(x_r - x_l)))
        if yaw > MAX_YAW_DEG:
            # a yaw the face cannot have (it stands square to the beam, give or take
            # MAX_YAW_DEG): the foot's slope between the corners is the fit's, not depth
            log.debug("foot slope gives a yaw of %.1f deg: the face depth at both sides", yaw)
            z_l = z_r = depth
            x_l = (ul_f - v.cx) * depth / v.fx
            x_r = (ur_f - v.cx) * depth / v.fx
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
        method=method,
        range_m=range_m,
        distance_m=range_m,
        height_m=float(height_m),
        width_m=float(width_m),
        box_px=box,
        confidence=round(conf, 3),
        lines=lines,
        height_px=float(h_px),
        width_px=float(ur_f - ul_f),
        clipped=v.unseen_sides(corners),
    )


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
    r0 = pred.round().astype(np.intp)
    np.maximum(r0, 3, out=r0)
    np.minimum(r0, h - 4, out=r0)
    win = ay[r0[None, :] + _WIN7, cols[None, :]]  # 7 x n
    peak = win[1:-1].argmax(axis=0) + 1  # 1..5
    strength = win.ravel()[peak * cols.size + np.arange(cols.size)]
    pos = r0 - 3 + peak + subpixel(win, peak)
    dev = pos - pred
    m = max(1, (ur - ul) // 4)
    # cols is consecutive: the centre columns are a slice
    centre = slice(max(0, ul + m - c_lo), max(0, ur - m - c_lo + 1))
    if strength[centre].size < 3:
        return None
    ref = median(strength[centre])
    on = ((np.abs(dev) <= 0.8) & (strength >= 0.4 * ref)).tolist()
    return _BottomProfile(cols, strength, pos, dev, ref, on)


def _side_face(
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
    vp: tuple[float, float, float],
) -> tuple[float, float]:
    """The front face's vertical edge on one side, moved inwards past a side face.

    ``vp``: the depth direction's vanishing point (u, v) in the level view and how far
    (columns) a yawed box moves it; a side face lies between its corner and that point,
    so one reaching past it is a seam or a print on the front face.

    ``direction`` -1 for the left side, +1 for the right; (va, vb) is the fitted edge
    u = va + vb v, returned unchanged when no side face is seen.
    """
    w = ax.shape[1]
    cols, strength, pos, dev, ref, on = bottom
    mid = int(cols.searchsorted((ul + ur) // 2))
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
    on_seg = seg.nonzero()[0]
    outer = on_seg[-3:] if direction > 0 else on_seg[:3]
    clear_rise = float(np.add.reduce(dev[outer])) / outer.size <= -1.5
    sa, sb = lsq(cols[seg].astype(np.float64), pos[seg])
    if (sb - bb) * direction <= -0.15:  # rising outwards: meets the front bottom there
        corner_u = (sa - ba) / (bb - sb)
    elif float(dev[nxt[0]] + dev[nxt[1]]) / 2 < -1.0:  # a step up (blur merges the slope)
        corner_u = end_u + 0.5 * direction
    else:
        return va, vb
    if not (min(end_u, edge_u) - 1.0 <= corner_u <= max(end_u, edge_u) + 1.0):
        return va, vb
    # the side face's bottom runs from the corner towards the vanishing point: over its
    # width it rises at least as steeply as a line to the farthest point a yaw allows
    vp_u, vp_v, reach = vp
    room = (vp_u + direction * reach - corner_u) * direction
    if room <= 1.0:
        return va, vb  # no side face shows on this side of the vanishing point
    slope_min = max(0.0, ba + bb * corner_u - vp_v) / room
    rise = -float(np.add.reduce(dev[outer])) / outer.size
    if rise < SIDE_FACE_RISE_SHARE * slope_min * abs(edge_u - corner_u):
        return va, vb  # flat: a seam or a print's edge on the front face
    # a vertical edge (front/side shading) near the corner gives the slope; else vertical
    mv = max(1, (rb - vt) // 10)
    rows = np.arange(vt + mv, rb - mv + 1)
    c = int(round(corner_u))
    if rows.size >= 3 and 3 <= c < w - 3:
        # .mean(axis=0) in float32, without the wrapper
        strip = np.add.reduce(ax[rows, c - 1 : c + 2], 0, dtype=np.float32) / rows.size
        edge_mean = np.add.reduce(ax[rows, int(round(edge_u))], dtype=np.float32) / rows.size
        if float(strip.max()) >= 0.25 * float(edge_mean):
            a2, b2 = fit_vertical(ax, rows, [c], w)[0]
            if abs((a2 + b2 * rb) - corner_u) <= 1.0:
                return a2, b2
    if not clear_rise:  # no shading edge at the corner and only a slight rise
        return va, vb
    return corner_u - vb * rb, vb


#: The sides' ends are taken for the front top corners (under a thin top face) only where
#: a horizontal edge runs between them (:func:`edge_at_ends`): a switch for the tests.
ENDS_NEED_EDGE = True
#: ... at least this share of the top edge's strength (mean |d/dy| over the face's inner
#: columns, the strongest of three rows round the top, of the two round the ends): a
#: thin top face, lit otherwise than the front, leaves its front edge in the gradient, or
#: its blur's tail where the two merge; the face's own colour running on unbroken (a step
#: of noise, a few hundredths of the top's) is no corner: the sides faded against a
#: background of the face's shade.
ENDS_EDGE_SHARE = 0.1
#: The face's inner columns read: a tenth of its width (ENDS_SIDE_SKIP_PARTS) in from each
#: side, past the sides' blur; none read (True) for fewer than ENDS_MIN_COLUMNS left.
ENDS_SIDE_SKIP_PARTS = 10
ENDS_MIN_COLUMNS = 3


def edge_at_ends(ay: F32, ul: int, ur: int, vt: int, end: float) -> bool:
    """Whether a horizontal edge runs at row ``end`` (the sides' mean end, view rows: the
    two rows round it) between the face's sides ``ul``..``ur`` at ENDS_EDGE_SHARE of the
    top's (row ``vt``) strength. True when switched off or unreadable."""
    n = ay.shape[0]
    m = max(1, (ur - ul) // ENDS_SIDE_SKIP_PARTS)
    r = int(end)
    if (
        not ENDS_NEED_EDGE
        or ur - ul - 2 * m < ENDS_MIN_COLUMNS
        or vt < 1
        or r + 2 > n
        or vt + 2 > n
    ):
        return True
    cols = ay[:, ul + m : ur - m + 1]
    top = float(cols[vt - 1 : vt + 2].mean(axis=1).max())
    if top <= 0.0:
        return True
    at = float(cols[r : r + 2].mean(axis=1).max())
    if at < ENDS_EDGE_SHARE * top:
        log.debug("sides end at %.1f with no edge there (%.2f of the top's): kept", end, at / top)
        return False
    return True


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
    cols = (a + b * rows).round().astype(np.intp)
    np.maximum(cols, 1, out=cols)  # np.clip's wrapper costs more than the work here
    np.minimum(cols, w - 2, out=cols)
    strength = ax3[rows, cols].astype(np.float32)  # cols are within 1..w-2: exact
    mid0 = vt + max(2, (rb - vt) // 4)
    ref_rows = strength[rows >= mid0]
    if ref_rows.size < 3:
        return None
    half = 0.5 * median(ref_rows)
    # going up from the reference part, the first row below half strength that stays
    # below for two more rows (a dip where the background behind the side changes, from
    # floor to wall, is not the end); the scan in Python bools
    weak = (strength < half).tolist()
    for i in range(int(rows.searchsorted(mid0)) - 1, 0, -1):
        if weak[i] and not weak[i + 1] and all(weak[max(0, i - 2) : i]):
            frac = (half - strength[i]) / max(float(strength[i + 1] - strength[i]), 1e-6)
            return float(rows[i] + frac)
    return None
