"""A face's sides checked against its top and bottom edges: a seam is not a side.

Receives the chosen face (floor-contact row, top row, side columns, in the levelled view)
and the view's |d/dy| and |d/dx|; returns the side columns moved outward past vertical
seams. A face is one surface at the sonar's depth: its floor-contact edge and its top edge
run along its whole width, and end at its true sides. A plank seam, a panel joint or the
edge of a poster is a strong vertical edge too, but the face's top and bottom edges run on
across it; the side search, ranking vertical edges by strength, took such seams for sides
and collapsed the width to one plank on independently made rooms.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.fused.profiles import (
    column_means,
    median_of,
    narrow_max,
    partitioned,
    share,
    walk_on,
)

_c_lines_on_rows: Callable[[Any, int, int, int, float, float, Any], None] | None
try:  # the optional C accelerator (setup.py); without it numpy takes the lines' passes
    from obstacle_fusion.vision.fused._cmiddle import lines_on_rows as _c_lines_on_rows
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_lines_on_rows = None

#: The edges count as running on while their strength stays above this share of the face's.
CONTINUE_SHARE = 0.5
#: Neither edge may fall under this share of its strength along the face.
EDGE_FLOOR_SHARE = 0.2
#: Along the chosen face, an edge's median must reach this share of its strong end
#: (an edge present over half the face only is not the face's).
EVEN_SHARE = 0.5
#: A side moves only when the edges run on past it by this share of the face's width
#: (a few columns more are the side face's receding edges, not a seam).
MIN_WIDEN_SHARE = 0.15
#: Columns averaged when walking along an edge (one noisy column stops nothing).
WALK_WINDOW = 3
_WALK_KERNEL = np.ones(WALK_WINDOW, np.float32) / WALK_WINDOW  # the walks' running mean
#: Columns where the edges may dip (a seam, a joint) without ending the face.
MAX_GAP = 4
#: Where the top and bottom edges end, a side as strong as this share of the chosen
#: (seam) sides' weaker one must stand, else the widening is refused.
SIDE_SHARE_OF_SEAM = 0.5
#: Share of the face's rows the new side's edge must be present in.
SIDE_COVERAGE = 0.8
#: The lowest share of the face's rows where a new side must be present (its foot).
FOOT_SHARE = 0.15
#: Rows either side of an edge row searched for its peak (blur, sub-pixel position).
EDGE_ROWS = 1
#: Side columns searched for the strongest vertical edge where the walk stopped.
SNAP_COLUMNS = 6
#: The face's own edges must stand this many noise levels above the floor's texture.
MIN_EDGE_SNR = 3.0
#: With the foot edge fainter than that (a face in the floor's shade), the top edge alone
#: must stand this many noise levels (session 38: 10 -> 6; procedural/2090 hard, a seam
#: face in the floor's shade whose top stood 6.8, was measured as one panel, -68 %) ...
TOP_ALONE_SNR = 6.0
#: ... and runs on while at this share of its strength along the face.
TOP_ALONE_SHARE = 0.5
#: A plank or brick of another shade dims the face's top and foot edges, but both stay
#: edges on their rows (:func:`_line_on_row`): at least MIN_EDGE_SNR noise levels and this
#: many times the weaker of the |d/dy| a few rows above and below (a textured floor or
#: wall has its detail on every row, a face's edge only on its own) ...
LINE_CONTRAST = 2.0
#: ... read over these rows either side of the edge's row (clear of the edge's blur).
LINE_SIDE_ROWS = (3, 5)
#: The widening walks on where both edges stand on their rows (a switch for the tests).
SAME_ROW_EDGES = True
#: An edge uneven along the chosen face (under EVEN_SHARE of its strong end) is still the
#: face's where it stands on its own row over this share of the face's columns: a top
#: edge against a background of varying shade (a lit structure behind one corner) is
#: strong at that end only, yet one line on one row (a switch for the tests: 0 is off).
UNEVEN_LINE_SHARE = 0.9
#: Where the face's top and foot lines end together, its side stands there even where no
#: vertical edge reaches the foot (planks of the floor's colour against the floor): the
#: face is one surface square to the beam, its top and foot each a line on one row from
#: side to side, and both end at its sides (a switch for the tests).
LINES_END_TOGETHER = True
#: Both lines must stand on their rows over this share of the columns walked past the
#: chosen side (a dark seam breaks the foot line for a few columns) ...
LINES_WALKED_SHARE = 0.7
#: ... and over at most this share of the columns just past the new side: they end there ...
LINES_PAST_SHARE = 0.2
#: ... read over this many columns, from LINES_PAST_GAP columns past it (the edge's blur).
LINES_PAST_COLUMNS = 6
LINES_PAST_GAP = 3
#: The side's vertical edge must still be present over this share of the face's rows (the
#: part against the background; the part against a floor of its colour may show none).
LINES_SIDE_COVERAGE = 0.5
#: With the rig, a last plank narrower than MIN_WIDEN_SHARE of the face is still the
#: face's when its top and foot lines stand on the face's own rows across it and end
#: together at a side standing down to the floor-contact row: the seam left behind has
#: the face's surface on both sides, the contact edge running on under it, while a side
#: face's receding strip has its top and foot lines sloping off those rows (a switch).
NARROW_PLANK_ON_ROWS = True
#: A top edge walked alone (the foot too faint) under TOP_ALONE_SNR is still the face's
#: when it stands on its row over UNEVEN_LINE_SHARE of the face (a face in the floor's
#: shade against a wall near its shade: its top stands only 3-6 noise levels, but is one
#: line on one row across it); the walk then runs on at TOP_ALONE_SHARE of its strength as
#: for a strong top (0.5 x 6 = 3 = MIN_EDGE_SNR, so a column still on the line already
#: passes that share; a switch for the tests).
TOP_ALONE_LINE = True
#: Where the walk (the top and foot edges running on past a side) ended, the side is the
#: outermost vertical edge in the snap window reaching the seams' ``need``, at its own
#: peak (:func:`_outermost_peak`), before the strongest one: the face is one surface at
#: the sonar's depth, and its top and foot edges ran on across every column up to the
#: walk's end, so an edge they crossed is a seam inside it (a dark seam a few columns in
#: from the side is often the strongest column there: photo/3307 ordinary, seam 271,
#: side 278, -13 % wide at 0.63). Where that edge stands no face's side, the strongest
#: is tried as before (a switch for the tests) ...
OUTERMOST_PAST_SEAMS = True
#: ... and only where it is another edge than the strongest: the profile between the two
#: falls under this share of the outer one's strength, or the outer one stands under this
#: share of the strongest (a plateau of its own). A dark seam's band, its two edges merged
#: into one plateau by the blur and the 1x3 dilation, is one edge, its outer column still
#: the seam (procedural/2079 ordinary, no rig: the plateau 286-290 at 140-141, the face's
#: side a weak edge past it; its outer column taken, the colour walk from it stopped
#: short, 2.3 -> 5.1 %).
OUTER_DIP_SHARE = 0.9
#: With the foot too faint (the top edge walked alone), where no side stands in the snap
#: window, the side is sought over FAINT_SIDE_COLUMNS either side of where the walk ended
#: (session 47, branch ``wt-e-47``, from an untested diff of session 46; a switch): the
#: strongest local peak of the vertical edges reaching the seams' ``need`` and present over
#: SIDE_COVERAGE of the face's rows. The top edge alone runs on along a background line
#: level with it (a horizon behind a low face) or stops short on a plank of the wall's
#: shade, so its end lies up to a plank's width from the side either way; with no foot
#: edge to end with it, the snap window (SNAP_COLUMNS back, 2 on) misses the side (photo
#: 3329 hard, planks in the floor's shade: sides 143 and 467, the walk's ends 132 and 451,
#: w -87 %). The side is not asked to stand down to the floor: a face in the floor's shade
#: shows no side against it at its foot.
FAINT_SIDE_WINDOW = True
FAINT_SIDE_COLUMNS = 16
#: ... standing at least FAINT_SIDE_CONTRAST times the side profile's mean over the
#: columns FAINT_INSIDE (3-6) inside it: the face's surface just inside its side shows no
#: vertical edge of that strength, while a textured floor or a glow beside the face shows
#: one on every column (photo 741 hard, panels before a gravel floor and a lamp's glow: a
#: column of that texture 25 past the side, 1.1 times the columns inside it, +0.7 -> +17 %;
#: photo 3329's sides 3.7 and 3.1 times).
FAINT_SIDE_CONTRAST = 2.0
FAINT_INSIDE = (3, 6)
#: With the rig given, the widening walk runs on over a plank whose grey is that of what
#: lies beyond one of the face's edges (the wall above its top, the floor below its foot):
#: there that edge fades out (under MIN_EDGE_SNR noise levels: no edge at all, not a dim
#: one) while the other stands on its own row (:func:`_line_on_row`), the face one surface
#: at the sonar's depth (session 48, helper B; procedural/3423 ordinary: a last plank of the
#: pink wall's grey, top 0 over 266-272 while the foot runs on to the side at 272, -62 %;
#: procedural/3431 hard: a dark plank on a dark floor, foot 1-2 noise levels over 199-225
#: while the top runs on to the side at 162, -57 %). The side reached so is against the same
#: background as the faded edge: it needs only MIN_EDGE_SNR noise levels (not the seams'
#: share; the seams part planks of other shades), still standing the face's height down to
#: the floor (a switch) ...
FADED_PLANK_WALK = True
#: ... over at most this share of the chosen pair's width of such one-line columns (a
#: plank is no wider than the planks found; a floor seam or a wall's line on the foot's or
#: the top's row runs on much farther).
FADED_MAX_SHARE = 1.0
#: ... the side standing at least this many times the median vertical edge over the
#: one-line columns crossed: a plank is one plain surface, while a textured floor beside a
#: low face (photo/747 ordinary, bricks on a brick floor: a joint 0.84 times the crossed
#: median, 39 columns past the side, the answer then refused) or clutter beside a small
#: one (photo/2105 hard, 1.15 and 1.19 times) shows vertical edges on every column; the
#: planks of 3423, 3431, 3080 hard and 3371 hard 2.8-35 times. 2.5, not 2.0 (review,
#: helper F): photo/3288 ordinary's ordinary walk overruns the face's side 305 to 342, and
#: the faded walk ran on from there to a cylinder's edge at 354, 2.27 times (-7.3 %).
FADED_SIDE_CONTRAST = 2.5


def _p90(values: npt.NDArray[np.float32]) -> float:
    """The 90th percentile by one partition (np.percentile costs more than the stage)."""
    k = int(0.9 * (values.size - 1))
    return float(partitioned(values, k)[k])


def _edge_profile(ay: npt.NDArray[np.float32], row: int) -> npt.NDArray[np.float32]:
    """Per column, the strongest |d/dy| within EDGE_ROWS of ``row``."""
    r0 = max(0, row - EDGE_ROWS)
    r1 = min(ay.shape[0], row + EDGE_ROWS + 1)
    return np.asarray(ay[r0:r1].max(axis=0), np.float32)


def _line_on_row(ay: npt.NDArray[np.float32], row: int, noise: float) -> npt.NDArray[np.bool_]:
    """Per column, whether a horizontal edge stands on ``row`` (within EDGE_ROWS): at least
    MIN_EDGE_SNR noise levels and LINE_CONTRAST times the weaker of the mean |d/dy| over
    the rows LINE_SIDE_ROWS above and below it (a step between two surfaces, whatever its
    contrast; texture that fills every row is no line)."""
    a, b = LINE_SIDE_ROWS
    if row - b < 0 or row + b + 1 > ay.shape[0]:
        return np.zeros(ay.shape[1], bool)
    return _lines_on_rows(ay, row, row + 1, noise)[0]


def _lines_on_rows(
    ay: npt.NDArray[np.float32], r0: int, r1: int, noise: float
) -> npt.NDArray[np.bool_]:
    """:func:`_line_on_row` for the rows r0..r1-1 at once (row r at r - r0), every row at
    least LINE_SIDE_ROWS[1] from the array's top and bottom. ``ay`` holds no NaN (Sobel
    magnitudes of an 8-bit image): the C path's maximum drops a NaN, numpy's keeps it."""
    a, b = LINE_SIDE_ROWS
    n = r1 - r0
    x = np.asarray(ay[r0 - b : r1 + b], np.float32)  # row r at r - r0 + b
    edge_min = MIN_EDGE_SNR * noise
    if (
        _c_lines_on_rows is not None
        and n >= 0
        and x.ndim == 2
        and x.shape[0] == n + 2 * b
        and type(edge_min) in (float, np.float32)  # compared in float32, as numpy does
    ):
        # the same passes in one C call (its float32 sums in the loop's order)
        out = np.empty((n, x.shape[1]), bool)
        _c_lines_on_rows(x, b, a, EDGE_ROWS, float(edge_min), LINE_CONTRAST, out)
        return out

    def rows(first: int) -> npt.NDArray[np.float32]:  # each row's row + first - b
        return x[first : first + n]

    edge = rows(b - EDGE_ROWS)
    for k in range(1, 2 * EDGE_ROWS + 1):
        edge = np.maximum(edge, rows(b - EDGE_ROWS + k))
    above, below = rows(0).copy(), rows(b + a).copy()  # rows r - b .. r - a, r + a .. r + b
    for k in range(1, b - a + 1):
        above += rows(k)
        below += rows(b + a + k)
    above /= b - a + 1
    below /= b - a + 1
    return (edge >= edge_min) & (edge >= LINE_CONTRAST * np.minimum(above, below))


def _stands(present: npt.NDArray[np.bool_]) -> bool:
    """A side's edge present over most of the face's rows and down to the floor: the
    face stands on the floor-contact row, while anything behind it (a chair's leg, a
    side face's far corner) meets the floor higher up in the image."""
    if present.size == 0:
        return False
    foot = present[-max(3, int(FOOT_SHARE * present.size)) :]
    return share(present) >= SIDE_COVERAGE and share(foot) >= SIDE_COVERAGE


def _snap_window(side: int, end: int, step: int, width: int) -> tuple[int, int]:
    """Columns to look for the real side where a walk from ``side`` ended at ``end``:
    mostly back towards the start (the walk's smoothing overshoots), never onto the
    edge it started from."""
    lo, hi = sorted((end - step * SNAP_COLUMNS, end + step * 2))
    if step < 0:
        hi = min(hi, side - 3)
    else:
        lo = max(lo, side + 3)
    return max(lo, 0), min(hi, width - 1)


def widen_across_seams(
    ay: npt.NDArray[np.float32],
    ax: npt.NDArray[np.int16],
    bottom: int,
    top: int,
    left: int,
    right: int,
    noise: float,
    top_alone: bool = False,
    narrow: bool = False,
    faded: bool = False,
) -> tuple[int, int]:
    """The face's side columns, moved out to where its top and bottom edges both end
    (``top_alone``: or, with the foot edge too faint, where a strong top edge ends, or a
    fainter one standing on its row across the face, see TOP_ALONE_LINE; only
    with the rig: under a row merely tried, that top is often a background line;
    ``narrow``: a last plank under the minimum move taken on the face's rows, see
    NARROW_PLANK_ON_ROWS, with the rig only; ``faded``: the walk run on over a plank whose
    top or foot edge faded out, see FADED_PLANK_WALK, with the rig given only)."""
    if right - left < 4 or bottom - top < 3:
        return left, right
    gb = _edge_profile(ay, bottom)
    gt = _edge_profile(ay, top)
    inner = slice(left + 1, right)
    ref_b = float(median_of(gb[inner]))
    ref_t = float(median_of(gt[inner]))
    faint_b = top_alone and ref_b < MIN_EDGE_SNR * noise
    if ref_b < MIN_EDGE_SNR * noise and not faint_b:
        return left, right  # too faint to tell a seam from a side
    top_line = (
        TOP_ALONE_LINE
        and faint_b
        and MIN_EDGE_SNR * noise <= ref_t < TOP_ALONE_SNR * noise
        and _one_line(ay, top, inner, noise)
    )
    if ref_t < MIN_EDGE_SNR * noise or (faint_b and ref_t < TOP_ALONE_SNR * noise and not top_line):
        return left, right  # too faint to tell a seam from a side
    for profile, ref, row in (
        ((gt, ref_t, top),) if faint_b else ((gb, ref_b, bottom), (gt, ref_t, top))
    ):
        if ref < EVEN_SHARE * _p90(profile[inner]) and not _one_line(ay, row, inner, noise):
            return left, right  # the edge does not run along the face itself: no face here
    kernel = _WALK_KERNEL
    st = np.convolve(gt, kernel, mode="same") / ref_t
    if faint_b:
        # a face in the floor's shade shows no foot edge: a strong top edge alone, running
        # on at the face's strength (the sides found must still stand down to the floor)
        runs_on = st >= TOP_ALONE_SHARE
    else:
        # both edges run on: together at CONTINUE_SHARE of the face's, neither below
        # EDGE_FLOOR_SHARE (a board of the wall's shade dims the top edge, not both)
        sb = np.convolve(gb, kernel, mode="same") / ref_b
        runs_on = ((sb + st) >= 2.0 * CONTINUE_SHARE) & (np.minimum(sb, st) >= EDGE_FLOOR_SHARE)
        if SAME_ROW_EDGES:
            # one surface at the sonar's depth, square to the beam: its top and foot are
            # one row each across planks or bricks of other shades, dimmer or not
            runs_on |= _line_on_row(ay, bottom, noise) & _line_on_row(ay, top, noise)
    sides = column_means(ax[top : bottom + 1])
    # a side stands as a vertical edge at least this strong (the chosen seams' weaker half)
    need = max(
        SIDE_SHARE_OF_SEAM * min(float(sides[left]), float(sides[right])), MIN_EDGE_SNR * noise
    )
    min_move = max(SNAP_COLUMNS // 2, MIN_WIDEN_SHARE * (right - left))
    lines = None
    if LINES_END_TOGETHER and not faint_b:
        lines = (_line_on_row(ay, top, noise), _line_on_row(ay, bottom, noise))
    faded_on = None
    if FADED_PLANK_WALK and faded and not faint_b:
        # one edge on its row, the other faded out: a plank of the background's grey
        edge_min = MIN_EDGE_SNR * noise
        line_t = lines[0] if lines is not None else _line_on_row(ay, top, noise)
        line_b = lines[1] if lines is not None else _line_on_row(ay, bottom, noise)
        one_line = (line_t & (gb < edge_min)) | (line_b & (gt < edge_min))
        faded_on = (runs_on, runs_on | one_line, one_line)
    new = []
    for side, step in ((left, -1), (right, 1)):
        moved = _outer_side(
            ax[top + 1 : bottom],
            sides,
            runs_on,
            side,
            step,
            min_move,
            need,
            lines,
            narrow and NARROW_PLANK_ON_ROWS,
            OUTERMOST_PAST_SEAMS,
            faint_b and FAINT_SIDE_WINDOW,
        )
        if faded_on is not None:
            past = _past_faded_plank(
                ax[top + 1 : bottom], sides, faded_on, side, step, min_move, right - left, noise
            )
            if past is not None and (moved is None or step * (past - moved) > min_move):
                # the side past a plank of the background's grey (not a side the ordinary
                # walk found already, a column or two out onto its blur: procedural/111
                # ordinary, photo/719 ordinary, fresh procedural/2175 hard, +1.5-1.8 %)
                moved = past
        new.append(side if moved is None else moved)
    return new[0], new[1]


def _past_faded_plank(
    ax_rows: npt.NDArray[np.int16],
    sides: npt.NDArray[np.float32],
    walks: tuple[npt.NDArray[np.bool_], npt.NDArray[np.bool_], npt.NDArray[np.bool_]],
    side: int,
    step: int,
    min_move: float,
    width: int,
    noise: float,
) -> int | None:
    """The side past ``side`` (towards ``step``) where the walk, run on over columns where
    one edge stands on its row and the other has faded out (``walks``: the ordinary walk's
    columns, those with the one-line columns, the one-line columns), ends at a vertical edge
    of MIN_EDGE_SNR noise levels standing down to the floor; None where that walk goes no
    farther than the ordinary one, crosses over FADED_MAX_SHARE of ``width`` one-line
    columns, or ends at no side more than ``min_move`` from ``side`` standing
    FADED_SIDE_CONTRAST times the vertical edges' median over the one-line columns (see
    FADED_PLANK_WALK)."""
    ordinary, widened, one_line = walks
    end0 = walk_on(ordinary, side, step, MAX_GAP)
    end = walk_on(widened, side, step, MAX_GAP)
    if step * (end - end0) <= 0 or abs(end - side) <= min_move:
        return None
    a, b = sorted((side, end))
    crossed = int((one_line[a : b + 1] & ~ordinary[a : b + 1]).sum())
    if crossed > FADED_MAX_SHARE * width:
        return None
    need = MIN_EDGE_SNR * noise
    lo, hi = _snap_window(side, end, step, sides.size)
    best = int(lo + sides[lo : hi + 1].argmax())
    if abs(best - side) <= min_move:
        return None  # the side's own blur (photo/3422 ordinary: 221 -> 218, +5.5 %)
    if float(sides[best]) < need or not _stands(_present(ax_rows, best, need)):
        return None
    plain = sides[a : b + 1][one_line[a : b + 1] & ~ordinary[a : b + 1]]
    if plain.size and float(sides[best]) < FADED_SIDE_CONTRAST * float(median_of(plain)):
        return None  # vertical edges all across: texture or clutter, not one plank
    return best


def _one_line(ay: npt.NDArray[np.float32], row: int, inner: slice, noise: float) -> bool:
    """Whether the edge on ``row`` stands on that row over UNEVEN_LINE_SHARE of the
    face's columns ``inner``: one line however its strength varies along it."""
    if UNEVEN_LINE_SHARE <= 0.0:
        return False
    return share(_line_on_row(ay, row, noise)[inner]) >= UNEVEN_LINE_SHARE


def _outer_side(
    ax_rows: npt.NDArray[np.int16],
    sides: npt.NDArray[np.float32],
    runs_on: npt.NDArray[np.bool_],
    side: int,
    step: int,
    min_move: float,
    need: float,
    lines: tuple[npt.NDArray[np.bool_], npt.NDArray[np.bool_]] | None = None,
    narrow: bool = False,
    outermost: bool = False,
    faint: bool = False,
) -> int | None:
    """Where the edges that run on past ``side`` (towards ``step``) end, the column of the
    face's real side: ``side`` itself when they stop within ``min_move`` columns, None when
    no side stands there (``ax_rows``: the rows the side must stand over, down to the floor;
    ``outermost``: the outermost strong edge where they end tried first, see
    OUTERMOST_PAST_SEAMS).

    No vertical edge where the edges end: a background line ran on, not the face; an edge
    that does not stand the whole height down to the floor (a side face's far corner, a
    chair's leg behind) is not the face's side either."""
    end = walk_on(runs_on, side, step, MAX_GAP)  # a dark seam dims the top edge across it
    if abs(end - side) <= min_move:
        if narrow and lines is not None and abs(end - side) > SNAP_COLUMNS // 2:
            return _narrow_plank(ax_rows, sides, side, end, step, need, lines)
        return side  # the edges stop at (or just past) the side: it is the face's
    lo, hi = _snap_window(side, end, step, sides.size)
    strongest = int(lo + sides[lo : hi + 1].argmax())
    tried = [strongest]
    if outermost:
        outer = _outermost_peak(sides, lo, hi, step, need)
        if outer is not None and _another_edge(sides, strongest, outer):
            tried.insert(0, outer)  # the edges ran on across the columns inside it
    for best in tried:
        if _side_at(ax_rows, sides, side, best, step, need, lines):
            return best
    if faint:
        return _faint_side(ax_rows, sides, side, end, step, need, (lo, hi))
    return None


def _faint_side(
    ax_rows: npt.NDArray[np.int16],
    sides: npt.NDArray[np.float32],
    side: int,
    end: int,
    step: int,
    need: float,
    judged: tuple[int, int] = (0, -1),
) -> int | None:
    """The side where a walk on the top edge alone (the foot too faint) ended at ``end``
    and no side stood in the snap window: the strongest local peak of ``sides`` within
    FAINT_SIDE_COLUMNS of ``end`` (never onto the edge the walk started from) reaching
    ``need`` and present over SIDE_COVERAGE of the rows ``ax_rows``, outside the snap
    window ``judged`` (its columns refused by :func:`_side_at` already: none is taken
    again on this looser test); None where none is (see FAINT_SIDE_WINDOW)."""
    lo = max(0, end - FAINT_SIDE_COLUMNS)
    hi = min(sides.size - 1, end + FAINT_SIDE_COLUMNS)
    if step < 0:
        hi = min(hi, side - 3)
    else:
        lo = max(lo, side + 3)
    best = None
    for c in range(lo, hi + 1):
        if judged[0] <= c <= judged[1]:
            continue  # the snap window's columns, judged by _side_at already
        v = float(sides[c])
        if v < need or (c > lo and v < sides[c - 1]) or (c < hi and v < sides[c + 1]):
            continue
        if share(_present(ax_rows, c, need)) < SIDE_COVERAGE:
            continue
        a, b = FAINT_INSIDE
        # (towards the face: to the left of a right side; clipped at the image's edge, where
        # a negative start would wrap round to the far end)
        inside = sides[max(0, c - b) : c - a + 1] if step > 0 else sides[c + a : c + b + 1]
        if inside.size and v < FAINT_SIDE_CONTRAST * float(inside.mean()):
            continue  # no single edge: texture on every column round it
        if best is None or v > float(sides[best]):
            best = c
    return best


def _another_edge(sides: npt.NDArray[np.float32], strongest: int, outer: int) -> bool:
    """Whether column ``outer`` is an edge apart from column ``strongest`` in the profile
    ``sides``: the outer one under OUTER_DIP_SHARE of the strongest, or the profile between
    them falling under OUTER_DIP_SHARE of the outer one (else one plateau: one edge)."""
    if outer == strongest:
        return False
    if float(sides[outer]) < OUTER_DIP_SHARE * float(sides[strongest]):
        return True
    a, b = sorted((strongest, outer))
    if b - a < 2:
        return False
    return float(sides[a + 1 : b].min()) < OUTER_DIP_SHARE * float(sides[outer])


def _side_at(
    ax_rows: npt.NDArray[np.int16],
    sides: npt.NDArray[np.float32],
    side: int,
    best: int,
    step: int,
    need: float,
    lines: tuple[npt.NDArray[np.bool_], npt.NDArray[np.bool_]] | None,
) -> bool:
    """Whether column ``best`` is the face's side where the walk from ``side`` ended: a
    vertical edge at least ``need`` strong standing the height down to the floor, or over
    LINES_SIDE_COVERAGE of the rows where the top and foot lines end together there."""
    present = _present(ax_rows, best, need)
    if float(sides[best]) < need:
        return False
    if _stands(present):
        return True
    if lines is not None and share(present) >= LINES_SIDE_COVERAGE:
        # the top and foot lines end together: the face's side
        return all(_line_ends_at(line, side, best, step) for line in lines)
    return False


def _present(ax_rows: npt.NDArray[np.int16], col: int, need: float) -> npt.NDArray[np.bool_]:
    """The rows of ``ax_rows`` where column ``col`` shows a side's edge: |d/dx| at least
    SIDE_SHARE of ``need``."""
    return np.asarray(ax_rows[:, col], np.float32) >= SIDE_SHARE * need


def _narrow_plank(
    ax_rows: npt.NDArray[np.int16],
    sides: npt.NDArray[np.float32],
    side: int,
    end: int,
    step: int,
    need: float,
    lines: tuple[npt.NDArray[np.bool_], npt.NDArray[np.bool_]],
) -> int:
    """The side of a last plank past ``side`` (the edges ran on to ``end``, under the
    minimum move): its column where a side (standing down to the floor, or over
    LINES_SIDE_COVERAGE of the rows) ends the top and foot lines together, both on the
    face's rows across the plank; else ``side``."""
    lo, hi = _snap_window(side, end, step, sides.size)
    best = _outermost_peak(sides, lo, hi, step, need)
    if best is None:
        return side
    present = _present(ax_rows, best, need)
    if not _stands(present) and share(present) < LINES_SIDE_COVERAGE:
        return side  # (a plank of the floor's colour shows no side against the floor)
    if all(_line_ends_at(line, side, best, step) for line in lines):
        return best
    return side


def _outermost_peak(
    sides: npt.NDArray[np.float32], lo: int, hi: int, step: int, need: float
) -> int | None:
    """The outermost (farthest towards ``step``) side in ``sides[lo..hi]`` at least
    ``need`` strong, at its own peak: from the outermost column reaching ``need``, inward
    while the next column is stronger. A plank of 4-5 columns puts the seam's blurred
    edge, stronger than the plank's side, in the window: the strongest column would be
    the seam's. None when no column reaches ``need``."""
    strong = np.flatnonzero(sides[lo : hi + 1] >= need)
    if strong.size == 0:
        return None
    best = lo + int(strong[0] if step < 0 else strong[-1])
    inward = -step
    while lo <= best + inward <= hi and sides[best + inward] > sides[best]:
        best += inward
    return best


def _line_ends_at(line: npt.NDArray[np.bool_], side: int, best: int, step: int) -> bool:
    """Whether a line on its row stands over LINES_WALKED_SHARE of the columns from
    ``side`` to ``best`` and ends there: at most LINES_PAST_SHARE of the columns just past."""
    a, b = sorted((side + step, best))
    walked = line[a : b + 1]
    p0 = best + step * LINES_PAST_GAP
    p1 = p0 + step * (LINES_PAST_COLUMNS - 1)
    lo, hi = min(p0, p1), max(p0, p1)
    if walked.size == 0 or lo < 0 or hi >= line.size:
        return False
    return share(walked) >= LINES_WALKED_SHARE and share(line[lo : hi + 1]) <= LINES_PAST_SHARE


#: A side counts as present in a row when its |d/dx| is at least this share of its
#: strength along the chosen face.
SIDE_SHARE = 0.4
#: Rows the sides may fade over (a dark band, a seam across) without ending the face.
MAX_ROW_GAP = 3
#: Rows searched for the strongest top edge where the sides stopped.
SNAP_ROWS = 4


def raise_top_past_inner_edges(
    ay: npt.NDArray[np.float32],
    ax: npt.NDArray[np.int16],
    bottom: int,
    top: int,
    left: int,
    right: int,
    noise: float,
) -> int:
    """The face's top row, moved up to where both its sides end.

    A label, a poster's lower edge or a band of another colour across the face is a
    horizontal edge between the sides; the face's sides run on above it, up to the face's
    real top (a top face, or the background, starts there and the sides stop)."""
    if right - left < 4 or bottom - top < 3 or top < 2:
        return top
    cols = []
    for side in (left, right):
        c0, c1 = max(0, side - 1), min(ax.shape[1], side + 2)
        cols.append(np.asarray(narrow_max(ax[:bottom, c0:c1]), np.float32))
    strength = [float(median_of(c[top:bottom])) for c in cols]
    if min(strength) < MIN_EDGE_SNR * noise:
        return top
    on = (cols[0] >= SIDE_SHARE * strength[0]) & (cols[1] >= SIDE_SHARE * strength[1])
    end = walk_on(on, top, -1, MAX_ROW_GAP)  # up, over a dark band or a seam across
    if top - end <= SNAP_ROWS // 2:
        return top
    # the top edge lies where the sides ended, or just above (blur): never back down
    # on the inner edge the sides ran past
    return _snap_top(ay, end, bottom, left, right)


#: A raise past the inner edges must end on the face's own top edge (session 41): the face
#: is one surface square to the beam, its top edge one line on one row from side to side.
#: Where the found top's line (:func:`top_line_share`) spans the face (over
#: RAISE_SPAN_HELD of its columns) and the raised top's spans under RAISE_SPAN_SHORT of
#: them, the sides ran on up an object standing behind in line with the face (a rocket
#: or a post narrower than the face, rarely of exactly its width), not up to its top, and
#: the raise is refused (a switch for the tests).
RAISE_SPANS_FACE = True
RAISE_SPAN_HELD = 0.8
RAISE_SPAN_SHORT = 0.5
#: Rows either side of a top's row read for its line (blur, the snap's one row below).
RAISE_SPAN_ROWS = 2


def top_line_share(
    ay: npt.NDArray[np.float32], row: int, left: int, right: int, noise: float
) -> float:
    """The largest share of the columns between ``left`` and ``right`` where a line
    (:func:`_line_on_row`) stands, over the rows within RAISE_SPAN_ROWS of ``row``."""
    _, b = LINE_SIDE_ROWS
    r0 = max(row - RAISE_SPAN_ROWS, b)
    r1 = min(row + RAISE_SPAN_ROWS + 1, ay.shape[0] - b)
    if r1 <= r0 or right - left < 3:
        return 0.0
    on = _lines_on_rows(ay, r0, r1, noise)[:, left + 1 : right]
    return float(on.mean(axis=1).max())


def raise_spans_face(
    ay: npt.NDArray[np.float32], top: int, raised: int, left: int, right: int, noise: float
) -> bool:
    """Whether a raise from ``top`` to ``raised`` stands by the face's top line
    (RAISE_SPANS_FACE): False where the found top's line spans the face and the raised
    top's does not (an object behind in line with the face, not its top)."""
    if not RAISE_SPANS_FACE or raised >= top:
        return True
    held = top_line_share(ay, top, left, right, noise)
    reached = top_line_share(ay, raised, left, right, noise)
    return not (held >= RAISE_SPAN_HELD and reached < RAISE_SPAN_SHORT)


def _snap_top(ay: npt.NDArray[np.float32], end: int, bottom: int, left: int, right: int) -> int:
    """The strongest top edge where the face's lines ended (SNAP_ROWS above, or one row
    below: blur), never back down on the edge they ran past: one snap for sides and seams."""
    r0, r1 = max(0, end - SNAP_ROWS), min(bottom - 1, end + 1)
    rows = np.asarray(ay[r0 : r1 + 1, left + 1 : right].mean(axis=1), np.float32)
    return int(r0 + rows.argmax())


#: The frame's sides must be at least this share of the print's sides' strength.
FRAME_SHARE_OF_PRINT = 0.25
#: The enclosing frame's sides must stand this far above the inner face's top (a share
#: of the inner face's height, at least 3 rows): the frame is taller than what it holds.
ABOVE_SHARE = 0.1


def enclose_inner_frame(
    ay: npt.NDArray[np.float32],
    ax: npt.NDArray[np.int16],
    bottom: int,
    top: int,
    left: int,
    right: int,
    noise: float,
) -> tuple[int, int, int]:
    """A face found inside a larger one standing on the same floor-contact edge.

    A poster, a page or a panel of bricks printed on the face with a margin of the face's
    own colour is a rectangle of its own, with a uniform shade inside, and the side search
    prefers it. The face's floor-contact edge runs on past the print's sides to the face's
    own sides, which stand from the floor to above the print's top: when both are found,
    the face is that frame, its top raised to where its sides end."""
    if right - left < 4 or bottom - top < 3:
        return left, right, top
    gb = _edge_profile(ay, bottom)
    inner = slice(left + 1, right)
    ref_b = float(median_of(gb[inner]))
    if ref_b < MIN_EDGE_SNR * noise or ref_b < EVEN_SHARE * _p90(gb[inner]):
        return left, right, top
    kernel = _WALK_KERNEL
    runs_on = np.convolve(gb, kernel, mode="same") >= CONTINUE_SHARE * ref_b
    sides = column_means(ax[top : bottom + 1])
    # a print's edges may be far stronger than the face's own sides against the room
    need = max(
        FRAME_SHARE_OF_PRINT * min(float(sides[left]), float(sides[right])), MIN_EDGE_SNR * noise
    )
    above = max(3, int(ABOVE_SHARE * (bottom - top)))
    if top - above < 0:
        return left, right, top
    new = []
    for side, step in ((left, -1), (right, 1)):
        # the frame's sides stand from the floor to above the print's top
        moved = _outer_side(
            ax[top - above : bottom], sides, runs_on, side, step, SNAP_COLUMNS // 2, need
        )
        if moved is None:
            return left, right, top
        new.append(moved)
    if new == [left, right]:
        return left, right, top
    outer_top = raise_top_past_inner_edges(ay, ax, bottom, top, new[0], new[1], noise)
    if outer_top >= top:
        return left, right, top
    return new[0], new[1], outer_top


#: How far beyond a print's side its face's outline is sought, as a share of the print's
#: larger side (a margin of up to 12 % of the face is 16 % of the print inside it).
OUTLINE_REACH = 0.25
#: ... and how far (metres at the face's depth) a margin still running on at that reach
#: is followed (the piece found is a small part of a print covering most of the face).
OUTLINE_FAR_M = 0.6
#: A foot under a print may be faint in grey (a margin of the floor's shade, a contact
#: shadow): its row need only stand this many noise levels (the margin's colour decides).
OUTLINE_FOOT_SNR = 1.5


def foot_in_band(
    ay: npt.NDArray[np.float32],
    bottom: int,
    left: int,
    right: int,
    band: tuple[int, int],
    noise: float,
) -> int | None:
    """The row in the floor-contact ``band`` below ``bottom`` where the horizontal edge
    across the face's columns is strongest (the face's foot under a print standing above
    it), or None when none stands OUTLINE_SNR noise levels."""
    n = ay.shape[0]
    r0, r1 = max(bottom + 2, band[0]), min(band[1], n - 2)
    if r0 > r1 or right - left < 4:
        return None
    foot = np.asarray(ay[r0 : r1 + 1, left + 1 : right].mean(axis=1), np.float32)
    if float(foot.max()) < OUTLINE_FOOT_SNR * noise:
        return None
    return r0 + int(foot.argmax())


#: Seams (vertical lines inside the face, panel joints, plank gaps) that raise a top:
#: at least this many, each standing over this share of the face's rows as found.
MIN_SEAMS = 2
SEAM_COVERAGE = 0.8
#: The seams must end within this many rows of one another (a face's top cuts all of
#: its joints at one row; stickers and prints end wherever they end).
SEAM_END_SPREAD = 3
#: Edge peaks this many columns apart or closer are one seam (a thin line's two edges).
SEAM_WIDTH = 4
#: No stretch of the face between its sides and the seams running on may be wider than
#: this share of it.
SEAM_PART_SHARE = 0.5


def raise_top_along_seams(
    ay: npt.NDArray[np.float32],
    ax: npt.NDArray[np.int16],
    bottom: int,
    top: int,
    left: int,
    right: int,
    noise: float,
) -> int:
    """The face's top row, moved up to where the face's own seams end.

    A face in the wall's shade shows no sides against it: they end where a band behind it
    (a skirting board, a dado rail) ends beside them, and that row is taken for the top
    though no edge of the face's crosses it there. The face's panel joints or plank gaps
    run from its foot to its top and are part of the face: a real top edge ends every one
    of them at one row, while a line behind the face cannot cut lines on the face. Seams
    that run on past ``top`` together and end together put the top where they end."""
    # no seam looked for in the side's own blur
    c0, c1 = left + SNAP_COLUMNS // 2, right - SNAP_COLUMNS // 2
    if c1 - c0 < 3 or bottom - top < 3 or top < 2:
        return top
    face = np.asarray(ax[top + 1 : bottom, c0:c1], np.float32)
    means = face.mean(axis=0)
    need = MIN_EDGE_SNR * noise
    peaks: list[int] = []
    for c in range(1, means.size - 1):
        if not (means[c] >= need and means[c] >= means[c - 1] and means[c] > means[c + 1]):
            continue
        if peaks and c - peaks[-1] <= SEAM_WIDTH:
            # a thin line's two edges are one seam: its stronger edge stands for it
            if means[c] > means[peaks[-1]]:
                peaks[-1] = c
            continue
        peaks.append(c)
    ends: list[tuple[int, int]] = []  # (row where the seam ends, its column)
    for c in peaks:
        col = np.asarray(narrow_max(ax[:bottom, c0 + c - 1 : c0 + c + 2]), np.float32)
        strength = float(median_of(col[top + 1 : bottom]))
        on = col >= SIDE_SHARE * strength
        if strength < need or share(on[top + 1 : bottom]) < SEAM_COVERAGE:
            continue
        ends.append((walk_on(on, top, -1, MAX_ROW_GAP), c0 + c))
    # the seams that ran on past the top, ending together; most of the face's seams
    ran = sorted(e for e in ends if top - e[0] > SNAP_ROWS // 2)
    best: list[tuple[int, int]] = []
    for e0, _ in ran:
        group = [e for e in ran if e0 <= e[0] <= e0 + SEAM_END_SPREAD]
        if len(group) > len(best):
            best = group
    if len(best) < MIN_SEAMS or 2 * len(best) < len(ends):
        return top
    # a panelled face's joints part all of it: a stretch of it over SEAM_PART_SHARE with no
    # seam running on is another surface the pair took in (a box beside the panels)
    cuts = [left, *sorted(c for _, c in best), right]
    if int(np.diff(cuts).max()) > SEAM_PART_SHARE * (right - left):
        return top
    end = int(np.median([e for e, _ in best]))
    if end <= SNAP_ROWS:
        return top  # lines running out of the view: no top seen where they end
    return _snap_top(ay, end, bottom, left, right)


#: A face chosen between a seam and a background edge in line with it (a tower behind the
#: planks) runs up past the face's top: where a line on one row crosses the chosen face and
#: runs on past both its sides, ending at vertical edges standing down towards the foot,
#: that line is the face's top and its ends are the sides (a switch for the tests).
TOP_LINE_ACROSS = True
#: The line must stand on its row over this share of the chosen face's columns (a
#: background edge crossing it breaks it for a column or two) ...
ACROSS_INNER_SHARE = 0.8
#: ... and run on past each side by this share of the chosen width (at least 3 columns).
ACROSS_REACH_SHARE = 0.5
#: The rows searched end this share of the face's height above the foot (a line lower
#: than that is the floor's, or a plinth's) ...
ACROSS_LOW_SHARE = 0.3
#: ... and start this share of it (at least 3 rows) below the chosen top (a line just
#: under the top is the top's own blur or a top face's front edge: the widening's).
ACROSS_HIGH_SHARE = 0.1
#: Above the line, a side where it ends is present over at most this share of the rows
#: read (a quarter of the face's height under the line, at least 3): the side ends there.
ACROSS_ABOVE_SHARE = 0.5
#: A side where the line ends stands at least this share of the chosen sides' weaker one
#: (a dark joint between planks is far stronger than the face's side against the room).
ACROSS_SIDE_SHARE = 0.25


def top_line_across(
    ay: npt.NDArray[np.float32],
    ax: npt.NDArray[np.int16],
    bottom: int,
    top: int,
    left: int,
    right: int,
    noise: float,
) -> tuple[int, int, int] | None:
    """The face's (top, left, right) where a line on one row below the chosen top crosses
    the chosen face and runs on past both its sides, both its ends at vertical edges that
    stand from that row down (over LINES_SIDE_COVERAGE of the rows): the chosen sides were
    a seam and an edge behind in line with it; None when no row shows such a line."""
    w = right - left
    if not TOP_LINE_ACROSS or w < 4 or bottom - top < 9:
        return None
    inner = slice(left + 1, right)
    reach = max(3, int(ACROSS_REACH_SHARE * w))
    best: tuple[float, int, int, int] | None = None
    first = top + max(3, int(ACROSS_HIGH_SHARE * (bottom - top)))
    last = bottom - max(3, int(ACROSS_LOW_SHARE * (bottom - top)))
    for r in _rows_lined(ay[:, inner], first, last, noise):
        line = _line_on_row(ay, r, noise)
        ends = walk_on(line, left, -1, MAX_GAP), walk_on(line, right, 1, MAX_GAP)
        if left - ends[0] < reach or ends[1] - right < reach:
            continue
        sides = column_means(ax[r : bottom + 1])
        need = max(
            ACROSS_SIDE_SHARE * min(float(sides[left]), float(sides[right])),
            MIN_EDGE_SNR * noise,
        )
        new = []
        for side, end, step in ((left, ends[0], -1), (right, ends[1], 1)):
            lo, hi = _snap_window(side, end, step, sides.size)
            col = int(lo + sides[lo : hi + 1].argmax())
            present = _present(ax[r + 1 : bottom], col, need)
            if float(sides[col]) < need or share(present) < LINES_SIDE_COVERAGE:
                break
            new.append(col)
        if len(new) < 2:
            continue
        if raise_top_past_inner_edges(ay, ax, bottom, r, new[0], new[1], noise) < r or any(
            _runs_on_above(ax, bottom, r, col) for col in new
        ):
            continue  # the sides run on up past the line: a joint across the face, no top
        strength = float(ay[r, new[0] + 1 : new[1]].mean())
        if best is None or strength > best[0]:
            best = (strength, r, new[0], new[1])
    return None if best is None else best[1:]


def _runs_on_above(ax: npt.NDArray[np.int16], bottom: int, row: int, col: int) -> bool:
    """Whether the vertical edge at ``col`` runs on above ``row``: present (at SIDE_SHARE
    of its median under the row) over more than ACROSS_ABOVE_SHARE of the rows just above
    it (a quarter of the height under it, at least 3)."""
    n = max(3, (bottom - row) // 4)
    c0, c1 = max(0, col - 1), min(ax.shape[1], col + 2)
    if row - n - 1 < 0:
        return False
    below = np.asarray(narrow_max(ax[row + 2 : bottom, c0:c1]), np.float32)
    above = np.asarray(narrow_max(ax[row - n - 1 : row - 1, c0:c1]), np.float32)
    return share(above >= SIDE_SHARE * float(median_of(below))) > ACROSS_ABOVE_SHARE


def _rows_lined(block: npt.NDArray[np.float32], first: int, last: int, noise: float) -> list[int]:
    """The rows ``first``..``last - 1`` where a line (:func:`_line_on_row`) stands over
    ACROSS_INNER_SHARE of ``block``'s columns."""
    _, b = LINE_SIDE_ROWS
    r0, r1 = max(first, b), min(last, block.shape[0] - b)
    if r1 <= r0:
        return []
    on = _lines_on_rows(block, r0, r1, noise)
    return [r0 + i for i in np.nonzero(on.mean(axis=1) >= ACROSS_INNER_SHARE)[0].tolist()]


#: The face's top edge spans it (session 38, a switch for the tests): where the top line
#: (:func:`_line_on_row` on the top's row) is absent next to one side over a stretch of
#: TOP_SPAN_MIN_SHARE to TOP_SPAN_MAX_SHARE of the face's width, and stands over
#: TOP_SPAN_HELD of the columns from where it ends to the other side, that side is moved
#: in to the strongest vertical edge within SNAP_COLUMNS of where it ends, present over
#: TOP_SPAN_SIDE_COVERAGE of the face's rows: the face is one surface whose top edge runs
#: from side to side, and a side taken on an object beside it (procedural/116 hard: a
#: cylinder's edge 70 px past a low box in the floor's shade, width +58 %) has no top line
#: over the stretch between.
TOP_LINE_SPANS = True
TOP_SPAN_MIN_SHARE = 0.2
#: (a longer stretch with no top line says the top found is not yet the face's own: a
#: background line in line with one part of it, which a later stage corrects; photo/718
#: hard's top at this stage stood over 42 % of the pair, trimmed to it +28 % and +140 %)
TOP_SPAN_MAX_SHARE = 0.5
TOP_SPAN_HELD = 0.9
TOP_SPAN_SIDE_COVERAGE = 0.5


def trim_to_top_line(
    ay: npt.NDArray[np.float32],
    ax: npt.NDArray[np.int16],
    bottom: int,
    top: int,
    left: int,
    right: int,
    noise: float,
) -> tuple[int, int]:
    """The side columns moved in to where the face's top line ends (TOP_LINE_SPANS): a
    side with no top line next to it over a part of the face's width stands on something
    beside the face. ``ax``: |d/dx| (dilated), the side's edge must stand over the face's
    rows there. Returns (left, right), unchanged where no side moves."""
    if not TOP_LINE_SPANS or right - left < 8 or bottom - top < 3:
        return left, right
    line = _line_on_row(ay, top, noise)
    width = right - left
    sides = column_means(ax[top : bottom + 1])
    new = [left, right]
    for k, (side, step) in enumerate(((left, 1), (right, -1))):
        end = side  # the top line's first column walking in from this side
        while (end - side) * step < width and not line[end]:
            end += step
        if not TOP_SPAN_MIN_SHARE * width <= abs(end - side) <= TOP_SPAN_MAX_SHARE * width:
            continue
        held = (end, right) if step > 0 else (left, end)
        if share(line[held[0] : held[1] + 1]) < TOP_SPAN_HELD:
            continue
        # the snap window inside the face: the side's own edge is no place to move in to
        s0, s1 = max(left + 1, end - SNAP_COLUMNS), min(right - 1, end + SNAP_COLUMNS)
        if s1 < s0:
            continue
        best = int(s0 + sides[s0 : s1 + 1].argmax())
        strength = float(sides[best])
        if strength < MIN_EDGE_SNR * noise:
            continue
        present = np.asarray(ax[top + 1 : bottom, best], np.float32) >= SIDE_SHARE * strength
        if share(present) < TOP_SPAN_SIDE_COVERAGE:
            continue
        new[k] = best
    if new[1] - new[0] < 4:
        return left, right
    return new[0], new[1]
