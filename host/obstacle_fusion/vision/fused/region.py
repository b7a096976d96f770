"""The face's extent and confidence from its colour, after the edges chose a face.

Receives the chosen face (floor-contact row, top row, side columns, in the levelled view)
and the input BGR frame (read in CIE Lab, only the view pixels each stage needs); returns
the face's sides, top or frame moved to where its colour ends, a confidence factor, or a
face found by colour alone. A face is one surface standing on the floor-contact row: just
above that row, across its whole width, it shows its own colour (plank seams, joints and
tape are a few columns of another one), and just below it the floor; above the contact row
beyond its sides is what stands farther back. On photographed floors and walls the face's
edges drown in the texture while its colour does not: gradients alone collapsed the width
to one plank, took a wall line crossing the face for its top and a print for the face.

* :func:`widen_by_colour`: the sides, out along the foot's colour run (or in, over columns
  with no foot at all);
* :func:`trim_to_foot`: the sides, in to where the face's foot ends (a face of any colours);
* :func:`enclose_by_margin`: a print inside a margin of one colour is enclosed by its frame;
  :func:`margin_under_print` (no rig) the same for a thin frame running on under the row
  tried, its foot the floor contact;
* :func:`raise_top_by_colour`: the top, up past a background line crossing the face;
* :func:`stops_at_colour_top`, :func:`ends_in_colour`: a short raise past a top where the
  face's colour ends is undone (the sides ran on up what stands behind the face);
* :func:`lower_top_to_background`: a top on what stands behind comes down to where the
  background shows past the face (past one side is enough over several rows);
* :func:`lower_top_past_top_face`: a top on a top face's back edge, seen from above, comes
  down to where the background stops showing just inside both sides;
* :func:`raise_top_by_sides`: the top, up while both sides still part the face from what
  stands beside it (a band across the whole face stops the colour walks, not the sides);
* :func:`raise_top_by_windows`: the colour rescue's top, up while windows of rows keep
  the face's mean colour (a textured face's courses and lines stop the row walks);
* :func:`looks_like_top_face`: whether rows under the top are a box's top face;
* :func:`top_agreement`, :func:`side_agreement`: confidence factors, how clearly the
  colour ends at the top and at the weaker side;
* :func:`face_from_colour`: a face where the edges found none.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from typing import Any, NamedTuple

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.fused.extent import (
    MIN_EDGE_SNR,
    _line_on_row,
    _stands,
    foot_in_band,
)
from obstacle_fusion.vision.fused.profiles import (
    clamp,
    column_means,
    median_of,
    median_u8,
    narrow_max,
    norm,
    row_norms,
    share,
    walk_on,
)
from obstacle_fusion.vision.types import View

log = logging.getLogger(__name__)

_c_floor_chroma: Callable[..., None] | None
try:  # the optional C accelerator (setup.py); without it numpy takes floor_chroma's passes
    from obstacle_fusion.vision.fused._cmiddle import floor_chroma as _c_floor_chroma
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_floor_chroma = None
_c_side_walk: Callable[..., bool] | None
try:  # (apart, as floor_chroma): one side's reading in the sides' walk
    from obstacle_fusion.vision.fused._cmiddle import side_walk as _c_side_walk
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_side_walk = None

#: Rows just above (face) and below (floor) the contact row skipped (the edge's blur).
EDGE_SKIP = 2
#: Face rows sampled above the contact row: this share of the face's height, within limits.
FACE_BAND_SHARE = 0.25
FACE_BAND_ROWS = (3, 12)
#: Floor rows sampled below the contact row.
FLOOR_BAND_ROWS = 4
#: A column's foot is the face's when its colour (CIE Lab, 8-bit scale) is within this
#: many times the face's own spread of the face's colour ...
SPREAD_FACTOR = 3.0
#: ... and never farther than MAX_FACE_DISTANCE, never required closer than MIN_FACE_DISTANCE.
MIN_FACE_DISTANCE = 18.0
MAX_FACE_DISTANCE = 35.0
#: ... and when it differs from the floor just below by at least this (the face's foot is
#: an edge; farther floor above the contact row is the same floor as below it).
MIN_FLOOR_STEP = 12.0
#: A face whose colour has at least this chroma (8-bit Lab: a, b about 128) ...
CHROMATIC_FACE = 25.0
#: ... and whose hue stands at least this far (a, b) from the floor's just below it ...
HUE_APART_FROM_FLOOR = 20.0
#: ... is told along its foot with its lightness weighed this much against its hue: a
#: gloss highlight or the light's fall-off shades a coloured face, it does not change its
#: hue (a face of the floor's hue keeps the full weight: the floor behind beside it, in
#: the face's shadow, differs from the face only in lightness).
SHADE_WEIGHT = 0.3
#: Rows just above the contact row (past EDGE_SKIP) read as the foot when moving a side in.
FOOT_ROWS = 5
#: Columns each foot colour is averaged over.
SMOOTH_COLUMNS = 5
#: The lowest face (rows) whose foot's colour is read along it: the foot's rows must lie
#: clear of the contact edge's blur below and of the top edge's above. On a lower strip
#: the "foot" is the whole strip and its colour is any horizontal band's on that row (a
#: skirting, the wall's foot), which runs on beside the face: the run found no side.
MIN_COLOUR_FACE_ROWS = 2 * EDGE_SKIP + FOOT_ROWS + 1
#: Columns of another colour crossed without ending the face (a seam, a joint, tape), metres
#: at the face.
MAX_GAP_M = 0.04
#: A side moves only when the face's colour runs on past it by this share of its width.
MIN_WIDEN_SHARE = 0.1
#: A side moves in only over columns where this share shows no foot (no step from the
#: floor below to what is above the contact row).
MIN_TRIM_FLOORLESS = 0.7
#: ... and, where the foot found stands above the contact rows the rig predicts, not
#: where the columns cut off show the face's own colour above that row over this share of
#: them: a foot found a few rows above the real one leaves face under it too, floor-like
#: to the cut test (TRIM_KEEPS_FACE_COLOUR: a switch for the tests).
TRIM_KEEPS_FACE_COLOUR = True
MAX_TRIM_FACE_SHARE = 0.7
#: No side comes in where the columns cut off rise as the face's up to its top: the face
#: is one surface from its foot to its top, and its real side's edge runs the whole height.
#: A face in the floor's shade shows no foot step over a shaded or lighter strip at its
#: side, but above the foot that strip is still the face's colour (within TRIM_RISE_NEAR,
#: Lab) and stands TRIM_RISE_APART or more from what lies just beyond the side (a strip of
#: background the side search took in matches what lies beyond it instead). Read in the
#: face's upper rows as RISES_AS_FACE reads them (a switch for the tests). Wherever a rig
#: is known: one given, and also the rig a no-rig reading guesses for a row and builds the
#: face with (measure's rows read as with a rig; FusedMethod.rig_guessed is not checked,
#: and e.g. photo 733 ordinary with no rig leans on it); not in the no-rig trials under a
#: row merely tried, where the strip beside may be any band's (no-rig answers on fresh and
#: held-out rooms moved both ways with it there).
TRIM_KEEPS_RISING = True
TRIM_RISE_NEAR = 10.0
TRIM_RISE_APART = 25.0
#: Columns either side of the colour's end searched for the strongest vertical edge.
SNAP_COLUMNS = 3
#: A foot whose chroma (CIE Lab a, b, 8-bit scale) is within this of the floor's just
#: below is floor: farther floor, or its shadow, lit otherwise than the floor below ...
FLOOR_CHROMA = 6.0
#: ... where the face's own chroma differs from that floor's by at least this (a grey face
#: on a grey floor leaves the chroma no say).
FACE_CHROMA_STEP = 12.0
#: A foot within FLOOR_CHROMA_FAR of the floor's chroma is floor too where it is within
#: this share of its chroma distance to the face's colour (a floor of two shades).
FLOOR_CHROMA_NEAR_SHARE = 0.2
FLOOR_CHROMA_FAR = 12.0
#: ... and while at most this share of the face's own foot looks like floor.
MAX_FLOORLIKE_FOOT = 0.5
#: A foot within this Lab distance of the floor below it is the floor itself running on
#: above the contact row (a seam between planks or bricks is a line of its own colour).
FLOOR_THROUGH_STEP = 0.5 * MIN_FLOOR_STEP
#: A side moved out along the foot must rise as the face's (`RISES_AS_FACE`, with the rig):
#: the face is one surface standing up from its foot to its top, while a shadow or the
#: floor beyond it lies on the floor and shows only at the foot. In the face's upper rows
#: (RISE_ROWS_SHARE of its height under the top, past RISE_SKIP rows of the top's blur),
#: the columns just inside the new side (RISE_BAND columns, RISE_SKIP from it) that match
#: what lies just beyond it within RISE_NEAR (Lab) while standing RISE_FACE_APART or more
#: from the face's own colour there are no face, where their foot shows the floor's chroma
#: (within FLOOR_CHROMA_FAR of the floor just below: the floor's shadow or the floor itself,
#: farther back; a face of its own colour standing there keeps the walk's side): the side
#: stays where it was.
RISES_AS_FACE = True
RISE_ROWS_SHARE = 0.4
RISE_SKIP = 2
RISE_BAND = 7
RISE_NEAR = 10.0
RISE_FACE_APART = 25.0
#: A strip the walk took in that is, in the face's upper rows, the colour of the same
#: columns just over the face's top (within RISE_NEAR) is the background seen beside the
#: face, not its own part, even where what lies beyond the side differs (another object
#: standing farther back, whose edge stopped the walk): the face's top edge spans the
#: face from side to side and parts its own columns from what is over them; beside the
#: face nothing parts the rows under the top's row from those over it. Only where the
#: strip is not one surface from its foot up (its foot more than RISE_NEAR from its upper
#: rows): a margin of the face's round a print shows over the print's top too, and stands
#: from the foot up in one colour (procedural/711 hard, no rig). Rows read over the top:
#: RISE_OVER_ROWS, RISE_SKIP clear of the top's blur.
RISES_OVER_TOP = True
RISES_OVER_ONE_SURFACE = True
RISE_OVER_ROWS = 6
#: Columns a side that does not rise is brought back by at a time (within SNAP_COLUMNS of
#: the strongest edge each time).
RISE_BACK = SNAP_COLUMNS


def spread_limit(seed_distances: npt.NDArray[Any], least: float) -> float:
    """How far from the face's reference colour a pixel may lie and still be the face's:
    SPREAD_FACTOR times the seed's own median distance (a textured face spreads wider),
    never under ``least``, never over MAX_FACE_DISTANCE. One rule for every colour walk
    (along the foot, up the sides, past the foot, under a raised top)."""
    return float(clamp(SPREAD_FACTOR * float(median_of(seed_distances)), least, MAX_FACE_DISTANCE))


def _band(
    image: npt.NDArray[Any],
    view: View,
    r0: int,
    r1: int,
    c0: int = 0,
    c1: int | None = None,
    step: int = 1,
) -> npt.NDArray[np.float32]:
    """The view's rows r0..r1-1 (columns c0..c1-1, every ``step``-th) of ``image`` in CIE
    Lab (float, 8-bit scale): only the pixels a stage reads are undistorted and converted."""
    return np.asarray(_lab8(image, view, r0, r1, c0, c1, step), np.float32)


def _lab8(
    image: npt.NDArray[Any],
    view: View,
    r0: int,
    r1: int,
    c0: int = 0,
    c1: int | None = None,
    step: int = 1,
) -> npt.NDArray[np.uint8]:
    """:func:`_band` in 8 bits: the stages take only medians of it, by median_u8 (the
    float32 medians' values, without the float copy)."""
    return view.lab(image, r0, r1, c0, c1, step)


def _face_colour_weights(
    face: npt.NDArray[Any], floor: npt.NDArray[Any]
) -> npt.NDArray[np.float32]:
    """Weights of (L, a, b) in a colour's distance from the face's colour ``face`` (8-bit
    Lab): the lightness counts SHADE_WEIGHT for a chromatic face of a hue apart from the
    ``floor``'s, else as much as the hue."""
    chroma = math.hypot(float(face[1]) - 128.0, float(face[2]) - 128.0)
    apart = math.hypot(float(face[1]) - float(floor[1]), float(face[2]) - float(floor[2]))
    if chroma >= CHROMATIC_FACE and apart >= HUE_APART_FROM_FLOOR:
        return np.array([SHADE_WEIGHT, 1.0, 1.0], np.float32)
    return np.ones(3, np.float32)


def widen_by_colour(
    image: npt.NDArray[Any] | None,
    view: View,
    ax: npt.NDArray[np.int16],
    bottom: int,
    top: int,
    left: int,
    right: int,
    depth_m: float,
    chroma: bool = True,
    rises: bool = False,
    foot_above: bool = False,
    rising_kept: bool = False,
    outline_past: bool = False,
    shadow: bool = False,
) -> tuple[int, int]:
    """The face's sides, moved out to where its colour along its foot ends.

    ``shadow`` (with ``chroma`` off, from the beam's core): no side moves out over a foot
    in the floor's shadow where the face's own colour is no such shade (CORE_SHADOW_FOOT).

    ``outline_past`` (the rig given: the contact row known): a side the colour run moved
    out moves on along the face's outline (OUTLINE_PAST_COLOUR).

    ``rising_kept`` (a rig known, given or guessed for a row): no side comes in over
    columns that rise as the face's up to its top (TRIM_KEEPS_RISING).

    ``foot_above``: the foot found stands above the contact rows the rig predicts; no side
    comes in over columns showing the face's colour at the foot (TRIM_KEEPS_FACE_COLOUR).

    ``rises``: a side moved out only where the columns it took in rise as the face's
    under ``top`` (:func:`sides_rising`; the method asks that after settling the top).

    ``chroma``: no side moves out over a foot showing the floor's own chroma (see
    :func:`floor_chroma`), nor past a foot of the floor's own colour (a gap between two
    objects, however narrow, is no seam); off where the sides are a core a few centimetres
    wide in the beam, whose colour may be a tape's or a label's on a face of the floor's
    chroma (or a print's, its dark lines at the foot of a dark floor's colour).

    A face lower than MIN_COLOUR_FACE_ROWS is not widened (its foot's colour is any band's
    along that row), only brought in over columns with no foot."""
    if image is None or image.ndim != 3 or right - left < 6 or bottom - top < 4:
        return left, right
    h_view = view.out.shape[0]
    rows = int(clamp(FACE_BAND_SHARE * (bottom - top), *FACE_BAND_ROWS))
    r0 = bottom - EDGE_SKIP - rows
    r1 = min(bottom + EDGE_SKIP + FLOOR_BAND_ROWS + 1, h_view)
    floor_rows = r1 - (bottom + EDGE_SKIP + 1)
    if r0 < 0 or floor_rows < 1:
        return left, right  # the face's foot at the image's edge: no floor to compare
    lab = _lab8(image, view, r0, r1)
    # per column, W x 3, then over SMOOTH_COLUMNS (a textured floor's grain averages out)
    face = cv2.blur(median_u8(lab[:rows], axis=0)[None], (SMOOTH_COLUMNS, 1))[0]
    floor = cv2.blur(median_u8(lab[-floor_rows:], axis=0)[None], (SMOOTH_COLUMNS, 1))[0]
    # the foot itself, just above the contact row: what stands a little farther back
    # beside the face (another box) shows above it, not here
    foot = cv2.blur(
        median_u8(lab[max(0, rows - FOOT_ROWS) : rows], axis=0)[None], (SMOOTH_COLUMNS, 1)
    )[0]
    seed = slice(left + 2, right - 1)
    ref = median_of(face[seed], axis=0)
    floor_ref = median_of(floor[seed], axis=0)
    weights = _face_colour_weights(ref, floor_ref)
    d_face = row_norms((face - ref) * weights)
    limit = spread_limit(d_face[seed], MIN_FACE_DISTANCE)
    d_floor = row_norms(face - floor)
    on = (d_face <= limit) & (d_floor >= MIN_FLOOR_STEP)
    if share(on[seed]) < 0.5:  # (right - left >= 6: not empty)
        return left, right  # the face's own foot is not one colour over the floor
    # the smoothing spreads a seam over SMOOTH_COLUMNS - 1 more columns
    max_gap = max(2, int(round(view.fx * MAX_GAP_M / depth_m))) + SMOOTH_COLUMNS - 1
    min_move = max(SNAP_COLUMNS, MIN_WIDEN_SHARE * (right - left))
    d_foot_floor = row_norms(foot - floor)
    on_foot = (row_norms((foot - ref) * weights) <= limit) & (d_foot_floor >= MIN_FLOOR_STEP)
    # beyond a side the floor runs on above the contact row, farther back or in the
    # face's shadow: another lightness, the floor's own chroma. No side moves out over it
    # (unless the face's own foot shows it too: a contact row below the foot)
    floorlike = floor_chroma(foot, floor, ref)
    chroma_told = chroma and share(floorlike[seed]) <= MAX_FLOORLIKE_FOOT
    if not chroma_told:
        floorlike[:] = False
        if shadow and not chroma and CORE_SHADOW_FOOT:
            # ... where the face's colour is no such shade of the floor there, a shade the
            # room's diffuse light leaves at least CORE_SHADOW_LIGHT of the floor's
            # lightness (a near-black print's part at the foot, a helmet, a dark line,
            # keeps too little chroma to tell from the floor's shade), and not along most
            # of the face's own foot (then the face's foot is that shade: no telling)
            shade = floor_shade(foot, floor, ref, CORE_SHADOW_LIGHT, floor_ref)
            if share(shade[seed]) <= MAX_FLOORLIKE_FOOT:
                floorlike = shade
    on_both = (on & on_foot & ~floorlike).tolist()  # Python lists for the walks
    on_foot_flags = on_foot.tolist()
    # the face's run starts from its foot's middle: the on-column nearest the centre
    inside = np.nonzero(on[left : right + 1])[0] + left
    centre = int(inside[np.argmin(np.abs(inside - 0.5 * (left + right)))])
    outline: list[bool] | None = None  # columns with both a foot and a top step
    top_step: list[bool] = []
    outline_gap = max(2, int(round(view.fx * OUTLINE_GAP_M / depth_m))) + SMOOTH_COLUMNS - 1
    # a strip too low to read a foot clear of its top's blur finds no side outwards (its
    # colour is any band's along that row); where no foot steps from the floor at all, the
    # floor runs on behind and the side may still come in
    outwards = bottom - top >= MIN_COLOUR_FACE_ROWS
    new = []
    # where the floor itself shows at the foot (its own colour: a dark seam's chroma may
    # be the floor's, its lightness is not) nothing stands: a gap between two objects side
    # by side, never a seam of one face. The colour run outwards stops there, however
    # narrow the gap.
    through = ((d_foot_floor < FLOOR_THROUGH_STEP) & ~on & chroma).tolist()
    for side, step in ((left, -1), (right, 1)):
        end = (
            walk_on(
                _up_to_floor(on_both, through, side - step * 2, step),
                side - step * 2,
                step,
                max_gap,
            )
            if outwards
            else side
        )
        coloured = (end - side) * step > min_move  # the colour run moved the side
        if outwards and (not coloured or (outline_past and OUTLINE_PAST_COLOUR)):
            # a face of several colours (planks, tape, a print) ends its colour run at
            # the first change; its outline runs on: a foot on the floor and a top
            # against what is behind, where beside the face there is neither
            if outline is None:
                # a faint top step counts on a face tall enough to tell its top's
                # colour from its foot's apart (a low strip's are one band's)
                tall = bottom - top >= OUTLINE_SURFACE_ROWS
                top_step = _top_step_columns(
                    image, view, top, foot if tall else None, (left, right)
                )
                # a foot stands out from the floor in lightness, or (where the chroma
                # tells the face from the floor) in chroma: a dark strip of tape on a dark
                # floor differs from it only in hue
                stands = d_foot_floor >= MIN_FLOOR_STEP
                if chroma_told and OUTLINE_CHROMA_FOOT:
                    stands |= chroma_apart(floor, ref)
                outline = (np.asarray(top_step) & stands & ~floorlike).tolist()
            end_outline = walk_on(outline, side - step * 2, step, outline_gap)
            # the face's top edge ends at its side: a top edge running on past the outline's
            # end is a background line at the top's row (the wall's foot), no evidence
            span = outline[min(side, end_outline) : max(side, end_outline) + 1]
            solid = sum(span) >= OUTLINE_MIN_SHARE * len(span)  # not a floor's pattern
            if (
                solid
                and abs(walk_on(top_step, side - step * 2, step, outline_gap) - end_outline)
                <= max_gap
            ):
                moved = _snap_side(ax, top, bottom, end_outline)
                # ... and there the face has a side as clear as the one it ran on from
                need = _snap_side(ax, top, bottom, side)[1]
                grey_side = moved[1] >= OUTLINE_SIDE_SHARE * need or (
                    moved[1] >= OUTLINE_WEAK_SIDE_SHARE * need
                    and _stands_up(ax, top, bottom, moved[0])
                )
                if not coloured:
                    if grey_side and (
                        not OUTLINE_SIDE_ON_FOOT or _reaches_foot(ax, top, bottom, moved[0])
                    ):
                        end = end_outline
                elif (end_outline - end) * step > 0 and (
                    (grey_side and _stands_on_foot(ax, top, bottom, moved[0]))
                    or (OUTLINE_COLOUR_SIDE and _colour_stands(image, view, top, bottom, moved[0]))
                ):
                    # past the colour run, to a side standing on the contact row (what
                    # stands farther back beside the face ends higher up)
                    end = end_outline
        if (end - side) * step <= min_move:
            # not wider: narrower when the face's colour ends well inside the side (the
            # side search took in the background beside it: nothing stands on the contact
            # row there, the floor runs on behind. A print or tape of another colour on
            # the face's foot is not cut off: it stands out from the floor.
            end = walk_on(on_foot_flags, centre, step, max_gap)
            cut = slice(min(end, side) + 1, max(end, side))
            if (
                (side - end) * step <= min_move
                or float(np.mean(d_foot_floor[cut] < MIN_FLOOR_STEP)) < MIN_TRIM_FLOORLESS
                or (
                    TRIM_KEEPS_FACE_COLOUR
                    and foot_above
                    and float(np.mean(d_face[cut] <= limit)) >= MAX_TRIM_FACE_SHARE
                )
                or (
                    TRIM_KEEPS_RISING
                    and rising_kept
                    and _cut_rises_as_face(image, view, bottom, top, (left, right), side, end)
                )
            ):
                new.append(side)
                continue
        new.append(_snap_side(ax, top, bottom, end)[0])
    if rises:
        return sides_rising(image, view, ax, bottom, top, (left, right), (new[0], new[1]))
    return new[0], new[1]


def _upper_rows_colours(
    image: npt.NDArray[Any],
    view: View,
    bottom: int,
    top: int,
    bands: tuple[tuple[int, int], ...],
) -> list[npt.NDArray[Any]] | None:
    """The median Lab colour of each band of columns (first, end) in the face's upper rows
    (RISE_SKIP under its top, RISE_ROWS_SHARE of its height), where a strip beside a side
    shows whether it rises as the face's; None when the rows or a band are empty."""
    r0 = max(top, 0) + RISE_SKIP
    r1 = min(r0 + max(2, int(RISE_ROWS_SHARE * (bottom - top))), bottom)
    return _rows_colours(image, view, r0, r1, bands)


def _rows_colours(
    image: npt.NDArray[Any],
    view: View,
    r0: int,
    r1: int,
    bands: tuple[tuple[int, int], ...],
) -> list[npt.NDArray[Any]] | None:
    """The median Lab colour of each band of columns (first, end) in rows r0..r1 (end
    excluded); None when the rows leave the view's top, or the rows or a band are empty."""
    if r0 < 0 or r1 <= r0 or min(b1 - b0 for b0, b1 in bands) < 1:
        return None
    lab = _lab8(image, view, r0, r1)
    return [median_of(lab[:, b0:b1].reshape(-1, 3).astype(np.float32), axis=0) for b0, b1 in bands]


def _cut_rises_as_face(
    image: npt.NDArray[Any],
    view: View,
    bottom: int,
    top: int,
    face_cols: tuple[int, int],
    side: int,
    end: int,
) -> bool:
    """Whether the columns a trim would cut off between ``side`` and ``end`` (where the
    face's colour along its foot ends) rise as the face's (TRIM_KEEPS_RISING): in the
    face's upper rows they are the face's colour and unlike what lies just beyond
    ``side``, so ``side`` is the face's own."""
    step = 1 if side > end else -1
    width = view.out.shape[1]
    lo, hi = sorted((end + step, side - step * RISE_SKIP))
    if step > 0:
        outer = (side + RISE_SKIP + 1, min(side + RISE_SKIP + 1 + RISE_BAND, width))
        face = (face_cols[0] + RISE_SKIP, min(end, face_cols[1]) - RISE_SKIP + 1)
    else:
        outer = (max(side - RISE_SKIP - RISE_BAND, 0), side - RISE_SKIP)
        face = (max(end, face_cols[0]) + RISE_SKIP, face_cols[1] - RISE_SKIP + 1)
    colours = _upper_rows_colours(image, view, bottom, top, ((lo, hi + 1), face, outer))
    if colours is None:
        return False  # nothing to read: the trim stands
    inside, face_colour, beyond = colours
    to_face = float(norm(inside - face_colour))
    to_beyond = float(norm(inside - beyond))
    rises = to_face <= TRIM_RISE_NEAR and to_beyond >= TRIM_RISE_APART
    log.debug(
        "side %d: the columns to %d are %.1f from the face, %.1f from beyond%s",
        side,
        end,
        to_face,
        to_beyond,
        ": they rise as the face's, not cut" if rises else "",
    )
    return rises


def sides_rising(
    image: npt.NDArray[Any],
    view: View,
    ax: npt.NDArray[np.int16],
    bottom: int,
    top: int,
    walked_from: tuple[int, int],
    walked_to: tuple[int, int],
) -> tuple[int, int]:
    """The sides :func:`widen_by_colour` moved from ``walked_from`` to ``walked_to``, each
    moved out only as far as its strip rises as the face's under ``top`` (the method calls
    it after the top is settled between the walked sides: RISES_AS_FACE)."""
    if not RISES_AS_FACE or image is None or image.ndim != 3:
        return walked_to
    left, right = walked_to
    if left < walked_from[0]:
        left = _rising_side(image, view, ax, bottom, top, walked_from, walked_from[0], left, -1)
    if right > walked_from[1]:
        right = _rising_side(image, view, ax, bottom, top, walked_from, walked_from[1], right, 1)
    return left, right


def _rising_side(
    image: npt.NDArray[Any],
    view: View,
    ax: npt.NDArray[np.int16],
    bottom: int,
    top: int,
    face_cols: tuple[int, int],
    side: int,
    moved_to: int,
    step: int,
) -> int:
    """The side the walk moved from ``side`` out to ``moved_to``, brought back (RISE_BACK
    columns at a time, snapped to the strongest edge there) to the outermost column whose
    strip rises as the face's (:func:`_rises_as_face`): a walk through the face and on
    over its shadow ends at the face's side; ``side`` where none does."""
    col = moved_to
    while (col - side) * step > 0:
        # the walk's own side first, as it was snapped
        snapped = col if col == moved_to else _snap_side(ax, top, bottom, col)[0]
        if (snapped - side) * step <= 0:
            break
        if _rises_as_face(image, view, bottom, top, face_cols, snapped, step):
            if snapped != moved_to:
                log.debug(
                    "side %d -> %d: shows at the foot only, back to %d", side, moved_to, snapped
                )
            return snapped
        col -= step * RISE_BACK
    log.debug("side %d -> %d: shows at the foot only, kept", side, moved_to)
    return side


def _over_top_colour(
    image: npt.NDArray[Any], view: View, top: int, band: tuple[int, int]
) -> npt.NDArray[Any] | None:
    """The median Lab colour of the columns ``band`` (first, end) in the RISE_OVER_ROWS
    rows over the face's ``top`` (RISE_SKIP clear of it); None when out of the view."""
    r1 = top - RISE_SKIP
    colours = _rows_colours(image, view, r1 - RISE_OVER_ROWS, r1, (band,))
    return None if colours is None else colours[0]


def _rises_as_face(
    image: npt.NDArray[Any],
    view: View,
    bottom: int,
    top: int,
    face_cols: tuple[int, int],
    column: int,
    step: int,
) -> bool:
    """A side moved out to ``column`` (``step`` outwards) rises as the face's: in the
    face's upper rows the columns just inside it are the face's colour (the face between
    ``face_cols`` there) or differ from what lies just beyond it. A shadow's or a floor
    patch's edge at the foot has the background beside and above it alike up there."""
    width = view.out.shape[1]
    if step > 0:
        inner = (max(column - RISE_SKIP - RISE_BAND, face_cols[1]), column - RISE_SKIP)
        outer = (column + RISE_SKIP + 1, min(column + RISE_SKIP + 1 + RISE_BAND, width))
    else:
        inner = (column + RISE_SKIP + 1, min(column + RISE_SKIP + 1 + RISE_BAND, face_cols[0] + 1))
        outer = (max(column - RISE_SKIP - RISE_BAND, 0), column - RISE_SKIP)
    face = (face_cols[0] + RISE_SKIP, face_cols[1] - RISE_SKIP + 1)
    colours = _upper_rows_colours(image, view, bottom, top, (inner, outer, face))
    if colours is None:
        return True  # nothing to read: the walk's side stands
    inside, beyond, face_colour = colours
    like_beyond = float(norm(inside - beyond)) <= RISE_NEAR
    unlike_face = float(norm(inside - face_colour)) >= RISE_FACE_APART
    if not unlike_face:
        return True  # the strip is the face's colour up there: it rises as the face
    # the strip's foot (just above the contact row) against the floor just below it
    f0, f1 = bottom - EDGE_SKIP - FOOT_ROWS, bottom - EDGE_SKIP
    g0, g1 = (
        bottom + EDGE_SKIP + 1,
        min(bottom + EDGE_SKIP + 1 + FLOOR_BAND_ROWS, view.out.shape[0]),
    )
    if f0 < 0 or g1 <= g0:
        return True
    foot = median_of(_lab8(image, view, f0, f1, *inner).reshape(-1, 3).astype(np.float32), axis=0)
    if RISES_OVER_TOP and not like_beyond:
        # what is over the top shows in the strip up there, and the strip is not one
        # surface from its foot up (a margin framing a print is: it stands)
        over = _over_top_colour(image, view, top, inner)
        like_beyond = (
            over is not None
            and float(norm(inside - over)) <= RISE_NEAR
            and (not RISES_OVER_ONE_SURFACE or float(norm(inside - foot)) > RISE_NEAR)
        )
    if not like_beyond:
        return True
    floor = median_of(_lab8(image, view, g0, g1, *inner).reshape(-1, 3).astype(np.float32), axis=0)
    return float(norm(foot[1:] - floor[1:])) > FLOOR_CHROMA_FAR


def _up_to_floor(on: list[bool], through: list[bool], start: int, step: int) -> list[bool]:
    """``on`` with every column from the first ``through`` one (from ``start`` towards
    ``step``) onwards turned off: a walk over ``on`` ends before the floor shows."""
    col, n = start, len(on)
    if step in (1, -1) and 0 <= col < n:
        # the first true flag from ``start`` by list.index (C) rather than a Python loop
        try:
            col = through.index(True, col) if step > 0 else col - through[col::-1].index(True)
        except ValueError:  # none: the walk runs to the end
            return on
    while 0 <= col < n and not through[col]:
        col += step
    if not 0 <= col < n:
        return on
    out = list(on)
    if step > 0:
        out[col:] = [False] * (n - col)
    else:
        out[: col + 1] = [False] * (col + 1)
    return out


#: A pair is trimmed to its foot only when the face kept stands on a foot over this share
#: of its columns.
MIN_KEPT_FOOT = 0.6


#: A side standing down to the contact row is still brought in (and the face's colour
#: running on above is no reason to keep it) where at least this share of the columns
#: between it and where the face's foot ends shows the floor's own chroma, judged against
#: the colour of the face's foot where it steps from the floor: the floor seen between the
#: face and another object standing farther back (a frame's leg, a can, a stand), whose
#: edge the search took for the side (photo/2062 hard +53 -> +0.7 % wide, 2035 hard
#: +31 -> +0.8 %; fresh photo/2185 hard +307 -> -9 %). A face's own columns step from the
#: floor (a print's floor-coloured part is a gap the walk crosses).
FLOOR_BETWEEN_SHARE = 0.7
#: The switch of the rule above (for the tests).
FLOOR_BETWEEN = True


#: ... and where the floor under those columns runs on past the side (within this chroma
#: distance, CIE Lab a, b, 8-bit, of the floor band's median over FLOOR_PAST_COLUMNS
#: columns just beyond it): one floor seen under the other object's edge and beyond it. A
#: print's lower edge taken for the contact row has the print's margin under it, and the
#: real floor or the wall beyond the print's side (procedural/2080 hard with no rig).
FLOOR_PAST_CHROMA = 6.0
#: The columns read beyond the side for the floor running on past it.
FLOOR_PAST_COLUMNS = 7
#: The rule is off where the foot the walk finds is narrower than this (m at the sonar's depth): a
#: strip's foot, a shadow's or a leg's, no face's (photo/2175 ordinary, a face's shadow
#: between it and a can, 0.04 m: the trim kept that strip, 1.1 -> 86 % off).
FLOOR_BETWEEN_MIN_M = 0.08
#: A side with the floor seen between it and the foot's end (the rule above) that does not
#: stand down to the contact row comes in by a move of more than this many columns, not
#: only of more than ``min_move`` (a tenth of the pair's width; the smaller limit holds):
#: the face's foot ends there, and what the side stands on is farther back (a can's edge a
#: few centimetres beyond the face's side, procedural/3328 hard: a 15-column gap of floor,
#: w +8.8 % at 0.999). More than the colour smoothing's reach (SMOOTH_COLUMNS), over which
#: the foot's end is blurred.
FLOOR_BETWEEN_MIN_MOVE = 6
#: The switch of the rule above (for the tests).
FLOOR_BETWEEN_ANY_MOVE = True


def _floor_runs_past(
    image: npt.NDArray[Any],
    view: View,
    bottom: int,
    side: int,
    step: int,
    floor_between: npt.NDArray[Any],
) -> bool:
    """Whether the floor band under the contact row just beyond ``side`` (``step``
    outwards) has the chroma of the floor band between the side and the face's foot."""
    r0 = bottom + EDGE_SKIP + 1
    r1 = min(r0 + FLOOR_BAND_ROWS, view.out.shape[0])
    width = view.out.shape[1]
    if step > 0:
        c0, c1 = side + SNAP_COLUMNS, min(side + SNAP_COLUMNS + FLOOR_PAST_COLUMNS, width)
    else:
        c0, c1 = max(side - SNAP_COLUMNS - FLOOR_PAST_COLUMNS, 0), max(side - SNAP_COLUMNS, 0)
    if r1 <= r0 or c1 - c0 < 1:
        return False
    past = median_u8(_lab8(image, view, r0, r1, c0, c1).reshape(-1, 3), axis=0)
    between = median_of(floor_between.astype(np.float32), axis=0)
    return float(norm(past[1:].astype(np.float32) - between[1:])) <= FLOOR_PAST_CHROMA


def trim_to_foot(
    image: npt.NDArray[Any] | None,
    view: View,
    ax: npt.NDArray[np.int16],
    bottom: int,
    top: int,
    left: int,
    right: int,
    depth_m: float,
    found: tuple[int, int] | None = None,
) -> tuple[int, int]:
    """The sides moved in to where the face's foot ends, whatever the face's colours.

    A face stands on the contact row along its whole width: just above that row it steps
    from the floor below, and not to a shade of the floor itself. A side the search took
    out on a neighbour or a background edge has columns between it and the face where the
    floor runs on above the contact row (no step, or only the floor's own chroma).
    :func:`widen_by_colour` brings such a side in only for a face of one colour along its
    foot; a print, planks or a label at the foot leave that to this walk over the foot's
    step alone (at most the gaps of a seam).

    A side that stands down to the contact row as strongly as along the face is kept: it
    stands on the floor there (a margin of the face's colour under a print whose lower edge
    was taken for the contact row shows no step either). ``found``: the search's sides; one
    moved out past them across seams (its new column the floor's texture may make stand) is
    brought back no farther in than the search's side, unless that does not stand."""
    if image is None or image.ndim != 3 or right - left < 6 or bottom - top < 4:
        return left, right
    found = found or (left, right)
    # only the pair's columns (and the smoothing's reach beyond): a walk past a side ends
    # there as it would farther out, with the side kept
    c0 = max(0, left - SMOOTH_COLUMNS)
    c1 = min(view.out.shape[1], right + SMOOTH_COLUMNS + 1)
    bands = _foot_bands(image, view, bottom, top, c0, c1, (left + 2 - c0, right - 1 - c0))
    if bands is None:
        return left, right
    foot, floor, ref = bands
    floorlike = floor_chroma(foot, floor, ref)
    if share(floorlike[left + 2 - c0 : right - 1 - c0]) > MAX_FLOORLIKE_FOOT:
        floorlike[:] = False
    stands = (row_norms(foot - floor) >= MIN_FLOOR_STEP) & ~floorlike
    inside = np.nonzero(stands[left - c0 : right - c0 + 1])[0] + left
    if inside.size == 0:
        return left, right  # no foot anywhere: a face of the floor's colour, say nothing
    centre = int(inside[np.argmin(np.abs(inside - 0.5 * (left + right)))])
    # the floor's chroma against the face's colour where its foot steps from the floor (the
    # pair's median colour is the floor's where the sides hold more floor than face)
    floor_seen = floor_chroma(foot, floor, median_of(foot[inside - c0], axis=0))
    max_gap = max(2, int(round(view.fx * MAX_GAP_M / depth_m))) + SMOOTH_COLUMNS - 1
    min_move = max(SNAP_COLUMNS, MIN_WIDEN_SHARE * (right - left))
    flags = stands.tolist()
    foot_l = walk_on(flags, centre - c0, -1, max_gap)
    if walk_on(flags, centre - c0, 1, max_gap) - foot_l < view.fx * FLOOR_BETWEEN_MIN_M / depth_m:
        floor_seen[:] = False  # a strip's foot (a shadow's, a leg's): no face to trim to
    new = []
    for side, step, first in ((left, -1, found[0]), (right, 1, found[1])):
        end = walk_on(flags, centre - c0, step, max_gap) + c0
        if (first - side) * step < 0:  # moved out across seams
            if _stands_on_foot(ax, top, bottom, first):
                end = first if (end - first) * step < 0 else end
        cut = slice(min(end, side) + 1 - c0, max(end, side) - c0)
        # the floor seen between the face and the side: another object's edge
        floor_between = (
            FLOOR_BETWEEN
            and cut.stop > cut.start
            and share(floor_seen[cut]) >= FLOOR_BETWEEN_SHARE
            and _floor_runs_past(image, view, bottom, side, step, floor[cut])
        )
        side_stands = _stands_on_foot(ax, top, bottom, side)
        if (first - side) * step >= 0 and not floor_between and side_stands:
            new.append(side)
            continue
        least = min_move
        if FLOOR_BETWEEN_ANY_MOVE and floor_between and not side_stands:
            # the floor seen up to a side standing farther back: a small gap is no blur
            least = min(min_move, FLOOR_BETWEEN_MIN_MOVE)
        if (
            (side - end) * step <= least
            or share(~stands[cut]) < MIN_TRIM_FLOORLESS
            or (not floor_between and _face_runs_on(image, view, top, bottom, centre, end, side))
        ):
            new.append(side)
        else:
            new.append(_snap_side(ax, top, bottom, end)[0])
    if new == [left, right] or new[1] - new[0] < 6:
        return left, right
    if share(stands[new[0] - c0 : new[1] - c0 + 1]) < MIN_KEPT_FOOT:
        return left, right  # what is left does not stand on a foot either
    return new[0], new[1]


#: The face's upper rows (shares of its height from the top) compared beside the cut ...
UPPER_ROWS = (0.05, 0.3)
#: ... on a face at least this many rows high (on a lower one they are its foot's strip).
MIN_UPPER_FACE_ROWS = 40
#: The columns to be cut are the face's own when this share of them shows, over the face's
#: upper rows, the colour of the face kept (within MIN_FACE_DISTANCE).
MIN_FACE_SHARE_CUT = 0.6


def _face_runs_on(
    image: npt.NDArray[Any], view: View, top: int, bottom: int, centre: int, end: int, side: int
) -> bool:
    """Whether the columns between ``end`` (where the foot's step ended) and ``side`` show
    the face's colour over its upper rows: a face in the floor's own colour steps from it
    only where the floor's tiles differ, yet the face runs on above, while beyond a real
    side the wall stands at the face's upper rows."""
    h = bottom - top
    r0, r1 = top + int(UPPER_ROWS[0] * h), top + int(UPPER_ROWS[1] * h)
    lo, hi = sorted((centre, side))
    if h < MIN_UPPER_FACE_ROWS or hi - lo < 2:
        return False
    lab = _lab8(image, view, r0, r1, lo, hi + 1, 1)[::SUBSAMPLE]
    upper = median_u8(lab, axis=0)  # per column
    kept = slice(0, end - lo + 1) if side > centre else slice(end - lo, None)
    cut = slice(end - lo + 1, None) if side > centre else slice(0, end - lo)
    if upper[kept].shape[0] == 0 or upper[cut].shape[0] == 0:
        return False
    ref = median_of(upper[kept], axis=0)
    return share(row_norms(upper[cut] - ref) <= MIN_FACE_DISTANCE) >= MIN_FACE_SHARE_CUT


#: A side stands on the contact row when its edge just above that row is at least this share
#: of its strength along the face; an edge standing farther back ends higher up.
SIDE_FOOT_SHARE = 0.6


def _stands_on_foot(ax: npt.NDArray[np.int16], top: int, bottom: int, column: int) -> bool:
    """The side's |d/dx| (strongest of 3 columns) over the foot's rows against its median
    along the face."""
    c0, c1 = max(column - 1, 0), min(column + 2, ax.shape[1])
    col = narrow_max(ax[max(top, 0) : bottom, c0:c1])
    if col.size <= FOOT_ROWS + EDGE_SKIP:
        return True
    along = float(median_of(col.astype(np.float32)))
    foot = float(col[-(FOOT_ROWS + EDGE_SKIP) : -1].mean())
    return foot >= SIDE_FOOT_SHARE * along


def _reaches_foot(ax: npt.NDArray[np.int16], top: int, bottom: int, column: int) -> bool:
    """Whether the side's |d/dx| (strongest of 3 columns) over the REACH_ROWS rows just
    above the contact row (the row under them left out) holds REACH_SHARE of its own over
    the FOOT_ROWS rows above those: a face's side stands down to that row; what stands
    farther back ends a few rows above it, where :func:`_stands_on_foot`'s mean over a
    taller foot still counts its upper rows. (Against itself just above, not its median
    along the face: a faint side in noise does not end.)"""
    c0, c1 = max(column - 1, 0), min(column + 2, ax.shape[1])
    col = narrow_max(ax[max(top, 0) : bottom, c0:c1]).astype(np.float32)
    if col.size < REACH_ROWS + FOOT_ROWS + 1:
        return True
    low = float(median_of(col[-(REACH_ROWS + 1) : -1]))  # (the last row: the foot's blur)
    upper = float(median_of(col[-(REACH_ROWS + FOOT_ROWS + 1) : -(REACH_ROWS + 1)]))
    return low >= REACH_SHARE * upper


def _foot_bands(
    image: npt.NDArray[Any],
    view: View,
    bottom: int,
    top: int,
    c0: int,
    c1: int,
    face_cols: tuple[int, int],
) -> tuple[npt.NDArray[Any], npt.NDArray[Any], npt.NDArray[Any]] | None:
    """Per column c0..c1-1 (W x 3 Lab, smoothed over SMOOTH_COLUMNS): the foot just above
    the contact row, the floor just below it; and the face's colour (the median of the face
    band over ``face_cols``, counted from c0). None at the image's edge."""
    rows = int(clamp(FACE_BAND_SHARE * (bottom - top), *FACE_BAND_ROWS))
    r0 = bottom - EDGE_SKIP - rows
    r1 = min(bottom + EDGE_SKIP + FLOOR_BAND_ROWS + 1, view.out.shape[0])
    floor_rows = r1 - (bottom + EDGE_SKIP + 1)
    if r0 < 0 or floor_rows < 1:
        return None
    lab = _lab8(image, view, r0, r1, c0, c1)
    face = cv2.blur(median_u8(lab[:rows], axis=0)[None], (SMOOTH_COLUMNS, 1))[0]
    floor = cv2.blur(median_u8(lab[-floor_rows:], axis=0)[None], (SMOOTH_COLUMNS, 1))[0]
    foot = cv2.blur(
        median_u8(lab[max(0, rows - FOOT_ROWS) : rows], axis=0)[None], (SMOOTH_COLUMNS, 1)
    )[0]
    return foot, floor, median_of(face[face_cols[0] : face_cols[1]], axis=0)


def floor_chroma(
    foot: npt.NDArray[Any], floor: npt.NDArray[Any], ref: npt.NDArray[Any]
) -> npt.NDArray[np.bool_]:
    """Per column (W x 3 Lab): the foot shows the floor's chroma where the face's colour
    ``ref`` does not: floor above the contact row (farther back, or shadowed), not the face.
    In C where the accelerator built, for float32 colours (the stages' medians): the same
    steps in float32, one call."""
    if (
        _c_floor_chroma is not None
        and foot.dtype == np.float32
        and floor.dtype == np.float32
        and ref.dtype == np.float32
        and foot.ndim == 2
        and foot.shape[1] == 3
        and floor.shape == foot.shape
        and ref.shape == (3,)
    ):
        flags = np.empty(foot.shape[0], bool)
        _c_floor_chroma(
            foot,
            floor,
            ref,
            FLOOR_CHROMA_NEAR_SHARE,
            FLOOR_CHROMA_FAR,
            FLOOR_CHROMA,
            FACE_CHROMA_STEP,
            SHADOW_FOOT,
            SHADOW_DARKER,
            SHADOW_FLOOR_CHROMA,
            flags,
        )
        return flags
    foot_step = row_norms(foot[:, 1:] - floor[:, 1:])
    face_step = row_norms(ref[None, 1:] - floor[:, 1:])
    # a floor of two shades (a plank's stripe, a seam crossing the contact row) moves
    # the chroma a little more; the foot is still the floor's where it stays far nearer
    # that than the face's own
    near = foot_step < FLOOR_CHROMA_NEAR_SHARE * row_norms(foot[:, 1:] - ref[None, 1:])
    near &= foot_step < FLOOR_CHROMA_FAR
    out: npt.NDArray[np.bool_] = ((foot_step < FLOOR_CHROMA) | near) & (
        face_step >= FACE_CHROMA_STEP
    )
    # the floor in the face's shadow, its chroma dimmed with its light, is floor too
    # where the face's own colour is no such shade of it (a face near the floor's chroma)
    if SHADOW_FOOT:
        out |= floor_shade(foot, floor, ref)
    return out


def floor_shade(
    foot: npt.NDArray[Any],
    floor: npt.NDArray[Any],
    ref: npt.NDArray[Any],
    light: float | None = None,
    face_floor: npt.NDArray[Any] | None = None,
) -> npt.NDArray[np.bool_]:
    """Per column (W x 3 Lab): the ``foot`` is the ``floor``'s shade
    (:func:`shadow_columns`) where the face's colour ``ref`` is no such shade of it, and,
    with ``light``, keeps at least that share of the floor's lightness. The face's colour
    is held against the floor in each column, or against the one colour ``face_floor``.

    Only face_from_colour's core walk passes ``light`` (CORE_SHADOW_LIGHT): there a shade
    stops the walk at a side, and a near-black print's part at the foot keeps too little
    chroma to tell from a deep shade; it passes ``face_floor`` too (the floor's median
    under the face's foot), as a face's colour near the floor's shade would pass and fail
    the check column by column with the floor's grain. :func:`floor_chroma`
    (SHADOW_FOOT) takes neither: its C twin (_cmiddle) has no such bound, and its
    answers stand as they are."""
    shade = shadow_columns(foot, floor)
    if light is not None:
        shade &= np.asarray(foot, np.float32)[:, 0] >= light * np.asarray(floor, np.float32)[:, 0]
    if face_floor is not None:
        if _shadow_of(ref, face_floor):
            shade[:] = False
        return shade
    out: npt.NDArray[np.bool_] = shade & ~shadow_columns(
        np.broadcast_to(np.asarray(ref)[None], np.shape(floor)), floor
    )
    return out


def chroma_apart(floor: npt.NDArray[Any], ref: npt.NDArray[Any]) -> npt.NDArray[np.bool_]:
    """Per column (W x 3 Lab): the face's colour ``ref`` stands FACE_CHROMA_STEP or more
    from the ``floor``'s chroma there, so that a foot not of the floor's chroma
    (:func:`floor_chroma`) is something standing on it."""
    out: npt.NDArray[np.bool_] = row_norms(ref[None, 1:] - floor[:, 1:]) >= FACE_CHROMA_STEP
    return out


def _snap_side(ax: npt.NDArray[np.int16], top: int, bottom: int, column: int) -> tuple[int, float]:
    """The strongest vertical edge within SNAP_COLUMNS of ``column``: (column, its mean
    |d/dx| over the face's rows)."""
    lo, hi = max(column - SNAP_COLUMNS, 0), min(column + SNAP_COLUMNS, ax.shape[1] - 1)
    # the sides' strength only over the columns searched (sums of integers: exact, the
    # same means as over the whole width)
    strength = column_means(ax[max(top, 0) : bottom + 1, lo : hi + 1])
    best = int(np.argmax(strength))
    return lo + best, float(strength[best])


def _stands_up(ax: npt.NDArray[np.int16], top: int, bottom: int, column: int) -> bool:
    """The column's |d/dx| (strongest of 3) over the face's upper half is at least
    OUTLINE_UPPER_SHARE of that over its lower half."""
    c0, c1 = max(column - 1, 0), min(column + 2, ax.shape[1])
    col = narrow_max(ax[max(top, 0) : bottom + 1, c0:c1]).astype(np.float32)
    half = col.size // 2
    if half < 2:
        return False
    return float(col[:half].mean()) >= OUTLINE_UPPER_SHARE * float(col[half:].mean())


#: Columns off the outline crossed (metres at the face): a seam's, a joint's width.
OUTLINE_GAP_M = 0.02
#: ... and the outline must hold over this share of the columns it crossed.
OUTLINE_MIN_SHARE = 0.8
#: A side moved out along the outline must be an edge at least this share as strong as
#: the side it moved from ...
OUTLINE_SIDE_SHARE = 0.25
#: ... or this share, when it stands up the face's upper half at least OUTLINE_UPPER_SHARE
#: as strongly as in its lower half (a dark plank's edges may be several times the face's
#: own sides; a shadow's edge on the floor beside the face stands in the lower rows only).
OUTLINE_WEAK_SIDE_SHARE = 0.15
OUTLINE_UPPER_SHARE = 0.4
#: Along the outline a foot not of the floor's chroma stands on the floor even where its
#: lightness matches the floor's (a switch for the tests).
OUTLINE_CHROMA_FOOT = True
#: A strip down a face (a tape, a plank of another colour) found as the face: the face
#: beside it may part from the wall above it only faintly (a face nearly the wall's
#: colour). Its top is then a step of OUTLINE_TOP_STEP (Lab) where the column under the top
#: has its foot's colour (within OUTLINE_SAME_SURFACE: one surface down to the floor) and
#: that surface is the same just outside both of the strip's sides (the face on either
#: side of the strip; a post or a shadow beside one side is not), on a face at least
#: OUTLINE_SURFACE_ROWS tall (a low strip's top and foot bands are one band).
OUTLINE_TOP_STEP = 8.0
OUTLINE_SAME_SURFACE = 12.0
OUTLINE_SURFACE_ROWS = 3 * MIN_COLOUR_FACE_ROWS
#: Columns outside each side where the surface beside a strip is read (past the side's
#: blur and the smoothing).
OUTLINE_PROBE = SNAP_COLUMNS + SMOOTH_COLUMNS // 2 + 1
OUTLINE_PROBE_WIDTH = 8


def _top_step_columns(
    image: npt.NDArray[Any],
    view: View,
    top: int,
    foot: npt.NDArray[Any] | None = None,
    sides: tuple[int, int] | None = None,
) -> list[bool]:
    """Per column: the face's top row is a colour step (the rows just above it against
    those just below) of MIN_FLOOR_STEP; with the ``foot``'s colour per column (W x 3 Lab)
    and the found face's ``sides``, also a fainter one of OUTLINE_TOP_STEP on the surface
    that stands beside both sides from its top to its foot (see OUTLINE_TOP_STEP)."""
    r0, r1 = top - TOP_STEP_ROWS[1] - 1, top + TOP_STEP_ROWS[1] + 2
    if r0 < 0 or r1 > view.out.shape[0]:
        return [False] * view.out.shape[1]
    lab = _lab8(image, view, r0, r1)
    n = TOP_STEP_ROWS[1] - TOP_STEP_ROWS[0] + 1
    above = cv2.blur(median_u8(lab[:n], axis=0)[None], (SMOOTH_COLUMNS, 1))[0]
    below = cv2.blur(median_u8(lab[-n:], axis=0)[None], (SMOOTH_COLUMNS, 1))[0]
    step = row_norms(above - below)
    strong = step >= MIN_FLOOR_STEP
    if foot is None or sides is None:
        return strong.tolist()
    cl, cr = sides[0] - OUTLINE_PROBE, sides[1] + OUTLINE_PROBE
    if cl - OUTLINE_PROBE_WIDTH < 0 or cr + OUTLINE_PROBE_WIDTH > step.shape[0]:
        return strong.tolist()
    d_foot = row_norms(below - foot)
    faint = (step >= OUTLINE_TOP_STEP) & (d_foot <= OUTLINE_SAME_SURFACE)
    probes = (slice(cl - OUTLINE_PROBE_WIDTH + 1, cl + 1), slice(cr, cr + OUTLINE_PROBE_WIDTH))
    # the surface beside each side: a faint top step on it, its colour down to its foot
    # (median_of and norm: np.median's and np.linalg.norm's values, without their wrappers)
    if any(
        float(median_of(step[p])) < OUTLINE_TOP_STEP
        or float(median_of(d_foot[p])) > OUTLINE_SAME_SURFACE
        for p in probes
    ):
        return strong.tolist()
    left_c, right_c = (median_of(below[p], axis=0) for p in probes)
    if norm(left_c - right_c) > OUTLINE_SAME_SURFACE:
        return strong.tolist()  # another surface on either side: no strip down one face
    beside = row_norms(below - 0.5 * (left_c + right_c)) <= OUTLINE_SAME_SURFACE
    return (strong | (faint & beside)).tolist()


#: Every SUBSAMPLE-th row or column read where a median runs over a face's whole width or
#: height (the colours are smooth at that scale; the medians cost the stage's time).
SUBSAMPLE = 3
#: Rows of the face sampled under its top for the face's colour (a share of its height).
TOP_BAND_SHARE = 0.3
#: Columns beside each side sampled for what stands beside the face.
BESIDE_COLUMNS = 6
#: Columns inside each side left out (the side's blur).
SIDE_SKIP = 3
#: Rows of another colour crossed going up without ending the face (a band, a label's edge),
#: metres at the face.
MAX_ROW_GAP_M = 0.02
#: A row is the face's when it also differs from both sides' surroundings by this much.
MIN_BESIDE_STEP = 12.0
#: Going up, a row is the face's within this colour distance (or SPREAD_FACTOR times the
#: face's spread, up to MAX_FACE_DISTANCE): tighter than across, since a box's top face
#: is its own material in another light, a few units off.
MIN_TOP_DISTANCE = 6.0
#: Rows either side of the colour's end searched for the strongest horizontal edge.
SNAP_ROWS = 3


#: With the rig, the outline (a foot that stands out from the floor, a top against what is
#: behind) carries a side on past where the face's colour run moved it (session 40): that
#: run ends at the first plank or panel of another colour, the outline at the face's side
#: (photo/2060 ordinary: -24 -> +1 %). Only out, and only to a side that stands on the
#: contact row (what stands farther back beside the face, its foot higher up, does not:
#: procedural/102 hard, a box behind a seam face, 2.2 -> 129 % without) (a switch).
OUTLINE_PAST_COLOUR = True
#: ... to a side whose grey edge is as clear as OUTLINE_SIDE_SHARE asks, or (a switch) a
#: side that parts two colours (:func:`_colour_side`) over the face's rows and its foot's:
#: a grey plank before a green wall of its lightness has no grey edge to speak of.
OUTLINE_COLOUR_SIDE = True
#: The outline's side past the colour run's end stands down to the contact row
#: (:func:`_reaches_foot`) where the colour run did not move: what stands farther back
#: beside the face (another box, its foot a few rows higher) ends above it.
OUTLINE_SIDE_ON_FOOT = True
#: ... read over this many rows just above the contact row (the row right above it, in
#: the foot edge's blur, left out).
REACH_ROWS = 3
#: ... holding this share of the edge just above them (an edge that ends falls to the
#: floor's grain, under a tenth; a poster face's side fades to half of itself over its
#: last rows and still stands: photo 2034 hard, 0.48, with the rig's reading alone).
REACH_SHARE = 0.25
#: A column parts two colours where the mean Lab of the COLOUR_SIDE_STRIP columns just
#: inside and just outside it (its blur, COLOUR_SIDE_SKIP columns either side, left out)
#: differ by MIN_BESIDE_STEP over COLOUR_SIDE_ROWS of the rows read.
COLOUR_SIDE_STRIP = 3
COLOUR_SIDE_SKIP = 2
COLOUR_SIDE_ROWS = 0.8


def _colour_side(image: npt.NDArray[Any], view: View, r0: int, r1: int, column: int) -> bool:
    """Whether ``column`` parts two colours over COLOUR_SIDE_ROWS of the rows r0..r1-1
    (see COLOUR_SIDE_STRIP)."""
    reach = COLOUR_SIDE_SKIP + COLOUR_SIDE_STRIP
    c0, c1 = column - reach, column + reach + 1
    if c0 < 0 or c1 > view.out.shape[1] or r0 < 0 or r1 - r0 < 3:
        return False
    block = _lab8(image, view, r0, r1, c0, c1).astype(np.float32)
    inner = block[:, :COLOUR_SIDE_STRIP].mean(axis=1)
    outer = block[:, -COLOUR_SIDE_STRIP:].mean(axis=1)
    return share(row_norms(inner - outer) >= MIN_BESIDE_STEP) >= COLOUR_SIDE_ROWS


def _colour_stands(image: npt.NDArray[Any], view: View, top: int, bottom: int, column: int) -> bool:
    """Whether ``column`` parts two colours (:func:`_colour_side`) over the face's rows
    and over its foot's (the FOOT_ROWS rows EDGE_SKIP over the contact row ``bottom``)."""
    foot = bottom - EDGE_SKIP
    return _colour_side(image, view, top + 1, bottom, column) and _colour_side(
        image, view, foot - FOOT_ROWS, foot, column
    )


#: A face running off the view's side (nothing beside one side to read) has its top
#: walked up by its colour against the other side's background alone.
CLIPPED_COLOUR_WALK = True


def raise_top_by_colour(
    image: npt.NDArray[Any] | None,
    view: View,
    ay: npt.NDArray[np.float32],
    bottom: int,
    top: int,
    left: int,
    right: int,
    depth_m: float,
    reach: int | None = None,
    one_side: bool = False,
    edge_sides: bool = False,
) -> int:
    """The face's top row, moved up while the rows above it show the face's colour
    (at most ``reach`` rows up; default twice the face's height as found). ``one_side``:
    a face running off the view is walked against its other side's background alone
    (CLIPPED_COLOUR_WALK; the colour rescues', whose face no edges found).
    ``edge_sides``: the sides are edges standing up from the floor (the edge search's),
    so the face's colour must reach them (COLOUR_REACHES_SIDES); a colour rescue's sides
    end a colour run along the foot and may lie on floor or shadow beside the face.

    A background line crossing the face (the wall's foot, a shelf) is a horizontal edge
    between the face's sides; the search takes it for the face's top when the face's sides
    are faint against the wall in grey. Above it the face shows its own colour still, while
    the wall beside it does not."""
    if image is None or image.ndim != 3 or right - left < 2 * SIDE_SKIP + 4 or bottom - top < 4:
        return top
    w_view = view.out.shape[1]
    c0, c1 = left - SIDE_SKIP - BESIDE_COLUMNS, right + SIDE_SKIP + BESIDE_COLUMNS + 1
    # a face running off the view (CLIPPED_COLOUR_WALK): the side at the view's border has
    # nothing beside it to read; the other side alone tells the face from the background
    read = (c0 >= 0, c1 <= w_view)
    if not (read[0] and read[1]) and not (one_side and CLIPPED_COLOUR_WALK and any(read)):
        return top
    if top < 3:
        return top
    band = max(3, int(TOP_BAND_SHARE * (bottom - top)))
    r1 = min(bottom, top + band + 1)
    max_gap = max(2, int(round(view.fy * MAX_ROW_GAP_M / depth_m)))
    # first only the rows a first step up reads: most tops do not move, and the tall band
    # (up to twice the face's height) costs the stage's time
    short = max(0, top - max_gap - STEP_ROWS - SNAP_ROWS - 2)
    r0, end, k, capped = _colour_walk_up(image, view, short, r1, top, c0, c1, max_gap, read)
    if short > 0 and end <= max_gap + STEP_ROWS:  # it may run on above the short band
        r0 = max(0, top - (2 * (bottom - top) if reach is None else reach))
        r0, end, k, capped = _colour_walk_up(image, view, r0, r1, top, c0, c1, max_gap, read)
    if edge_sides and COLOUR_REACHES_SIDES:
        end = capped
    if k - end <= SNAP_ROWS:
        return top
    return _snap_top_edge(ay, r0, end, k, left + SIDE_SKIP, right - SIDE_SKIP)


def _snap_top_edge(ay: npt.NDArray[np.float32], r0: int, end: int, k: int, c0: int, c1: int) -> int:
    """The strongest top edge (mean |d/dy| over columns c0:c1) within SNAP_ROWS of row
    ``end`` of a walk that read from row ``r0`` and started at ``k``: the walks' ends are
    a few rows off the edge (blur), and every walk up snaps to it alike."""
    lo, hi = max(0, end - SNAP_ROWS), min(k - 1, end + SNAP_ROWS)
    rows = np.asarray(ay[r0 + lo : r0 + hi + 1, c0:c1].mean(axis=1))
    return int(r0 + lo + np.argmax(rows))


def _colour_walk_up(
    image: npt.NDArray[Any],
    view: View,
    r0: int,
    r1: int,
    top: int,
    c0: int,
    c1: int,
    gap: int,
    read: tuple[bool, bool] = (True, True),
) -> tuple[int, int, int, int]:
    """The walk of :func:`raise_top_by_colour` over the view's rows r0..r1-1 (columns
    c0..c1-1: the face and BESIDE_COLUMNS either side): (r0, the band row it reached,
    the band row of ``top``, the band row reached where the face's colour must reach its
    sides, COLOUR_REACHES_SIDES). ``read``: whether the (left, right) side has columns beside
    it in the view (one past the view's border is not read: its columns are the border's
    repeated)."""
    w_view = view.out.shape[1]
    lab = _lab8(image, view, r0, r1, max(c0, 0), min(c1, w_view))
    if c0 < 0 or c1 > w_view:
        lab = np.pad(lab, ((0, 0), (max(0, -c0), max(0, c1 - w_view)), (0, 0)), mode="edge")
    inner = median_u8(
        lab[:, BESIDE_COLUMNS + 2 * SIDE_SKIP : -(BESIDE_COLUMNS + 2 * SIDE_SKIP) : SUBSAMPLE],
        axis=1,
    )
    left_out = median_u8(lab[:, :BESIDE_COLUMNS], axis=1)
    right_out = median_u8(lab[:, -BESIDE_COLUMNS:], axis=1)
    k = top - r0  # the current top's row in the band
    ref = median_of(inner[k + 2 :], axis=0)
    d_face = row_norms(inner - ref)
    limit = spread_limit(d_face[k + 2 :], MIN_TOP_DISTANCE)
    s = BESIDE_COLUMNS + SIDE_SKIP
    on = d_face <= MAX_FACE_DISTANCE
    edges: list[int] = []  # how far the strip just inside each side runs up
    strips: list[npt.NDArray[Any]] = []
    for seen_beside, near, out in (
        (read[0], lab[:, s : s + BESIDE_COLUMNS], left_out),
        (read[1], lab[:, -s - BESIDE_COLUMNS : -s], right_out),
    ):
        if not seen_beside:
            continue
        beside = row_norms(inner - out)
        if float(median_of(beside[k + 2 :])) < MIN_BESIDE_STEP:
            # the face's colour runs on past this side below the top too: the side is a
            # seam the width stage will cross, and what is beside it tells nothing
            continue
        on &= beside >= MIN_BESIDE_STEP
        # the face's colour reaches its sides: a top face narrows as it recedes (its
        # sides run towards the vanishing point), so just inside the front face's sides
        # it is not there
        strip = median_u8(near, axis=1)
        strip_step = row_norms(strip - out)
        # a side of little contrast (a green face on a greenish wall) is held to half its
        # own step along the face: a top face's strip is the background, no step at all
        level = float(median_of(strip_step[k + 2 :]))
        strip_on = strip_step >= min(MIN_BESIDE_STEP, max(MIN_TOP_DISTANCE, 0.5 * level))
        on &= strip_on
        # a print over the middle of the face (a poster, a page, text) changes the
        # middle's colour row by row; a margin of the face's own colour along its sides
        # runs on up to the face's top
        d_strip = row_norms(strip - median_of(strip[k + 2 :], axis=0))
        strip_limit = spread_limit(d_strip[k + 2 :], MIN_TOP_DISTANCE)
        strip_on &= d_strip <= strip_limit  # the margin keeps its own colour, no drift
        edges.append(_walk_colour(strip, strip_on, k, float(strip_limit), gap))
        strips.append(strip)
    if not edges:
        return r0, k, k, k  # no side tells the face from what stands beside it
    end = capped = min(_walk_colour(inner, on, k, limit, gap), max(edges))
    if end < min(edges):
        # the face's colour reaches its sides up to its top: a face square to the beam
        # is one surface, so just inside each side the middle's colour runs up as far as
        # in the middle. Where the middle's colour runs on above where every side strip
        # lost the face's colour, and those strips no longer show the middle's colour
        # either, what runs on is narrower than the face (an object in line behind it)
        if all(
            _parts_from_middle(strip, inner, end, edge)
            for strip, edge in zip(strips, edges, strict=True)
        ):
            capped = min(edges)
    return r0, end, k, capped


#: The colour walk up stops where the face's own colour no longer reaches its sides
#: (:func:`_colour_walk_up`): a side strip parts from the middle above its own walk's end
#: when it differs from the middle's colour by MIN_BESIDE_STEP in this share of the rows
#: the middle's walk climbed past it.
COLOUR_REACHES_SIDES = True
SIDE_PARTS_SHARE = 0.8


def _parts_from_middle(
    strip: npt.NDArray[Any], inner: npt.NDArray[Any], end: int, edge: int
) -> bool:
    """Whether a side ``strip`` (band rows) differs from the ``inner`` colour over the
    rows ``end``..``edge``-1 the middle's walk reached above the strip's own walk: the
    middle's colour does not reach that side there."""
    if edge <= end:
        return False  # no rows
    d = row_norms(strip[end:edge].astype(np.float32) - inner[end:edge].astype(np.float32))
    return bool(np.mean(d >= MIN_BESIDE_STEP) >= SIDE_PARTS_SHARE)


#: A row's side stands when its colour step is at least this share of the side's step
#: along the face (a side against a wall of another shade steps less, not nothing: a
#: gloss's light upper half against a night sky steps a third of what its dark foot does
#: against the lights beside it).
SIDE_WALK_SHARE = 0.3
#: ... but a step this large (Lab) is a side whatever the step along the face (a face
#: found on its foot's strip, against a floor far from its colour).
CLEAR_SIDE_STEP = 24.0
#: Rows where a side shows no colour step that the walk up crosses (a tape, a label's
#: band in the background's shade), metres at the face.
SIDE_WALK_GAP_M = 0.05
#: In the sides' walk, a row whose strip keeps the face's own colour is a side at any clear
#: step (MIN_BESIDE_STEP), whatever the side's step along the foot.
HELD_COLOUR_SIDE = True
#: In the sides' walk, a chromatic face's strip (CHROMATIC_FACE) of a hue apart from what
#: is beside it (HUE_APART_FROM_FLOOR) is held to its own colour with its lightness weighed
#: SHADE_WEIGHT: a gloss's highlight or the light's fall-off lightens a coloured face
#: without changing its hue (a tall glossy face's walk stopped under its highlight).
SHADED_SIDE_WALK = True
#: ... and a row of its strip is the face's only within this hue distance (a, b) of the
#: face's colour below the top: a gloss changes the lightness, not the hue.
SHADED_HUE_STEP = 6.0
#: Rows over which the sides' walk compares a strip's colour with the rows below it.
DRIFT_ROWS = 3
#: How far up the sides' walk may go at least, metres at the face.
SIDE_WALK_REACH_M = 1.0
#: With ``held_band_share`` (:func:`raise_top_by_sides`, the edge search's face with the
#: rig: method.SIDES_HOLD_BAND), a band where the sides lose their step while the strips
#: just inside both keep the face's own colour is crossed when it is at most that share of
#: the face found under it and the face comes back above it (TAPE_RETURN_SHARE of as many
#: rows): a skirting or a wall band behind the face near its colour weakens the step beside
#: a side, the face itself goes on (procedural/757 hard: a mauve frame's side before a pink
#: skirting, 8-11 Lab, its strips within 5 of the face's colour; the top stayed on the
#: print's lower edge, -80 %). Above a real top the strips take the background's colour,
#: and where the wall is the face's colour nothing beside the sides steps for the return.
#: At least this share of the band's rows hold the face's colour at both sides.
HELD_BAND_ROWS_SHARE = 0.9


#: The sides' walk is judged against the horizon by the top edge it snaps to, not by the
#: row where its step faded (:func:`raise_top_by_sides`): the step fades a few rows under
#: the face's top edge (the edge's blur), so a face whose top stands at the camera's
#: height ends its walk just under the horizon while its edge lies over it. A top face's
#: back edge, which the horizon guard keeps the walk off, lies under the horizon always
#: (nearer the camera's height than the front edge, never over it): an edge over the
#: horizon is no top face's (photo/3546 hard with the rig: a taped face whose top is
#: 1 cm over the camera, the walk's end 1 row under the horizon, the edge 2 over it).
#: Over the horizon the view's ``horizon_slack_px`` allows for too (a no-rig trial's
#: guessed pitch may put the true horizon that many rows over ``cy``, and a top face's
#: back edge with it; session 50's review).
WALK_EDGE_HORIZON = True


def raise_top_by_sides(
    image: npt.NDArray[Any] | None,
    view: View,
    ay: npt.NDArray[np.float32],
    bottom: int,
    top: int,
    left: int,
    right: int,
    depth_m: float,
    one_side: bool = False,
    held_band_share: float = 0.0,
) -> int:
    """The face's top row, moved up while both its sides still part the face from what
    stands beside it (``one_side``: as :func:`raise_top_by_colour`'s; ``held_band_share``:
    bands of up to that share of the face found where the sides' strips keep the face's
    colour are crossed, HELD_BAND_ROWS_SHARE).

    A band across the whole face (a tape, a label strip, a gloss) changes the face's
    colour in its middle and just inside its sides alike, so the colour walks stop there;
    but the face goes on while, at both sides, what is just inside differs from what is
    just outside. Above the real top the background lies on both sides of each side
    column: no step."""
    if image is None or image.ndim != 3 or right - left < 2 * SIDE_SKIP + 4 or bottom - top < 6:
        return top
    w_view = view.out.shape[1]
    c0, c1 = left - SIDE_SKIP - BESIDE_COLUMNS, right + SIDE_SKIP + BESIDE_COLUMNS + 1
    # at most the face's height again, or SIDE_WALK_REACH_M (a face found as its foot's
    # strip only: a frame's lower margin under a print)
    reach = max(bottom - top, int(round(view.fy * SIDE_WALK_REACH_M / depth_m)))
    r0 = max(0, top - reach)
    # a face running off the view: the side with columns beside it walks alone
    read = (c0 >= 0, c1 <= w_view)
    if not (read[0] and read[1]) and not (one_side and CLIPPED_COLOUR_WALK and any(read)):
        return top
    if top - r0 < 4:
        return top
    gap = max(2, int(round(view.fy * SIDE_WALK_GAP_M / depth_m)))
    # a taller band across the face (TAPE_BAND_SHARE of the face found under it) is
    # crossed where the face comes back above it for as many rows again
    tape = int(TAPE_BAND_SHARE * (bottom - top))
    need = max(gap, 2 * tape)
    # first only the rows a first step up reads: most tops do not move, and the whole
    # reach (up to 1 m of rows) would cost most of the stage's time
    short = max(r0, top - need - SNAP_ROWS - 2)
    held = int(held_band_share * (bottom - top))
    if held > 0:
        need = max(need, 2 * held)
        short = max(r0, top - need - SNAP_ROWS - 2)
    end = _sides_walk(image, view, short, bottom, top, c0, c1, gap, read, tape, held)
    if end is not None and short > r0 and end <= need + 1:  # it may run on above
        end = _sides_walk(image, view, r0, bottom, top, c0, c1, gap, read, tape, held)
        short = r0
    if end is None:
        return top  # a side that does not part the face from its surroundings
    r0, k = short, top - short
    if k - end <= SNAP_ROWS:
        return top
    snapped = _snap_top_edge(ay, r0, end, k, left + SIDE_SKIP, right - SIDE_SKIP)
    # (the edge over the highest the true horizon may lie: a guessed pitch's horizon may
    # lie horizon_slack_px rows over cy, and a top face's back edge under it)
    over = snapped < view.cy - view.horizon_slack_px
    if r0 + end > view.cy and not (WALK_EDGE_HORIZON and over):
        # below the horizon the lens looks down on the face's top: a top face's colour
        # stands apart from the wall beside it as well, so the walk cannot tell its end
        return top
    return snapped


#: The face's hue walk (:func:`raise_top_by_hue`) reads a plain face only: its rows under
#: the top (their medians between the sides) at most this far (a, b) from their median
#: hue, the median over the rows (a plain face's rows are one hue: 0-0.5; a print's or a
#: photographed face's vary, 2-5) ...
PLAIN_HUE_SPREAD = 1.0
#: ... going up, a row between the sides keeps that hue within SHADED_HUE_STEP (a gloss or
#: the light's fall-off changes a face's lightness, not its hue; a lid's, a print's
#: margin's or the background's hue is another) and its colour moves at most this much
#: (Lab) over DRIFT_ROWS rows: a gloss's highlight is a ramp, the face's end (against a
#: wall, a lid, a box behind of the face's hue in another light) a step within the edge's
#: blur.
HUE_DRIFT = 10.0
#: ... and the top it reaches is an edge at least this many times as strong (mean |d/dy|
#: between the sides, the strongest of the three rows round each) as the top it left: the
#: face's end against what is behind it is a clear edge, a highlight's a ramp (the raises
#: under 1.3x on the tuning rooms went past a right top or from a wrong one).
HUE_TOP_EDGE_GAIN = 2.0
#: ... unless the top it left is no edge of the face at all (``HUE_RAMP_TOP``): where the
#: lightness between the sides runs across it as a ramp (a gloss's highlight fading down the
#: face, or no change), no change over DRIFT_ROWS rows centred within HUE_RAMP_ROWS rows
#: either side of it standing out by more than HUE_RAMP_STEP (L, 8-bit Lab) from the
#: changes HUE_RAMP_APART rows before and after it, nothing ended the face there and the
#: walk's top is taken however faint its own edge (a face before a wall of nearly its
#: lightness: photo/3009 ordinary, a beige gloss face before a grey photograph, the top on
#: the ramp, -40 %). A step stands out of its neighbours' changes, which lie clear of it (so
#: it sets no reference of its own, wherever it lies in the window); a ramp's changes run
#: evenly or bend where it starts, and stand out of nothing. The limit is on one change:
#: a step blurred over 4-5 rows (sigma 1 row) shows 0.87 of itself in one, the rows'
#: medians round to 1 L and a ramp's bend next to the step takes up to its own change, so
#: on the drawn test face a step of 8 L is refused at every row of the window, 6-7 L at
#: most, 3 L nowhere (a change over more rows, the blur whole in it, let a photographed
#: gloss ramp's noise stand out: photo/3009 ordinary lost its top again).
#: Only on a face of at least HUE_RAMP_MIN_CHROMA (a, b from the neutral 128): within
#: SHADED_HUE_STEP of a grey face's hue lies every grey, so a grey wall or photograph above
#: it "keeps its hue" (photo/3083 ordinary with no rig: a trial's face on a grey
#: photograph walked up it and outscored the box, 1 -> 110 %); at twice that step the
#: greys are well outside the walk's hue band.
HUE_RAMP_TOP = True
HUE_RAMP_ROWS = 6
HUE_RAMP_STEP = 4.0
HUE_RAMP_APART = DRIFT_ROWS + 1
HUE_RAMP_MIN_CHROMA = 2 * SHADED_HUE_STEP
#: The hue walk reads this many gaps' rows above the top first (the whole reach only where
#: the walk runs on past them): the same top, at a fraction of the rows on most faces.
HUE_FIRST_ROWS = 4


def raise_top_by_hue(
    image: npt.NDArray[Any] | None,
    view: View,
    ay: npt.NDArray[np.float32],
    bottom: int,
    top: int,
    left: int,
    right: int,
    depth_m: float,
) -> int:
    """The face's top row, moved up while the rows between its sides keep the face's hue,
    change colour only slowly and differ from what is beside both sides.

    The face is one surface from its foot to its top: a gloss's highlight lightens its
    upper part (the colour walks stop where the highlight starts, the sides' walk where
    a background band beside it has the highlight's lightness), but its hue stays the
    face's and the lightness changes as a ramp. Its true top is where it ends against
    what is behind it: there the colour between the sides steps to the background's (the
    wall continues across, no longer apart from what is beside the sides) or to another
    hue (a lid, a print's margin, an object behind). A line inside the face (the
    highlight's edge) has the face's hue on both sides of it and the face's sides still
    apart from the background beside them. Only to a top above the horizon, as
    :func:`raise_top_by_sides` (below it a box's top face of the front's hue shows)."""
    narrow = right - left < 2 * (SIDE_SKIP + BESIDE_COLUMNS) + 4
    if image is None or image.ndim != 3 or narrow or bottom - top < 6:
        return top
    w_view = view.out.shape[1]
    c0, c1 = left - SIDE_SKIP - BESIDE_COLUMNS, right + SIDE_SKIP + BESIDE_COLUMNS + 1
    if c0 < 0 or c1 > w_view:
        return top
    reach = max(bottom - top, int(round(view.fy * SIDE_WALK_REACH_M / depth_m)))
    r0 = max(0, top - reach)
    k = top - r0
    if k <= SNAP_ROWS + DRIFT_ROWS:
        return top
    # the face under the top first (most faces are no plain face: read no more), then the
    # rows above it
    w = BESIDE_COLUMNS + 2 * SIDE_SKIP
    inner_cols = slice(w, -w, SUBSAMPLE)
    strips = (slice(w, w + BESIDE_COLUMNS), slice(-(w + BESIDE_COLUMNS + 1), -(w + 1)))
    below = _lab8(image, view, top + 2, bottom, c0, c1)
    inner_below = median_u8(below[:, inner_cols], axis=1)
    ref = median_of(inner_below[:, 1:], axis=0)
    for cols in (inner_cols, *strips):
        d_below = row_norms(
            (inner_below if cols is inner_cols else median_u8(below[:, cols], axis=1))[:, 1:] - ref
        )
        # a plain face (its rows of one hue), one surface from side to side: the strips
        # just inside both sides are of its hue too (a side out on the background beside
        # the face reads the background there)
        if float(median_of(d_below)) > (
            PLAIN_HUE_SPREAD if cols is inner_cols else SHADED_HUE_STEP
        ):
            return top
    gap = max(2, int(round(view.fy * MAX_ROW_GAP_M / depth_m)))

    def walk(rs: int) -> tuple[int, bool]:
        """The walk up over the rows rs..top+1 (and the top's colour drift from the rows
        under it): the row it reached, and whether it may run on above rs."""
        kk = top - rs
        above = _lab8(image, view, rs, top + 2, c0, c1)
        inner = np.concatenate([median_u8(above[:, inner_cols], axis=1), inner_below[:DRIFT_ROWS]])
        d_hue = row_norms(inner[:kk, 1:] - ref)
        for cols in strips:
            d_hue = np.maximum(d_hue, row_norms(median_u8(above[:kk, cols], axis=1)[:, 1:] - ref))
        drift = row_norms(inner[:kk] - inner[DRIFT_ROWS : kk + DRIFT_ROWS])
        # another hue or a step in the colour ends the face: no gap is crossed past it
        # (the rows a walk over gaps would skip are an edge's blur)
        ends = np.flatnonzero((d_hue > SHADED_HUE_STEP) | (drift > HUE_DRIFT))
        # the rows apart from what is beside both sides (a band beside the face of the
        # highlight's shade is crossed as a gap)
        on = np.ones(kk + 1, bool)
        for out in (above[: kk + 1, :BESIDE_COLUMNS], above[: kk + 1, -BESIDE_COLUMNS:]):
            on &= row_norms(inner[: kk + 1] - median_u8(out, axis=1)) >= MIN_TOP_DISTANCE
        reached = walk_on(on.tolist(), kk, -1, gap)
        if ends.size:
            return rs + max(reached, int(ends[-1]) + 1), False
        return rs + reached, reached <= gap + 1

    # first only the rows a short walk reads: most tops do not move, and the whole reach
    # (up to 1 m of rows) would cost most of the stage's time
    short = max(r0, top - HUE_FIRST_ROWS * gap)
    end, runs_on = walk(short)
    if runs_on and short > r0:
        end, _ = walk(r0)
    end -= r0
    if k - end <= SNAP_ROWS or r0 + end > view.cy:
        return top
    raised = _snap_top_edge(ay, r0, end, k, left + SIDE_SKIP, right - SIDE_SKIP)
    # the face's end against what is behind it is an edge, the highlight's a ramp
    cols = slice(left + SIDE_SKIP, right - SIDE_SKIP)
    e_raised = float(ay[max(raised - 1, 0) : raised + 2, cols].mean(axis=1).max())
    e_top = float(ay[max(top - 1, 0) : top + 2, cols].mean(axis=1).max())
    chromatic = float(np.hypot(*(ref - NEUTRAL_AB))) >= HUE_RAMP_MIN_CHROMA
    if e_raised < HUE_TOP_EDGE_GAIN * e_top and not (
        HUE_RAMP_TOP and chromatic and _lightness_ramps_across(image, view, top, c0 + w, c1 - w)
    ):
        return top
    return raised


def _lightness_ramps_across(
    image: npt.NDArray[Any], view: View, row: int, c0: int, c1: int
) -> bool:
    """Whether the lightness of the rows' medians between columns c0..c1 runs across
    ``row`` as a ramp (or flat): no change over DRIFT_ROWS rows centred within
    HUE_RAMP_ROWS of it stands out by more than HUE_RAMP_STEP from the changes
    HUE_RAMP_APART rows before and after it (outside the interval they span). A gloss's
    highlight fades as a ramp, its changes running evenly or bending where it starts; a
    face's edge, a line or a band across it is a step, a change that rises above the
    changes on both sides of it (:func:`raise_top_by_hue`). The step sets no reference of
    its own: its neighbours' changes lie clear of it, read past the window's ends where it
    lies near them."""
    n, d = DRIFT_ROWS, HUE_RAMP_APART
    # change k reads rows r0 + k .. r0 + k + n; those centred in the window start at
    # first .. last
    first, last = row - HUE_RAMP_ROWS - n // 2, row + HUE_RAMP_ROWS - (n + 1) // 2
    r0 = max(0, first - d)
    r1 = min(view.out.shape[0], last + d + n + 1)
    if r1 - r0 <= 2 * d + n:
        return False
    light = median_u8(_lab8(image, view, r0, r1, c0, c1)[:, ::SUBSAMPLE, 0], axis=1)
    change = light[n:].astype(np.float32) - light[:-n]
    mid, before, after = change[d:-d], change[: -2 * d], change[2 * d :]
    start = r0 + d + np.arange(mid.size)
    inside = (start >= first) & (start <= last)
    if not inside.any():
        return False
    stands_out = np.maximum(mid - np.maximum(before, after), np.minimum(before, after) - mid)
    return bool(stands_out[inside].max() <= HUE_RAMP_STEP)


#: With the rig, the colour rescue's top walks on up while windows of rows between its sides
#: keep the face's mean colour (:func:`raise_top_by_windows`): a print's row, a brick course,
#: a texture line or tape across the face stops the row-by-row walks, which compare each
#: row's colour with the face's, but not the mean over a window a few texture periods tall.
#: (Its switch is method.WINDOW_RESCUE_TOP.)
#: The window's height at the face's depth (brick courses, a print's dots: 2-4 cm), and the
#: least rows of one.
WINDOW_M = 0.05
WINDOW_MIN_ROWS = 5
#: A window's mean (Lab, 8-bit scale) is the face's within this.
WINDOW_FACE_TOL = 10.0
#: ... and is apart from the mean beside the face's sides by this much (on either side):
#: the wall above a face of its colour runs on past the sides, the face does not.
WINDOW_BESIDE_STEP = 15.0
#: Windows not the face's (tape, a print's band) are crossed over at most this share of
#: the face's rows walked so far.
WINDOW_GAP_SHARE = 0.35
#: ... where the face's windows resume for this share of a window's rows at least.
WINDOW_RESUME_SHARE = 0.5
#: A pattern coarser than the window is read over windows this many times as tall (where
#: the face found holds them); a face whose windows stray more than WINDOW_MAX_SPREAD from
#: its mean has no steady colour to follow.
WINDOW_WIDER = 2
WINDOW_MAX_SPREAD = 6.0
#: A raise shorter than this share of the face as found is not taken (the row walks' own
#: business), and only to a top above the horizon (below it a top face of the front's
#: colour shows; as :func:`raise_top_by_hue`).
WINDOW_MIN_RAISE = 0.5


def raise_top_by_windows(
    image: npt.NDArray[Any] | None,
    view: View,
    ay: npt.NDArray[np.float32],
    bottom: int,
    top: int,
    left: int,
    right: int,
    depth_m: float,
) -> int:
    """The face's top row, moved up while windows of WINDOW_M of rows between the middle
    half of its columns keep the face's mean colour and differ from the mean beside a side.

    A textured face (a brick print, a poster's pattern, a plank's grain) changes its
    colour row by row, so the row walks stop at its first course or pattern row; over a
    window a few of its periods tall its mean is the face's. Its true top is where the
    window's mean steps to the background's (or to that beside the sides)."""
    narrow = right - left < 2 * (SIDE_SKIP + BESIDE_COLUMNS) + 8
    if image is None or image.ndim != 3 or narrow:
        return top
    w_view = view.out.shape[1]
    c0, c1 = left - SIDE_SKIP - BESIDE_COLUMNS, right + SIDE_SKIP + BESIDE_COLUMNS + 1
    read = (c0 >= 0, c1 <= w_view)
    if not any(read):
        return top
    win = max(WINDOW_MIN_ROWS, int(round(view.fy * WINDOW_M / depth_m)))
    h = bottom - top
    if h < win + 4 + 2 * EDGE_SKIP:
        return top
    r0 = max(0, bottom - int(round(view.fy * SIDE_WALK_REACH_M / depth_m)))
    k = top - r0
    if k < WINDOW_MIN_RAISE * h:
        return top
    lab = np.asarray(_lab8(image, view, r0, bottom, max(c0, 0), min(c1, w_view)), np.float32)
    if c0 < 0 or c1 > w_view:
        lab = np.pad(lab, ((0, 0), (max(0, -c0), max(0, c1 - w_view)), (0, 0)), mode="edge")
    q = (right - left) // 4
    a0 = left - c0 + q
    inner = lab[:, a0 : a0 + right - left - 2 * q].mean(axis=1)
    outs = [
        lab[:, sl].mean(axis=1)
        for seen_side, sl in zip(
            read, (slice(0, BESIDE_COLUMNS), slice(-BESIDE_COLUMNS, None)), strict=True
        )
        if seen_side
    ]

    def windows(rows: npt.NDArray[np.float32], n: int) -> npt.NDArray[np.float32]:
        """Window means: row i holds the mean of rows i..i+n-1."""
        c = np.concatenate([np.zeros((1, 3), np.float32), np.cumsum(rows, axis=0)])
        return np.asarray((c[n:] - c[:-n]) / n, np.float32)

    ref = inner[k + EDGE_SKIP : h + k - EDGE_SKIP].mean(axis=0)

    def steady(n: int) -> tuple[npt.NDArray[np.float32], float]:
        """The window means over n rows, and the farthest those inside the face stray."""
        w = windows(inner, n)
        inside = w[k + EDGE_SKIP : h + k - EDGE_SKIP - n + 1]
        return w, float(row_norms(inside - ref).max()) if inside.size else math.inf

    w_in, spread = steady(win)
    if h >= WINDOW_WIDER * win + 4 + 2 * EDGE_SKIP:
        # a pattern coarser than the window (a poster's dots): a window twice as tall
        wide, wide_spread = steady(WINDOW_WIDER * win)
        if wide_spread < spread:
            win, w_in, spread = WINDOW_WIDER * win, wide, wide_spread
    if spread > WINDOW_MAX_SPREAD:
        return top  # no steady mean to follow
    on = row_norms(w_in - ref) <= WINDOW_FACE_TOL
    apart = np.zeros_like(on)
    for out in outs:
        apart |= row_norms(windows(out, win) - ref) >= WINDOW_BESIDE_STEP
    on &= apart
    end = k
    i = k - 1
    while i >= 0:
        if not on[i]:
            if end - i > win + WINDOW_GAP_SHARE * (h + k - end):
                break
            i -= 1
            continue
        j = i
        while j > 0 and on[j - 1]:
            j -= 1
        if i == end - 1 or i - j + 1 >= WINDOW_RESUME_SHARE * win:
            # the face's windows run on, or resume past a band for half a window's rows
            # at least (not one window passing from one colour to another on its mean)
            end = j
        i = j - 1
    log.debug("windows from %d: win %d (spread %.1f), to %d", top, win, spread, r0 + end)
    if k - end < WINDOW_MIN_RAISE * h or r0 + end > view.cy:
        return top
    # the top edge within the last window held, from the walk's end down (that window's
    # rows reached past the top)
    lo, hi = end, min(k - 1, end + win)
    cols = slice(left + SIDE_SKIP, right - SIDE_SKIP)
    rows = np.asarray(ay[r0 + lo : r0 + hi + 1, cols].mean(axis=1))
    return int(r0 + lo + np.argmax(rows))


def _held(
    strip: npt.NDArray[Any],
    dist: npt.NDArray[Any],
    limit: float,
    weights: npt.NDArray[np.float32],
) -> npt.NDArray[np.bool_]:
    """The rows of a side's ``strip`` holding the face's colour in the sides' walk:
    within ``limit`` of it (``dist``: each row's distance from it), or within
    MAX_FACE_DISTANCE of it and ``limit`` of the row DRIFT_ROWS under it (a slow drift), the
    colour differences weighed by ``weights`` (L, a, b)."""
    drift = np.zeros_like(dist)
    drift[:-DRIFT_ROWS] = row_norms((strip[:-DRIFT_ROWS] - strip[DRIFT_ROWS:]) * weights)
    held: npt.NDArray[np.bool_] = (dist <= limit) | ((dist <= MAX_FACE_DISTANCE) & (drift <= limit))
    return held


def _side_reading(
    inside: npt.NDArray[np.uint8], outside: npt.NDArray[np.uint8], k: int
) -> tuple[npt.NDArray[np.bool_], npt.NDArray[np.bool_]] | bool:
    """One side's reading in :func:`_sides_walk` (its strip ``inside``, what is ``outside``
    it; the face's rows from ``k + 2``): per row, whether the side stands (parts the face
    from what is beside it) and whether the strip holds the face's colour; False when the
    side's step along the face is too weak (the walk's None)."""
    strip = median_u8(inside, axis=1)
    beside = median_u8(outside, axis=1)
    step = row_norms(strip - beside)
    level = float(median_of(step[k + 2 :]))
    if level < MIN_BESIDE_STEP:
        return False
    stands = step >= clamp(SIDE_WALK_SHARE * level, MIN_BESIDE_STEP, CLEAR_SIDE_STEP)
    # and the face's own colour there: a background edge in line with a side (a
    # pole, a shadow) parts two background colours, not the face from one
    own = median_of(strip[k + 2 :], axis=0)
    d_strip = row_norms(strip - own)
    limit = spread_limit(d_strip[k + 2 :], MIN_TOP_DISTANCE)
    if HELD_COLOUR_SIDE:
        # the background beside the face changes going up (a bright skirting beside
        # its foot, a wall of nearly the face's shade above it): the side's step along
        # the foot says nothing of the wall's; where the strip keeps the face's own
        # colour (within its spread, no drift) any clear step (MIN_BESIDE_STEP) is a
        # side, while above the top both the colour and the step go at once
        stands |= (step >= MIN_BESIDE_STEP) & (d_strip <= limit)
    # light falling off along a face (a lamp's gradient, vignetting) moves its colour
    # slowly away from what it is below the top: a row within the face's spread of the
    # row DRIFT_ROWS under it (and within MAX_FACE_DISTANCE of the colour below the
    # top) is taken as the face's still, while the background starts with a step
    held = _held(strip, d_strip, limit, np.ones(3, np.float32))
    weights = _face_colour_weights(own, median_of(beside[k + 2 :], axis=0))
    if SHADED_SIDE_WALK and weights[0] < 1.0:
        # a gloss's highlight or the light's fall-off changes a coloured face's
        # lightness, not its hue (SHADE_WEIGHT, as along the foot, for a hue apart from
        # what is beside it): a row of the face's hue (SHADED_HUE_STEP) is the face's
        # also where its lightness alone left the face's spread
        d_shaded = row_norms((strip - own) * weights)
        limit_shaded = spread_limit(d_shaded[k + 2 :], MIN_TOP_DISTANCE)
        held |= _held(strip, d_shaded, limit_shaded, weights) & (
            row_norms(strip[:, 1:] - own[1:]) <= SHADED_HUE_STEP
        )
    return stands, held


def _side_walk_constants() -> npt.NDArray[np.float64]:
    """The sides' walk's constants for the C reading of a side (read at each call: the
    tests move them)."""
    return np.array(
        [
            SIDE_WALK_SHARE,
            MIN_BESIDE_STEP,
            CLEAR_SIDE_STEP,
            MIN_TOP_DISTANCE,
            SPREAD_FACTOR,
            MAX_FACE_DISTANCE,
            HELD_COLOUR_SIDE,
            SHADED_SIDE_WALK,
            SHADED_HUE_STEP,
            CHROMATIC_FACE,
            HUE_APART_FROM_FLOOR,
            SHADE_WEIGHT,
            DRIFT_ROWS,
        ],
        np.float64,
    )


def _side_in_c(
    inside: npt.NDArray[np.uint8], outside: npt.NDArray[np.uint8], k: int
) -> tuple[npt.NDArray[np.bool_], npt.NDArray[np.bool_]] | bool | None:
    """One side's reading in :func:`_sides_walk` (its strip ``inside``, what is ``outside``
    it; the face's rows from ``k + 2``) by the C accelerator: per row, whether the side
    stands and whether the strip holds the face's colour, the numpy steps' flags in one
    call; False when the side's step along the face is too weak (the walk's None); None
    where the accelerator is missing or does not take the strips (numpy reads them)."""
    rows = inside.shape[0]
    if _c_side_walk is None or inside.dtype != np.uint8 or rows - (k + 2) < 1 or k + 2 < 0:
        return None
    stands = np.empty(rows, bool)
    held = np.empty(rows, bool)
    try:
        if not _c_side_walk(inside, outside, k, _side_walk_constants(), stands, held):
            return False
    except ValueError:  # strips it does not take
        return None
    return stands, held


def _sides_walk(
    image: npt.NDArray[Any],
    view: View,
    r0: int,
    bottom: int,
    top: int,
    c0: int,
    c1: int,
    gap: int,
    read: tuple[bool, bool] = (True, True),
    tape: int = 0,
    held_band: int = 0,
) -> int | None:
    """The walk of :func:`raise_top_by_sides` over the view's rows r0..bottom-1: the band
    row it reached (``top - r0`` if none above), or None when a side does not part the
    face from its surroundings along the face. ``read``: the (left, right) sides walked
    (one at the view's border has nothing beside it); ``tape``: the tallest band across
    the face crossed past ``gap`` (:func:`_cross_bands`); ``held_band``: the tallest band
    crossed where the strips keep the face's colour (:func:`_cross_held_bands`)."""
    k = top - r0
    on = np.ones(bottom - r0, bool)
    kept = np.ones(bottom - r0, bool)  # the strips inside both sides hold the face's colour
    span = 2 * (BESIDE_COLUMNS + SIDE_SKIP)  # what is beside a side, its blur, the face
    bands = []
    if read[0]:
        band = _lab8(image, view, r0, bottom, c0, c0 + span)
        bands.append((band[:, span - BESIDE_COLUMNS :], band[:, :BESIDE_COLUMNS]))
    if read[1]:
        band = _lab8(image, view, r0, bottom, c1 - span, c1)
        bands.append((band[:, :BESIDE_COLUMNS], band[:, -BESIDE_COLUMNS:]))
    for inside, outside in bands:
        reading = _side_in_c(inside, outside, k)
        if reading is None:  # (the accelerator's flags are these, in one call)
            reading = _side_reading(inside, outside, k)
        if not isinstance(reading, tuple):  # (False) too weak a side
            return None
        stands, held = reading
        on &= stands & held
        kept &= held
    flags = on.tolist()
    end = _cross_bands(flags, walk_on(flags, k, -1, gap), gap, tape)
    if held_band > 0:
        end = _cross_held_bands(flags, kept.tolist(), end, gap, held_band)
    return end


def _cross_held_bands(on: list[bool], kept: list[bool], end: int, gap: int, band: int) -> int:
    """The sides' walk (``on``, ``end`` as in :func:`_cross_bands`) carried on across bands
    of up to ``band`` rows where the sides lose their step but the strips inside both keep
    the face's colour (``kept`` in at least HELD_BAND_ROWS_SHARE of the band's rows): what
    is beside the face changed (a skirting near its colour), not the face; the face must
    come back above the band over TAPE_RETURN_SHARE of as many rows."""
    while True:
        j = end - 1
        while j >= 0 and not on[j]:
            j -= 1
        rows = end - 1 - j  # the band's rows
        if j < 0 or rows <= gap or rows > band or j + 1 < rows:
            return end
        if sum(kept[j + 1 : end]) < HELD_BAND_ROWS_SHARE * rows:
            return end
        if sum(on[j + 1 - rows : j + 1]) < TAPE_RETURN_SHARE * rows:
            return end
        end = walk_on(on, j, -1, gap)


#: A frame's side, next to the face's side, is at most this many columns wide (its own
#: width with the blur of the edge beside it) ...
FRAME_SIDE_COLUMNS = 6
#: ... and holds the rail's colour in at least this many of them in a row of the frame.
FRAME_SIDE_MIN_COLUMNS = 2
#: The frame's sides must run on above the rail for at least this many times its height
#: (a frame is taller than its bottom rail; a box's corner posts are not a frame).
FRAME_RISE_SHARE = 1.0
#: Between the frame's sides, above the rail, the middle must be off the rail's colour
#: in at least this share of the rows (the inner panel: a wall of the rail's colour
#: behind a low face would hold the middle too), and so must FRAME_SIDE_COLUMNS columns
#: beside each side (a stripe of that colour running on past the sides is no frame).
FRAME_INNER_SHARE = 0.8


def raise_top_along_frame(
    image: npt.NDArray[Any] | None,
    view: View,
    ay: npt.NDArray[np.float32],
    bottom: int,
    top: int,
    left: int,
    right: int,
    depth_m: float,
) -> int:
    """The top of a face found as its frame's bottom rail, moved up to where the frame's
    sides end.

    A framed face (a panel or a print inside a border of another colour) shows a strong
    horizontal edge where the inner panel meets the bottom rail; the search can take that
    strip for the face. The frame's sides are the rail's colour carried up from both its
    ends, a few columns wide just inside the face's sides, while the middle above the rail
    is the panel's colour: the face runs on up to where both sides end. The side walk
    (:func:`raise_top_by_sides`) reads columns past a thin frame's side (the panel) and
    stops at the rail; a box whose top is the strip's top shows no rail colour above it
    at its sides, or shows it across the middle too (a background of its colour)."""
    if image is None or image.ndim != 3:
        return top
    rail_rows, n = bottom - top, FRAME_SIDE_COLUMNS
    if rail_rows < 4 or right - left < 4 * n:
        return top
    reach = max(rail_rows, int(round(view.fy * SIDE_WALK_REACH_M / depth_m)))
    r0 = max(0, top - reach)
    k = top - r0
    if k < FRAME_RISE_SHARE * rail_rows:
        return top
    c0, c1 = left - n - 2, right + n + 3  # with the columns beside the face
    if c0 < 0 or c1 > view.out.shape[1]:
        return top
    block = _lab8(image, view, r0, bottom, c0, c1).astype(np.float32)
    lab = block[:, n + 2 : -n - 2]
    rows, cols = lab.shape[:2]
    # the rail's colour, clear of the blur of its top edge and its foot
    seed = lab[k + 2 : rows - 1, 2 : cols - 2].reshape(-1, 3)
    if seed.shape[0] == 0:
        return top
    rail = median_of(seed, axis=0)
    # each pixel's distance from the rail's colour, once over the block with the columns
    # beside the face (the same values wherever a part below reads them; the seed's
    # median distance is a median of values, whatever their order)
    whole = row_norms((block - rail).reshape(-1, 3)).reshape(rows, -1)
    dist = whole[:, n + 2 : -n - 2]
    limit = spread_limit(dist[k + 2 : rows - 1, 2 : cols - 2], MIN_TOP_DISTANCE)
    held = dist <= limit
    sides_on = (held[:, 1 : n + 1].sum(axis=1) >= FRAME_SIDE_MIN_COLUMNS) & (
        held[:, cols - n - 1 : cols - 1].sum(axis=1) >= FRAME_SIDE_MIN_COLUMNS
    )
    gap = max(2, int(round(view.fy * SIDE_WALK_GAP_M / depth_m)))
    end = walk_on(sides_on.tolist(), k, -1, gap)
    if k - end < FRAME_RISE_SHARE * rail_rows:
        return top
    # the middle is the panel's colour, and beside both sides is no more of the rail's
    # colour (a band of it running on past the sides: a background stripe, no frame)
    quarter = cols // 4
    beside = whole[end:k]
    for part in (dist[end:k, quarter : cols - quarter], beside[:, :n], beside[:, -n:]):
        if share(median_of(part, axis=1) > limit) < FRAME_INNER_SHARE:
            return top
    return _snap_top_edge(ay, r0, end, k, left + 1, right)


#: A band across the face taller than SIDE_WALK_GAP_M (a tape, a label strip: in the
#: generated faces 6-14 % of the face's height, 30-60 % down it) is crossed by the sides'
#: walk up to this share of the face found under it, when the face comes back above it.
TAPE_BAND_SHARE = 0.6
#: ... over at least this share of as many rows above the band as the band is tall.
TAPE_RETURN_SHARE = 0.8


def _cross_bands(on: list[bool], end: int, gap: int, band: int) -> int:
    """The sides' walk (``on``: per row, the face's at both sides; ``end``: where the walk
    over gaps of ``gap`` rows stopped) carried on across bands of over ``gap`` and up to
    ``band`` rows that are not the face's: a tape across the face stops its colour at both
    sides, and above it the face comes back, over at least TAPE_RETURN_SHARE of as many rows as the
    band is tall (the face goes on above a tape; above a real top, a background that
    matches the face's colour and parts from what is beside both sides for that long is
    rare)."""
    while band > gap:
        j = end - 1
        while j >= 0 and not on[j]:
            j -= 1
        rows = end - 1 - j  # the band's rows
        if j < 0 or rows > band or j + 1 < rows:
            break
        if sum(on[j + 1 - rows : j + 1]) < TAPE_RETURN_SHARE * rows:
            break
        end = walk_on(on, j, -1, gap)
    return end


#: A top where the background beside the face changes at both sides (a skirting's or a
#: rail's edge behind the face: at least BAND_EDGE_STEP Lab between the rows BAND_EDGE_ROWS
#: above and below it, beside each side) is walked on up past that edge
#: (:func:`raise_top_past_band`).
BAND_EDGE_STEP = 20.0
BAND_EDGE_ROWS = (2, 6)
#: ``runs_on`` (the edge search's top): the band under the top beside each side must run
#: on this many columns farther out (a frame's margin round a print is a few columns wide,
#: photo/713 hard: 7-8; a skirting runs along the wall) ...
BAND_RUNS_ON_COLUMNS = 12
#: ... within this Lab distance of its colour next to the side (MIN_BESIDE_STEP: the
#: least step that parts a side from what is beside it).
BAND_RUNS_ON_STEP = MIN_BESIDE_STEP


def raise_top_past_band(
    image: npt.NDArray[Any] | None,
    view: View,
    ay: npt.NDArray[np.float32],
    bottom: int,
    top: int,
    left: int,
    right: int,
    depth_m: float,
    runs_on: bool = False,
) -> int:
    """The face's top row, moved up past a band's edge in the background where the face's
    sides merely lost their contrast.

    A face standing in front of a skirting or a rail band steps far from that band beside
    its sides, so the walks up hold its sides to that step; above the band the wall beside
    it may be nearly the face's shade, and they stop at the band's edge, though the face's
    own colour goes on. Where the background beside both sides changes at the top, the
    face is walked on up while its colour between the sides holds (within its spread) and
    differs from what is beside both sides by MIN_TOP_DISTANCE, the least step the colour
    walk up takes as a change. Above the real top the wall lies between the sides too: no
    step beside, and another colour than the face's. No horizon bounds the walk (unlike
    :func:`raise_top_by_sides`): the face before a skirting may stand below it.
    ``runs_on``: the band under the top must also run on BAND_RUNS_ON_COLUMNS farther out
    beside both sides, of one colour (BAND_RUNS_ON_STEP), else the top is kept."""
    if image is None or image.ndim != 3 or right - left < 2 * SIDE_SKIP + 4:
        return top
    w_view = view.out.shape[1]
    c0, c1 = left - SIDE_SKIP - BESIDE_COLUMNS, right + SIDE_SKIP + BESIDE_COLUMNS + 1
    a, b = BAND_EDGE_ROWS
    # as far up as the sides' walk goes (the face may stand far above the band)
    r0 = max(0, top - max(bottom - top, int(round(view.fy * SIDE_WALK_REACH_M / depth_m))))
    if c0 < 0 or c1 > w_view or top - r0 <= b + SNAP_ROWS or bottom - top <= b + 2:
        return top
    k = top - r0
    if runs_on:
        far = BAND_RUNS_ON_COLUMNS
        if c0 - far < 0 or c1 + far > w_view:
            return top
        wide = _lab8(image, view, r0 + k + a, r0 + k + b + 1, c0 - far, c1 + far)
        for near, out_far in (
            (wide[:, far : far + BESIDE_COLUMNS], wide[:, :BESIDE_COLUMNS]),
            (wide[:, -far - BESIDE_COLUMNS : -far], wide[:, -BESIDE_COLUMNS:]),
        ):
            # the band under the top runs on out past the face's side, one colour: a
            # skirting along the wall, not a frame's margin round a print
            step = norm(
                median_of(median_u8(near, axis=1), axis=0)
                - median_of(median_u8(out_far, axis=1), axis=0)
            )
            if step >= BAND_RUNS_ON_STEP:
                return top
    lab = _lab8(image, view, r0, bottom, c0, c1)
    outs = [median_u8(lab[:, :BESIDE_COLUMNS], axis=1), median_u8(lab[:, -BESIDE_COLUMNS:], axis=1)]
    for out in outs:  # the background beside both sides steps at the top: a band's edge
        above = median_of(out[k - b : k - a + 1], axis=0)
        below = median_of(out[k + a : k + b + 1], axis=0)
        if norm(above - below) < BAND_EDGE_STEP:
            return top
    inner = median_u8(
        lab[:, BESIDE_COLUMNS + 2 * SIDE_SKIP : -(BESIDE_COLUMNS + 2 * SIDE_SKIP) : SUBSAMPLE],
        axis=1,
    )
    d_face = row_norms(inner - median_of(inner[k + 2 :], axis=0))
    on = d_face <= spread_limit(d_face[k + 2 :], MIN_TOP_DISTANCE)
    for out in outs:
        on &= row_norms(inner - out) >= MIN_TOP_DISTANCE
    gap = max(2, int(round(view.fy * MAX_ROW_GAP_M / depth_m)))
    end = walk_on(on.tolist(), k, -1, gap)
    if k - end <= SNAP_ROWS:
        return top
    return _snap_top_edge(ay, r0, end, k, left + SIDE_SKIP, right - SIDE_SKIP)


#: Rows over which the colour going up is compared (an edge's blur spans about three).
STEP_ROWS = 3
#: A top face thinner than this (rows) is left to the gradients: its colour is blur.
MIN_TOP_FACE_ROWS = 6


def looks_like_top_face(
    image: npt.NDArray[Any] | None,
    view: View,
    upper: int,
    lower: int,
    left: int,
    right: int,
    pattern: bool = False,
) -> bool:
    """Whether the rows between ``upper`` and ``lower`` (the face's top as found, and a
    front top edge below it) differ in colour from the face below ``lower``: a box's top
    face is lit unlike its front, while a texture line inside the front is not a top face
    and must not cut the face's height. ``pattern``: nor are rows across which the face's
    own pattern runs (PATTERN_NOT_TOP_FACE: a brick print's courses above a joint)."""
    n = lower - upper
    if image is None or image.ndim != 3 or n < MIN_TOP_FACE_ROWS or right - left < 8:
        return True
    if lower <= view.cy - view.horizon_slack_px:
        return False  # a top face shows only below the horizon: the lens above the box
    r1 = min(view.out.shape[0], lower + n + 2)
    lab = _lab8(image, view, upper, r1, left + SIDE_SKIP, right - SIDE_SKIP)
    strip = median_u8(lab[1 : n - 1].reshape(-1, 3), axis=0)
    front = median_u8(lab[n + 2 :].reshape(-1, 3), axis=0)
    if norm(strip - front) < MIN_TOP_DISTANCE and not (
        TOP_FACE_BANDS and _differs_by_bands(lab[1 : n - 1], lab[n + 2 :])
    ):
        return False
    if PATTERN_NOT_TOP_FACE and pattern:
        # a top face is one surface: none of the front's joints (a brick print's vertical
        # mortar lines) run across it; where the rows carry as many steps along them as
        # the face below, they are the front face's pattern (a course of bricks and the
        # print's margin above it), the edge under them a joint of it
        light = lab[:, :, 0].astype(np.int16)
        steps = np.abs(np.diff(light, axis=1))
        band, face = float(steps[1 : n - 1].mean()), float(steps[n + 2 :].mean())
        if face >= PATTERN_MIN_STEP and band >= PATTERN_SHARE * face:
            log.debug("rows %d-%d: the face's pattern runs across them", upper, lower)
            return False
    return True


#: A top face and the front are two planes, each lit evenly, and differ in colour all
#: along the edge between them; a gloss's highlight lightens the front unevenly along its
#: rows, and the median colour of its rows under the edge may then fall on the top face's
#: own (procedural/3234 ordinary with no rig: a 5-row top face of L 143-146 in every column
#: band, the front under it L 129, 140, 165, 158 band by band, its median within 6 of the
#: top face's: the top face was kept in the height, +12 %). So where the rows' medians are
#: alike, the rows between and the front under them are compared in TOP_FACE_BAND_COUNT
#: column bands, each against its own: the median band's difference at MIN_TOP_DISTANCE
#: or more is a top face (a line inside the front has the front's colour above it in every
#: band), where the rows between are one plane lit evenly, every band of them within
#: MIN_TOP_DISTANCE of their median (without that, the first full run took uneven bands
#: for top faces: fresh procedural/2199 hard with no rig -19 -> -33 %, the strip's bands
#: L 54-69). A switch for the tests.
TOP_FACE_BANDS = True
TOP_FACE_BAND_COUNT = 4


def _differs_by_bands(strip: npt.NDArray[np.uint8], front: npt.NDArray[np.uint8]) -> bool:
    """Whether the rows ``strip`` and ``front`` (rows x columns x Lab) differ by at least
    MIN_TOP_DISTANCE in the median of TOP_FACE_BAND_COUNT column bands (each band's
    medians compared with each other)."""
    cols = strip.shape[1]
    if cols < 2 * TOP_FACE_BAND_COUNT or not strip.shape[0] or not front.shape[0]:
        return False
    cuts = np.linspace(0, cols, TOP_FACE_BAND_COUNT + 1).astype(np.int64)
    bands = list(zip(cuts[:-1], cuts[1:], strict=True))
    upper = np.array([median_u8(strip[:, a:b].reshape(-1, 3), axis=0) for a, b in bands])
    lower = np.array([median_u8(front[:, a:b].reshape(-1, 3), axis=0) for a, b in bands])
    # the rows between are one plane lit evenly: every band within MIN_TOP_DISTANCE of
    # their median colour
    if float(row_norms(upper - np.median(upper, axis=0)).max()) > MIN_TOP_DISTANCE:
        return False
    return float(np.median(row_norms(upper - lower))) >= MIN_TOP_DISTANCE


#: Rows between a found top and a front top edge under it across which the face's own
#: pattern runs (as many steps between neighbouring columns as on the face below) are the
#: front face, not a top face (photo/740: a joint of a brick print taken for the front top
#: edge, height -28 %); a switch for the tests. Used on the colour and texture rescue's
#: face only (method.rescue_by_colour): on the edge search's face, a top face with the
#: first course of a print under it (procedural/128) or a floor of the print's pattern
#: (photo/716 hard) made as many answers worse as better.
PATTERN_NOT_TOP_FACE = True
#: The face's mean step between neighbouring columns (lightness, 8-bit) for it to have a
#: pattern at all (a plain face's grain steps 1-2; brick prints 4-7).
PATTERN_MIN_STEP = 3.0
#: The rows' mean step is at least this share of the face's for the pattern to run across
#: them (photo/740: 4.3 against 5.4, 0.8; photo/735 hard 0.83, photo/110 hard 0.92; a top
#: face's grain over a planks face, procedural/704 hard: 0.73, which the edge search's
#: face would take for the pattern: that face is not judged so).
PATTERN_SHARE = 0.6


#: A top row whose rows just above differ by at least this (Lab, 8-bit scale) from both
#: the rows just below it and the face's colour over the floor ends the face in colour.
TOP_COLOUR_STEP = 20.0
#: Rows sampled just above and just below the top row (past its blur).
STEP_BAND_ROWS = (1, 5)
#: Rows of the face's own colour sampled above the floor-contact row (past its blur).
FOOT_BAND_ROWS = (3, 12)


#: Sides running on above a top where the face's colour ends move it up only by at least
#: this share of the face's height (a print's lower edge low on the face, the face's own
#: colour far above it); a shorter way up is a top face or a band behind the face.
SHORT_RAISE = 0.5


def stops_at_colour_top(
    image: npt.NDArray[Any] | None,
    view: View,
    bottom: int,
    top: int,
    raised: int,
    left: int,
    right: int,
) -> bool:
    """Whether a top the sides ran on past (up to ``raised``) stays: the way up is short
    (under SHORT_RAISE of the face) and the face's colour ends at ``top``
    (:func:`ends_in_colour`). The sides' edges there belong to what stands behind the
    face in line with it (a pole, a wall band, the top face's receding edges)."""
    return (
        raised < top
        and top - raised < SHORT_RAISE * (bottom - top)
        and ends_in_colour(image, view, bottom, top, left, right)
    )


#: Rows right under a raised top read for the face's colour (a share of the way up, at
#: least RETURN_MIN_ROWS): a face's top has the face under it.
RETURN_BAND_SHARE = 0.15
RETURN_MIN_ROWS = 3
#: The face found shows the face's colour when the way up is at most this many times its
#: height (a band, a label or a print's margin at the foot is thinner than what is above).
RETURN_MAX_RAISE = 2.0
#: ... and at least this share of it (shorter: a frame's top margin, a top face, blur;
#: the same share as SHORT_RAISE, where stops_at_colour_top judges the way up).
RETURN_MIN_RAISE = 0.5


def _raise_judged(bottom: int, top: int, raised: int) -> bool:
    """Whether the way up from ``top`` to ``raised`` is judged by the colour under the
    raised top: the face found at least 4 rows, the way RETURN_MIN_RAISE ..
    RETURN_MAX_RAISE of it (:func:`face_under_raised_top`, :func:`margin_up_to_raised_top`)."""
    way, found = top - raised, bottom - top
    return found >= 4 and RETURN_MIN_RAISE * found <= way <= RETURN_MAX_RAISE * found


def _under_raised_rows(way: int) -> tuple[int, int]:
    """For rows read from a raised top ``way`` rows above the found top down to the foot:
    the first row of the face found (past its top's blur), and how many rows right under
    the raised top (past its blur, from row 2) are read for what is back there."""
    return way + 2, max(RETURN_MIN_ROWS, int(RETURN_BAND_SHARE * way))


class _UnderRaised(NamedTuple):
    """A strip read from a raised top down to the foot (:func:`_read_under_raised`)."""

    ref: npt.NDArray[np.float32]  # the face found's colour: its rows' median
    dist: npt.NDArray[np.float32]  # each row's distance from it, from the raised top down
    limit: float  # the spread_limit of the face found's rows
    back: bool  # the rows right under the raised top within it


def _read_under_raised(part: npt.NDArray[np.uint8], way: int) -> _UnderRaised:
    """The columns ``part`` (rows from a raised top ``way`` rows above the found top down
    to the foot, 8-bit Lab) by their median across each row: the face found's colour, the
    rows' distances from it, its spread limit, and whether the rows right under the raised
    top are back within it. One reading for :func:`face_under_raised_top`'s strips and
    :func:`margin_up_to_raised_top`'s."""
    k, n = _under_raised_rows(way)
    rows = median_u8(part, axis=1).astype(np.float32)
    ref = median_of(rows[k:], axis=0)
    dist = row_norms(rows - ref)
    limit = spread_limit(dist[k:], MIN_FACE_DISTANCE)
    return _UnderRaised(ref, dist, limit, float(median_of(dist[2 : 2 + n])) <= limit)


def face_under_raised_top(
    image: npt.NDArray[Any] | None,
    view: View,
    bottom: int,
    top: int,
    raised: int,
    left: int,
    right: int,
    one_strip: bool = False,
) -> bool:
    """Whether the face's colour is back right under ``raised``, a top the sides ran on up
    to past ``top``.

    The face is one surface: past a label, a tape or a band across it, its own colour
    comes back under its real top. Sides that run on past where the face's colour ended,
    into something else all the way up, are the edges of what stands behind the face in
    line with it (a pole, a rocket in a photograph on the wall), not the face's."""
    if image is None or image.ndim != 3 or right - left < 2 * SIDE_SKIP + 4:
        return True
    if not _raise_judged(bottom, top, raised):
        # a short way up is a frame's top margin, a top face or a blurred top
        # (stops_at_colour_top judges it); and a strip found at the face's foot (a band,
        # a print's lower margin) does not show the face's colour: neither is judged
        return True
    c0, c1 = left + SIDE_SKIP, right - SIDE_SKIP + 1
    lab = _lab8(image, view, raised, bottom, c0, c1)

    def back(part: npt.NDArray[np.uint8]) -> bool:
        return _read_under_raised(part, top - raised).back

    # the middle, or both strips just inside the sides (a print over the middle, in a
    # margin of the face's colour that runs up to the face's top)
    if back(lab):
        return True
    strips = (back(lab[:, :BESIDE_COLUMNS]), back(lab[:, -BESIDE_COLUMNS:]))
    return any(strips) if one_strip else all(strips)


#: The columns of each margin strip :func:`margin_up_to_raised_top` reads, and how far in
#: from the side they start (the snapped side's own column and one more, the side's blur,
#: about a pixel at these cameras' focus, left out; a print's margin is a few columns wide
#: at the face's depth, so the strips stay in it where face_under_raised_top's, SIDE_SKIP
#: in and BESIDE_COLUMNS wide, reach the print: photo/3297 hard's is about 4, which
#: MARGIN_STRIP_SKIP 3 or 1 misses on one side). The two must fit in the margin, and the
#: face is wider than both strips with 4 columns between them.
MARGIN_STRIP_COLUMNS = 2
MARGIN_STRIP_SKIP = 2
#: The share of the rows from the raised top down to the foot (the face found's own rows
#: counted too) whose strip colour must be the margin's (within its spread_limit,
#: inclusive), in each strip.
MARGIN_HOLDS_SHARE = 0.9
#: The two strips' colours at most this far apart (8-bit Lab): one margin round the print.
MARGIN_STRIPS_APART = 18.0


def margin_up_to_raised_top(
    image: npt.NDArray[Any] | None,
    view: View,
    bottom: int,
    top: int,
    raised: int,
    left: int,
    right: int,
) -> bool:
    """Whether a margin of one colour runs up both of the face's sides, hugging them, from
    its foot to ``raised``, a top the sides ran on up to past ``top`` (a colour walk's top).

    A poster is one board: its margin frames the print on every side. The colour walk up
    the middle stops inside the print, and face_under_raised_top's strips, a few columns
    in, lie in the print too; but the margin's narrow strips just inside the sides keep
    one colour all the way up to the board's top. What stands behind the face in line with
    its sides (a pole, a rail) does not carry the face's own colour down both its sides to
    its foot. Judged over the same raises as face_under_raised_top."""
    if image is None or image.ndim != 3:
        return False
    if right - left < 2 * (MARGIN_STRIP_SKIP + MARGIN_STRIP_COLUMNS) + 4:
        return False
    if not _raise_judged(bottom, top, raised):
        return False
    lab = _lab8(
        image, view, raised, bottom, left + MARGIN_STRIP_SKIP, right - MARGIN_STRIP_SKIP + 1
    )
    refs = []
    for part in (lab[:, :MARGIN_STRIP_COLUMNS], lab[:, -MARGIN_STRIP_COLUMNS:]):
        read = _read_under_raised(part, top - raised)
        # the margin keeps its colour from the foot up, and runs right up to the raised
        # top: its rows there are the margin's too (as face_under_raised_top reads them)
        if share(read.dist <= read.limit) < MARGIN_HOLDS_SHARE or not read.back:
            return False
        refs.append(read.ref)
    return norm(refs[0] - refs[1]) <= MARGIN_STRIPS_APART


#: A face's hue (a, b) at least this far from grey holds a top for :func:`hue_back_under_top`
#: (session 38's review: a grey face under a white wall kept its hue, and the whole way up
#: was never refused).
HUE_MIN_CHROMA = 8.0
NEUTRAL_AB = np.array([128.0, 128.0], np.float32)  # (a, b) of grey in 8-bit Lab


def hue_back_under_top(
    image: npt.NDArray[Any] | None,
    view: View,
    bottom: int,
    top: int,
    raised: int,
    left: int,
    right: int,
) -> bool:
    """Whether the rows right under ``raised`` (as :func:`face_under_raised_top` reads
    them) keep the hue (a, b) of the face found between ``top`` and ``bottom`` within
    SHADED_HUE_STEP, whatever their lightness: a gloss's highlight or the light's fall-off
    lightens a face up to its top without changing its hue. A face of under HUE_MIN_CHROMA
    (grey, white, black) has no hue to hold: every grey above it would keep it."""
    if image is None or image.ndim != 3 or right - left < 2 * SIDE_SKIP + 4:
        return True
    if bottom - top < 6 or top <= raised:
        return True
    c0, c1 = left + SIDE_SKIP, right - SIDE_SKIP + 1
    lab = _lab8(image, view, raised, bottom, c0, c1)
    k, n = _under_raised_rows(top - raised)
    face = median_u8(lab[k : bottom - raised - 2].reshape(-1, 3), axis=0).astype(np.float32)
    if norm(face[1:] - NEUTRAL_AB) < HUE_MIN_CHROMA:
        return False
    under = median_u8(lab[2 : 2 + n].reshape(-1, 3), axis=0).astype(np.float32)
    return norm(under[1:] - face[1:]) <= SHADED_HUE_STEP


#: Rows of the face sampled just under its top (past the top edge's blur) when a short
#: way up is judged for a top face: a frame's top margin is at least this thick.
UNDER_TOP_ROWS = (2, 5)


def top_face_above(
    image: npt.NDArray[Any] | None,
    view: View,
    bottom: int,
    top: int,
    raised: int,
    left: int,
    right: int,
) -> bool:
    """Whether the rows between ``raised`` and ``top`` (a short way up, under
    RETURN_MIN_RAISE of the face) are a box's top face seen from above, ``top`` its front
    top edge.

    Below the horizon the lens looks down on a low box's top face: it is the box's own
    material in another light, so its colour differs from the face's just under the front
    top edge (MIN_BESIDE_STEP), and its sides run towards the vanishing point, so in its
    upper (farther) half the strips just inside the front face's sides show the floor
    behind, not the top face's colour, at both sides. A colour that runs on past a
    frame's top margin and fills the face's width up there is the face's own."""
    if image is None or image.ndim != 3 or right - left < 2 * (SIDE_SKIP + BESIDE_COLUMNS) + 4:
        return False
    way, found = top - raised, bottom - top
    u0, u1 = UNDER_TOP_ROWS
    if way < MIN_TOP_FACE_ROWS or way >= RETURN_MIN_RAISE * found or found <= u1 + 2:
        return False
    if top <= view.cy + view.horizon_slack_px:
        return False  # a top face shows only below the horizon: the lens above the box
    lab = _lab8(image, view, raised, top + u1, left + SIDE_SKIP, right - SIDE_SKIP + 1)
    b = BESIDE_COLUMNS
    mid = lab[:, 2 * b : -2 * b]
    half = way // 2
    near_face = median_u8(mid[half : way - 1].reshape(-1, 3), axis=0)
    under = median_u8(mid[way + u0 : way + u1].reshape(-1, 3), axis=0)
    if norm(near_face - under) < MIN_BESIDE_STEP:
        return False
    far_face = median_u8(mid[2:half].reshape(-1, 3), axis=0)
    for strip in (lab[2:half, :b], lab[2:half, -b:]):
        if norm(median_u8(strip.reshape(-1, 3), axis=0) - far_face) < MIN_BESIDE_STEP:
            return False
    return True


#: Above the face's top the strip just inside each side is within this (Lab, 8-bit) of
#: the strip just outside it: the background seen past the face on both sides of its side.
BACKGROUND_MATCH = 10.0
#: Below it the two strips differ by at least this at both sides (the face's sides).
SIDE_STEP = 20.0
#: The face under a lower top keeps at least this share of the height found.
LOWER_MIN_SHARE = 0.2
#: A top moves down by at least this share of the height found (and STEP_BAND_ROWS' far
#: rows): nearer, it is the same top's blur, not what stands behind the face.
LOWER_MIN_MOVE = 0.05
#: The background is seen past a side when the strips just inside and just outside it
#: match (BACKGROUND_MATCH) in at least this share of the rows above the row tried ...
PAST_SHARE = 0.8
#: ... of the ONE_SIDE_ROWS rows right above it, where one side is enough (the other may
#: have an object behind it in line with it, a pole, a cup's rim), and where both sides
#: show the background too ...
ONE_SIDE_ROWS = 8
#: ... and, for a top face seen past both sides, of every row from the top found down,
#: over at least this many rows (fewer are the top edge's own blur).
PAST_MIN_ROWS = 6


def _window_mean(rows: npt.NDArray[np.float32], lo: int, hi: int) -> npt.NDArray[np.float32]:
    """Per row r, the mean of ``rows[r + lo : r + hi]`` (NaN where it runs off the ends)."""
    return _window_means(rows, ((lo, hi),))[0]


def _window_means(
    rows: npt.NDArray[np.float32], windows: tuple[tuple[int, int], ...]
) -> list[npt.NDArray[np.float32]]:
    """:func:`_window_mean` for several windows (lo, hi) over one cumulative sum.

    Each column's running sum is its own (numpy's cumsum adds down the rows in order), so
    a block of several stages' columns gives every column the values it gives alone; the
    rows a window covers whole are a slice (no index arrays)."""
    n = rows.shape[0]
    c = np.empty((n + 1, *rows.shape[1:]), np.float64)
    c[0] = 0.0
    c[1:] = np.cumsum(rows, axis=0)  # float32 sums, as np.cumsum gives them, then float64
    outs = []
    for lo, hi in windows:
        out = np.full(rows.shape, np.nan, np.float32)
        a, b = max(0, -lo), min(n, n - hi + 1)  # rows r with 0 <= r + lo, r + hi <= n
        if a < b:
            out[a:b] = (c[a + hi : b + hi] - c[a + lo : b + lo]) / (hi - lo)
        outs.append(out)
    return outs


def _strip_columns(s: int, width: int) -> npt.NDArray[np.intp]:
    """Columns of :func:`lower_top_to_background`'s four strips in a band ``width`` wide
    (inside then outside the left side, inside then outside the right one), ``s`` columns
    from the inner strips' outer ends to the band's."""
    b = BESIDE_COLUMNS
    cols = np.concatenate(
        [
            np.arange(s, s + b),
            np.arange(b),
            np.arange(width - s - b, width - s),
            np.arange(width - b, width),
        ]
    )
    return cols


def _sides_band(
    image: npt.NDArray[Any] | None, view: View, top: int, left: int, right: int
) -> tuple[int, int] | None:
    """The columns c0..c1 of a band around both sides (each side's strips just inside and
    just outside, past its blur), or None: no colour frame, a face too narrow for its
    strips, a band past the view's edges or a top too near the view's first row."""
    if image is None or image.ndim != 3 or right - left < 2 * (SIDE_SKIP + BESIDE_COLUMNS):
        return None
    s = SIDE_SKIP + BESIDE_COLUMNS
    c0, c1 = left - s, right + s + 1
    if c0 < 0 or c1 > view.out.shape[1] or top < STEP_BAND_ROWS[1]:
        return None
    return c0, c1


def _inside_minus_outside(lab: npt.NDArray[Any]) -> npt.NDArray[Any]:
    """Per row of a band of :func:`_sides_band`'s columns, in Lab: each side's strip just
    inside minus the one just outside (rows x side x colour), the four strips' per-row
    medians taken in one call."""
    strips = median_u8(
        lab[:, _strip_columns(SIDE_SKIP + BESIDE_COLUMNS, lab.shape[1])].reshape(
            lab.shape[0], 4, BESIDE_COLUMNS, 3
        ),
        axis=2,
    )
    return strips[:, 0::2] - strips[:, 1::2]


def lower_top_to_background(
    image: npt.NDArray[Any] | None,
    view: View,
    bottom: int,
    top: int,
    left: int,
    right: int,
) -> int:
    """The top moved down to the highest row under it where the face's colour ends and
    both its sides end: above that row what shows just inside a side is what shows just
    outside it (at one side at least, over the ONE_SIDE_ROWS rows right above), below it
    the two differ at both sides.

    An object behind the face in line with its sides (a cup, a pole, a shelf) carries the
    sides' edges on up, and the top found is that object's; at the face's own top the
    background is seen past it, the same colour on both sides of a side (occlusion),
    while a label or a print on the face keeps the face's sides. One side is enough: an
    object behind may stand in line with the other side too (a spoon beside a cup), but
    a face's own colour beside a side, a label's or a print's, does not look like the
    background over several rows."""
    band = _sides_band(image, view, top, left, right)
    if band is None or image is None:
        return top
    c0, c1 = band
    s = SIDE_SKIP + BESIDE_COLUMNS
    near, far = STEP_BAND_ROWS
    f0, f1 = FOOT_BAND_ROWS
    low = bottom - max(f1 + far + 1, int(LOWER_MIN_SHARE * (bottom - top)))
    if low <= top + far:
        return top
    r0 = top - far
    lab = _lab8(image, view, r0, bottom, c0, c1)
    mid = np.asarray(median_u8(lab[:, 2 * s : -2 * s : SUBSAMPLE], axis=1), np.float32)
    foot = median_of(mid[bottom - f1 - r0 : bottom - f0 - r0], axis=0)
    diffs = _inside_minus_outside(lab)
    # the middle's colour and both sides' differences, windowed above and below each row
    # over one running sum: rows x (middle, left, right) x colour
    above_all, below_all = _window_means(
        np.concatenate([mid[:, None], diffs], axis=1), ((-far, -near), (near + 1, far + 1))
    )
    above_m, below_m = above_all[:, 0], below_all[:, 0]
    ok = (row_norms(above_m - below_m) >= TOP_COLOUR_STEP) & (
        row_norms(above_m - foot) >= TOP_COLOUR_STEP
    )
    # the background seen past at least one side (the other may have an object behind
    # it in line, a pole or a cup's rim), held over the ONE_SIDE_ROWS rows right above,
    # and both sides parting the face from it below
    idx = np.arange(ok.size)
    lo_i, hi_i = np.maximum(idx - near - ONE_SIDE_ROWS, 0), np.maximum(idx - near, 0)
    held = hi_i - lo_i >= ONE_SIDE_ROWS
    seen_past = np.zeros_like(ok)
    for k in (1, 2):
        ok &= row_norms(below_all[:, k]) >= SIDE_STEP
        matched = row_norms(diffs[:, k - 1]) <= BACKGROUND_MATCH
        counts = np.concatenate([[0], np.cumsum(matched)])
        past = (counts[hi_i] - counts[lo_i]) / np.maximum(hi_i - lo_i, 1)
        seen_past |= (row_norms(above_all[:, k]) <= BACKGROUND_MATCH) & held & (past >= PAST_SHARE)
    ok &= seen_past
    first = far + max(far, int(LOWER_MIN_MOVE * (bottom - top)))
    rows = np.flatnonzero(ok[first : low - r0]) + first
    if rows.size == 0:
        return top
    # the run of rows that pass nearest the top, at the row whose colour steps most from
    # the row above it (the first row of the face)
    run = rows[: int(np.argmax(np.diff(np.append(rows, rows[-1] + 2)) > 1)) + 1]
    step = row_norms(mid[run] - mid[run - 1])
    lowered = int(r0 + run[int(np.argmax(step))])
    if BAND_ACROSS_KEEPS_TOP and _face_over_band(mid, diffs, foot, 2 * far, lowered - r0):
        log.debug("top %d kept: the face's colour and sides run on over %d", top, lowered)
        return top
    return lowered


#: A top is not lowered to where the background seems to show past the sides when the
#: face's own colour and both its sides hold over most of the rows above that (a tape or
#: a course across the face in the background's colour, crossed: the face is one surface
#: from its foot to its top). A switch for the tests.
BAND_ACROSS_KEEPS_TOP = True
#: A row above the lowered top is the face's where its middle is within this (Lab, 8-bit)
#: of the face's foot colour (the face's own colour, as BACKGROUND_MATCH is the
#: background's) ...
FACE_OVER_BAND_MATCH = 10.0
#: ... and both sides part it from what is beside it by SIDE_STEP; the face runs on over
#: the band where at least this share of the rows from the top (past its blur) down to
#: the lowered top are the face's: the rest is the band (an object behind the face, seen
#: past a gap of background, holds the face's colour and sides in none of them).
FACE_OVER_BAND_SHARE = 0.6


def _face_over_band(
    mid: npt.NDArray[np.float32],
    diffs: npt.NDArray[Any],
    foot: npt.NDArray[Any],
    start: int,
    end: int,
) -> bool:
    """Whether the rows ``start:end`` (of :func:`lower_top_to_background`'s band, from the
    top past its blur down to the lowered top) are mostly the face's own: its foot's colour
    in the middle (FACE_OVER_BAND_MATCH) and both sides parting it from what is beside it
    (SIDE_STEP), in at least FACE_OVER_BAND_SHARE of them."""
    if end <= start:
        return False
    own = row_norms(mid[start:end] - foot) <= FACE_OVER_BAND_MATCH
    for k in (0, 1):
        own &= row_norms(diffs[start:end, k]) >= SIDE_STEP
    return bool(np.count_nonzero(own) >= FACE_OVER_BAND_SHARE * (end - start))


def lower_top_past_top_face(
    image: npt.NDArray[Any] | None,
    view: View,
    bottom: int,
    top: int,
    left: int,
    right: int,
) -> int:
    """The top moved down past rows where the background shows on both sides of both
    sides, to where the face's sides part it from the background again: a top face.

    Below the horizon the lens looks down on the box's top face, and that face narrows
    as it recedes (its back edge spans the front's columns scaled by D / (D + l) about the
    principal point), so just inside each side column the background shows above the
    front top edge, as it does outside: an edge found above that (the back edge, or an
    object behind the box) is not the face's top. Unlike :func:`lower_top_to_background`
    no colour step in the middle is needed: a top face is often of the front's colour.
    Returns the highest such row (the top face's back edge or its front top edge, for
    :func:`.top.front_top` to settle), or ``top``."""
    band = _sides_band(image, view, top, left, right)
    if band is None or image is None:
        return top
    c0, c1 = band
    near, far = STEP_BAND_ROWS
    low = bottom - max(FOOT_BAND_ROWS[1] + far + 1, int(LOWER_MIN_SHARE * (bottom - top)))
    first = far + PAST_MIN_ROWS + near  # band index of the first row that may pass
    if low <= top + first - far:
        return top
    if low - 1 <= view.cy - view.horizon_slack_px:
        return top  # every row it could come down to is above the horizon (see below)
    r0 = top - far
    lab = _lab8(image, view, r0, low + far + 1, c0, c1)
    diffs = _inside_minus_outside(lab)
    above_all, below_all = _window_means(diffs, ((-far, -near), (near + 1, far + 1)))
    ok = np.ones(diffs.shape[0], bool)
    for k in (0, 1):
        ok &= row_norms(above_all[:, k]) <= BACKGROUND_MATCH
        ok &= row_norms(below_all[:, k]) >= SIDE_STEP
    # the background seen past both sides in most rows from the top found down
    seen = (row_norms(diffs[:, 0]) <= BACKGROUND_MATCH) & (
        row_norms(diffs[:, 1]) <= BACKGROUND_MATCH
    )
    counts = np.concatenate([[0], np.cumsum(seen)])
    idx = np.arange(diffs.shape[0])
    ends = np.maximum(idx - near, far)
    past = (counts[ends] - counts[far]) / np.maximum(ends - far, 1)
    ok &= past >= PAST_SHARE
    # below the horizon only: a lens below the box's top sees no top face
    ok &= idx + r0 > view.cy - view.horizon_slack_px
    rows = np.flatnonzero(ok[first : low - r0]) + first
    if rows.size == 0:
        return top
    # the windows pass a few rows early (one row of a strong step fills a window's
    # mean): the row where both sides first step on their own, the face's first row
    sides = (row_norms(diffs[:, 0]) >= SIDE_STEP) & (row_norms(diffs[:, 1]) >= SIDE_STEP)
    start = int(rows[0])
    own = np.flatnonzero(sides[start : start + 2 * far + 1])
    return int(r0 + start + (int(own[0]) if own.size else 0))


def ends_in_colour(
    image: npt.NDArray[Any] | None,
    view: View,
    bottom: int,
    top: int,
    left: int,
    right: int,
    step: float = TOP_COLOUR_STEP,
) -> bool:
    """Whether the face's colour ends at ``top`` from side to side: the rows just above it
    differ from the rows just below it and from the face's colour over the floor by
    ``step`` (TOP_COLOUR_STEP), and so do those rows in the strips just inside each side.

    Over a label's or a print's lower edge the colour differs from the face's just below
    but, across a short band, the sides run on; over a face's real top it is something
    else altogether (a top face, the wall band or the object behind it), and sides that
    run on there are the background's edges in line with the face's. A print's frame
    keeps its colour along the sides past the print's top: that is no end."""
    near, far = STEP_BAND_ROWS
    f0, f1 = FOOT_BAND_ROWS
    if image is None or image.ndim != 3 or right - left < 2 * (SIDE_SKIP + BESIDE_COLUMNS):
        return False
    if top - far < 0 or bottom - f1 < top + far + 1:
        return False
    c0, c1 = left + SIDE_SKIP, right - SIDE_SKIP + 1
    lab = _lab8(image, view, top - far, bottom - f0, c0, c1)
    above, below = lab[: far - near], lab[far + near + 1 : 2 * far + 1]
    foot = median_u8(lab[bottom - f1 - (top - far) :].reshape(-1, 3), axis=0)
    a = median_u8(above.reshape(-1, 3), axis=0)
    if min(norm(a - median_u8(below.reshape(-1, 3), axis=0)), norm(a - foot)) < step:
        return False
    steps = []
    for strip in (slice(0, BESIDE_COLUMNS), slice(-BESIDE_COLUMNS, None)):
        up = median_u8(above[:, strip].reshape(-1, 3), axis=0)
        down = median_u8(below[:, strip].reshape(-1, 3), axis=0)
        steps.append(norm(up - down))
    return max(steps) >= step


def _walk_colour(
    colour: npt.NDArray[np.float32],
    on: npt.NDArray[np.bool_],
    start: int,
    limit: float,
    max_gap: int,
) -> int:
    """Highest row above ``start`` reached through ``on`` rows whose colour is within
    ``limit`` of a row reached at least STEP_ROWS below (a gloss or a shadow shades the
    face slowly; the edge to a top face or to the background is a step, blurred over a
    few rows, that no gap crosses)."""
    reached = [start]  # descending: the reference is the last one STEP_ROWS below r
    at = 0  # reached[at]: the reference for the row walked into next (start, at first)
    gap, r = 0, start
    while r - 1 >= 0 and gap <= max_gap:
        r -= 1
        while at + 1 < len(reached) and reached[at + 1] >= r + STEP_ROWS:
            at += 1  # (r falls row by row: the reference only moves up)
        ref = reached[at]
        if on[r] and norm(colour[r] - colour[ref]) <= limit:
            reached.append(r)
            gap = 0
        else:
            gap += 1
    return reached[-1]


#: A face's top edge with a colour step under this (Lab distance between the rows just
#: above and just below it, inside the sides) scales the confidence down in proportion.
TOP_STEP_FULL = 12.0
#: Rows either side of the top edge sampled (past the edge's blur).
TOP_STEP_ROWS = (2, 5)


def top_agreement(
    image: npt.NDArray[Any] | None, view: View, top: int, left: int, right: int
) -> float:
    """0..1: how clearly the face's colour ends at its top row.

    Where the top found is the face's own, the colour changes there (to a top face, the
    wall, a label's margin); where it is a line on the face or in the room behind it,
    the rows above and below it look alike. Measured on independently made rooms, most
    confident detections with a wrong height had a step under 10 here, right ones over 12."""
    a, b = TOP_STEP_ROWS
    if image is None or image.ndim != 3 or top < b or right - left < 2 * SIDE_SKIP + 4:
        return 1.0
    lab = _lab8(image, view, top - b, top + b + 1, left, right)
    left, right = 0, right - left  # columns of the band
    n = b - a + 1
    # the middle, and just inside each side: a top face of the front's own shade is no
    # step in the middle, but it narrows as it recedes, so beside it the wall shows
    steps = []
    for c0, c1 in (
        (left + SIDE_SKIP, right - SIDE_SKIP),
        (left + SIDE_SKIP, left + SIDE_SKIP + BESIDE_COLUMNS),
        (right - SIDE_SKIP - BESIDE_COLUMNS, right - SIDE_SKIP),
    ):
        above = median_u8(lab[:n, c0:c1].reshape(-1, 3), axis=0)
        below = median_u8(lab[-n:, c0:c1].reshape(-1, 3), axis=0)
        steps.append(norm(above - below))
    return min(1.0, max(steps) / TOP_STEP_FULL)


#: Width of the strips sampled around a face for a frame's margin, metres at the face.
MARGIN_STRIP_M = 0.01
#: The margin's three strips (left, right, below) agree within this colour distance ...
MARGIN_AGREE = 15.0
#: ... and differ from the print they surround by at least this.
MARGIN_VS_PRINT = 20.0
#: A frame's margin is at most this share of the print's width (and height) wide.
MAX_MARGIN_SHARE = 0.35
#: A "margin" of the floor's chroma (within FLOOR_CHROMA) at least this much darker (Lab
#: lightness, 8-bit) than the floor just past its end below is the face's shadow on the
#: floor, not a frame of the face's own colour.
SHADOW_DARKER = 6.0
#: ... on a floor of at least this chroma (a grey floor's shade has no hue to tell it by:
#: a grey margin round a print on it is as dark).
SHADOW_FLOOR_CHROMA = 10.0
#: Whether a foot in the floor's shadow counts as floor when a face's sides move.
SHADOW_FOOT = True
#: Whether a margin of the floor's hue, darker (read as the face's shadow), is a frame
#: after all where it runs over the print's top too: a shadow lies on the floor round a
#: face's foot, never over its top (procedural/708 hard with no rig: a dark teal frame
#: round a yellow brick print on a teal floor, measured as the print, -10 %).
MARGIN_OVER_NOT_SHADOW = True
#: Rows the margin's colour runs over the print's top, at least, for that.
MARGIN_OVER_ROWS = 2


def shadow_columns(colour: npt.NDArray[Any], floor: npt.NDArray[Any]) -> npt.NDArray[np.bool_]:
    """Per entry (N x 3, 8-bit Lab): ``colour`` looks like the ``floor``'s in shadow,
    SHADOW_DARKER or more darker, its chroma the floor's scaled by the lightness ratio
    within FLOOR_CHROMA (less light off the same surface dims its chroma in proportion;
    its hue stays), on a floor of SHADOW_FLOOR_CHROMA or more."""
    c = np.asarray(colour, np.float32).reshape(-1, 3)
    f = np.asarray(floor, np.float32).reshape(-1, 3)
    lc, lf = c[:, 0], f[:, 0]
    k = (lc / np.maximum(lf, 1.0))[:, None]
    off = row_norms((c[:, 1:] - 128.0) - k * (f[:, 1:] - 128.0))
    hued = row_norms(f[:, 1:] - 128.0) >= SHADOW_FLOOR_CHROMA
    out: npt.NDArray[np.bool_] = (lf - lc >= SHADOW_DARKER) & (off <= FLOOR_CHROMA) & hued
    return out


def _shadow_of(colour: npt.NDArray[Any], floor: npt.NDArray[Any]) -> bool:
    """Whether one colour (8-bit Lab) looks like the ``floor``'s in shadow
    (:func:`shadow_columns`)."""
    return bool(shadow_columns(colour, floor)[0])


def _margin_over_print(
    rows: npt.NDArray[Any], first: int, margin: npt.NDArray[Any], reach: int
) -> bool:
    """Whether the ``margin``'s colour runs MARGIN_OVER_ROWS or more (and less than
    ``reach``: no wall of it) up the per-row colours ``rows`` from row ``first`` (over a
    print's top): the margin is a frame's round the print, not a shadow under a face."""
    if not MARGIN_OVER_NOT_SHADOW or first < 0:
        return False
    ref = np.asarray(margin, np.float32)
    run = _run_length(np.asarray(rows[first::-1][:reach], np.float32), ref, MARGIN_AGREE)
    return MARGIN_OVER_ROWS <= run < reach


def _run_length(colour: npt.NDArray[np.float32], ref: npt.NDArray[np.float32], limit: float) -> int:
    """How many leading entries of ``colour`` stay within ``limit`` of ``ref``."""
    off = row_norms(colour - ref) > limit
    return int(np.argmax(off)) if off.any() else colour.shape[0]


def enclose_by_margin(
    image: npt.NDArray[Any] | None,
    view: View,
    bottom: int,
    top: int,
    left: int,
    right: int,
    depth_m: float,
) -> tuple[int, int, int, int] | None:
    """A print (a poster, a page, bricks) on a face with a margin of the face's colour.

    The found rectangle is the print when it is surrounded, left, right and below, by one
    colour unlike its own that ends within a margin's width on each of those sides: the
    face is then that frame (returned as bottom, top, left, right), its top where the
    margin colour ends above. Without a rig the print's lower edge can be taken for the
    floor contact; with one, the print's sides for the face's. Returns None: no frame."""
    if image is None or image.ndim != 3 or right - left < 10 or bottom - top < 6:
        return None
    h, w = view.out.shape
    m = max(3, int(round(view.fx * MARGIN_STRIP_M / depth_m)))
    reach_u = int(MAX_MARGIN_SHARE * (right - left)) + m + 2
    reach_v = int(MAX_MARGIN_SHARE * (bottom - top)) + m + 2
    if left - reach_u < 3 or right + reach_u + 4 > w or bottom + reach_v >= h or top < reach_v:
        return None
    k_v = max(1, (bottom - top) // 5)
    k_u = max(1, (right - left) // 5)
    r0, r1 = top - reach_v, bottom + reach_v + 1
    # first the three strips and the print alone (most faces are no print: a quick no)
    inner_rows = (top + k_v, bottom - k_v)
    print_colour = median_u8(
        _lab8(image, view, *inner_rows, left + k_u, right - k_u, SUBSAMPLE).reshape(-1, 3),
        axis=0,
    )
    strips = [
        median_u8(_lab8(image, view, *inner_rows, left - 2 - m, left - 2).reshape(-1, 3), axis=0),
        median_u8(_lab8(image, view, *inner_rows, right + 3, right + 3 + m).reshape(-1, 3), axis=0),
        median_u8(
            _lab8(image, view, bottom + 2, bottom + 2 + m, left + k_u, right - k_u).reshape(-1, 3),
            axis=0,
        ),
    ]
    margin = median_of(np.stack(strips), axis=0)
    if max(norm(s - margin) for s in strips) > MARGIN_AGREE or any(
        norm(s - print_colour) < MARGIN_VS_PRINT for s in strips
    ):
        return None
    c0 = left - reach_u - 3  # a margin's reach past the 2-3 columns skipped at a side
    lab = _lab8(image, view, r0, r1, c0, right + reach_u + 4)
    left, right = left - c0, right - c0  # columns of the band
    rows = slice(top + k_v - r0, bottom - k_v - r0)
    # per-column colours across the side strips' rows, per-row colours under (and over)
    # the print
    side_cols = median_u8(lab[rows][::SUBSAMPLE], axis=0)  # W x 3
    below_rows = median_u8(lab[:, left + k_u : right - k_u : SUBSAMPLE], axis=1)  # rows x 3
    # the margin ends within its reach on each side (a floor or wall of one colour all
    # round runs on: no frame)
    out_left = _run_length(side_cols[left - 2 :: -1][:reach_u], margin, MARGIN_AGREE)
    out_right = _run_length(side_cols[right + 3 :][:reach_u], margin, MARGIN_AGREE)
    out_below = _run_length(below_rows[bottom + 2 - r0 :][:reach_v], margin, MARGIN_AGREE)
    if min(out_left, out_right, out_below) < 2 or max(
        out_left >= reach_u, out_right >= reach_u, out_below >= reach_v
    ):
        return None
    # a face's shadow round its foot is no margin: the floor past where it ends below,
    # darker, its chroma scaled down with its lightness (a margin is the face's own paint)
    past = bottom + 2 + out_below - r0
    if (
        past < below_rows.shape[0]
        and _shadow_of(margin, median_u8(below_rows[past : past + m], axis=0))
        and not _margin_over_print(below_rows, top - 2 - r0, margin, reach_v)
    ):
        return None
    above = median_u8(below_rows[max(0, top - 2 - m - r0) : top - 2 - r0 + 1], axis=0)
    if norm(above - print_colour) < MARGIN_VS_PRINT:
        # what stands over the print differs from it (the margin, or the room): a strip at
        # a face's foot (its lowest rows, a shadow) has the face itself over it, and the
        # floor beside and below it, which a stripe or a tile line ends within a margin's
        # reach
        return None
    out_above = _run_length(below_rows[top - 2 - r0 :: -1][:reach_v], margin, MARGIN_AGREE)
    new_top = top - 2 - out_above if 2 <= out_above < reach_v else top
    return bottom + 2 + out_below, new_top, c0 + left - 2 - out_left, c0 + right + 3 + out_right


#: Columns (rows) skipped past a print's edge before its margin is read: the edge's blur.
RING_SKIP = 1
#: Leading entries of the margin above a print read for the margin's colour.
RING_SEED = 4
#: Entries a margin above a print runs at least (its end is sought past them).
RING_MIN = 2
#: A margin's run holds while within this (Lab) of the margin's colour, and ends where
#: the next few entries (their median, not one blurred entry) are farther than this.
RING_AGREE = 20.0
#: Entries outward from a side within which a margin's run may start (the print's edge
#: blurred past the side found: RING_SKIP plus these).
RING_BLUR = 4
#: ... where its colour shows within this share of RING_AGREE (clearly the margin's).
RING_CLEAR = 0.75


def _ring_run(profile: npt.NDArray[np.float32], ring: npt.NDArray[np.float32], reach: int) -> int:
    """How far (entries) a margin of colour ``ring`` runs out along ``profile`` (the
    colours outward from a print's edge, past its blur): -1 when it runs on past
    ``reach`` (a wall of that colour, no margin) or what lies beyond it is no other colour
    (one entry of blur or noise)."""
    # the print's edge may stand a column or two farther out than the side found (its
    # blur): where the first entry is not the margin's, the margin starts where its colour
    # first shows clearly within RING_BLUR entries, reached by a ramp (each entry nearer
    # the margin's colour, as a blurred step is; a band of a third colour is no blur). The
    # margin's colour seen beyond the side means the side is inside the face
    start = 0
    dist = row_norms(profile[:RING_BLUR] - ring)
    clear = dist <= RING_CLEAR * RING_AGREE
    if dist.size and dist[0] > RING_AGREE and clear.any():
        first = int(np.argmax(clear))
        if bool(np.all(np.diff(dist[: first + 1]) <= 0.0)):
            start = first
    run = start + _run_length(profile[start:reach], ring, RING_AGREE)
    if run >= reach:
        return -1
    beyond = median_of(profile[run : run + 3], axis=0)
    if norm(beyond - ring) <= RING_AGREE:
        return -1
    if run == start:
        return 0
    # the margin ends at its sharpest step (a top face of another shade of the same
    # paint, lit otherwise, may lie within the tolerance next to it), past the first
    # RING_MIN entries (the margin itself; a blurred step spreads over its last ones)
    lo = start + min(RING_MIN, run - start)
    steps = row_norms(np.diff(profile[: run + 1], axis=0))
    return lo + int(np.argmax(steps[lo - 1 : run]))


#: :func:`enclose_by_ring`: the margin is the face's own surface round the print, a
#: rectangle's band: each side's margin ends as far out at the print's upper or lower
#: rows as at its middle (its outer edge a straight side of the face, upright). A
#: "margin" that is the room seen beside and over the face (its colour by chance the
#: background's, ending on whatever clutter stands there) ends at other columns at other
#: heights, or nowhere (a switch for the tests).
RING_SIDES_STRAIGHT = True
#: ... the rows read: bands centred this share of the print's height down from its top
#: and up from its foot (the middle band is the one the margin was found in).
RING_SIDE_BAND_AT = 0.25
#: ... a side's margin there ends within this many columns of where it ends in the
#: middle (a frame's edge blurred, the face rolled by a degree or two).
RING_SIDE_SLACK = 3


def _beside(
    image: npt.NDArray[Any], view: View, rm: int, q_v: int, c0: int, c1: int, lf: int, rt: int
) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]:
    """The colours outward from a print's left and right sides (columns ``lf``, ``rt`` of
    the columns ``c0``-``c1`` read), past each side's blur (RING_SKIP): per-column medians
    over the band of rows ``rm`` +- ``q_v``."""
    cols = np.asarray(
        median_u8(_lab8(image, view, rm - q_v, rm + q_v + 1, c0, c1), axis=0), np.float32
    )
    return cols[lf - RING_SKIP :: -1], cols[rt + RING_SKIP :]


def _ring_sides_straight(
    beside: Callable[[int], tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]],
    bottom: int,
    top: int,
    ring: npt.NDArray[np.float32],
    reach_u: int,
    out: list[int],
) -> bool:
    """Whether the margin :func:`enclose_by_ring` read beside a print's middle rows (runs
    ``out``, columns past each side's blur) holds at its upper and lower rows as well
    (``beside``: the profiles outward from the sides along the band centred at a row): a
    side with a margin (RING_MIN columns or more) ends within RING_SIDE_SLACK columns of
    its middle run at one of them at least (RING_SIDES_STRAIGHT)."""
    height = bottom - top
    seen = [out[0] < RING_MIN, out[1] < RING_MIN]  # sides with no margin ask for nothing
    for at in (RING_SIDE_BAND_AT, 1.0 - RING_SIDE_BAND_AT):
        for side, profile in enumerate(beside(top + int(at * height))):
            if seen[side]:
                continue  # no margin at the middle, or its edge seen at the upper band
            run = _ring_run(profile, ring, reach_u)
            # (elsewhere a run of 0: the margin not seen past the print's edge there, its
            # blur; -1 or another column: a background of nearly its colour beside it)
            seen[side] = seen[side] or (run > 0 and abs(run - out[side]) <= RING_SIDE_SLACK)
    return all(seen)


def enclose_by_ring(
    image: npt.NDArray[Any] | None,
    view: View,
    bottom: int,
    top: int,
    left: int,
    right: int,
    foot_rows: tuple[int, int],
) -> tuple[int, int, int, int] | None:
    """A print (bricks, a poster) covering most of a face, found instead of the face,
    whose margin of the face's own colour is too thin or uneven for
    :func:`enclose_by_margin`'s fixed strips (a margin of 1-4 px at a side).

    The face is one surface: the margin above the print is its colour, and where the
    margin shows beside the print (at least one side) and under it, it is that same
    colour, ending within a margin's reach where the room (at another depth) begins. The
    face stands on the floor: the margin's foot must fall in the rig's band of
    floor-contact rows ``foot_rows`` (a print's lower edge above the band is no foot).
    Returns the frame (bottom, top, left, right) or None."""
    if image is None or image.ndim != 3 or right - left < 10 or bottom - top < 10:
        return None
    h, w = view.out.shape
    reach_u = int(MAX_MARGIN_SHARE * (right - left)) + RING_SKIP + 3
    reach_v = int(MAX_MARGIN_SHARE * (bottom - top)) + RING_SKIP + 3
    r0, r1 = top - reach_v, min(h, foot_rows[1] + 4)
    c0, c1 = left - reach_u, right + reach_u + 1
    if r0 < 0 or c0 < 0 or c1 > w or r1 <= bottom + 4:
        return None
    # two bands through the print's middle, a tenth of its size wide: rows over its
    # middle columns (above, the print, below), columns over its middle rows (beside)
    q_u, q_v = max(2, (right - left) // 10), max(2, (bottom - top) // 10)
    cm, rm = (left + right) // 2, (top + bottom) // 2
    band = _lab8(image, view, r0, r1, cm - q_u, cm + q_u + 1)
    k_v = max(1, (bottom - top) // 5)
    t, b = top - r0, bottom - r0
    print_colour = median_u8(band[t + k_v : b - k_v].reshape(-1, 3), axis=0)
    rows = np.asarray(median_u8(band, axis=1), np.float32)
    above = rows[t - RING_SKIP :: -1]
    ring = median_of(above[:RING_SEED], axis=0)
    if norm(ring - print_colour) < MARGIN_VS_PRINT:
        return None
    up = _ring_run(above, ring, reach_v)
    if up < RING_MIN:
        return None
    below = rows[b + RING_SKIP :]
    down = _ring_run(below, ring, below.shape[0])
    new_bottom = bottom + RING_SKIP + down
    if down < 1 or not foot_rows[0] <= new_bottom <= foot_rows[1]:
        return None
    lf, rt = left - c0, right - c0

    def beside(row: int) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]:
        return _beside(image, view, row, q_v, c0, c1, lf, rt)

    out = []
    for profile in beside(rm):
        run = _ring_run(profile, ring, reach_u)
        out.append(max(run, 0))
        if run < 0 and norm(profile[0] - ring) < RING_AGREE:
            return None  # the margin's colour runs on beside the print: a wall of it
    if max(out) < 2:
        return None  # no margin beside the print: the ring above it is something else
    if RING_SIDES_STRAIGHT and not _ring_sides_straight(beside, bottom, top, ring, reach_u, out):
        return None
    return (
        new_bottom,
        top - RING_SKIP - up,
        left - RING_SKIP - out[0],
        right + RING_SKIP + out[1],
    )


#: :func:`margin_under_print`: columns read just outside each side of a print for its side
#: margins' colour (past RING_SKIP columns of the edge's blur).
SIDE_MARGIN_COLUMNS = 3
#: With no rig the row tried may be a line across the print a course above its lower edge
#: (a brick course's mortar, a stripe of the print): the print's own colour runs on under
#: that row to the print's lower edge, and the frame's margin begins only there. The
#: margin under is then sought past that run of the print's colour (within RING_AGREE of
#: it), of at most PRINT_UNDER_SHARE of the found height (a course or two of a print's
#: pattern: procedural 3274 hard, bricks 9-10 rows a course on a 97-row print, the row tried
#: a mortar line 5 rows over the print's edge). A switch for the tests.
PRINT_RUNS_UNDER_ROW = True
PRINT_UNDER_SHARE = 0.1


def _margin_past_blur(
    profile: npt.NDArray[np.float32], ring: npt.NDArray[np.float32], reach: int
) -> int | None:
    """How far (entries) a margin of colour ``ring`` runs out along ``profile`` (outward
    from a print's edge): it starts within the first RING_BLUR entries (the edge's blur)
    and must end within ``reach`` (and inside the profile) on another colour; None when
    it does not show, or runs on."""
    near = row_norms(profile[:RING_BLUR] - ring) <= RING_AGREE
    if not near.any():
        return None
    first = int(np.argmax(near))
    run = first + _run_length(profile[first:reach], ring, RING_AGREE)
    if run >= min(reach, profile.shape[0]):
        return None  # the colour runs on (a floor or wall of it) or past the view
    if norm(median_of(profile[run : run + 3], axis=0) - ring) <= RING_AGREE:
        return None
    return run


def margin_under_print(
    image: npt.NDArray[Any] | None, view: View, bottom: int, top: int, left: int, right: int
) -> tuple[int, int, int, int] | None:
    """The frame round a print found for the face (``left``-``right`` x ``top``-``bottom``,
    working view) whose margin runs on under the print's lower edge, as (bottom, top,
    left, right), or None: the colour just outside both its sides (one colour, unlike the
    print's, ending within a margin's reach where the room begins) is also the colour
    just under its lower edge, where it ends within a margin's reach too, on another
    colour (the floor), and just over its top, where it ends within the reach too: the
    frame's top.

    A face stands on the floor: under its foot lies the floor, running on down, not a
    thin band of the colour that flanks the face. With no rig the row tried for the floor
    contact may be a print's lower edge over a margin too thin for
    :func:`enclose_by_margin`'s fixed strips and with too little margin over the print
    for :func:`enclose_by_ring` (bricks in a frame 2-4 px thick at the top and the foot):
    the size found is the print's, its foot not the floor contact."""
    if image is None or image.ndim != 3 or right - left < 10 or bottom - top < 10:
        return None
    h, w = view.out.shape
    reach_u = int(MAX_MARGIN_SHARE * (right - left)) + RING_SKIP + 3
    reach_v = int(MAX_MARGIN_SHARE * (bottom - top)) + RING_SKIP + 3
    # (the frame may end a few columns inside the image's edge: the reach is clamped)
    c0, c1 = max(0, left - reach_u), min(w, right + reach_u + 1)
    r0, r1 = max(0, top - reach_v), min(h, bottom + reach_v + 4)
    least = RING_SKIP + SIDE_MARGIN_COLUMNS + RING_MIN  # a side margin and what ends it
    if min(left - c0, c1 - right) < least or r1 - bottom < RING_SKIP + RING_BLUR + 3:
        return None
    q_u, q_v = max(2, (right - left) // 10), max(2, (bottom - top) // 10)
    cm, rm = (left + right) // 2, (top + bottom) // 2
    k_v = max(1, (bottom - top) // 5)
    band = _lab8(image, view, r0, r1, cm - q_u, cm + q_u + 1)
    t, b = top - r0, bottom - r0
    print_colour = median_u8(band[t + k_v : b - k_v].reshape(-1, 3), axis=0)
    profiles = _beside(image, view, rm, q_v, c0, c1, left - c0, right - c0)
    # the side margins' colours: their first columns out from the print's sides
    colours = [median_of(p[:SIDE_MARGIN_COLUMNS], axis=0) for p in profiles]
    ring = 0.5 * (colours[0] + colours[1])
    if norm(colours[0] - colours[1]) > RING_AGREE or norm(ring - print_colour) < MARGIN_VS_PRINT:
        return None
    out = []
    for profile in profiles:
        run = _ring_run(profile, ring, min(reach_u, profile.shape[0]))
        if run < RING_MIN:
            return None  # no side margin, or a wall of its colour beside the face
        out.append(run)
    rows = np.asarray(median_u8(band, axis=1), np.float32)
    down = _margin_past_blur(rows[b + RING_SKIP :], ring, reach_v)
    if down is None and PRINT_RUNS_UNDER_ROW:
        # the row tried a line on the print: its colour runs on under it to its lower edge
        under = _run_length(rows[b + RING_SKIP :], np.asarray(print_colour, np.float32), RING_AGREE)
        if under <= PRINT_UNDER_SHARE * (bottom - top):
            past = _margin_past_blur(rows[b + RING_SKIP + under :], ring, reach_v)
            down = None if past is None else under + past
    if down is None:
        return None
    # ... and over it: a frame is a ring, its margin round the print on all four sides (a
    # band under a face whose sides a shade's or a seam's blur flanks has none over it)
    up = _margin_past_blur(rows[t - RING_SKIP :: -1], ring, reach_v) if t > RING_SKIP else None
    log.debug(
        "margin under %d-%d x %d-%d: down %d, up %s, sides %s",
        left,
        right,
        top,
        bottom,
        down,
        up,
        out,
    )
    if up is None:
        return None
    return (
        bottom + RING_SKIP + down,
        top - RING_SKIP - up,
        left - RING_SKIP - out[0],
        right + RING_SKIP + out[1],
    )


#: How far above a print's found top (a share of the found face's height) the frame's
#: top is sought along its side margins.
FOOT_FRAME_REACH = 0.8
#: Rows in a row without the margin's colour that end its run up a frame's side.
FOOT_FRAME_GAP = 3
#: A row shows the margin where some pixel between the face's edge and the found side is
#: within this (Lab) of the margin's colour (the nearest of many: tighter than RING_AGREE).
FOOT_FRAME_AGREE = 10.0


def _margin_run_up(
    part: npt.NDArray[Any], ring: npt.NDArray[np.float32], agree: float | None = None
) -> int | None:
    """How many rows a frame's side margin of colour ``ring`` runs up ``part`` (rows x
    columns x Lab, read from its last row up; on each row some pixel within ``agree``,
    FOOT_FRAME_AGREE unless told): it ends at the first FOOT_FRAME_GAP rows in a row
    without it. None when it never ends (the colour runs on up past ``part``)."""
    rows = np.asarray(part, np.float32)
    near = row_norms((rows - ring).reshape(-1, 3)).reshape(rows.shape[:2]).min(axis=1)
    margin = (near <= (FOOT_FRAME_AGREE if agree is None else agree))[::-1]
    miss = np.convolve(~margin, np.ones(FOOT_FRAME_GAP, int), mode="valid") >= FOOT_FRAME_GAP
    return int(np.argmax(miss)) if miss.any() else None


#: Whether :func:`enclose_from_foot` reads the lower margin's colour past the print's
#: blurred edge (the row farthest from the print's colour within RING_BLUR rows).
FOOT_RING_PAST_BLUR = True


def enclose_from_foot(
    image: npt.NDArray[Any] | None,
    view: View,
    bottom: int,
    top: int,
    left: int,
    right: int,
    foot_rows: tuple[int, int],
) -> tuple[int, int, int, int] | None:
    """A print found instead of the face, its found top and sides rows and columns inside
    the print (a colour or texture walk stopped on the print's own pattern), so that no
    margin shows above or beside it for :func:`enclose_by_ring`.

    With the rig the face's foot is known: under the print, its margin runs down to a foot
    in the band of floor-contact rows ``foot_rows`` (a colour unlike the print's and the
    floor's). The face is one surface standing there: along that lower margin its colour
    runs out past the found sides to the face's (ending within a margin's reach: the room
    at another depth beyond), and up the face's edges, just inside them, the same colour
    runs up past the found top to the face's top (the frame's side margins). Returns the
    frame (bottom, top, left, right) or None."""
    if image is None or image.ndim != 3 or right - left < 10 or bottom - top < 10:
        return None
    h, w = view.out.shape
    reach_u = int(MAX_MARGIN_SHARE * (right - left)) + RING_SKIP + 3
    reach_up = int((1.0 + FOOT_FRAME_REACH) * (bottom - top))
    r0, r1 = top - int(FOOT_FRAME_REACH * (bottom - top)) - 4, min(h, foot_rows[1] + 4)
    c0, c1 = left - reach_u - 1, right + reach_u + 2
    if r0 < 0 or c0 < 0 or c1 > w or r1 <= bottom + 4:
        return None
    q_u = max(2, (right - left) // 10)
    cm = (left + right) // 2
    k_v = max(1, (bottom - top) // 5)
    lab = _lab8(image, view, r0, r1, c0, c1)
    t, b, lf, rt = top - r0, bottom - r0, left - c0, right - c0
    mid = lab[:, cm - q_u - c0 : cm + q_u + 1 - c0]
    print_colour = median_u8(mid[t + k_v : b - k_v].reshape(-1, 3), axis=0)
    rows = np.asarray(median_u8(mid, axis=1), np.float32)
    below = rows[b + RING_SKIP :]
    ring = median_of(below[:2], axis=0)
    if FOOT_RING_PAST_BLUR:
        # the found foot may lie on the print's blurred edge: the rows just under it are
        # between the print's colour and the margin's; the margin's own is the farthest
        # from the print's within the blur's rows
        far = row_norms(below[:RING_BLUR] - np.asarray(print_colour, np.float32))
        ring = below[int(np.argmax(far))]
    if norm(ring - print_colour) < MARGIN_VS_PRINT:
        return None
    down = _ring_run(below, ring, below.shape[0])
    new_bottom = bottom + RING_SKIP + down
    if down < 1 or not foot_rows[0] <= new_bottom <= foot_rows[1]:
        return None
    # along the lower margin, out past the found sides
    strip = np.asarray(median_u8(lab[b + RING_SKIP : b + RING_SKIP + down], axis=0), np.float32)
    out = []
    for profile in (strip[lf::-1], strip[rt:]):
        run = _ring_run(profile, ring, reach_u + 1)
        if run < 0:
            return None  # the colour runs on along the foot: a floor's band, no frame
        out.append(run)
    if min(out) < 2:
        return None  # no margin past the print on both sides: the face's own foot
    new_left, new_right = left - out[0], right + out[1]
    # up the frame's side margins: on each row, somewhere between the face's edge and the
    # found side (the print's side is not known: the found one may be inside it)
    tops = []
    for lo, hi in ((new_left, left), (right + 1, new_right + 1)):
        up = _margin_run_up(lab[: new_bottom - r0, lo - c0 : hi - c0], ring)
        if up is None or up >= reach_up:
            return None  # the colour runs on up: a wall of it, no frame
        tops.append(new_bottom - up)
    new_top = max(tops)
    if new_top >= top or abs(tops[0] - tops[1]) > max(2, (bottom - top) // 10):
        return None  # the frame's top stands above the print's, level across the face
    return new_bottom, new_top, new_left, new_right


#: Rows of a print's lower half read for the margin beside it (a share of its height).
BESIDE_ROWS_SHARE = 0.5
#: Whether a margin beside a print must differ from the floor under it (beside the foot):
#: the floor seen past a face's sides is no margin of it.
BESIDE_NOT_FLOOR = True
#: ... by at least this (Lab): frames 24-111 from the floor under them on our rooms, the
#: floor seen beside a face 3-4 (procedural/2153 hard).
BESIDE_FLOOR_APART = 12.0


def enclose_beside_foot(
    image: npt.NDArray[Any] | None,
    view: View,
    bottom: int,
    top: int,
    left: int,
    right: int,
    foot_rows: tuple[int, int],
) -> tuple[int, int, int, int] | None:
    """A print found instead of the face, its found foot the face's own (no margin shows
    under it: a margin of a pixel or two, or none), its sides and top inside the print.

    With the rig the face's foot is known: the found foot in the band of floor-contact
    rows ``foot_rows``, the floor under it. The face is one surface standing there: beside
    the print's lower half, on both sides, a margin of one colour (unlike the print's and
    the floor's) runs out from the found sides to the face's edges (ending within a
    margin's reach: the room at another depth beyond), and up the face's edges, just
    inside them, the same colour runs up past the found top to the face's top (the frame's
    side margins, as in :func:`enclose_from_foot`). Returns the frame (bottom, top, left,
    right) or None."""
    if image is None or image.ndim != 3 or right - left < 10 or bottom - top < 10:
        return None
    if not foot_rows[0] <= bottom <= foot_rows[1]:
        return None
    h, w = view.out.shape
    reach_u = int(MAX_MARGIN_SHARE * (right - left)) + RING_SKIP + 3
    reach_up = int((1.0 + FOOT_FRAME_REACH) * (bottom - top))
    r0, r1 = top - int(FOOT_FRAME_REACH * (bottom - top)) - 4, min(h, bottom + 9)
    c0, c1 = left - reach_u - 1, right + reach_u + 2
    if r0 < 0 or c0 < 0 or c1 > w or r1 <= bottom + 4:
        return None
    q_u = max(2, (right - left) // 10)
    cm = (left + right) // 2
    k_v = max(1, (bottom - top) // 5)
    lab = _lab8(image, view, r0, r1, c0, c1)
    t, b, lf, rt = top - r0, bottom - r0, left - c0, right - c0
    mid = lab[:, cm - q_u - c0 : cm + q_u + 1 - c0]
    print_colour = np.asarray(median_u8(mid[t + k_v : b - k_v].reshape(-1, 3), axis=0), np.float32)
    floor = np.asarray(median_u8(mid[b + 2 : b + 5].reshape(-1, 3), axis=0), np.float32)
    # the colours beside the print, over its lower half (above the foot's blur)
    lo = b - max(2, int(BESIDE_ROWS_SHARE * (bottom - top)))
    strip = np.asarray(median_u8(lab[lo : b - 1], axis=0), np.float32)
    # outward from each found side: the print's colour may run on a way (a texture walk
    # stopped short of a fainter end of it), then the margin's
    profiles = (strip[lf - RING_SKIP :: -1], strip[rt + RING_SKIP :])
    starts, seeds = [], []
    for profile in profiles:
        off = row_norms(profile[: (right - left) // 2] - print_colour) > MARGIN_VS_PRINT
        if not off.any():
            return None
        p = int(np.argmax(off))
        starts.append(p)
        seeds.append(profile[min(p + 1, profile.shape[0] - 1)])
    if norm(seeds[0] - seeds[1]) > RING_AGREE:
        return None  # no one colour beside the print on both sides
    ring = (seeds[0] + seeds[1]) / 2.0
    if norm(ring - print_colour) < MARGIN_VS_PRINT or norm(ring - floor) < MARGIN_VS_PRINT:
        return None  # the print's own colour, or the floor's beside it: no margin
    out = []
    for profile, p in zip(profiles, starts, strict=True):
        # the margin must end within the window (past it: a wall of that colour)
        run = _ring_run(profile[p:], ring, min(reach_u + 1, profile.shape[0] - p))
        if run < 2:
            return None  # the colour runs on (a wall of it), or no margin past the side
        out.append(p + run)
    new_left, new_right = left - RING_SKIP - out[0], right + RING_SKIP + out[1]
    if BESIDE_NOT_FLOOR:
        # the margin is the face's, standing on the foot: under it (beside the foot) the
        # floor; the floor's own colour there is the floor seen beside the face
        for c_lo, c_hi in ((new_left, left - RING_SKIP), (right + RING_SKIP + 1, new_right + 1)):
            under = median_u8(lab[b + 3 : b + 8, c_lo - c0 : c_hi - c0].reshape(-1, 3), axis=0)
            if norm(np.asarray(under, np.float32) - ring) < BESIDE_FLOOR_APART:
                return None
    # up the frame's side margins, as enclose_from_foot reads them
    tops = []
    for c_lo, c_hi in ((new_left, left), (right + 1, new_right + 1)):
        up = _margin_run_up(lab[:b, c_lo - c0 : c_hi - c0], ring)
        if up is None or up >= reach_up:
            return None  # the colour runs on up: a wall of it, no frame
        tops.append(bottom - up)
    new_top = max(tops)
    if new_top >= top + k_v or abs(tops[0] - tops[1]) > max(2, (bottom - top) // 10):
        return None  # the frame's top level across the face, not far under the print's
    return bottom, min(new_top, top), new_left, new_right


#: A frame's side margin read this share of the face's width in from each of its sides.
FRAME_SIDE_SHARE = 0.1
#: The frame's top level across the face: its two sides' tops within this many rows, or
#: the face's height (from its foot to the frame's top closed, with ``window``) over
#: FRAME_LEVEL_SHARE.
FRAME_LEVEL_MIN_PX = 2
FRAME_LEVEL_SHARE = 20
#: ... and runs up the sides from the print's lower edge at least this share of the height
#: between the face's foot and the top found above the frame.
FRAME_MIN_SHARE = 0.3


def frame_top_by_margin(
    image: npt.NDArray[Any] | None,
    view: View,
    print_bottom: int,
    foot: int,
    top: int,
    left: int,
    right: int,
    window: bool = False,
) -> int | None:
    """The top of a frame round a print, the face (``left``..``right``, its foot
    ``foot``) found round a print whose lower edge is ``print_bottom``, its top ``top``
    found above the frame's (the sides run on up past the face into the background).

    The margin under the print has the face's own colour; it runs up both sides just
    inside the face's edges (the frame's side margins) to the face's top, and closes
    across it above the print: the face's top is where that colour ends going up both
    sides, level across the face, with the same colour just under it in the face's middle
    columns. Returns that row, or None (no frame closing there). ``window``: ``top`` is
    only how far up to read (the frame's rise is then weighed against the face it
    closes, not against ``foot - top``)."""
    if image is None or image.ndim != 3 or right - left < 10:
        return None
    h, w = view.out.shape
    r0, r1 = print_bottom + EDGE_SKIP, foot - 1
    if r1 - r0 < MARGIN_MIN_ROWS or top < 0 or foot - top < 10 or r1 > h:
        return None
    lab = _lab8(image, view, top, foot, left, right + 1)
    q = max(3, int(FRAME_SIDE_SHARE * (right - left)))
    ring = np.asarray(
        median_u8(lab[r0 - top : r1 - top, q : right - left - q].reshape(-1, 3), axis=0),
        np.float32,
    )
    tops = []
    far_in = right - left - RING_SKIP
    # (with ``window``, walked from the rail's top: a shadow at a corner of the foot may
    # darken the rail's end there)
    start = r0 + 1 if window else r1
    agree = FRAME_CLOSE_AGREE if window else None
    for lo, hi in ((RING_SKIP, q + RING_SKIP), (far_in - q, far_in)):
        up = _margin_run_up(lab[: start - top, lo:hi], ring, agree)
        if up is None:
            return None  # the colour runs on up past the top found: no frame's top below it
        tops.append(start - up)
    new_top = max(tops)
    height = foot - (new_top if window else top)  # the face's, as found or as closed
    if abs(tops[0] - tops[1]) > max(FRAME_LEVEL_MIN_PX, height // FRAME_LEVEL_SHARE):
        return None  # not level across the face
    if print_bottom - new_top < max(10, FRAME_MIN_SHARE * height):
        return None  # a band along the foot (a plinth, a shadow), no margin up the sides
    # inside the frame a print of another colour (a face of the margin's own colour with a
    # stripe across it is no frame: its top is no stripe's lower edge)
    cm = (right - left) // 2
    k = (print_bottom - new_top) // 4
    inside = lab[new_top - top + k : print_bottom - top - k, cm - q : cm + q + 1]
    print_colour = np.asarray(median_u8(inside.reshape(-1, 3), axis=0), np.float32)
    if norm(print_colour - ring) < MARGIN_VS_PRINT:
        return None
    # the frame closes above the print: the margin's colour across the middle under it
    under = lab[new_top - top + 1 : new_top - top + 1 + MARGIN_MIN_ROWS, cm - q : cm + q + 1]
    if under.size == 0:
        return None
    if norm(np.asarray(median_u8(under.reshape(-1, 3), axis=0), np.float32) - ring) > RING_AGREE:
        return None
    return new_top


#: A face's foot rows read for its frame's bottom rail colour (under the top found:
#: :func:`raise_top_to_frame`), clear of the foot edge's blur (EDGE_SKIP).
RAIL_SEED_ROWS = 2
#: The rail (rows up from the foot, the middle half's median within RING_AGREE of its
#: colour) at most this share of the face's width high: a frame's rail, not the face.
RAIL_MAX_SHARE = MAX_MARGIN_SHARE
#: A side margin's pixel is the rail's colour within this (Lab) on the way up to the
#: frame's top (the frame's paint shaded along a side: a shadow at one corner of the foot).
FRAME_CLOSE_AGREE = RING_AGREE
#: Rows under the frame's top read beside both sides for the room (not the frame's colour;
#: 0 reads none).
CLOSE_BESIDE_ROWS = 3
#: How far above the top found the frame's top is sought, metres at the face ...
FRAME_CLOSE_REACH_M = 1.0
#: ... at least this many rows (the image's top row may cut it shorter: then none).
CLOSE_MIN_REACH_ROWS = 10
#: A face narrower than this (columns), or with fewer rows than CLOSE_MIN_FACE_ROWS
#: between its top and foot, is too small to read a frame round.
CLOSE_MIN_WIDTH_PX = 10
CLOSE_MIN_FACE_ROWS = 4


def raise_top_to_frame(
    image: npt.NDArray[Any] | None,
    view: View,
    bottom: int,
    top: int,
    left: int,
    right: int,
    depth_m: float,
) -> int:
    """The top of a framed print's face, found under the frame's top (the search's top a
    row of the print, or the print's lower edge over the frame's bottom rail).

    A print lies inside the face: the face is the frame round it, whose bottom rail
    stands on the floor-contact row, and the frame's side margins (the rail's colour)
    run up both sides from it past the print to the frame's top, where the rail's colour
    closes across over the print (:func:`frame_top_by_margin`). The rail is read up from
    the foot over the face's middle half: rows whose median colour stays within
    RING_AGREE of the foot's, at most RAIL_MAX_SHARE of the width high. Returns that top
    where it lies above ``top``, else ``top``."""
    if (
        image is None
        or image.ndim != 3
        or right - left < CLOSE_MIN_WIDTH_PX
        or bottom - top < CLOSE_MIN_FACE_ROWS
    ):
        return top
    seed_hi = bottom - EDGE_SKIP
    seed_lo = seed_hi - RAIL_SEED_ROWS
    if seed_lo <= top:
        return top
    reach = int(round(view.fy * FRAME_CLOSE_REACH_M / depth_m))
    r0 = max(0, top - reach)
    if top - r0 < CLOSE_MIN_REACH_ROWS:
        return top
    q = (right - left) // 4
    lab = _lab8(image, view, top, seed_hi, left + q, right - q + 1)
    rows = np.asarray(median_u8(lab, axis=1), np.float32)
    rail = median_of(rows[seed_lo - top :], axis=0)
    off = row_norms(rows - rail) > RING_AGREE
    j = seed_lo - top
    while j >= 0 and not off[j]:
        j -= 1
    print_bottom = top + j + 1  # the lowest row of the rail's colour under the print
    if bottom - print_bottom > RAIL_MAX_SHARE * (right - left):
        return top  # the face's own colour from the foot up: no rail, or no frame's
    closed = frame_top_by_margin(image, view, print_bottom, bottom, r0, left, right, window=True)
    if closed is None or closed >= top - EDGE_SKIP:
        return top
    # the frame's top is where its colour ends against the room: beside both sides, just
    # under that row, the room shows (a wall stripe of the frame's colour right over it
    # carried the side margins' walk on up past the frame)
    # (the sides inside the image only; with neither in it the room is not seen, and the
    # frame's top is not taken)
    if CLOSE_BESIDE_ROWS > 0:
        w = view.out.shape[1]
        strips = (
            (left - SIDE_SKIP - BESIDE_COLUMNS, left - SIDE_SKIP),
            (right + SIDE_SKIP + 1, right + SIDE_SKIP + BESIDE_COLUMNS + 1),
        )
        inside = [(a, b) for a, b in strips if a >= 0 and b <= w]
        if not inside:
            return top
        if all(
            norm(
                np.asarray(
                    median_u8(
                        _lab8(image, view, closed, closed + CLOSE_BESIDE_ROWS, a, b).reshape(-1, 3),
                        axis=0,
                    ),
                    np.float32,
                )
                - rail
            )
            <= FRAME_CLOSE_AGREE
            for a, b in inside
        ):
            return top
    return closed


#: Half the beam's core sampled for the face's colour at its foot, metres at the face.
CORE_HALF_M = 0.03
#: Rows either side of a contact row read for the face (above) and the floor (below).
CONTACT_ROWS = 5
#: Rows above the contact row taken as the face before its top is sought (enough for a
#: brick course, so that the face's own spread of colour is known).
SEED_ROWS = 24
#: A colour face needs a foot this distinct from the floor (Lab) for full evidence.
FULL_FOOT_STEP = 40.0
#: ... and sides this distinct from what stands beside it.
FULL_SIDE_STEP = 30.0


#: The colour face's sides, walked along its foot from the beam's core, stop at the face's
#: shadow on the floor: a foot whose colour is the floor's lit less (``shadow_columns``: at
#: least SHADOW_DARKER darker, its chroma the floor's scaled by the lightness ratio, on a
#: floor of SHADOW_FLOOR_CHROMA or more) lies on the floor, not on the face, where the
#: face's own colour is no such shade of the floor (the core walk reads no floor chroma
#: else: a tape's or a label's colour in the core may be the floor's).
CORE_SHADOW_FOOT = True
#: ... a shade keeping at least this share of the floor's lightness (Lab L, 8-bit): the
#: room's diffuse light still reaches the floor in a box's shadow (shadows read on the
#: rooms 0.6-0.85 of the floor's L); a foot darker than that is no shade the hue test can
#: tell from a dark print's part (photo/2034 hard: a black helmet on a poster's foot over
#: a dark blue floor, 0.31-0.43, read as the floor's shade, h 0.4 -> -68 %; photo/3089
#: hard with the rig, h -51.6 -> -74.6 %, without this bound).
CORE_SHADOW_LIGHT = 0.5
CORE_SHADOW_NO_RIG = False


#: The colour face's sides, walked along its foot from the beam's core, rise as the face's
#: up to its top (:func:`sides_rising` from the core's columns; the top read again between
#: the sides kept): a shadow or a dark band along the foot lies on the floor or behind.
#: With no rig only (``clip`` False): with the rig a print's piece walked from the core is
#: grown to the face round it (enclose_from_foot, the foot outline) from the walk's width,
#: and the rising check, reading the print's pattern, cut it (photo/746 hard 4 -> 82 %).
#: Session 36 (wt-a-36b): photo/136 ordinary no rig 46 -> 2.5 %, 2057 hard 35 -> 17 %;
#: fresh photo/2167 ordinary no rig 75 -> 0.4 %. A switch for the tests.
CORE_WALK_RISES = True

#: With the rig, a colour face whose walk up from the foot stops at once is tried again
#: with its sides moved to the strong colour steps next to them (:func:`snap_sides_to_steps`,
#: within SNAP_SIDE_M) (session 47, branch ``wt-d-47``, a switch): the foot's colour run
#: from the beam's core (no chroma read) runs a few columns on past a grey face's side
#: over floor of about its grey seen beside it, or its shadow, so the strip just inside
#: that side is background up the face's whole height and the walk reads no face; the
#: face is one surface standing on the predicted row, its side the strong colour step a
#: few columns in (photo 3363 hard: a grey text print on grey paving, 172-342 for
#: 172-336, h -75 -> -0.1 %; photo 3259 hard -26 -> +0.5 %). With the rig or a no-rig
#: row read as with one (``clip``) only: rows merely tried with no rig are left as they
#: were (CORE_WALK_RISES reads the sides there).
COLOUR_SIDES_SNAP_RETRY = True


def face_from_colour(
    image: npt.NDArray[Any] | None,
    view: View,
    ax: npt.NDArray[np.int16],
    ay: npt.NDArray[np.float32],
    rows: tuple[int, int],
    depth_m: float,
    clip: bool = True,
) -> tuple[int, int, int, int, float] | None:
    """A face found by its colour alone, where the edges found none: (contact row, top row,
    left, right, evidence 0..1) in the levelled view, or None.

    The sonar says something stands at this depth, and the rig where its foot meets the
    floor (``rows``: the band of likely contact rows). Just above that row, in the beam's
    core, is the face; just below, the floor. The contact row is where that colour step
    is largest; the face runs along its foot as far as its colour does (as in
    :func:`widen_by_colour`), and up as far as :func:`raise_top_by_colour` follows it.
    Faces whose texture drowns their edges (a brick pattern's joints) are found so."""
    if image is None or image.ndim != 3:
        return None
    h, w = view.out.shape
    r0, r1 = rows
    core = max(2, int(round(view.fx * CORE_HALF_M / depth_m)))
    c0, c1 = int(view.cx) - core, int(view.cx) + core + 1
    # a band running past the image's foot (a near box low in the view) is searched over
    # the rows that leave the floor below them in view (``clip``; with the rig only: with
    # none, a band low in the view is one of many rows tried, the face found by colour
    # there outbid the rows whose sides confirm it)
    if clip:
        r1 = min(r1, h - CONTACT_ROWS - 3)
    lo, hi = r0 - CONTACT_ROWS - 2, r1 + CONTACT_ROWS + 3
    if lo < 0 or r1 < r0 or hi > h or c0 < 0 or c1 > w:
        return None
    prof = median_u8(_lab8(image, view, lo, hi, c0, c1), axis=1)  # per row
    best_step, contact = 0.0, -1
    for r in range(r0, r1 + 1):
        i = r - lo
        above = median_of(prof[i - CONTACT_ROWS - 1 : i - 1], axis=0)
        below = median_of(prof[i + 2 : i + CONTACT_ROWS + 2], axis=0)
        step = norm(above - below)
        if step > best_step:
            best_step, contact = step, r
    if contact < 0 or best_step < MIN_FLOOR_STEP or contact - SEED_ROWS < 3:
        return None  # no step, or no room above it for a face (a tiny or tilted frame)
    # sides: the foot's colour run from the core, as wide as the face's colour goes
    left, right = widen_by_colour(
        image,
        view,
        ax,
        contact,
        contact - 4 * CONTACT_ROWS,
        c0,
        c1,
        depth_m,
        chroma=False,
        shadow=clip or CORE_SHADOW_NO_RIG,
    )
    if right - left < 2 * SIDE_SKIP + 6:
        return None
    start = contact - SEED_ROWS

    def walk_up(sides: tuple[int, int]) -> int:
        # the face's top walked up by its colour from the made-up start between ``sides``
        return raise_top_by_colour(
            image, view, ay, contact, start, *sides, depth_m, start, one_side=True
        )

    top = walk_up((left, right))
    if top >= start and COLOUR_SIDES_SNAP_RETRY and clip:
        # the foot's colour run took the face's shadow (or a strip of floor) in beside it
        # (shadow=True): the rows above it read that side's columns as background, so the
        # walk up stops at once; the face's real sides are the strong colour steps next
        # to the run's ends (snap_sides_to_steps, as the rescue snaps them afterwards); the
        # face is taken with them where its colour now runs up
        snapped = snap_sides_to_steps(image, view, contact, start, left, right, depth_m)
        if snapped != (left, right):
            again = walk_up(snapped)
            log.debug("colour face %d-%d: snapped to %d-%d, top %d", left, right, *snapped, again)
            # (a walk that stops at once again ends in the no-face return below all the same)
            (left, right), top = snapped, again
    if top >= start:
        return None  # the face's colour does not run up: no face shape
    if CORE_WALK_RISES and not clip:
        risen = sides_rising(image, view, ax, contact, top, (c0, c1), (left, right))
        if risen != (left, right):
            log.debug("colour face %d-%d: sides rising %d-%d", left, right, *risen)
            left, right = risen
            top = walk_up(risen)
            if top >= start:
                return None
    side_step = _side_step(image, view, contact, top, left, right)
    evidence = min(1.0, best_step / FULL_FOOT_STEP) * min(1.0, side_step / FULL_SIDE_STEP)
    return contact, top, left, right, evidence


#: How far (metres at the face) the colour rescue's sides may move to the strongest
#: vertical colour step near them (:func:`snap_sides_to_steps`).
SNAP_SIDE_M = 0.03
#: ... and at least this colour step (Lab, across SNAP_SPAN columns) there.
SNAP_MIN_STEP = 15.0
#: Columns either side of a column over which its vertical colour step is read.
SNAP_SPAN = 2


def snap_sides_to_steps(
    image: npt.NDArray[Any] | None,
    view: View,
    bottom: int,
    top: int,
    left: int,
    right: int,
    depth_m: float,
) -> tuple[int, int]:
    """The colour rescue's sides moved to the strongest vertical colour step within
    SNAP_SIDE_M of each (left, right).

    The foot's colour run ends where the colour stops being the face's by a share of the
    way to the floor's: a face of about the floor's shade in grey casts a shadow on the
    floor beside it, darker than the floor, that the run takes in, so a side lies a few
    pixels out, on the floor. The strip just inside it is then floor, and the sides' walk
    up (:func:`raise_top_by_sides`) finds no side at once. The face's real side is the
    colour step nearby, stronger than the shadow's soft edge."""
    if image is None or image.ndim != 3 or bottom - top < 4:
        return left, right
    w = view.out.shape[1]
    reach = max(2, int(round(view.fx * SNAP_SIDE_M / depth_m)))
    reach = min(reach, (right - left) // 4)
    c0, c1 = left - reach - SNAP_SPAN, right + reach + SNAP_SPAN + 1
    if reach < 1 or c0 < 0 or c1 > w:
        return left, right
    r1 = bottom - 2
    r0 = max(top, r1 - max(8, (bottom - top) // 2))
    prof = median_u8(_lab8(image, view, r0, r1, c0, c1), axis=0).astype(np.float32)
    step = np.zeros(prof.shape[0], np.float32)
    step[SNAP_SPAN:-SNAP_SPAN] = row_norms(prof[2 * SNAP_SPAN :] - prof[: -2 * SNAP_SPAN])
    out = []
    for side in (left, right):
        i = side - c0
        window = step[i - reach : i + reach + 1]
        j = int(np.argmax(window))
        # a side on a step already stays (a brick's joints beside it are steps too)
        weak = float(step[i - 1 : i + 2].max()) < SNAP_MIN_STEP
        out.append(side - reach + j if weak and float(window[j]) >= SNAP_MIN_STEP else side)
    nl, nr = out
    if nr - nl < 2 * SIDE_SKIP + 6:
        return left, right
    return nl, nr


def _side_step(
    image: npt.NDArray[Any], view: View, bottom: int, top: int, left: int, right: int
) -> float:
    """The weaker side's colour step: the face just inside against what is just beside
    (a side with no room beside it in the view, at the image's border, is not read; with
    neither side read, 0)."""
    w = view.out.shape[1]
    r0, r1 = top + (bottom - top) // 4, bottom - (bottom - top) // 4
    if r1 - r0 < 2:
        return 0.0
    steps = []
    for a, b, c, d in (
        (left + 2, left + 2 + BESIDE_COLUMNS, left - 2 - BESIDE_COLUMNS, left - 2),
        (right - 2 - BESIDE_COLUMNS, right - 2, right + 3, right + 3 + BESIDE_COLUMNS),
    ):
        if c < 0 or d > w:
            continue
        inside = median_u8(_lab8(image, view, r0, r1, a, b).reshape(-1, 3), axis=0)
        beside = median_u8(_lab8(image, view, r0, r1, c, d).reshape(-1, 3), axis=0)
        steps.append(norm(inside - beside))
    return min(steps, default=0.0)


#: Sides with a colour step under this (Lab, the face just inside against what is just
#: beside) scale the confidence down in proportion.
SIDE_STEP_FULL = 12.0


def side_agreement(
    image: npt.NDArray[Any] | None, view: View, bottom: int, top: int, left: int, right: int
) -> float:
    """0..1: how clearly the face's colour ends at its weaker side (a seam inside the face
    or a shadow beside it is no colour step)."""
    if image is None or image.ndim != 3 or bottom - top < 8:
        return 1.0
    return min(1.0, _side_step(image, view, bottom, top, left, right) / SIDE_STEP_FULL)


#: The margin under a print: a column is the margin's while its colour is within this
#: share of the margin's step from what lies beside the face (8-bit Lab distance) ...
MARGIN_SHARE = 0.5
#: ... and the margin must step at least this much from what is beside it.
MARGIN_MIN_STEP = 12.0
#: Columns of another colour the walk along the margin crosses (a seam, a fleck).
MARGIN_GAP = 2
#: Rows of the margin that must show clear of the blur of the print's lower edge and of
#: the foot (a face found whole, standing a little above the predicted row, has only the
#: two edges' blur tails between them).
MARGIN_MIN_ROWS = 2


#: The margin's sides come in too (:func:`widen_along_margin`): where the margin's run from
#: the middle of the piece found ends over MARGIN_IN_MIN_SHARE of the pair's width (and
#: SNAP_COLUMNS) inside a side, and the columns from there to that side show, in the
#: margin's rows, the floor just under the foot (the median over them within
#: MARGIN_IN_FLOOR, Lab): nothing stands on the contact row there, the floor runs on up
#: past it, so what the side stands on is farther back (a can or a frame beside the face
#: whose foot meets the floor higher up, its edge taken for the side). The face's side is
#: where its margin ends.
MARGIN_SIDES_IN = True
MARGIN_IN_MIN_SHARE = 0.1
MARGIN_IN_FLOOR = 12.0
#: ... and at least this share of those columns off the margin's colour (a seam across
#: the margin ends its run, the margin resumes past it: procedural/2090 hard, a face of
#: the floor's colour whose seam stopped the run, cut to its left part without it).
MARGIN_IN_OFF_SHARE = 0.7
#: Rows read under the foot for the floor (EDGE_SKIP clear of the foot's blur).
MARGIN_IN_FLOOR_ROWS = FLOOR_BAND_ROWS


def _margin_side_in(
    image: npt.NDArray[Any],
    view: View,
    cols: npt.NDArray[np.float32],
    dist: npt.NDArray[np.float32],
    c0: int,
    foot: int,
    left: int,
    right: int,
) -> tuple[int, int]:
    """(left, right) of :func:`widen_along_margin`'s pair, each brought in to where the
    margin's run from the pair's middle ends when the floor shows from there to the side
    (MARGIN_SIDES_IN); ``cols`` the margin rows' column colours from column ``c0``,
    ``dist`` their distance from the margin's colour."""
    g0 = foot + EDGE_SKIP + 1  # clear of the foot's blur, as every other floor reader
    g1 = min(g0 + MARGIN_IN_FLOOR_ROWS, view.out.shape[0])
    if g1 - g0 < 2:
        return left, right
    on = (dist <= MARGIN_MIN_STEP).tolist()
    mid = (left + right) // 2 - c0
    if not on[mid]:
        return left, right
    min_move = max(SNAP_COLUMNS, MARGIN_IN_MIN_SHARE * (right - left))
    out = []
    for side, step in ((left, -1), (right, 1)):
        end = walk_on(on, mid, step, MARGIN_GAP) + c0
        if (side - end) * step <= min_move:
            out.append(side)
            continue
        a, b = sorted((end + step * (MARGIN_GAP + 1), side))
        if b - a < SNAP_COLUMNS:
            out.append(side)
            continue
        if share(~np.asarray(on[a - c0 : b - c0 + 1])) < MARGIN_IN_OFF_SHARE:
            out.append(side)  # the margin resumes past a seam: its end is no side
            continue
        below = _band(image, view, g0, g1, a, b + 1)
        floor = median_of(below.reshape(-1, 3), axis=0)
        seen = median_of(cols[a - c0 : b - c0 + 1], axis=0)
        if float(norm(seen - floor)) > MARGIN_IN_FLOOR:
            out.append(side)
            continue
        log.debug("margin: side %d in to %d, the floor runs on past the foot beyond", side, end)
        out.append(end)
    return out[0], out[1]


def widen_along_margin(
    image: npt.NDArray[Any] | None,
    view: View,
    print_bottom: int,
    foot: int,
    left: int,
    right: int,
    reach: int,
    far: int = 0,
) -> tuple[int, int] | None:
    """The face's sides round a print, walked along the margin under it.

    A print standing above the floor-contact row leaves a strip of the face's own colour
    between its lower edge and the foot; that strip runs out past the print's sides to the
    face's own sides, where what stands beside the face (the floor behind it, the wall)
    starts. Returns the new sides, or None where no margin of one colour shows there.
    ``far`` (> ``reach``): where the margin still runs on ``reach`` beyond a side (the
    piece found is a small part of the print, the print's own lower edge), it is followed
    on up to ``far`` columns to where it ends at a step to what is beside the face."""
    if image is None or image.ndim != 3 or right - left < 6:
        return None
    r0, r1 = print_bottom + EDGE_SKIP, foot - 1
    # a thinner strip only where it runs on far past the piece found (the blur tails of a
    # face's own foot and the floor's edge under it do not end in a step on both sides)
    thin = r1 - r0 < MARGIN_MIN_ROWS
    if r1 - r0 < (MARGIN_MIN_ROWS if far <= reach else MARGIN_MIN_ROWS - 1):
        return None
    w = view.out.shape[1]
    span = max(reach, far)
    c0, c1 = max(0, left - span - SMOOTH_COLUMNS), min(w, right + span + SMOOTH_COLUMNS + 1)
    lab = _lab8(image, view, r0, r1, c0, c1)
    cols = cv2.blur(median_u8(lab, axis=0)[None], (3, 1))[0].astype(np.float32)
    inner = cols[left - c0 + 1 : right - c0]
    margin = np.median(inner, axis=0)
    dist = np.sqrt(((cols - margin) ** 2).sum(axis=1))
    if float(np.median(dist[left - c0 + 1 : right - c0])) > MARGIN_MIN_STEP:
        return None  # under the print: no one colour
    new = []
    followed = False
    for side, step in ((left, -1), (right, 1)):
        out = side - c0 + step * (reach + 1)
        out = int(clamp(out, 0, cols.shape[0] - 1))
        beside = float(dist[out])
        limit = reach
        if beside < MARGIN_MIN_STEP and far > reach:
            # the margin runs on past the reach: follow it to its end, the step beyond
            limit, followed = far, True
            run = walk_on(dist < MARGIN_MIN_STEP, side - c0, step, MARGIN_GAP)
            if abs(run - (side - c0)) <= far:
                last = cols.shape[0] - 1
                a = int(clamp(run + step * (MARGIN_GAP + 1), 0, last))
                b = int(clamp(run + step * (MARGIN_GAP + 1 + SMOOTH_COLUMNS), 0, last))
                beside = float(np.median(dist[min(a, b) : max(a, b) + 1]))
        if beside < MARGIN_MIN_STEP:
            return None  # no step from the margin to what is beside the face
        on = dist <= MARGIN_SHARE * beside
        end = walk_on(on, side - c0, step, MARGIN_GAP)
        new.append(int(clamp(end + c0, left - limit, right + limit)))
    if thin and not followed:
        return None
    if MARGIN_SIDES_IN:
        in_left, in_right = _margin_side_in(image, view, cols, dist, c0, foot, left, right)
        if in_left > left:
            new[0] = in_left
        if in_right < right:
            new[1] = in_right
    return new[0], new[1]


#: Rows at the view's foot read for the colour of a face whose foot lies below the view.
PAST_FOOT_ROWS = 8
#: ... starting this many rows above the view's last row (its last rows repeat the
#: image's border where the levelled view reads past it).
PAST_FOOT_SKIP = 3


def face_past_foot(
    image: npt.NDArray[Any] | None,
    view: View,
    ay: npt.NDArray[np.float32],
    depth_m: float,
) -> tuple[int, int, int, int, float] | None:
    """A face whose foot lies below the view (the rig puts its floor-contact row there):
    (bottom row read, top row, left, right, evidence 0..1) in the levelled view, or None.

    Between the face's top and the view's foot nothing nearer than the face shows in the
    beam's core (the floor there lies behind the face), so the rows at the view's foot in
    the core are the face. Its sides are where that colour along the view's foot ends (a
    side may run off the view); its top where :func:`raise_top_by_colour` and
    :func:`raise_top_by_sides` end it. The evidence is the sides' colour step (those with
    room beside them in the view) times the top's agreement."""
    if image is None or image.ndim != 3:
        return None
    h, w = view.out.shape
    bottom = min(h, ay.shape[0]) - PAST_FOOT_SKIP
    r0 = bottom - PAST_FOOT_ROWS
    core = max(2, int(round(view.fx * CORE_HALF_M / depth_m)))
    c0, c1 = int(view.cx) - core, int(view.cx) + core + 1
    if r0 - SEED_ROWS < 3 or c0 < 0 or c1 > w:
        return None
    lab = _lab8(image, view, r0, bottom)
    cols = cv2.blur(median_u8(lab, axis=0)[None], (SMOOTH_COLUMNS, 1))[0]
    ref = median_of(cols[c0:c1], axis=0)
    d_face = row_norms(cols - ref)
    limit = spread_limit(d_face[c0:c1], MIN_FACE_DISTANCE)
    on = (d_face <= limit).tolist()
    max_gap = max(2, int(round(view.fx * MAX_GAP_M / depth_m))) + SMOOTH_COLUMNS - 1
    centre = (c0 + c1) // 2
    left, right = walk_on(on, centre, -1, max_gap), walk_on(on, centre, 1, max_gap)
    if right - left < 2 * SIDE_SKIP + 6:
        return None
    start = r0 - SEED_ROWS
    top = raise_top_by_colour(
        image, view, ay, bottom, start, left, right, depth_m, start, one_side=True
    )
    if top >= start:
        return None  # the colour does not run up: no face shape
    top = raise_top_by_sides(image, view, ay, bottom, top, left, right, depth_m, one_side=True)
    side_step = _side_step(image, view, bottom, top, left, right)
    evidence = min(1.0, side_step / FULL_SIDE_STEP) * top_agreement(image, view, top, left, right)
    return bottom, top, left, right, evidence


#: A print's outline (:func:`raise_top_by_outline`): the side rows read from the top up
#: to this many metres at the face (as SIDE_WALK_REACH_M: a face is seldom taller).
OUTLINE_REACH_M = 1.0
#: ... a side stands where what is just inside it differs from what is just outside by
#: at least this (Lab; MIN_BESIDE_STEP, the sides' walk's clear step) ...
OUTLINE_SIDE_STEP = 12.0
#: ... and above the top, the band between the sides is within this (Lab) of what is
#: beside them (the background closes over the print: a horizontal boundary).
OUTLINE_CLOSE_DISTANCE = 14.0
#: The outline's top at least this share of the face's height found above it (a few rows
#: up are a plain face's top blur or the brick, seam or plank joints of a face before
#: a background with edges in line: photo/108 ordinary 3 -> 20 % without it) ...
OUTLINE_MIN_RAISE = 0.5
#: ... with both sides standing in at least this share of the rows up to it (clutter's
#: edges beside the sides stand here and there: 0.2-0.7 of them on photo/2058, 2072 hard;
#: a print's outline 0.84-0.98) ...
OUTLINE_COVER = 0.8
#: ... and the raised part's median colour within this (Lab) of the face's under it: the
#: same print (13.6 on photo/731's cat, 2 on procedural/2046's blocks), not a thing of
#: another colour standing behind a plain face in line with its sides (43 on photo/2003's
#: rocket behind a pink face).
OUTLINE_SAME_PRINT = 25.0
#: Rows above the outline's end read for its closing band (a few: the background's
#: colour just over the top, as the blur leaves it).
OUTLINE_CLOSE_ROWS = 4


def raise_top_by_outline(
    image: npt.NDArray[Any] | None,
    view: View,
    ay: npt.NDArray[np.float32],
    bottom: int,
    top: int,
    left: int,
    right: int,
    depth_m: float,
) -> int:
    """The top of a print (a photograph, a drawn pattern covering the face): where both
    its sides end together and the background closes over it.

    A print changes its colour row by row, so walks that follow the face's colour up
    (along its middle or just inside its sides) stop at a row of the pattern. Its
    outline does not: each side parts the varied inside from the background beside it
    all the way up, and both end at the top, where the background runs across."""
    if image is None or image.ndim != 3 or right - left < 2 * SIDE_SKIP + 4 or bottom - top < 6:
        return top
    w_view = view.out.shape[1]
    c0, c1 = left - SIDE_SKIP - BESIDE_COLUMNS, right + SIDE_SKIP + BESIDE_COLUMNS + 1
    if c0 < 0 or c1 > w_view:
        return top
    reach = int(round(view.fy * OUTLINE_REACH_M / depth_m))
    r0 = max(0, top - reach)
    if top - r0 < OUTLINE_CLOSE_ROWS + 4:
        return top
    gap = max(2, int(round(view.fy * SIDE_WALK_GAP_M / depth_m)))
    band = _lab8(image, view, r0, top + 1, c0, c1).astype(np.float32)
    k = top - r0
    span = BESIDE_COLUMNS + SIDE_SKIP
    if band.shape[1] <= 4 * span:
        # no middle between the inside strips to read: nothing says it is one print
        return top
    lo_out = np.median(band[:, :BESIDE_COLUMNS], axis=1)
    lo_in = np.median(band[:, 2 * span - BESIDE_COLUMNS : 2 * span], axis=1)
    hi_in = np.median(band[:, -2 * span : -2 * span + BESIDE_COLUMNS], axis=1)
    hi_out = np.median(band[:, -BESIDE_COLUMNS:], axis=1)
    step_l = row_norms(lo_in - lo_out)
    step_r = row_norms(hi_in - hi_out)
    on = (step_l >= OUTLINE_SIDE_STEP) & (step_r >= OUTLINE_SIDE_STEP)
    end = walk_on(on.tolist(), k, -1, gap)
    if k - end <= SNAP_ROWS or end < OUTLINE_CLOSE_ROWS + 2:
        return top
    # a print's top far above where its pattern stopped the walks (a few rows up are
    # the blur of a plain face's top, or a joint)
    if k - end < OUTLINE_MIN_RAISE * (bottom - top):
        return top
    # both sides stand along the whole way up, not a clutter's edges here and there
    if float(on[end:k].mean()) < OUTLINE_COVER:
        return top
    # ... and so does the middle between them, the print's inside: a rail or a frame
    # behind a plain face in line with its sides shows the background between its posts
    middle_rows = np.median(band[end:k, 2 * span : -2 * span], axis=1)
    background = 0.5 * (lo_out[end:k] + hi_out[end:k])
    if float((row_norms(middle_rows - background) >= OUTLINE_SIDE_STEP).mean()) < OUTLINE_COVER:
        return top
    # the raised part is the same print as the face under it (its colours alike): not
    # another thing standing behind a plain face in line with its sides
    face = _lab8(image, view, top, bottom, left + SIDE_SKIP, right - SIDE_SKIP)
    raised = band[end:k, 2 * span : -2 * span]
    face_colour = np.median(face.reshape(-1, 3).astype(np.float32), axis=0)
    if norm(np.median(raised.reshape(-1, 3), axis=0) - face_colour) > OUTLINE_SAME_PRINT:
        return top
    # the background closes over the print: the band above between the sides is what
    # is beside them
    above = slice(end - OUTLINE_CLOSE_ROWS - 2, end - 2)
    middle = np.median(band[above, span:-span].reshape(-1, 3), axis=0)
    beside = np.concatenate([band[above, :BESIDE_COLUMNS], band[above, -BESIDE_COLUMNS:]], axis=1)
    outside = np.median(beside.reshape(-1, 3), axis=0)
    if norm(middle - outside) > OUTLINE_CLOSE_DISTANCE:
        return top
    return _snap_top_edge(ay, r0, end, k, left + SIDE_SKIP, right - SIDE_SKIP)


#: The face's colour (the median across its middle) holds down a row while within this
#: (Lab) of the colour over the found foot.
FACE_DOWN_AGREE = 15.0
#: Rows over the found foot read for the face's colour there.
FACE_DOWN_ROWS = 4


def face_down_to_foot(
    image: npt.NDArray[Any] | None,
    view: View,
    ay: npt.NDArray[np.float32],
    bottom: int,
    left: int,
    right: int,
    band: tuple[int, int],
    noise: float,
) -> int | None:
    """The foot in the floor-contact ``band`` (:func:`.extent.foot_in_band`, the strongest
    edge across the face under ``bottom``) when every row between holds the face's colour
    over the found foot, in each of its side quarters and its middle half: the face runs on
    down to the floor the rig predicts (its found foot a shading step on it). Rows next to
    the new foot (its edge's blur) are not read. None
    when no foot stands in the band or a row between is something else (a margin, a
    shadow, the floor)."""
    if image is None or image.ndim != 3 or right - left < 16 or bottom - FACE_DOWN_ROWS < 0:
        return None  # (16: each quarter a few columns)
    foot = foot_in_band(ay, bottom, left, right, band, noise)
    if foot is None or foot - bottom < 2:
        return None
    # the face's quarters at each side and its middle half, each on its own: a found face
    # wider than the one standing (the outline of things beside it) leaves the floor
    # under its outer parts
    q = (right - left) // 4
    lab = _lab8(image, view, bottom - FACE_DOWN_ROWS, foot - 1, left + 2, right - 1)
    for c0, c1 in ((0, q - 2), (q - 2, 3 * q - 2), (3 * q - 2, lab.shape[1])):
        rows = np.asarray(median_u8(lab[:, c0:c1], axis=1), np.float32)
        face = median_of(rows[:FACE_DOWN_ROWS], axis=0)
        between = rows[FACE_DOWN_ROWS:]
        if between.shape[0] == 0 or float(row_norms(between - face).max()) > FACE_DOWN_AGREE:
            return None
    return foot


#: The face's colour is read on its lower part: this share of its height over the foot
#: (past FOOT_BAND_ROWS[0] rows of the foot's blur), in the middle and in the strips just
#: inside each side (a print over the middle keeps a margin of the face's colour).
SURFACE_REF_SHARE = 0.35
#: Rows of the face's colour in a row (middle or a side strip within the face's spread
#: of its colour, spread_limit) that start its surface going down from the top.
SURFACE_RUN_ROWS = 3
#: The rows above the surface's first row, down from the top, are something else in at
#: least this share (a band across the face's upper part comes back to its colour: a
#: label, a tape) ...
SURFACE_FOREIGN_SHARE = 0.85
#: ... over at least this share of the height as found (shorter: a top face, a frame's
#: top margin, the top edge's blur).
SURFACE_MIN_DROP = 0.2
#: ... and the colour steps by this much (Lab, 8-bit) at the surface's first row, in the
#: middle and both strips (STEP_BAND_ROWS either side): an edge where one thing ends and
#: the face begins; a gloss's highlight or the light's fall-off up a face is a ramp
#: (procedural/106 ordinary, 148 and 2053 hard: steps 2-10, lowered 30-38 % without it).
SURFACE_STEP = TOP_COLOUR_STEP
#: The surface found is the face's only when its colour differs by this much from the
#: floor's just under the foot: a patch of floor between a wall band and a found foot is
#: no face standing on the floor.
SURFACE_FLOOR_APART = MIN_FACE_DISTANCE
#: On a face of one colour (its lower part within the least spread, MIN_FACE_DISTANCE, in
#: the middle and both strips, each against its own colour: no print's colours; planks of
#: two shades running up the face are so) a row holds the face's surface only where the
#: face's colours span it: in the middle, or in the strips just inside both sides. Such a
#: face shows its colours from side to side up to its top; one strip alone in it is the
#: background above the top matching that strip's shade by chance (photo 3311 hard: a dark
#: plank's shade in the launch pad's rows), no surface: it neither starts the surface nor
#: keeps the rows above it the face's. On a print the colours change row by row, and a
#: strip alone may be the print's own (photo 3334 hard: not applied there).
SURFACE_SPANS_FACE = True


def lower_top_to_surface(
    image: npt.NDArray[Any] | None,
    view: View,
    ay: npt.NDArray[np.float32],
    bottom: int,
    top: int,
    left: int,
    right: int,
) -> int:
    """The top moved down to the first row under it from which the face's own colour
    (read on its lower part) holds, where the rows from ``top`` down to it are something
    else in the middle and just inside both sides (SURFACE_FOREIGN_SHARE) and the colour
    steps there (SURFACE_STEP), snapped to the strongest top edge within SNAP_ROWS. A row
    holds the face's colour in the middle or in either strip; on a face of one colour (all
    three parts' limits at the least, MIN_FACE_DISTANCE) in the middle or in both strips
    (SURFACE_SPANS_FACE), for the start of the surface and the foreign share alike.

    The face is one surface standing on the floor: from its foot up to its top its colour
    holds, a print in a margin of it or a band across it aside. A top taken on a line of
    the background (a rocket photographed in line above a small face, a platform's edge,
    a wall band) has that background between it and the face's real top, from side to
    side, ending at an edge where the face begins."""
    h = bottom - top
    if image is None or image.ndim != 3 or right - left < 2 * (SIDE_SKIP + BESIDE_COLUMNS):
        return top
    f0 = FOOT_BAND_ROWS[0]
    ref_rows = max(SURFACE_RUN_ROWS + 1, int(SURFACE_REF_SHARE * h))
    if h < 4 * SURFACE_RUN_ROWS or ref_rows + f0 >= h:
        return top
    lab = _lab8(image, view, top, bottom, left + SIDE_SKIP, right - SIDE_SKIP + 1)
    parts = [
        np.asarray(median_u8(part, axis=1), np.float32)
        for part in (
            lab[:, BESIDE_COLUMNS:-BESIDE_COLUMNS:SUBSAMPLE],
            lab[:, :BESIDE_COLUMNS],
            lab[:, -BESIDE_COLUMNS:],
        )
    ]
    held = []
    refs = []
    limits = []
    for rows in parts:
        seed = rows[h - f0 - ref_rows : h - f0]
        ref = median_of(seed, axis=0)
        refs.append(ref)
        limits.append(spread_limit(row_norms(seed - ref), MIN_FACE_DISTANCE))
        held.append(row_norms(rows - ref) <= limits[-1])
    middle, at_left, at_right = held
    if SURFACE_SPANS_FACE and max(limits) <= MIN_FACE_DISTANCE:
        face = middle | (at_left & at_right)
    else:
        face = middle | at_left | at_right
    run = np.convolve(face.astype(np.int32), np.ones(SURFACE_RUN_ROWS, np.int32), "valid")
    starts = np.flatnonzero(run == SURFACE_RUN_ROWS)
    if starts.size == 0:
        return top
    first = int(starts[0])
    if first < SURFACE_MIN_DROP * h or float(np.mean(~face[:first])) < SURFACE_FOREIGN_SHARE:
        return top
    near, far = STEP_BAND_ROWS
    for rows in parts:
        above = median_of(rows[max(0, first - far) : first - near + 1], axis=0)
        below = median_of(rows[first + near : first + far + 1], axis=0)
        if norm(above - below) < SURFACE_STEP:
            return top
    f1 = bottom + EDGE_SKIP + 1
    f2 = min(f1 + FLOOR_BAND_ROWS, view.out.shape[0])
    if f2 > f1:
        floor = _lab8(image, view, f1, f2, left + SIDE_SKIP, right - SIDE_SKIP + 1)
        floor_c = np.asarray(median_u8(floor.reshape(-1, 3), axis=0), np.float32)
        if norm(refs[0] - floor_c) < SURFACE_FLOOR_APART:
            return top
    lo, hi = max(0, first - SNAP_ROWS), min(h - 1, first + SNAP_ROWS)
    c0, c1 = left + SIDE_SKIP, right - SIDE_SKIP
    strength = np.asarray(ay[top + lo : top + hi + 1, c0:c1].mean(axis=1))
    return int(top + lo + np.argmax(strength))


#: lower_top_where_sides_end: columns read on each side of a side line (just inside the
#: face, just outside it), a blur's width off it ...
SIDES_END_STRIP = 3
SIDES_END_SKIP = 2
#: ... a side stands out where what is just inside it differs from what is just outside
#: by at least this (Lab, 8-bit) along the face's lower part (read as SURFACE_REF_SHARE
#: of its rows over its foot's): a side the background matches there tells nothing above.
SIDES_END_STAND = 20.0
#: A row is past the face's top where its standing sides keep on average under this share
#: of that contrast and under SIDES_END_LEVEL (Lab): above the face's top the background
#: behind runs on across its side lines, the same on both sides of each (a face's upper
#: part merely like the wall beside it still differs by more: photo/140, 13-17).
SIDES_END_KEEP = 0.5
SIDES_END_LEVEL = 10.0
#: The face's top is under this many rows in a row over which its sides no longer stand
#: (a row or two of the background's own edges' blur aside) ...
SIDES_END_RUN = 6
#: ... and the rows between it and the top as found are mostly so (this share): the top
#: was put on something standing in line behind the face, not a face whose sides fade.
SIDES_END_SHARE = 0.7
#: The top is moved only down by at least this share of the face's height as found (a
#: grossly high top: a few rows' move is the top edges' own business).
SIDES_END_MIN_DROP = 0.2
#: The face's surface ends there: an edge across it between the sides, its mean |d/dy| at
#: least this many times the median row's of the face under it (a line on the wall behind
#: it, where the sides' contrast changes, crosses no edge of the face: procedural/141).
SIDES_END_EDGE = 3.0


def lower_top_where_sides_end(
    image: npt.NDArray[Any] | None,
    view: View,
    ay: npt.NDArray[np.float32],
    bottom: int,
    top: int,
    left: int,
    right: int,
) -> int:
    """The top moved down to where the face's sides end: walking up from the face's lower
    part, the first row above which, for SIDES_END_RUN rows, the sides that stand out
    there (SIDES_END_STAND) lose their contrast (SIDES_END_KEEP), where the rows from it
    up to ``top`` mostly do too (SIDES_END_SHARE); snapped to the strongest top edge
    within SNAP_ROWS.

    The face is one surface at the sonar's depth: its own colour does not continue past
    its sides, so each side line parts it from what is beside it from the foot up to its
    top. Above its top the wall (or a rocket, a shelf) behind it runs on across the side
    lines at the same rows: a top put there has rows whose sides part nothing."""
    h = bottom - top
    if image is None or image.ndim != 3:
        return top
    f0 = FOOT_BAND_ROWS[0]
    ref_rows = max(SIDES_END_RUN, int(SURFACE_REF_SHARE * h))
    if h < 4 * SIDES_END_RUN or ref_rows + f0 >= h:
        return top
    w_img = view.out.shape[1]
    reach = SIDES_END_SKIP + SIDES_END_STRIP
    if left - reach < 0 or right + reach > w_img or right - left < 2 * reach + 2:
        return top
    s, g = SIDES_END_STRIP, SIDES_END_SKIP
    # only the strips round each side line are read: (outside, inside) of each
    lb = _lab8(image, view, top, bottom, left - reach, left + reach + 1)
    rb = _lab8(image, view, top, bottom, right - reach, right + reach + 1)
    strips = (
        (lb[:, :s], lb[:, reach + g + 1 :]),
        (rb[:, reach + g + 1 :], rb[:, :s]),
    )
    keep = np.zeros(h, np.float32)
    level = np.zeros(h, np.float32)
    n_stand = 0
    for outside, inside in strips:
        o = np.asarray(median_u8(outside, axis=1), np.float32)
        i = np.asarray(median_u8(inside, axis=1), np.float32)
        contrast = row_norms(i - o)
        ref = float(median_of(contrast[h - f0 - ref_rows : h - f0]))
        if ref < SIDES_END_STAND:
            continue
        n_stand += 1
        keep += contrast / ref
        level += contrast
    if n_stand == 0:
        return top
    box = np.ones(3, np.float32) / (3 * n_stand)
    face = (np.convolve(keep, box, "same") >= SIDES_END_KEEP) | (
        np.convolve(level, box, "same") >= SIDES_END_LEVEL
    )
    end = -1
    run = 0
    for r in range(h - f0 - ref_rows, -1, -1):
        if face[r]:
            run = 0
            continue
        run += 1
        if run == SIDES_END_RUN:
            end = r + SIDES_END_RUN  # the face's top row: the last one whose sides stand
            break
    if end < SIDES_END_MIN_DROP * h:
        return top
    if float(np.mean(~face[:end])) < SIDES_END_SHARE:
        return top
    lo, hi = max(0, end - SNAP_ROWS), min(h - 1, end + SNAP_ROWS)
    c0, c1 = left + SIDE_SKIP, right - SIDE_SKIP
    strength = np.asarray(ay[top : bottom - f0, c0:c1].mean(axis=1))
    at = lo + int(np.argmax(strength[lo : hi + 1]))
    below = float(median_of(strength[at + SNAP_ROWS + 1 :]))
    log.debug("sides end at %d: edge %.1f, face %.1f", top + at, strength[at], below)
    if strength[at] < SIDES_END_EDGE * below:
        return top
    return top + at


#: Whether a thin margin line round a print (a few rows or columns of the face's own
#: colour round it) moves the face's edges out to it.
MARGIN_LINE_OUT = True
#: The most rows such a margin line may be (wider ones are the frame rules' to find).
MARGIN_LINE_ROWS = 3
#: Rows of what lies past the line read for its colour.
MARGIN_LINE_PAST = 2
#: What lies past the line's outer step is one colour: its first two rows differ by at
#: most this share of that step (a blurred step's tail; a wider band's own step beyond
#: a weak one is larger).
MARGIN_LINE_SETTLED = 0.6
#: Rows inside the print's edge row read too (the print's side of its blurred edge).
MARGIN_LINE_INNER = 2
#: The line's own colour (its row at the blur's dip) stands this far (Lab) from both the
#: print's and what lies past the line.
MARGIN_LINE_APART = 20.0
#: The lines at the print's edges agree within this (Lab): one margin (the foot's line
#: darker by the floor's blur; a top face and a shadow are farther apart).
MARGIN_LINE_AGREE = 30.0
#: Whether the sides move out to that margin's line beside the print too.
MARGIN_LINE_SIDES = True
#: The line shows with an outer edge of its own at this many of the print's edges.
MARGIN_LINE_EDGES = 2


def _margin_edge(
    rows: npt.NDArray[np.float32], print_colour: npt.NDArray[np.float32]
) -> tuple[float, npt.NDArray[np.float32]] | None:
    """A thin line outward from a print's edge (``rows``: colours from MARGIN_LINE_INNER
    rows inside the print's edge row outward): where its outer edge lies (sub-pixel
    entry of ``rows``) and its colour. The print's edge is the larger colour step into
    or out of its row; then the steps shrink to the blur's dip, in the line; the line's
    outer edge is the largest step from there within MARGIN_LINE_ROWS, past which the
    colour settles. None: no line, or one the blur leaves no step of its own (the steps
    only shrink past the print's)."""
    n, k = MARGIN_LINE_ROWS, MARGIN_LINE_INNER
    end = k + 1 + n  # the first row past the line's reach
    steps = row_norms(np.diff(rows[: end + 2], axis=0))  # steps[r]: entry r to r + 1
    p = k - 1 + int(np.argmax(steps[k - 1 : k + 1]))
    # the blur's dip between the two steps: where the steps stop shrinking past the print's
    q = p + 1
    while q < end - 1 and steps[q + 1] < steps[q]:
        q += 1
    o = q + int(np.argmax(steps[q:end]))
    if norm(rows[o + 1] - rows[o + 2]) > MARGIN_LINE_SETTLED * float(steps[o]):
        return None  # the colour runs on changing past the step: no thin line's end
    past = np.asarray(median_of(rows[o + 1 : o + 1 + MARGIN_LINE_PAST], axis=0), np.float32)
    # the line's own colour: at the dip, its row farther from the print's (blur the least)
    line = np.asarray(max(rows[q], rows[q + 1], key=lambda c: norm(c - print_colour)), np.float32)
    if min(norm(line - print_colour), norm(line - past)) < MARGIN_LINE_APART:
        return None
    if o == q and not steps[o] > steps[o - 1]:
        return None  # no dip before it: the steps only shrink past the print's
    den = float(steps[o - 1] - 2.0 * steps[o] + steps[o + 1])
    off = 0.5 * float(steps[o - 1] - steps[o + 1]) / den if den < 0.0 else 0.0
    return o + 0.5 + clamp(off, -0.5, 0.5), line


class MarginLine(NamedTuple):
    """A print's thin margin line's outer edges, sub-pixel (an edge the line leaves as
    found: -inf for the foot and the right side, +inf for the top and the left side)."""

    foot: float
    top: float
    left: float
    right: float
    col: float  # the column the foot and top are read at
    row: float  # the row the sides are read at


def margin_line_out(
    image: npt.NDArray[Any] | None,
    view: View,
    bottom: int,
    top: int,
    left: int,
    right: int,
) -> MarginLine | None:
    """A print's thin margin line's outer edges; None where there is no such line.

    A print (bricks, a poster) on a face with a margin of the face's own colour one to
    three pixels wide: the edges found are the print's, the margin lies in their blur and
    no frame rule reads it. Where a line of one colour, unlike the print's and unlike
    what lies past it, shows with an outer edge of its own at MARGIN_LINE_EDGES or more of
    the print's four edges (one margin round the print: a top face's strip over a front
    alone is no margin, nor is a top face lighter over it and a shadow darker under it,
    of two colours), the face's edges are the line's outer edges there; the others stay
    as found. The sides take part with MARGIN_LINE_SIDES."""
    if not MARGIN_LINE_OUT or image is None or image.ndim != 3:
        return None
    h, w = view.out.shape
    n = MARGIN_LINE_ROWS + MARGIN_LINE_PAST + 2
    i = MARGIN_LINE_INNER
    k_u = max(1, (right - left) // 5)
    k_v = max(1, (bottom - top) // 5)
    if right - left < 10 or bottom - top < 2 * k_v + 4 or top - n < 0 or bottom + n + 1 > h:
        return None
    band = _lab8(image, view, top - n, bottom + n + 1, left + k_u, right - k_u)
    rows = np.asarray(median_u8(band, axis=1), np.float32)
    t, b = n, bottom - top + n  # the top and foot rows in the band
    inner = band[t + k_v : b - k_v + 1].reshape(-1, 3)
    print_colour = np.asarray(median_u8(inner, axis=0), np.float32)
    # each edge's line: (where its outer edge lies, its colour), outward from the edge
    found = {
        "top": _margin_edge(rows[t + i :: -1], print_colour),
        "foot": _margin_edge(rows[b - i :], print_colour),
    }
    if MARGIN_LINE_SIDES and left - n >= 0 and right + n + 1 <= w:
        across = _lab8(image, view, top + k_v, bottom - k_v + 1, left - n, right + n + 1)
        cols = np.asarray(median_u8(across, axis=0), np.float32)
        lc, rc = n, right - left + n  # the sides' columns in the band
        found["left"] = _margin_edge(cols[lc + i :: -1], print_colour)
        found["right"] = _margin_edge(cols[rc - i :], print_colour)
    edges = {k: e for k, e in found.items() if e is not None}
    if len(edges) < MARGIN_LINE_EDGES:
        return None
    colours = [c for _, c in edges.values()]
    if max(norm(c - d) for c in colours for d in colours) > MARGIN_LINE_AGREE:
        return None  # lines of more than one colour: no one margin
    out = MarginLine(
        bottom - i + edges["foot"][0] if "foot" in edges else -math.inf,
        top + i - edges["top"][0] if "top" in edges else math.inf,
        left + i - edges["left"][0] if "left" in edges else math.inf,
        right - i + edges["right"][0] if "right" in edges else -math.inf,
        0.5 * (left + k_u + right - k_u - 1),
        0.5 * (top + k_v + bottom - k_v),
    )
    log.debug("a margin line round the print %d-%d x %d-%d: %s", left, right, top, bottom, out)
    return out


#: A stripe down the face (a tape, a painted band) is a marking on it, not a gap between
#: two faces: its two edges are parallel a few centimetres apart, the face's surface is
#: the same on both sides, and its foot stands on the same floor-contact row across it.
#: The side search took the stripe's near edge for a side and the widening across seams
#: stopped at it (its top edge against a background of its own shade shows no line); the
#: face is crossed to its far half (a switch for the tests).
BRIDGE_STRIPES = True
#: The widest stripe crossed, at the face's depth.
STRIPE_MAX_M = 0.12
#: The narrowest stripe (columns; a narrower gap is a seam, the widening's own).
STRIPE_MIN_COLUMNS = 5
#: The foot line runs on its row over this share of the stripe's columns ...
STRIPE_FOOT_SHARE = 0.7
#: ... and the top and foot lines both stand over this share of the columns past it ...
STRIPE_PAST_SHARE = 0.7
#: ... read over this many columns, from STRIPE_PAST_GAP past the stripe's far edge (its blur).
STRIPE_PAST_COLUMNS = 8
STRIPE_PAST_GAP = 3
#: The face's colour (8-bit Lab) on both sides of the stripe apart by at most this.
STRIPE_SAME_SURFACE = 12.0
#: Columns read for the face's colour either side of the stripe, from this many columns
#: inside the side (its blur) ...
STRIPE_COLOUR_COLUMNS = 6
STRIPE_COLOUR_GAP = 2
#: ... over the face's rows but this share at its top and at its foot (their edges).
STRIPE_COLOUR_MARGIN = 0.25
#: The stripe's far edge is at least this share of the side's |d/dx| (and MIN_EDGE_SNR
#: noise levels), and stands down to the floor where present at this share of that.
STRIPE_EDGE_SHARE = 0.5
STRIPE_PRESENT_SHARE = 0.5
#: The fewest rows a face is looked at for a stripe (its colour read over half of them).
STRIPE_MIN_ROWS = 8


def bridge_stripe(
    image: npt.NDArray[Any],
    view: View,
    ay: npt.NDArray[np.float32],
    ax: npt.NDArray[np.int16],
    bottom: int,
    top: int,
    left: int,
    right: int,
    depth: float,
    noise: float,
) -> tuple[int, int]:
    """The side columns moved past a stripe down the face at either side: to the
    stripe's far edge where that edge stands down to the floor, the foot line runs on
    across the stripe, the top and foot lines stand on their rows past it and the face's
    colour past it is the colour inside the side (the caller widens on from there)."""
    if (
        not BRIDGE_STRIPES
        or right - left < 2 * STRIPE_COLOUR_COLUMNS
        or bottom - top < STRIPE_MIN_ROWS
    ):
        return left, right
    width = ay.shape[1]
    most = int(STRIPE_MAX_M * view.fx / max(depth, 1e-6))
    if most < STRIPE_MIN_COLUMNS:
        return left, right
    sides = np.asarray(ax[top + 1 : bottom], np.float32).mean(axis=0)
    top_line = _line_on_row(ay, top, noise)
    foot_line = _line_on_row(ay, bottom, noise)
    h = bottom - top
    r0, r1 = top + int(STRIPE_COLOUR_MARGIN * h), bottom - int(STRIPE_COLOUR_MARGIN * h)
    new = [left, right]
    for i, (side, step) in enumerate(((left, -1), (right, 1))):
        need = max(STRIPE_EDGE_SHARE * float(sides[side]), MIN_EDGE_SNR * noise)
        lo = side + step * STRIPE_MIN_COLUMNS
        hi = side + step * most
        a, b = sorted((lo, hi))
        a, b = max(a, 0), min(b, width - 1)
        if b - a < 1:
            continue
        far = int(a + sides[a : b + 1].argmax())
        if float(sides[far]) < need:
            continue
        if not _stands(
            np.asarray(ax[top + 1 : bottom, far], np.float32) >= STRIPE_PRESENT_SHARE * need
        ):
            continue
        s0, s1 = sorted((side + step, far))
        if share(foot_line[s0 : s1 + 1]) < STRIPE_FOOT_SHARE:
            continue  # no foot on the same row across it: a gap between two faces
        p0 = far + step * STRIPE_PAST_GAP
        p1 = p0 + step * (STRIPE_PAST_COLUMNS - 1)
        q0, q1 = min(p0, p1), max(p0, p1)
        if q0 < 0 or q1 >= width:
            continue
        if min(share(top_line[q0 : q1 + 1]), share(foot_line[q0 : q1 + 1])) < STRIPE_PAST_SHARE:
            continue  # the face's top and foot do not run on past it
        inside = side - step * (STRIPE_COLOUR_COLUMNS + STRIPE_COLOUR_GAP)
        c_in = sorted((inside, side - step * STRIPE_COLOUR_GAP))
        c_out = sorted((p0, p0 + step * (STRIPE_COLOUR_COLUMNS - 1)))
        face_in = np.median(_band(image, view, r0, r1, c_in[0], c_in[1] + 1).reshape(-1, 3), 0)
        face_out = np.median(_band(image, view, r0, r1, c_out[0], c_out[1] + 1).reshape(-1, 3), 0)
        if float(np.linalg.norm(face_in - face_out)) > STRIPE_SAME_SURFACE:
            continue  # another surface past it: another face
        new[i] = far
    return new[0], new[1]


#: The rim's colour is read in the rows this far over the found foot (the row of them
#: the most chromatic; the contact row itself not: the floor's): a board's coloured edge
#: band runs across its foot.
RIM_FOOT_ROWS = 6
#: The rim's line across the top is thinner than this (rows from its lowest row up to
#: where half of RIM_SPAN stops holding): a rim is a line, the background closes over it.
RIM_THIN_ROWS = 6
#: ... a rim this chromatic (8-bit Lab, from grey) only: a grey line is any print's row.
RIM_CHROMA = 20.0
#: ... and this far (Lab) from the face's inside under the found top: a rim, not the face.
RIM_APART = 20.0
#: A pixel is of the rim's colour within this (Lab) of it.
RIM_MATCH = 15.0
#: A row is the rim's line across the top where this share of the columns between the
#: sides are of its colour ...
RIM_SPAN = 0.8
#: ... and under this share of the columns beside the sides (the line ends at them).
RIM_BESIDE = 0.34
#: The rim's line is sought up to this height of the face (m; as RAISED_FACE_MAX_M).
RIM_REACH_M = 1.5


def raise_top_to_rim(
    image: npt.NDArray[Any] | None,
    view: View,
    bottom: int,
    top: int,
    left: int,
    right: int,
    depth_m: float,
) -> int:
    """The top of a board framed by a coloured rim: the nearest row over ``top`` where the
    rim's colour, read across the face's foot, runs across the face's whole width and
    stops at its sides; ``top`` where there is none.

    A print or a text panel inside the rim stops the colour walks at a row of the print
    (grey on grey, nothing there to say the face goes on). The rim does not: the same
    coloured line closes the face at its foot and at its top, between its sides only."""
    if image is None or image.ndim != 3 or right - left < 2 * SIDE_SKIP + 4 or bottom - top < 8:
        return top
    w_view = view.out.shape[1]
    c0, c1 = left - SIDE_SKIP - BESIDE_COLUMNS, right + SIDE_SKIP + BESIDE_COLUMNS + 1
    if c0 < 0 or c1 > w_view:
        return top
    reach = int(round(view.fy * RIM_REACH_M / depth_m))
    r0 = max(0, bottom - reach)
    if top - r0 < 4:
        return top
    band = _lab8(image, view, r0, bottom + 1, c0, c1).astype(np.float32)
    span = BESIDE_COLUMNS + SIDE_SKIP
    inner = band[:, 2 * span : -2 * span]
    beside = np.concatenate([band[:, :BESIDE_COLUMNS], band[:, -BESIDE_COLUMNS:]], axis=1)
    kb, kt = bottom - r0, top - r0
    # (the rows over the contact row: a chromatic floor's colour there is no rim)
    foot = np.median(inner[kb - RIM_FOOT_ROWS : kb], axis=1)
    chroma = np.hypot(foot[:, 1] - 128.0, foot[:, 2] - 128.0)
    rim = foot[int(np.argmax(chroma))]
    if float(chroma.max()) < RIM_CHROMA:
        return top
    inside = np.median(inner[kt : kb - RIM_FOOT_ROWS].reshape(-1, 3), axis=0)
    if norm(rim - inside) < RIM_APART:
        return top
    near_in = (np.linalg.norm(inner - rim, axis=2) <= RIM_MATCH).mean(axis=1)
    near_out = (np.linalg.norm(beside - rim, axis=2) <= RIM_MATCH).mean(axis=1)
    line = (near_in >= RIM_SPAN) & (near_out < RIM_BESIDE)
    for k in range(kt - 1, -1, -1):
        if line[k]:
            upper = k
            while upper > 0 and near_in[upper - 1] >= RIM_SPAN / 2:
                upper -= 1
            # a line, as thin as a rim: the background closes over it (a light rim
            # before a wall of its own colour: the wall over the face is no line; fresh
            # procedural 2120 hard, -8 -> +40 % without this)
            if k - upper >= RIM_THIN_ROWS:
                return top
            return r0 + upper
    return top
