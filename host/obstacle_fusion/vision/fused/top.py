"""The chosen face's front top edge: where a box lower than the lens shows its top face.

Receives the chosen face (floor-contact row rb, side columns ul..ur, top row vt), the
working view, the face depth and the gradients (|d/dy| float32, signed d/dy int16).
Returns the front top edge's row and its gradient's sign (:func:`front_top`), or, when the
chosen top is the top face's back edge (:func:`front_from_back`), the front edge's row,
sign and, when taken from the prediction alone, its sub-pixel row (not to be refined).
"""

from __future__ import annotations

import logging
import math

import numpy as np

from obstacle_fusion.vision.fused.profiles import F32, I16, median, row_means
from obstacle_fusion.vision.fused.tuning import (
    FRONT_TOP_SIGMAS,
    MIN_SIZE_M,
    TAIL_ROWS,
    TAIL_SHARE,
)
from obstacle_fusion.vision.types import View

log = logging.getLogger(__name__)

#: The longest top face sought behind a face's front top edge (metres).
TOP_FACE_LENGTH_M = 2.0


def front_top(
    view: View,
    depth: float,
    dy: I16,
    rb: int,
    ul: int,
    ur: int,
    vt: int,
    noise: float,
    from_back: bool = False,
    chained: bool = False,
    horizon_known: bool = False,
) -> tuple[int, float]:
    """A box lower than the lens shows its top face: prefer the face's front edge.

    The top face's back edge sits above the front one by at most
    (vt - cy) * (1 - D / (D + 2 m)) rows (a box up to 2 m long) when ``vt`` is near the
    front edge; ``from_back``: ``vt`` is a top raised up to the back edge (or past it),
    and the front lies below it by up to (vt - cy) * 2 m / D rows. In the signed vertical
    gradient the two edges stay apart even when only a pixel or two apart (the top
    face is lit differently from the wall and from the front face); the lowest
    significant extremum in that reach, within the upper 30 % of the face, is the
    front top edge. Returns the row and the sign of its gradient. ``chained``: sought
    again from a staircase step taken (STAIRS_CHAINED), only steps of the top edge's sign;
    ``horizon_known``: the rig given (no trial's guessed pitch), which STAIRS_CHAINED asks.
    """
    v = view
    m = max(1, (ur - ul) // 8)
    below_horizon = vt - v.cy
    if v.horizon_slack_px > 0.0:
        below_horizon = max(below_horizon, min(below_horizon, 0.0) + v.horizon_slack_px)
    share = TOP_FACE_LENGTH_M / (depth if from_back else depth + TOP_FACE_LENGTH_M)
    reach = int(min(below_horizon * share, 0.3 * (rb - vt)))
    if below_horizon <= 1.0 or reach < 1:
        return vt, (1.0 if int(dy[vt, ul + m : ur - m].sum()) >= 0 else -1.0)
    # the row means only where the scan reads them (rows vt..last), as Python floats;
    # prof[r - vt] is row r
    last = max(vt, min(vt + reach, rb - 3) + 1)
    # (a few rows more below: how far a peak's own rows run, see _ramp)
    prof = row_means(dy[vt : min(last + RAMP_ROWS, rb - 1) + 1, ul + m : ur - m]).tolist()
    # noise of a mean over the face's columns (Sobel smooths ~3 columns together); next
    # to the top edge also its own blur tail, further up only noise
    thr_noise = FRONT_TOP_SIGMAS * noise * math.sqrt(3.0 / max(1, ur - ul - 2 * m))
    thr_near = thr_noise + TAIL_SHARE * abs(prof[0])
    found = []
    for r in range(vt + 1, min(vt + reach, rb - 3) + 1):
        p_prev, p, p_next = prof[r - 1 - vt], prof[r - vt], prof[r + 1 - vt]
        a = abs(p)
        thr = thr_near if r - vt <= TAIL_ROWS else thr_noise
        if a >= thr and a >= abs(p_prev) and a >= abs(p_next):
            found.append(r)
        elif a >= thr and p * p_prev < 0 and a > abs(p_next):
            found.append(r)
    # a shading ramp (a gloss's highlight fading out, a shadow) is no edge
    found = [r for r in found if not _ramp(prof, r - vt)]
    # the lowest, unless it ends inside both sides: a print's or a label's top edge, inset
    # in the face, while the front top edge runs from side to side
    # ... and a step of its own (see _front_step): the lowest that is; under a dark line
    # (a dip) the rows above are the front's own as well
    peak = _top_peak(dy, vt, ul + m, ur - m) if FRONT_EDGE_STEPS else 0.0
    best = vt
    # ... and none under a print's top edge: the print lies on the front, under its top
    # (with the rig given only, as STAIRS_CHAINED: held-out procedural 6012 hard with no
    # rig went 0.7 -> 6.2 % by it under a trial's guessed pitch)
    bounded = PRINT_TOP_BOUNDS and horizon_known
    print_top = _print_top(dy, found, ul, ur) if bounded else None
    for r in reversed(found):
        if _inset(dy, r, ul, ur) or (chained and peak * prof[r - vt] <= 0.0):
            # (read on down a staircase: only its steps, see STAIRS_CHAINED)
            continue
        if print_top is not None and r > print_top[0] and _on_print(dy, r, ul, ur, print_top):
            continue
        step = _front_step(peak, prof[r - vt]) if r - vt >= 2 else STEP
        if FAINT_STAIRS and r - vt >= 2:
            step = _stair_across(dy, r, ul + m, ur - m, peak, prof[r - vt], step)
        if step != STEP:
            log.debug("top %d: row %d (%.1f against %.1f) is a %s", vt, r, prof[r - vt], peak, step)
        if step == STEP:
            best = r
        if step != WEAK:
            break
    if best != vt and _no_back_edge(v, dy, ul, ur, vt, best):
        # the top edge runs on flat where no top face's back edge could: it is the front
        # top edge, the line under it a joint or a gloss's edge inside the front face
        # (the lines between are the face's as well: a thinner top face is not told
        # apart from the top edge's blur here)
        best = vt
    if STAIRS_CHAINED and horizon_known and not from_back and not chained and best - vt >= 2:
        # a staircase of three steps: the top taken on a line behind the box (its own
        # band between it and the top face's back edge), the front top edge beyond the
        # reach from that line; sought again from the step taken, the staircase's steps
        # alone (the step taken and the one under it both of the top edge's sign). The
        # top edge's sign is its own row's as well: the peak is read two rows either side
        # of the top, where a stronger step taken a few rows under it may lie (new6
        # photo/3287 hard: the top rising, the step three rows under it falling, taken for
        # the peak, read on down the step's own blur tail, +1.0 -> -6.2 %)
        again, sign = front_top(view, depth, dy, rb, ul, ur, best, noise, chained=True)
        if (
            again - best >= 2
            and sign * prof[best - vt] > 0.0
            and peak * prof[best - vt] > 0.0
            and prof[0] * prof[best - vt] > 0.0
        ):
            log.debug("top %d: a staircase on from %d to %d", vt, best, again)
            return again, sign
    return best, (1.0 if prof[best - vt] >= 0 else -1.0)


#: Whether the front top edge is sought only above a print's or a label's top edge found
#: under the top (:func:`_print_top`): the print lies on the front face, so its top edge
#: is under the front top edge, and the lines under it (a text's rows) are the print's
#: (procedural/3099 hard with the rig: a text label inset 40 px from both sides, its top
#: passed as inset, a text row under it taken for a staircase step, -26 %). With the rig
#: given only (``horizon_known``). A switch for the tests.
PRINT_TOP_BOUNDS = True
#: A print's top edge ends this share of the face's width or more inside each side (a
#: top face's back edge, shrunk about the principal point, ends a few pixels inside).
PRINT_INSET_SHARE = 0.08


def _print_top(dy: I16, found: list[int], ul: int, ur: int) -> tuple[int, int, int] | None:
    """The highest row of ``found`` whose edge ends at least PRINT_INSET_SHARE of the
    face's width inside both sides (a print's or a label's top edge), with its ends'
    columns, or None."""
    least = PRINT_INSET_SHARE * (ur - ul)
    for r in found:
        ends = _edge_ends(np.abs(dy[max(0, r - 1) : r + 2]).astype(np.float32), 1, ul, ur)
        if ends is not None and ends[0] - ul >= least and ur - ends[1] >= least:
            return r, int(ends[0]), int(ends[1])
    return None


#: A line under a print's top edge is the print's where the margins beside the print
#: step under this share of the print's columns on its rows (a front top edge under a
#: top face's back edge runs on across them: 0.32 on procedural/3099 hard's text row).
PRINT_MARGIN_SHARE = 0.5


def _on_print(dy: I16, r: int, ul: int, ur: int, print_top: tuple[int, int, int]) -> bool:
    """Whether the line on row ``r`` steps between the print's ends (``print_top``'s
    columns) and not in the margins between them and the sides ``ul`` and ``ur``."""
    _, e0, e1 = print_top
    a = np.abs(dy[max(0, r - 1) : r + 2]).max(axis=0).astype(np.float32)
    inside = a[e0 + 2 : e1 - 1]
    margins = np.concatenate([a[ul + 2 : max(ul + 2, e0 - 2)], a[e1 + 3 : max(e1 + 3, ur - 2)]])
    if inside.size == 0 or margins.size == 0:
        return False
    return float(margins.mean()) < PRINT_MARGIN_SHARE * float(inside.mean())


#: Whether a staircase step taken for the front top edge is read on from (photo/3438
#: hard with the rig: the top on the background's platform edge, the top face's back
#: edge the step under it, its front edge past the reach from the platform's): the
#: front top edge sought again from the step taken, kept when it steps the same way
#: again. With the rig given only (``horizon_known``): the reach is the horizon's, and a
#: trial's guessed pitch read on down the staircases of three no-rig faces on the tuning
#: rooms (procedural/104 hard 7 -> 20 %, photo/716 hard, 736 ordinary). A switch for the
#: tests.
STAIRS_CHAINED = True


#: Whether a front top edge two or more rows under the top must be a step of its own
#: (:func:`_front_step`): the lowest extremum that is one is taken, none under a dark
#: line's lower edge; a switch for the tests.
FRONT_EDGE_STEPS = True
#: A front top edge with the top edge's sign (wall, top face, front: a staircase) is at
#: least this share of the top edge's peak: a weaker one on the same side is the top
#: edge's own blur tail or the face's grain (about 0.05 on procedural/2096, 0.09 on
#: photo/2035, 0.13 on photo/2013 hard; a real staircase 0.23, procedural/115 hard).
STAIR_MIN_SHARE = 0.15
#: A front top edge of the sign opposite the top edge's (the top face a bump between the
#: wall and the front) is at least this share of the top edge's peak: a weaker one is the
#: top edge's ringing (about 0.01 on procedural/715, 0.02 on procedural/134; thin bright
#: top faces 0.065 and more, photo/139 hard).
BUMP_MIN_SHARE = 0.04


#: Whether a staircase step (of the top edge's sign) is read along its row as well
#: (:func:`_stair_across`): a faint one running straight across is a front top edge, a
#: weak one not stepping the same way all along is none; a switch for the tests.
FAINT_STAIRS = True
#: The faintest staircase step taken when it runs straight across: a far box's top face
#: lit nearly as its front steps about 0.09 of the top edge's peak (the bench's far box,
#: README), a purple box's lighter top face 0.13; the top edge's blur tail and grain
#: under it mostly 0.02-0.05 (procedural/131, 2096, photo/729).
STAIR_FAINT_SHARE = 0.08
#: Column groups the step's row is cut into (inside the face's columns).
STRAIGHT_GROUPS = 8
#: A faint step runs straight across when every column group's step (the strongest of
#: the rows r-1..r+1, of the step's sign) is at least this share of the groups' mean:
#: two planes meeting on one straight line, each lit evenly, step alike all along it;
#: grain and a print's structure come and go along the row (weakest group 0.05-0.17 of
#: the mean on photo/2013 hard, 2035, procedural/704 hard, 2031 hard; 0.55-0.59 on
#: procedural/2067, photo/147, all 0.07-0.13 of the peak; real front top edges taken on
#: the tuning rooms mostly 0.76-0.97: procedural/115 hard, 2018, photo/137, 2092 hard).
STRAIGHT_MIN_SHARE = 0.75
#: A staircase step under this share of the top edge's peak (and at least
#: STAIR_FAINT_SHARE) must step the same way in every column group: a front top edge
#: runs from side to side; a print's structure taken at 0.17-0.19 steps against it in
#: a group (procedural/116 hard, photo/155); a real one at 0.23 does not (weakest group
#: 0.78 of the mean, procedural/115 hard).
STAIR_CHECK_SHARE = 0.3


def _stair_across(dy: I16, r: int, c0: int, c1: int, peak: float, p: float, step: str) -> str:
    """A same-signed (staircase) extremum ``p`` on row ``r`` under the top edge (peak
    ``peak``), which :func:`_front_step` made ``step``, read along the row (columns
    c0..c1): a faint one (STAIR_FAINT_SHARE up to STAIR_MIN_SHARE of the peak) running
    straight across is a STEP; one under STAIR_CHECK_SHARE that does not step the same
    way in every column group is WEAK (a print's structure, grain)."""
    share = abs(p) / abs(peak) if peak != 0.0 else 0.0
    if peak * p <= 0.0 or not STAIR_FAINT_SHARE <= share < STAIR_CHECK_SHARE:
        return step
    n = min(STRAIGHT_GROUPS, (c1 - c0) // 3)
    if n < 3:
        return step
    sign = 1.0 if p > 0.0 else -1.0
    band = dy[r - 1 : r + 2, c0:c1].astype(np.float32) * sign
    cuts = np.linspace(0, c1 - c0, n + 1).astype(np.int64)
    steps = np.array(
        [band[:, a:b].mean(axis=1).max() for a, b in zip(cuts[:-1], cuts[1:], strict=True)]
    )
    mean, least = float(steps.mean()), float(steps.min())
    if step == WEAK:
        return STEP if mean > 0.0 and least >= STRAIGHT_MIN_SHARE * mean else WEAK
    return step if least > 0.0 else WEAK


def _top_peak(dy: I16, vt: int, c0: int, c1: int) -> float:
    """The top edge's peak: the largest row mean (columns c0..c1) of the signed vertical
    gradient within two rows of ``vt``."""
    top = row_means(dy[max(0, vt - 2) : vt + 3, c0:c1])
    return float(top[int(np.argmax(np.abs(top)))])


#: What :func:`_front_step` makes of an extremum under the top.
STEP, WEAK, DIP = "step", "weak edge", "dark line's lower edge"


def _front_step(peak: float, p_out: float) -> str:
    """What the extremum ``p_out`` of the signed gradient's row means under the top,
    whose edge peaks at ``peak``, is. A top face lies between the wall and the front:
    at a level between theirs (two steps of one sign, the lower one a step of its own,
    STAIR_MIN_SHARE of the top edge) or, lit from above, brighter than both (a bump,
    its fall BUMP_MIN_SHARE of the top edge): STEP, a front top edge. A weaker one is
    the top edge's own blur tail, its ringing or the face's grain (WEAK). A band darker
    than both the wall and the front (the top edge falling, this one rising) is no top
    face lit from above: the front's own dark line or frame under its top, or the top
    edge's undershoot (DIP)."""
    if peak == 0.0:
        return STEP
    if peak * p_out > 0.0:
        return STEP if abs(p_out) >= STAIR_MIN_SHARE * abs(peak) else WEAK
    if peak < 0.0:
        return DIP
    return STEP if abs(p_out) >= BUMP_MIN_SHARE * abs(peak) else WEAK


#: A peak of the signed gradient whose same-signed run at half its value or more spans
#: this many rows is a shading ramp, not an edge: an edge blurred by the optics and the
#: 3-row Sobel spans 3 or 4, a gloss's highlight fading across the face spans 5 or more.
RAMP_ROWS = 5


#: A gloss's ramp is read through the noise of its row means (``RAMP_GAPS``): a faint
#: ramp's rows stand only a few noise levels above nothing, so one row of it may fall
#: under half of a peak that noise raised (photo/2138 ordinary: the highlight's upper
#: flank, rows 4-7 a row over 15 rows, one row at 1.2 under a bump of 7.0; the bump was
#: taken for a top face's front edge, -19 %). Up to RAMP_GAP_ROWS rows under half do not
#: end the run where it holds on beyond them for RAMP_RESUME_ROWS rows at half or more,
#: none stronger than the peak and none on the top edge's own rows (its row and TAIL_ROWS
#: under it): past a gap, a ramp's rows are the ramp's level; the top edge's blur is
#: another edge (procedural/752 hard with no rig, a top face's front edge of -62 whose run
#: crossed one row into the top edge's blur of -75 and -163; new photo/3026 hard with no
#: rig, a front edge of 18.6 two rows under a top edge of 18.4). An edge's blur is one
#: hump of 3-4 rows, and beyond it lies noise, not the edge again.
RAMP_GAPS = True
RAMP_GAP_ROWS = 1
RAMP_RESUME_ROWS = 2


def _ramp(prof: list[float], i: int) -> bool:
    """Whether the peak at ``prof[i]`` is a shading ramp (see RAMP_ROWS, RAMP_GAPS);
    ``prof[0]`` is the top edge's row."""
    p = prof[i]
    half = abs(0.5 * p)

    def holds(j: int, capped: bool) -> bool:
        return (
            0 <= j < len(prof)
            and prof[j] * p > 0
            and half <= abs(prof[j])
            and (not capped or _under_peak(prof, j, p))
        )

    def reach(step: int) -> int:
        """How far the run goes from i in the direction ``step`` (rows, >= 0)."""
        k, crossed = 0, False
        while True:
            if holds(i + step * (k + 1), crossed):
                k += 1
                continue
            if not RAMP_GAPS:
                return k
            # a gap of up to RAMP_GAP_ROWS rows, the run holding on beyond it, no stronger
            # than the peak (rows stronger than it are another edge's: the top edge's own
            # blur, a row or two over a front edge), the gap's own rows no such row either
            for gap in range(1, RAMP_GAP_ROWS + 1):
                gaps = [i + step * (k + j) for j in range(1, gap + 1)]
                beyond = [i + step * (k + gap + j) for j in range(1, RAMP_RESUME_ROWS + 1)]
                if all(_under_peak(prof, j, p) for j in gaps) and all(
                    holds(j, True) for j in beyond
                ):
                    k, crossed = k + gap + RAMP_RESUME_ROWS, True
                    break
            else:
                return k

    return reach(-1) + reach(1) + 1 >= RAMP_ROWS


def _under_peak(prof: list[float], j: int, peak: float) -> bool:
    """Whether row ``j`` may lie in a ramp's gap: no stronger than the peak, and not on
    the top edge's own rows (``prof[0]`` is the top edge's row)."""
    return 0 <= j < len(prof) and abs(prof[j]) <= abs(peak) and j > TAIL_ROWS


#: A back edge must be predicted at least this many columns inside each side.
BACK_INSET_MIN_PX = 6.0
#: Columns next to the side skipped (the side's own blur).
SIDE_SKIP_PX = 2
#: Next to the sides the top edge stays within this share of the way down to the row
#: below, and within a pixel: it runs on flat there (a receding side edge has come
#: most of the way down).
FLAT_SHARE = 0.25
#: Columns beyond a side (past its blur) where a front top edge has ended.
OUTSIDE_PX = (3, 7)


def _no_back_edge(view: View, dy: I16, ul: int, ur: int, vt: int, row: int) -> bool:
    """Whether the top edge on ``vt`` cannot be the back edge of a top face whose front
    edge is on ``row``. A top face recedes: with the horizon known (the rig), its back
    edge spans the front's columns scaled by s = (vt - cy) / (row - cy) about the
    principal point, and beyond its corners the top face's side edges run down to the
    front corners, on the front edge's row at the sides. So where s puts both back
    corners >= BACK_INSET_MIN_PX inside the sides, a top edge that still runs on near
    its own row next to both sides (within FLAT_SHARE of the way to ``row`` and a
    pixel) is the front top edge itself. Both sides: a yawed box moves its back
    corners one way, so one side may have its corner there; no yaw brings both out to
    the sides. The edge must stop
    at the sides too (a background line behind the box runs on)."""
    v = view
    if v.horizon_slack_px > 0.0 or row - v.cy <= 0.0 or row - vt < 2:
        return False
    s = max(0.0, (vt - v.cy) / (row - v.cy))
    left, right = (1.0 - s) * (v.cx - ul), (1.0 - s) * (ur - v.cx)
    if min(left, right) < BACK_INSET_MIN_PX:
        return False
    r0 = max(0, vt - 2)
    ay = np.abs(dy[r0 : row + 1]).astype(np.float32)
    m = max(2, (ur - ul) // 4)
    mid = ay[:, ul + m : ur - m]
    level = median(mid.max(axis=0))
    if level <= 0.0:
        return False
    # the top edge's own row (not a line under it)
    at = r0 + median(mid[: vt + 2 - r0].argmax(axis=0).astype(np.float32))
    for c0, c1 in (
        (ul + SIDE_SKIP_PX, ul + SIDE_SKIP_PX + max(2, int(left / 3))),
        (ur - SIDE_SKIP_PX - max(2, int(right / 3)), ur - SIDE_SKIP_PX),
    ):
        # the outer third of the way to the back corner: a receding side edge is there
        # most of the way down to the front edge's row (and blurred with it), the top
        # edge running on stays on its own row (the corner's blur weakens it a little)
        zone = ay[:, c0:c1]
        off = np.abs(r0 + zone.argmax(axis=0).astype(np.float32) - at)
        flat = median(off) <= min(1.0, FLAT_SHARE * (row - vt))
        if median(zone.max(axis=0)) < 0.5 * level or not flat:
            return False
    # ... and stops there: a line running on past the sides is the background's, which
    # may stand right behind a top face's back edge
    lo, hi = max(0, int(at) - 1 - r0), int(at) + 2 - r0
    for c0, c1 in (
        (ul - OUTSIDE_PX[1], ul - OUTSIDE_PX[0]),
        (ur + OUTSIDE_PX[0], ur + OUTSIDE_PX[1]),
    ):
        beyond = ay[lo:hi, max(0, c0) : max(0, c1)]
        if beyond.size and median(beyond.max(axis=0)) >= 0.5 * level:
            return False
    log.debug("top %d runs on to both sides: no top face's back edge over %d", vt, row)
    return True


#: An edge ending this many columns inside both of the face's sides is inset in it.
INSET_MIN_PX = 3.0


def _inset(dy: I16, row: int, ul: int, ur: int) -> bool:
    """Whether the horizontal edge on ``row`` ends well inside both sides."""
    ends = _edge_ends(np.abs(dy[max(0, row - 1) : row + 2]).astype(np.float32), 1, ul, ur)
    return ends is not None and ends[0] - ul >= INSET_MIN_PX and ur - ends[1] >= INSET_MIN_PX


def _edge_ends(ay: F32, row: int, ul: int, ur: int) -> tuple[float, float] | None:
    """The first and last columns, from just outside the sides ``ul`` and ``ur``, where
    the horizontal edge on ``row`` (or a row next to it) reaches half its median strength
    over the face's middle half, or None."""
    c0, c1 = max(1, ul - 4), min(ay.shape[1] - 1, ur + 5)
    prof = ay[max(0, row - 1) : row + 2, c0:c1].max(axis=0)
    m = max(2, (ur - ul) // 4)
    level = median(ay[max(0, row - 1) : row + 2, ul + m : ur - m].max(axis=0))
    if level <= 0.0:
        return None
    on = (prof >= 0.5 * level).nonzero()[0]
    if on.size < 4:
        return None
    return float(c0 + on[0]), float(c0 + on[-1])


def front_from_back(
    view: View, depth: float, ay: F32, dy: I16, rb: int, ul: int, ur: int, vt: int
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
    v = view
    if vt - v.cy < 3.0 or ur - ul < 12:
        return None
    ends = _edge_ends(ay, vt, ul, ur)
    if ends is None:
        return None
    a, b = ends
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
    min_h = max(3, int(v.fy * MIN_SIZE_M / depth))
    if vf <= vt + 1.0 or vf >= rb - min_h:
        return None
    mc = max(1, (ur - ul) // 8)
    r0, r1 = max(vt + 1, int(math.floor(vf)) - 2), min(rb - min_h, int(math.ceil(vf)) + 2)
    if r1 < r0:
        return None
    col = row_means(dy[vt : r1 + 2, ul + mc : ur - mc])  # col[r - vt] is row r
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
    if _inset(dy, r, ul, ur):
        # the front top edge spans the face from side to side; an edge that ends inside
        # both sides is a print's or a label's, inset in the face: no top face here
        log.debug("top %d: the edge below on row %d is inset, no top face's front", vt, r)
        return None
    log.debug(
        "top %d is a back edge (scale %.3f): front top edge at %d (pred %.1f)", vt, scale, r, vf
    )
    # with no extremum of its own, the predicted row itself, sub-pixel: refining near
    # it would slide onto the back edge's blur tail
    return r, (1.0 if col[r - vt] >= 0 else -1.0), (None if peaks else vf)
