"""The face's outline read from its foot up (session 35): a print found instead of the face.

Receives the face as found (floor-contact row, top row, side columns, in the levelled view),
the floor-contact row the rig and the range predict and the input BGR frame (read in CIE Lab,
only a block round the face); returns the face's outline (bottom, top, left, right) or None.

A print covering the face (a poster, a photograph, a drawn pattern) has strong edges of its
own inside the face: the search, the colour and the texture rescues take a piece of it (a
plain part at its foot, a column of its pattern) and every walk up or out stops on a row or
a column of the picture. Its outline does not depend on the picture: the face is one
surface standing on the floor the rig predicts, so just above that row, across its whole
width, it hides the floor that shows just below it (whatever it carries), and beside it
the floor runs on further back; and each of its sides parts it from what stands beside it
from the floor all the way up to its top, where both end together.
"""

from __future__ import annotations

import logging
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.fused.profiles import median_u8, row_norms
from obstacle_fusion.vision.types import View

log = logging.getLogger(__name__)

#: Rows just above the floor-contact row read for the face's foot (its edge's blur skipped).
FOOT_FACE_ROWS = (1, 5)
#: Rows just below it read for the floor the face hides.
FOOT_FLOOR_ROWS = (3, 7)
#: A column is the face's (it hides the floor) where its foot differs from the floor under
#: it by at least this (Lab; the sides' walk's clear step, region.MIN_BESIDE_STEP), and a
#: side stands on a row where what is just inside it differs as much from what is just
#: outside.
FOOT_STEP = 12.0
#: The foot's run is walked out from the found face over gaps of up to this (m at the face:
#: a print's dark part of the floor's shade at the foot) ...
FOOT_GAP_M = 0.02
#: ... and must end within this far (m) past the found sides on both sides: a run reaching
#: farther is a band along the wall's foot or a floor line, no face's foot.
FOOT_REACH_M = 1.0
#: The found face's own foot must hide the floor along this share of its columns (else
#: the found face is no face standing on the predicted row: nothing to widen from).
FOUND_FOOT_SHARE = 0.6
#: A face wider than this (m) is no face the sonar ranges (its foot run is clutter too).
MAX_FACE_M = 1.5
#: Columns read on each side of a side candidate (their means compared) ...
SIDE_STRIP = 3
#: ... and its rise walked up over gaps of up to this (m at the face: a print's part of
#: the background's shade along one side) ...
RISE_GAP_M = 0.05
#: ... from the floor up to at most this (m: a face is seldom taller).
RISE_REACH_M = 1.5
#: A side is sought within this share of the foot run's width inside each of its ends
#: (the run may end a shadow's or a blur's width outside the side) ...
SIDE_SEARCH_SHARE = 0.25
#: ... as the outermost column rising at least this many times the found face's height
#: (the outline round a piece of the picture rises past that piece's top) ...
SIDE_RISE_FACTOR = 1.3
#: ... and at least this far (m): the blur of a shadow or a floor line rises a few rows ...
SIDE_MIN_RISE_M = 0.1
#: ... standing in at least this share of the rows up to its end (region.OUTLINE_COVER: a
#: face's side stands nearly all the way, the leaning lines of a floor's grid crossed
#: one after another over the gaps here and there: with no cover asked, 5 of the own
#: rooms' answers the rule fixed went wrong again, procedural/746 hard among them).
SIDE_COVER = 0.8
#: The two sides' rises end together (a face's top is level): within this share of the
#: longer one (plus SIDE_AGREE_ROWS rows; photo/735 hard: its right side rises on up a
#: tripod's leg behind, 147 against 179 rows, 0.18).
SIDE_AGREE_SHARE = 0.25
SIDE_AGREE_ROWS = 3
#: Rows over and under a top row read for its step (its edge's blur skipped) ...
TOP_STEP_ROWS = (2, 5)
#: ... which must part the face under it from what is over it along at least this share
#: of the columns between the sides: a face's top is a boundary across it, not a row of
#: a textured background the sides' steps rose on into (procedural/746 hard's top: 0.84).
TOP_STEP_SHARE = 0.75
#: The outline is taken only where it grows the face found: its top at least this share
#: of the found face's height higher (region.OUTLINE_MIN_RAISE's figure: a few rows up
#: are a plain face's top blur, or a low box's top face; photo/2034 hard's print: 0.66) ...
MIN_RAISE_SHARE = 0.5
#: ... or its width this many times the found one.
MIN_WIDEN_FACTOR = 1.25
#: The outline holds at least this share of the found face's columns (a found side may lie
#: past the face's, on its shadow or the floor's blur beside it: procedural/746 hard, 0.87).
CONTAIN_SHARE = 0.7
#: Where no side rises past the found top (the found face's height right, its width a
#: piece between inner lines of the face: plank seams, panel joints, a gloss band, a
#: print's frame), the sides are read for the width alone (session 37, a switch): the
#: outermost columns near the foot run's ends rising at least WIDTH_RISE_SHARE of the
#: found face's height, both ending (within SIDE_AGREE_SHARE) at a top across them within
#: WIDTH_TOP_SHARE of the found height (plus SIDE_AGREE_ROWS) of the found top, which is
#: kept. A seam has the face on both sides: no colour step rises along it; the face's true
#: side parts it from the floor or wall.
WIDTH_FROM_FOOT = True
WIDTH_RISE_SHARE = 0.8
WIDTH_TOP_SHARE = 0.1
#: ... taken only where it widens the found face at least this many times (the failures
#: this is for were 30-90 % too narrow; procedural/2079 hard's tape box, widened 1.26
#: times onto its blur, lost 4.6 points at 1.25).
WIDTH_MIN_FACTOR = 1.4
#: ... or at least WIDTH_PLANK_FACTOR times where a width side moved out past the found
#: one by at least WIDTH_PLANK_M at the face (session 47, branch ``wt-e-47``, a switch):
#: the found side was a seam or a joint with a whole plank or panel of the face beyond it
#: (its foot hides the floor, its side rises from the floor to the found top), while a
#: blur or a shadow beside a face widens it by a few columns only (procedural/2079 hard's
#: tape box: 2-5 columns, 0.01-0.02 m, 1.26 times, stays refused). Neither width side
#: may lie WIDTH_PLANK_M or more inside the foot's run's end: with a plank's width of the
#: face's foot still past it, that side is itself an inner line, not the face's (procedural
#: 3302 ordinary, a brick print in a margin: its right width side the print's edge 20
#: columns, 0.10 m, inside the run's end; taken, -22 -> -11 % at 0.63, a sure wrong answer).
#: And the width sides' top must be the found top within SIDE_AGREE_ROWS (its blur), not
#: merely within WIDTH_TOP_SHARE: a plank past a seam is the same surface, its top the
#: face's one row, while a frame round a print rises past the print's top (procedural 2020
#: ordinary no rig: the frame's sides ending 7 rows over the print's top, which was kept:
#: h +1.0 -> -8.8 % at 0.24).
WIDTH_PAST_PLANK = True
WIDTH_PLANK_M = 0.08
WIDTH_PLANK_FACTOR = 1.1
#: Where WIDTH_PAST_PLANK alone takes the width sides (not WIDTH_MIN_FACTOR, not
#: WIDTH_ONE_MARGIN), their top (within SIDE_AGREE_ROWS of the found one, as asked there)
#: is the face's where it lies over the found top (session 47, review helper J, a
#: switch): the plank is the same surface as the face, its top the face's one row, and
#: the sides rising from the floor across the whole widened face step across there; a
#: found top under it was read on the found part alone, under a line on it (procedural
#: 3176 hard no rig, text on a face: the found top 199, the sides' 196, the truth about
#: 195: with the found top kept h -6.0 % at 0.74, a sure wrong answer; with the sides'
#: -0.4 % at 0.33). A sides' top under the found one is a rise ended early (a faded top
#: edge), not a lower face: the found top stays.
PLANK_TOP_RAISED = True
#: Where the sides read for the width (WIDTH_FROM_FOOT) rise from the floor, one ending
#: under the found top and the other running on past it, the face's top is lowered to
#: where the shorter one ends (session 44, branch ``wt-e-44``, a switch): the face is one
#: surface standing on the floor, each side parting it from what stands beside it from
#: the floor up to its top; a side running on past the found top is something behind in
#: line with it (a rocket in a photograph), up which the top was walked, and the other,
#: ending under it with the colour stepping there across the face from side to side,
#: ends at the face's top (photo 3214 hard +29 -> -3.0 %). A side standing up to the found
#: top keeps it (procedural 3109 hard and 3165 ordinary: a brick face's side losing its
#: colour step part of the way up, -19 % each, lowered); sides both ending under it
#: lower nothing (fresh photo 2163 hard no rig: a dark frame against a dark background,
#: both ending at the print's top inside it, -16 %; photo 3249 ordinary no rig, +31 %,
#: stayed: its sides end 82 and 104 rows up, the longer at the found top; merged with the
#: gloss rules of ``wt-a-44`` it reads +0.5 %, with or without this rule).
TOP_WHERE_SIDES_END = True
#: ... where the colour steps across that row along at least this share of the columns
#: between the found sides (TOP_STEP_SHARE made stricter: the face's top, not a band on
#: it; photo 3214 hard: 1.00) ...
END_STEP_SHARE = 0.9
#: ... more than this share of the found height (plus SIDE_AGREE_ROWS, the top's blur)
#: under the found top, the longer side more than as much over it: WIDTH_TOP_SHARE, the
#: width rule's "another top" (nearer, the width rule takes the sides' top for the found
#: one read again, and so does this rule). What keeps a frame's margin of the wall's
#: colour over a print (procedural 137 ordinary, 8 rows of 87) is that neither side runs
#: on past the found top (both end under it), not the share: measured again at 0.05 with
#: that guard, procedural 137 ordinary, photo 2038 hard and procedural 3237 ordinary,
#: with and without the rig, answer as at 0.1 (3237's sides also both end under its top,
#: so no share lowers it); so do all 400 answers of new5.
END_TOP_SHARE = 0.1


def _rises(on: npt.NDArray[np.bool_], gap: int) -> npt.NDArray[np.intp]:
    """Per column of ``on`` (rows going up from the floor), the rows up to the last one on
    before the first run of more than ``gap`` misses: how far the column's side rises."""
    n = on.shape[0]
    miss = (~on).astype(np.int32)
    run = gap + 1
    if n < run:
        ends = np.full(on.shape[1], n, np.intp)
    else:
        c = np.vstack([np.zeros((1, on.shape[1]), np.int32), np.cumsum(miss, axis=0)])
        window = c[run:] - c[:-run]  # misses in rows i .. i+gap
        full = window == run
        ends = np.where(full.any(axis=0), full.argmax(axis=0), n)
    rows = np.arange(n)[:, None]
    last = np.where(on & (rows < ends[None, :]), rows, -1).max(axis=0)
    return last + 1


def _outer_sides(
    rises: npt.NDArray[np.intp],
    on: npt.NDArray[np.bool_],
    s0: int,
    half: int,
    cols: tuple[range, range],
    need: float,
) -> list[tuple[int, int]] | None:
    """Per side, the first column of ``cols`` (walked from outside in) rising ``need`` rows
    from the floor, standing on SIDE_COVER of them: (column, rise); None where a side has
    none."""
    sides = []
    for walk in cols:
        found = None
        for c in walk:
            i = c - s0
            if (
                half <= i < rises.shape[0] - half
                and rises[i] >= need
                and float(on[: rises[i], i].mean()) >= SIDE_COVER
            ):
                found = (c, int(rises[i]))
                break
        if found is None:
            return None
        sides.append(found)
    return sides


#: An outline round the found face on all three sides (its top over the found top and
#: each side outside the found one by at least MARGIN_ROUND_ROWS) grows it enough where
#: its area is at least MARGIN_ROUND_FACTOR times the found one's (session 47, a switch):
#: the found face is a print inside a margin of the face, the margin showing over it and
#: beside it on both sides; each way alone grows the face by less than MIN_RAISE_SHARE or
#: MIN_WIDEN_FACTOR, but together they do as much as a raise by MIN_RAISE_SHARE (photo
#: 3378 hard: a grey print in a green panel, raised 0.35 of its height and widened 1.18
#: times, 1.59 in all: -20/-23 % to +1.5/-10 %). A found side on the outline's (within
#: MARGIN_ROUND_ROWS) is the face's own side, no margin beside the print there.
MARGIN_ROUND_GROWS = True
MARGIN_ROUND_ROWS = 3
MARGIN_ROUND_FACTOR = 1.0 + MIN_RAISE_SHARE


def grows_face(found: tuple[int, int, int, int], top: int, left: int, right: int) -> bool:
    """Whether an outline (``top``, ``left``, ``right``) grows the ``found`` face
    (bottom, top, left, right) enough to be taken: its top MIN_RAISE_SHARE of the found
    height higher, or its width MIN_WIDEN_FACTOR times the found one, or (a margin round a
    print, MARGIN_ROUND_GROWS) both sides out and the top up with the area grown
    MARGIN_ROUND_FACTOR times."""
    bottom, found_top, found_l, found_r = found
    raised = found_top - top >= MIN_RAISE_SHARE * (bottom - found_top)
    if raised or right - left >= MIN_WIDEN_FACTOR * (found_r - found_l):
        return True
    if not MARGIN_ROUND_GROWS:
        return False
    k = MARGIN_ROUND_ROWS
    if found_top - top < k or found_l - left < k or right - found_r < k:
        return False
    area = (bottom - top) * (right - left)
    return area >= MARGIN_ROUND_FACTOR * (bottom - found_top) * (found_r - found_l)


def _top_across(
    image: npt.NDArray[Any],
    view: View,
    end: int,
    left: int,
    right: int,
    gap: int,
    need: float | None = None,
) -> int | None:
    """The face's top near ``end``, where its sides' rises end: of the rows from there
    down to ``gap`` rows under it, the one across which the colour steps along the most of
    the columns between the sides (what is over the face differs from the face), if that
    is at least ``need`` of them (TOP_STEP_SHARE when None); else None (the sides rose on
    into a textured background, no top closes them)."""
    far = TOP_STEP_ROWS[1]
    c0, c1 = left + SIDE_STRIP, right - SIDE_STRIP + 1
    r0, r1 = end - far, min(view.out.shape[0], end + gap + far + 1)
    if r0 < 0 or c1 - c0 < 4 or r1 - r0 < 2 * far + 1:
        return None
    band = view.lab(image, r0, r1, c0, c1)
    best, best_share = None, -1.0
    for row in range(end, r1 - far):
        k = row - r0
        over = np.asarray(median_u8(band[k - far : k - TOP_STEP_ROWS[0] + 1], axis=0), np.float32)
        under = np.asarray(median_u8(band[k + TOP_STEP_ROWS[0] : k + far + 1], axis=0), np.float32)
        across = float((row_norms(over - under) >= FOOT_STEP).mean())
        if across > best_share:
            best, best_share = row, across
    log.debug("foot outline: top %s from %d, steps across %.2f", best, end, best_share)
    return best if best_share >= (TOP_STEP_SHARE if need is None else need) else None


def _top_where_sides_end(
    image: npt.NDArray[Any],
    view: View,
    foot: int,
    bottom: int,
    top: int,
    left: int,
    right: int,
    rises: tuple[int, int],
    gap: int,
) -> tuple[int, int, int, int] | None:
    """The found face (``bottom``, ``top``, ``left``, ``right``) with its top lowered to
    where the shorter of its sides' ``rises`` (rows up from the floor-contact row
    ``foot``) ends, the colour stepping across there (:func:`_top_across`) along
    END_STEP_SHARE of the columns between its sides, more than END_TOP_SHARE of its
    height (plus SIDE_AGREE_ROWS) under its top, where the longer rise runs on past the
    found top by more than that (TOP_WHERE_SIDES_END); else None."""
    near = END_TOP_SHARE * (bottom - top) + SIDE_AGREE_ROWS
    if top - (foot - 1 - max(rises)) <= near:
        return None  # no side runs on past the found top: nothing behind it walked up
    end = foot - 1 - min(rises)
    if end - top <= near:
        return None  # a side stands from the floor up to the found top: the top stands
    found = _top_across(image, view, end, left, right, gap, END_STEP_SHARE)
    if found is None:
        return None
    log.debug("foot outline: the sides end at %d, under the found top %d", found, top)
    return foot, found, left, right


#: The width sides (WIDTH_FROM_FOOT) are also taken where they widen the found face by
#: MIN_WIDEN_FACTOR on one side alone, the other found side on the outline's (within
#: ONE_MARGIN_HELD columns) (session 47, a switch): a print set to one side of its
#: backing, the found face's one side the backing's own edge and the other the print's,
#: the backing's margin beside it up to the found top (photo 3369 hard: a coin print on a
#: blue board, its right margin 25 columns of 86, -21 % to +3.5 %). An edge's blur or
#: a shadow's widens a face on both sides (procedural 2079 hard's tape box: 5 and 2
#: columns of 27, 1.26 times in all, its -2.7 % to +7.4 % with WIDTH_MIN_FACTOR at 1.25;
#: kept here: 5 columns alone are 0.19 of it).
WIDTH_ONE_MARGIN = True
ONE_MARGIN_HELD = 1


def _one_side_margin(left: int, right: int, new_l: int, new_r: int) -> bool:
    """Whether width sides (``new_l``, ``new_r``) widen the found face (``left``,
    ``right``) on one side alone by MIN_WIDEN_FACTOR, the other side held within
    ONE_MARGIN_HELD columns (WIDTH_ONE_MARGIN), the width MIN_WIDEN_FACTOR times the found
    one's as :func:`grows_face` then asks."""
    if not WIDTH_ONE_MARGIN:
        return False
    if new_r - new_l < MIN_WIDEN_FACTOR * (right - left):
        return False  # grows_face asks as much: a side held one column in takes it back
    need = (MIN_WIDEN_FACTOR - 1.0) * (right - left)
    out_l, out_r = left - new_l, new_r - right
    if abs(out_l) <= ONE_MARGIN_HELD and out_r >= need:
        return True
    return abs(out_r) <= ONE_MARGIN_HELD and out_l >= need


def _widens_enough(
    found: tuple[int, int],
    new: tuple[int, int],
    run: tuple[int, int],
    ppm_u: float,
    same_top: bool = True,
) -> bool:
    """Whether the width sides ``new`` (left, right) widen the ``found`` face's sides
    enough to be taken (``run``: the foot's run, ``ppm_u``: pixels per metre across the
    face): WIDTH_MIN_FACTOR times, or WIDTH_PLANK_FACTOR times where one of them lies
    WIDTH_PLANK_M or more past the found one, neither lies as far inside the run's end
    and their top is the found one (``same_top``; see WIDTH_PAST_PLANK)."""
    (left, right), (new_l, new_r), (run_l, run_r) = found, new, run
    plank = WIDTH_PLANK_M * ppm_u
    factor = WIDTH_MIN_FACTOR
    if (
        WIDTH_PAST_PLANK
        and same_top
        and max(left - new_l, new_r - right) >= plank
        and max(new_l - run_l, run_r - new_r) < plank
    ):
        factor = WIDTH_PLANK_FACTOR
    return new_r - new_l >= factor * (right - left)


def _lowered_outline(
    lowered: tuple[int, int, int, int], new_l: int, new_r: int
) -> tuple[int, int, int, int] | None:
    """The outline of a face whose top was lowered to where its sides end (``lowered``:
    foot, the lowered top and the found sides, :func:`_top_where_sides_end`), as the width
    rule takes its sides ``new_l``, ``new_r``: None where they hold under CONTAIN_SHARE of
    the found columns (not the found face's sides); with them as its sides where they
    widen it by WIDTH_MIN_FACTOR, else with the found sides."""
    foot, low_top, left, right = lowered
    if min(new_r, right) - max(new_l, left) < CONTAIN_SHARE * (right - left):
        return None
    if new_r - new_l < WIDTH_MIN_FACTOR * (right - left):
        return lowered
    return foot, low_top, new_l, new_r


def outline_from_foot(
    image: npt.NDArray[Any] | None,
    view: View,
    foot: int,
    bottom: int,
    top: int,
    left: int,
    right: int,
    depth_m: float,
) -> tuple[int, int, int, int] | None:
    """The face's outline read from its foot on the floor-contact row ``foot``: its sides
    the outermost columns near the ends of the run of columns whose foot hides the floor,
    rising up from the floor past the found top, its top where both end. Returns
    (``foot``, top, left, right) when it contains the found face and grows it by
    MIN_RAISE_SHARE of its height or MIN_WIDEN_FACTOR of its width, else None. Where no
    side rises past the found top (WIDTH_FROM_FOOT), the sides rising to it widen the face
    by WIDTH_MIN_FACTOR with the found ``top`` returned (its height stands). Where those
    width sides end under the found top, one running on past it (TOP_WHERE_SIDES_END),
    the top is lowered to where the shorter ends (:func:`_top_where_sides_end`), the
    outline holding CONTAIN_SHARE of the found columns, with the width sides where they
    widen the face by WIDTH_MIN_FACTOR and the found ones else; such an outline grows
    nothing and is not asked to (the caller still moves its top to a top face's front
    edge under it). The width sides are only those rising WIDTH_RISE_SHARE of the found
    height from the foot, so the top is lowered by at most about 1 - WIDTH_RISE_SHARE of
    it (and the rise gap the top is sought within under where the shorter side ends)."""
    if image is None or image.ndim != 3 or right - left < 4 or bottom - top < 2:
        return None
    h, w = view.out.shape
    ppm_u, ppm_v = view.fx / depth_m, view.fy / depth_m
    if foot - FOOT_FACE_ROWS[1] < 0 or foot + FOOT_FLOOR_ROWS[1] > h:
        return None
    reach = int(round(FOOT_REACH_M * ppm_u))
    edge = SIDE_STRIP + 3
    c0, c1 = max(edge, left - reach), min(w - edge, right + reach + 1)
    if right >= c1 or left < c0:
        return None
    # the foot's run: the columns whose foot hides the floor under it
    lab = view.lab(image, foot - FOOT_FACE_ROWS[1], foot + FOOT_FLOOR_ROWS[1], c0, c1)
    face = np.asarray(median_u8(lab[: FOOT_FACE_ROWS[1] - FOOT_FACE_ROWS[0]], axis=0))
    k = FOOT_FACE_ROWS[1]
    floor = np.asarray(median_u8(lab[k + FOOT_FLOOR_ROWS[0] : k + FOOT_FLOOR_ROWS[1]], axis=0))
    hides = row_norms(np.asarray(face - floor, np.float32)) >= FOOT_STEP
    fl, fr = left - c0, right - c0
    if float(hides[fl : fr + 1].mean()) < FOUND_FOOT_SHARE:
        return None
    gap = max(2, int(round(FOOT_GAP_M * ppm_u)))
    ends = []
    for way, stop in ((-1, -1), (1, c1 - c0)):
        c, last, miss = (fl + fr) // 2, None, 0
        while c != stop and miss <= gap:
            if hides[c]:
                last, miss = c, 0
            else:
                miss += 1
            c += way
        if miss <= gap or last is None:
            return None  # the run reaches the block's end: no face's foot
        ends.append(last + c0)
    run_l, run_r = ends[0], ends[1] + 1
    if (run_r - run_l) / ppm_u > MAX_FACE_M:
        return None
    # the sides: the outermost columns near the run's ends rising from the floor past the
    # found top (the steps between what is just inside and just outside each column)
    q = max(3, int(SIDE_SEARCH_SHARE * (run_r - run_l)))
    b0 = max(0, foot - int(round(RISE_REACH_M * ppm_v)))
    s0, s1 = max(0, run_l - 2 - edge), min(w, run_r + 2 + edge + 1)
    block = view.lab(image, b0, foot - 1, s0, s1)[::-1].astype(np.float32)
    if block.shape[0] < 4:
        return None
    mean = cv2.blur(block, (SIDE_STRIP, 1), borderType=cv2.BORDER_REPLICATE)
    half = SIDE_STRIP // 2 + 1
    steps = np.zeros(block.shape[:2], np.float32)
    diff = mean[:, 2 * half :] - mean[:, : -2 * half]
    # each pixel's colour step: row_norms (the squares added from the left in float32,
    # as numpy's sum over the 3 channels adds them) rather than numpy's reduction over a
    # 3-wide last axis, which costs ~1 ms on this block
    steps[:, half:-half] = row_norms(diff.reshape(-1, 3)).reshape(diff.shape[:2])
    rise_gap = max(2, int(round(RISE_GAP_M * ppm_v)))
    on = steps >= FOOT_STEP
    rises = _rises(on, rise_gap)
    cols_l, cols_r = range(run_l - 2, run_l + q), range(run_r + 2, run_r - q, -1)
    need = max(SIDE_RISE_FACTOR * (foot - top), SIDE_MIN_RISE_M * ppm_v)
    sides = _outer_sides(rises, on, s0, half, (cols_l, cols_r), need)
    widened = False  # the sides read for the width alone, the found top kept
    if sides is None and WIDTH_FROM_FOOT:
        need = max(WIDTH_RISE_SHARE * (foot - top), SIDE_MIN_RISE_M * ppm_v)
        sides = _outer_sides(rises, on, s0, half, (cols_l, cols_r), need)
        widened = sides is not None
    if sides is None:
        return None
    (new_l, rise_l), (new_r, rise_r) = sides
    log.debug(
        "foot outline: run %d-%d, sides %d (%d) %d (%d)", run_l, run_r, new_l, rise_l, new_r, rise_r
    )
    if widened and TOP_WHERE_SIDES_END:
        lowered = _top_where_sides_end(
            image, view, foot, bottom, top, left, right, (rise_l, rise_r), rise_gap
        )
        if lowered is not None:
            return _lowered_outline(lowered, new_l, new_r)
    if abs(rise_l - rise_r) > SIDE_AGREE_SHARE * max(rise_l, rise_r) + SIDE_AGREE_ROWS:
        return None  # a level top: both sides end together
    new_top = _top_across(image, view, foot - 1 - min(rise_l, rise_r), new_l, new_r, rise_gap)
    if new_top is None:
        return None
    held = min(new_r, right) - max(new_l, left)
    if widened:
        # the found face's height stands: its sides' top must be the found one's
        if abs(new_top - top) > WIDTH_TOP_SHARE * (bottom - top) + SIDE_AGREE_ROWS:
            log.debug("foot outline: width sides' top %d, not the found %d", new_top, top)
            return None
        if held < CONTAIN_SHARE * (right - left):
            return None
        same_top = abs(new_top - top) <= SIDE_AGREE_ROWS
        found, new, run = (left, right), (new_l, new_r), (run_l, run_r)
        wide = _widens_enough(found, new, run, ppm_u, False)  # WIDTH_MIN_FACTOR alone
        sides_top, new_top = new_top, top
        if not wide and not _one_side_margin(left, right, new_l, new_r):
            if not _widens_enough(found, new, run, ppm_u, same_top):
                return None
            if PLANK_TOP_RAISED:  # taken at WIDTH_PLANK_FACTOR alone: the plank's top
                new_top = min(sides_top, top)
    elif held < CONTAIN_SHARE * (right - left) or new_top >= top:
        return None
    if not widened and not grows_face((bottom, top, left, right), new_top, new_l, new_r):
        return None  # (widened: the width factor above is its growth)
    log.debug(
        "outline from the foot %d: %d-%d x %d (found %d-%d x %d)",
        foot,
        new_l,
        new_r,
        new_top,
        left,
        right,
        top,
    )
    return foot, new_top, new_l, new_r
