"""The fused method, frame by frame: the stages in order.

Receives one camera frame and the sonar's range (:meth:`FusedMethod.run`); returns a
:class:`~obstacle_fusion.vision.types.Measurement` (detected with height, width, box and
confidence, or not detected with the reason). Per frame: the working view and its
gradients here, then the candidate search (:mod:`.search`), the scoring and the
vanishing-point test (:mod:`.scoring`), the confidence decision (:mod:`.confidence`),
the front top edge (:mod:`.top`) and the sub-pixel refinement (:mod:`.refine`).
"""

from __future__ import annotations

import dataclasses
import logging
import math
from collections.abc import Sequence
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.fused.confidence import (
    FOOT_ABOVE_SHARE,
    FOOT_UNSEEN,
    FRAMED,
    FRONT_STEP_UNDONE,
    FRONT_STEP_UNDONE_SHARE,
    PRINT_OUTLINE,
    TOP_FACE_GAP,
    TOP_FACE_STEP,
    TOP_FROM_SIDES,
    confidence,
    contact_doubts,
    face_doubts,
    refusal,
    reported_confidence,
    top_face_band,
)
from obstacle_fusion.vision.fused.extent import (
    OUTLINE_FAR_M,
    OUTLINE_REACH,
    SNAP_COLUMNS,
    enclose_inner_frame,
    foot_in_band,
    raise_spans_face,
    raise_top_along_seams,
    raise_top_past_inner_edges,
    top_line_across,
    trim_to_top_line,
    widen_across_seams,
)
from obstacle_fusion.vision.fused.foot_outline import grows_face, outline_from_foot
from obstacle_fusion.vision.fused.past_seam import sides_past_seams
from obstacle_fusion.vision.fused.profiles import VerticalFits, clamp, median
from obstacle_fusion.vision.fused.refine import refine
from obstacle_fusion.vision.fused.region import (
    MIN_TOP_FACE_ROWS,
    RING_SKIP,
    TOP_COLOUR_STEP,
    TOP_STEP_FULL,
    bridge_stripe,
    enclose_beside_foot,
    enclose_by_margin,
    enclose_by_ring,
    enclose_from_foot,
    ends_in_colour,
    face_down_to_foot,
    face_from_colour,
    face_past_foot,
    face_under_raised_top,
    frame_top_by_margin,
    hue_back_under_top,
    looks_like_top_face,
    lower_top_past_top_face,
    lower_top_to_background,
    lower_top_to_surface,
    lower_top_where_sides_end,
    margin_line_out,
    margin_under_print,
    margin_up_to_raised_top,
    raise_top_along_frame,
    raise_top_by_colour,
    raise_top_by_hue,
    raise_top_by_outline,
    raise_top_by_sides,
    raise_top_by_windows,
    raise_top_past_band,
    raise_top_to_frame,
    raise_top_to_rim,
    side_agreement,
    sides_rising,
    snap_sides_to_steps,
    stops_at_colour_top,
    top_agreement,
    top_face_above,
    trim_to_foot,
    widen_along_margin,
    widen_by_colour,
)
from obstacle_fusion.vision.fused.scoring import (
    Candidate,
    edge_cover,
    enclosing_outline,
    nested,
    on_rigs_row,
    score_pairs,
    verified,
)
from obstacle_fusion.vision.fused.search import (
    beam_columns,
    bottom_candidates,
    min_width_px,
    side_candidates,
)
from obstacle_fusion.vision.fused.texture import face_from_texture
from obstacle_fusion.vision.fused.top import front_from_back, front_top
from obstacle_fusion.vision.fused.tuning import DEFAULT_MIN_CONFIDENCE, MIN_SIZE_M
from obstacle_fusion.vision.fused.undistort import TableRemap
from obstacle_fusion.vision.types import Line, Measurement, Timer, Uncovered, View

_c_uncovered: Uncovered | None
try:  # the optional C accelerator (setup.py): View.lab's held blocks' bookkeeping
    from obstacle_fusion.vision.fused._cmiddle import uncovered as _c_uncovered
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_uncovered = None

log = logging.getLogger(__name__)

#: A face's top edge must reach this share of its columns, else a rival whose top does
#: (and scores at least RIVAL_SHARE of it) is taken.
TOP_COVER_MIN = 0.6
#: Under a top where the face's colour ends, a front top edge must end a colour too, by
#: this much (Lab, 8-bit): a top face a few shades lighter than the front, with the
#: background above it differing more (region.TOP_COLOUR_STEP); a gloss's highlight
#: under the top is a ramp, which top.front_top skips, not an edge.
FRONT_COLOUR_STEP = 15.0
RIVAL_SHARE = 0.5


def _top_cover(ay: npt.NDArray[np.float32], c: Candidate) -> float:
    """Share of the face's columns where its top edge (its row or one next to it) has at
    least a third of the edge's upper-quartile strength."""
    return edge_cover(ay, c.vt, c.ul, c.ur)


#: The top is decided again between the settled sides when they moved from the search's
#: by at least this share of its width (both sides' moves together).
SETTLED_MOVE_SHARE = 0.1
#: ... and the top decided again is taken only where it moves by at least this share of
#: the face's height (nearer, it is the same edge: the answer is left as it was).
SETTLED_TOP_MOVE = 0.15
#: The top is decided again between the settled sides for a face whose first top (decided
#: between the search's sides) left it under the minimum confidence too (with the rig).
SETTLED_REFUSED = True
#: The top is not decided again between the settled sides where the face's top line
#: crossing the search's pair gave it (extent.top_line_across): that line runs from side
#: to side on one row, its ends at vertical edges standing from it down to the foot and
#: not on above it, i.e. the front face's top edge; an edge decided higher up between the
#: sides it gave is the background's in line with them (a tower behind a panel face).
SETTLED_KEEPS_ACROSS = True
#: The face's top line across the search's pair (extent.top_line_across) is taken only
#: where the face's colour ends on its row: a face's top edge parts the face from what
#: lies above it, while a panel joint across the face (a thin line on one surface) has
#: the face's own colour right above and below it (procedural/3307 ordinary, panels: the
#: joint 38 % of the way up taken, its colour step 2.6 Lab, height -48 %; the top line
#: the rule was made for, photo/3249 ordinary, steps >= 12). Read as
#: region.top_agreement does (the median Lab colour of rows 2-5 above and below the row,
#: over the middle and next to each side; the largest step counts); with the rig.
ACROSS_ENDS_COLOUR = True
#: ... by at least this step (Lab, 8-bit scale): half of region.TOP_STEP_FULL (12), the
#: step a face's own top reaches; a joint's rows above and below differ by grain only
#: (procedural/2002's joint, in line with a band behind, steps 4.2). At most
#: TOP_STEP_FULL: top_agreement's reading is capped there (a limit over it refuses all).
ACROSS_COLOUR_STEP = 6.0


def _across_ends_colour(
    seen: npt.NDArray[Any] | None, view: View, across: tuple[int, int, int]
) -> bool:
    """Whether the face's colour ends on the row of the top line across it (``across``:
    top, left, right in the working view): a colour step of at least ACROSS_COLOUR_STEP
    there (top_agreement's reading; a grey frame gives no colour and passes)."""
    if not ACROSS_ENDS_COLOUR:
        return True
    top, left, right = across
    return top_agreement(seen, view, top, left, right) * TOP_STEP_FULL >= ACROSS_COLOUR_STEP


#: A face the search's top refused is weighed again without its texture where a print of
#: its own covers it (``Candidate.print_evidence``), with the rig, in the rescuing try.
PRINT_EVIDENCE = True
#: ... and where that face is a frame (a print in a margin of one colour round it, found
#: by the edges: ``framed``), a rescue's face lying inside the frame does not replace it:
#: the colour or texture found the print again (its pattern), whose margin is the face's
#: own surface, and the frame already holds both (a switch for the tests).
FRAME_OVER_INNER_RESCUE = True
#: ... inside: each of the rescue's box sides within this many pixels outside the frame's.
FRAME_INSIDE_SLACK_PX = 2.0


def _inside_frame(view: View, found: Measurement, framed: tuple[int, int, int, int]) -> bool:
    """Whether the box of ``found`` (input pixels) lies inside the frame ``framed``
    (bottom, top, left, right, working view), within FRAME_INSIDE_SLACK_PX."""
    if found.box_px is None:
        return False
    bottom, top, left, right = framed
    corners = np.array([[left, bottom], [right, bottom], [right, top], [left, top]], float)
    pix = view.to_input(corners)
    x0, y0, x1, y1 = found.box_px
    slack = FRAME_INSIDE_SLACK_PX
    return bool(
        x0 >= float(pix[:, 0].min()) - slack
        and x1 <= float(pix[:, 0].max()) + slack
        and y0 >= float(pix[:, 1].min()) - slack
        and y1 <= float(pix[:, 1].max()) + slack
    )


def _front_ends_colour(
    seen: npt.NDArray[Any], v: View, rb: int, top: int, front: int, ul: int, ur: int
) -> bool:
    """Whether a front top edge on row ``front``, under a top on row ``top`` where the
    face's colour ends, ends a colour too: by FRONT_COLOUR_STEP where the band between
    is a top face thick enough to show its own colour (MIN_TOP_FACE_ROWS), else by the
    full TOP_COLOUR_STEP (a thinner band's colour is the edges' blur)."""
    step = FRONT_COLOUR_STEP if front - top >= MIN_TOP_FACE_ROWS else TOP_COLOUR_STEP
    return ends_in_colour(seen, v, rb, front, ul, ur, step)


#: With the rig given, a front top edge found under a top where the face's colour ends
#: and undone for want of a colour step there leaves the doubt FRONT_STEP_UNDONE
#: (:data:`~obstacle_fusion.vision.fused.confidence.FRONT_STEP_UNDONE`): the top kept may
#: be a faint top face's back edge. A switch for the tests.
FRONT_STEP_UNDONE_DOUBT = True
#: ... kept only where the top measured still lies over the midpoint between the top kept
#: and the front step undone: a later stage that moved the top down to that step (the top
#: face's band read to its end, TOP_FACE_TO_FRONT) measured the front top edge, and the
#: two readings the doubt weighs agree (own photo 2042 ordinary with the rig: the step at
#: 179 undone under 175, the band's end 178.8 measured, +2.1 %, doubted 0.58 -> 0.26;
#: session 50's review). A switch for the tests.
FRONT_STEP_UNDONE_KEPT_TOP = True


def _front_step_doubt_stands(
    v: View, lines: Sequence[Line], undone: tuple[int, int] | None
) -> bool:
    """Whether FRONT_STEP_UNDONE still holds for a face measured with ``lines``: its top
    line (input pixels) lies over the midpoint of ``undone`` (the view rows of the top kept
    and of the front step undone under it; FRONT_STEP_UNDONE_KEPT_TOP)."""
    if not FRONT_STEP_UNDONE_KEPT_TOP or undone is None or len(lines) != 4:
        return True
    top = lines[1]
    row = view_row(v, 0.5 * (top[0] + top[2]), 0.5 * (top[1] + top[3]))
    return row < 0.5 * (undone[0] + undone[1])


def _kept_doubts(
    v: View, doubts: list[str], lines: Sequence[Line], undone: tuple[int, int] | None
) -> list[str]:
    """``doubts`` without FRONT_STEP_UNDONE where the top measured left it
    (:func:`_front_step_doubt_stands`)."""
    if FRONT_STEP_UNDONE in doubts and not _front_step_doubt_stands(v, lines, undone):
        return [d for d in doubts if d != FRONT_STEP_UNDONE]
    return doubts


#: The colour rescue's face has its top raised to where its sides end only where the
#: face's colour is back under that row (region.face_under_raised_top), with the rig.
RESCUE_RAISE_BY_COLOUR = True
#: The top, after the colour and side walks (of the edge search's face and of the colour
#: rescue's), walked on up while the rows between the sides keep the face's hue
#: (region.raise_top_by_hue): a gloss's highlight stops those walks inside the face (a
#: switch for the tests).
HUE_HOLDS_TOP = True

#: A box lower than the lens shows its top face above its front; where a band of the
#: face's own colour, lighter, runs just under the top measured
#: (:func:`~obstacle_fusion.vision.fused.confidence.top_face_band`, at least
#: ``TOP_FACE_STEP``) and the top lies below the horizon, the top measured is the top
#: face's back edge: the face is measured again with its top where the band ends (the
#: front top edge), TOP_FACE_MIN_MOVE_PX rows lower at least. A switch for the tests.
TOP_FACE_TO_FRONT = True
TOP_FACE_MIN_MOVE_PX = 0.5
#: ... with no rig too (the no-rig trials and the readings as with a guessed rig), where
#: the horizon is a guessed pitch's (in the trials with the allowance for a lens looking
#: further down, ``horizon_slack_px``; the readings as with a guessed rig use none).
#: Session 42 kept the move to the rig given: with no rig two faces the lens looked up at
#: moved 8 and 18 rows down onto a brick's and a plank's lighter rows (procedural 3030
#: ordinary, photo 3034 ordinary). The band's own tests since (one run from the top line
#: down to one step, ending at the sides too: ``confidence._band_ends_at_sides``) read
#: neither as a top face, and the guessed pitch hides a low box's top face above its
#: horizon most often (session 43, branch ``wt-c-43``). A switch for the tests.
TOP_FACE_TO_FRONT_NO_RIG = True
#: With the rig, a front top row predicted from the top face's back edge
#: (:func:`~obstacle_fusion.vision.fused.top.front_from_back`: the back edge's row scaled
#: by the share of the face's width its ends span, taken where no edge of its own lies
#: near) is as sure as those ends, read where the edge fades at the blurred corners (1.5
#: columns off allowed: on a 134-column face a scale 0.02 off moves the front 2 rows). A
#: top face is of the face's own colour, lighter, from its back edge to its front one:
#: where that band (:func:`~obstacle_fusion.vision.fused.confidence.top_face_band`, read
#: from PREDICTED_TOP_GAP under the predicted row: a predicted row has no edge's blur of
#: its own) runs on under the predicted row, the front top edge is where it ends. Its
#: limit: the colour "above" is read 3 to 6 rows above the predicted row
#: (``confidence.FOOT_BAND_GAP``), so a row predicted more than 3 rows under the band's
#: first row reads the band itself as "above" and finds no band (a drawn lid on rows
#: 100-109: found from a top at 101.4, not from 108.4); the top then stays where
#: predicted. Reading "above" over the back edge's row instead was not tried (session 44,
#: helper G: it would move answers not checked in time). A switch for the tests.
TOP_FACE_PAST_PREDICTED = True
PREDICTED_TOP_GAP = 0.5


def looks_down_on(v: View, row: float) -> bool:
    """Whether the lens looks down on a face's top at view row ``row``: below the
    horizon, or within the rows a guessed pitch's horizon may lie above ``cy``
    (``horizon_slack_px``, 0 with the rig given). The one gate of TOP_FACE_UNDER_TOP's
    doubt and of TOP_FACE_TO_FRONT's move."""
    return row > v.cy - v.horizon_slack_px


def view_row(v: View, x: float, y: float) -> float:
    """The view row of input-image pixel (x, y): undistorted, turned to the view's frame."""
    ray = v.camera.unproject(np.array([[x, y]], np.float64))[0]
    level = v.rotation @ np.array([ray[0], ray[1], 1.0])
    return float(v.fy * level[1] / level[2] + v.cy)


def thin_strip(m: Measurement) -> bool:
    """Whether a detected face is a thin strip (height under THIN_STRIP_SHARE of its
    width) found at under THIN_STRIP_MAX_CONFIDENCE."""
    return (
        m.detected
        and (m.confidence or 0.0) < THIN_STRIP_MAX_CONFIDENCE
        and (m.height_px or 0.0) < THIN_STRIP_SHARE * (m.width_px or 0.0)
    )


def stands_for_strip(face: Measurement, strip: Measurement) -> bool:
    """Whether ``face`` (found another way) is the face a thin strip stood for: surer,
    and THIN_STRIP_TALLER times as high."""
    return (
        face.detected
        and (face.confidence or 0.0) > (strip.confidence or 0.0)
        and (face.height_px or 0.0) >= THIN_STRIP_TALLER * (strip.height_px or 0.0)
    )


def _unsure(m: Measurement) -> bool:
    """Whether a face found would be reported under FOOT_OUTLINE_CONFIDENCE (its doubts
    and its size in pixels applied, unfloored, the rig given)."""
    if not m.detected:
        return False
    sure, _ = reported_confidence(
        m.confidence or 0.0, m.doubts, m.height_px, m.width_px, 0.0, rig_given=True
    )
    return sure < FOOT_OUTLINE_CONFIDENCE


def foot_at_view_edge(vb0: float, h_img: int) -> bool:
    """The predicted floor-contact row ``vb0`` lies where no contact edge can be read: in
    the view's last FOOT_EDGE_FLOOR_ROWS rows or past them (FOOT_AT_VIEW_EDGE)."""
    return vb0 > h_img - FOOT_EDGE_FLOOR_ROWS


def foot_below_view(vb0: float, h_img: int) -> bool:
    """The predicted floor-contact row ``vb0`` lies past the view's last row (rows
    0..h_img-1, row r covering r..r+1): the view does not see the face's foot, and the
    face read from the view's foot up (PAST_FOOT_FACE, FOOT_AT_VIEW_EDGE) is flagged
    clipped there; a row in the view is not (its height is from that row, not cut)."""
    return vb0 >= h_img


#: A pair let through the gate on the rig's row (``Candidate.foot_unseen``,
#: scoring.FOOT_FROM_RIG) gives way where the same pair (each side within
#: FOOT_SEEN_SIDE_PX) stands on a foot edge seen on another row of the band: the rig's
#: row stands in for a foot the image does not show, never for one it shows a few rows up
#: (procedural 715 hard, rig: the stand-in 6 rows under the seen foot, -11 % wide); nor
#: is such a pair a rival of a face chosen on its seen foot (procedural 146 hard, rig:
#: pairs on the rig's row round a tape-wrapped face took its confidence, +1.4 -> +5.7 %).
FOOT_SEEN_FIRST = True
FOOT_SEEN_SIDE_PX = 3


def foot_seen_first(cands: list[Candidate]) -> list[Candidate]:
    """The candidates less those standing on the rig's row alone whose pair stands on a
    seen foot on another row (FOOT_SEEN_FIRST)."""
    seen = [c for c in cands if not c.foot_unseen]
    return [
        c
        for c in cands
        if not c.foot_unseen
        or not any(
            abs(d.ul - c.ul) <= FOOT_SEEN_SIDE_PX and abs(d.ur - c.ur) <= FOOT_SEEN_SIDE_PX
            for d in seen
        )
    ]


def _foot_read(floor_known: bool, rig_known: bool, rb: int, vb0: float, conf: float) -> bool:
    """Whether the face's foot row ``vb0`` may be read for its outline (FOOT_OUTLINE): the
    rig's predicted row on a known floor; with no rig (FOOT_OUTLINE_TRIALS), a trial's row
    within FOOT_TRIAL_ROWS of the found foot ``rb``, round a face found at least
    FOOT_TRIAL_MIN_CONFIDENCE surely (``conf``)."""
    if rig_known:
        return floor_known
    return (
        FOOT_OUTLINE_TRIALS
        and abs(rb - vb0) <= FOOT_TRIAL_ROWS
        and conf >= FOOT_TRIAL_MIN_CONFIDENCE
    )


def _raise_stands(
    seen: npt.NDArray[Any] | None,
    view: View,
    bottom: int,
    scored: int,
    top: int,
    left: int,
    right: int,
    depth: float,
) -> bool:
    """Whether a top raised from the ``scored`` one up to ``top`` (all the stages' steps
    together) stands (WHOLE_RAISE_JUDGED): the face no taller than RAISED_FACE_MAX_M at
    ``depth``, and its colour back under ``top`` (region.face_under_raised_top, which
    leaves a short or a very long way unjudged) or at least its hue
    (region.hue_back_under_top: a gloss lightens a face up to its top; procedural/2053
    hard, a dark blue face lit to a pale blue, 0.8 % with the hue, 34 % without)."""
    if (bottom - top) * depth / view.fy > RAISED_FACE_MAX_M:
        return False
    return face_under_raised_top(
        seen, view, bottom, scored, top, left, right
    ) or hue_back_under_top(seen, view, bottom, scored, top, left, right)


def off_axis_share(
    ul: float, ur: float, u_axis: float, beam_half: float, rig_given: bool = True
) -> float:
    """The share of its score a face candidate spanning columns ``ul``..``ur`` keeps when
    it leaves the beam's axis column ``u_axis`` out: OFF_AXIS_SHARE, or FAR_OFF_AXIS_SHARE
    where its nearer side lies more than FAR_OFF_AXIS_BEAM_SHARE of the beam's half-width
    ``beam_half`` (columns) from the axis (the cone's outer part, where the beam is weak).
    ``rig_given``: the camera's height and pitch come from a rig, not guessed from the
    image (under a guessed one the far share made no-rig answers worse only: photo/152
    hard and 723, 2050 ordinary)."""
    gap = max(ul - u_axis, u_axis - ur)
    if FAR_OFF_AXIS and rig_given and gap > FAR_OFF_AXIS_BEAM_SHARE * beam_half:
        return FAR_OFF_AXIS_SHARE
    return OFF_AXIS_SHARE


def _moved(found: tuple[int, int], settled: tuple[int, int]) -> bool:
    """Whether the width stages moved the sides far from the search's pair ``found``."""
    move = abs(settled[0] - found[0]) + abs(settled[1] - found[1])
    return move >= SETTLED_MOVE_SHARE * max(found[1] - found[0], 1)


#: A face candidate off the beam's axis keeps this share of its score.
OFF_AXIS_SHARE = 0.6
#: With the rig, a face candidate far off the beam's axis keeps only FAR_OFF_AXIS_SHARE
#: of its score (instead of OFF_AXIS_SHARE): a sonar's beam is strongest on its axis
#: and weak at the edge of its cone, so a face whose nearest column lies in the cone's
#: outer part, while the ranking holds a face at the same depth on the axis, is a floor
#: patch or a neighbour beside the ranged face (procedural/755 hard, photo/152 hard). A
#: box beside the axis in the cone's inner part keeps OFF_AXIS_SHARE (the first
#: generator's bench scenes put boxes off the axis: refusing every off-axis face failed
#: them, session 34).
FAR_OFF_AXIS = True
#: "Far": the gap between the face's nearer side and the axis column is more than this
#: share of the beam's half-width in columns at the face's depth.
FAR_OFF_AXIS_BEAM_SHARE = 0.5
#: The share of its score a face far off the axis keeps.
FAR_OFF_AXIS_SHARE = 0.3
#: The highest confidence a face found by its colour alone gets (under the 0.5 of a sure
#: detection: on textured rooms its height was often short of the face's).
RESCUE_MAX_CONFIDENCE = 0.4
#: With the rig, a face whose floor-contact row lies below the image is sought by its
#: colour from the view's foot up (:func:`.region.face_past_foot`), at most as sure as
#: the colour rescue's (a switch for the tests).
PAST_FOOT_FACE = True
#: With the rig, a face whose predicted floor-contact row lies in the view's last
#: FOOT_EDGE_FLOOR_ROWS rows (or past them, the contact band reaching into the view) and
#: which the edges and the colour rescue do not find is sought as PAST_FOOT_FACE's is: the
#: contact edge needs floor rows below it to show (the 3x3 Sobel, the band's search stops
#: that many rows short of the view's foot), so a foot there has no edge to be found by,
#: and the rows at the view's foot in the beam's core are the face (session 45, `wt-a-45`).
FOOT_AT_VIEW_EDGE = True
FOOT_EDGE_FLOOR_ROWS = 4
#: The highest confidence a face found by its texture alone gets: its sides and top are
#: where a smoothed texture changes, known to half a window.
TEXTURE_MAX_CONFIDENCE = 0.3
#: A face found by its colour has its sides walked again from its top (read-only in
#: use: a switch for the tests).
RESCUE_WIDEN_AT_TOP = True
#: The colour rescue's sides are snapped to strong colour steps next to them first
#: (read-only in use: a switch for the tests).
RESCUE_SNAP_SIDES = True
#: The colour rescue's top is walked on up past a band's edge in the background where
#: the face's sides merely lost the band's contrast (region.raise_top_past_band; a switch
#: for the tests).
SKIRTING_WALK = True
#: The top of the colour rescue and of the settled sides carried up a print's outline to
#: where both its sides end under the background closing over it (a photograph or a drawn
#: pattern stops the colour walks at a row of the pattern; region.raise_top_by_outline; a
#: switch for the tests).
PRINT_OUTLINE_TOP = True
#: With the rig, the colour rescue's top is raised to a coloured rim's line across the
#: face: a board's edge band of one hue, read across its foot, that runs across the
#: face's whole width at a row over the found top and stops at its sides
#: (region.raise_top_to_rim): a print or text panel inside the rim, grey on a grey
#: background, stopped every walk at a row of the print (photo/3458 hard). A switch for
#: the tests.
RIM_LINE_TOP = True
#: Whether the edge search's face, its foot in the contact band and no margin round it
#: found, is tried for a print whose frame shows only beside it
#: (:func:`.region.enclose_beside_foot`, else only after the texture rescue).
BESIDE_FOOT_FIRST = True
#: With no rig, the face found on a tried row, no frame found round it, is checked for a
#: frame whose margin runs on under that row (:func:`.region.margin_under_print`): the
#: print's lower edge was taken for the foot. The frame is then the face (as an
#: enclose_by_margin frame is), FRAMED among its doubts (a switch for the tests).
MARGIN_UNDER_TRIED_ROW = True
#: ... and where that frame's foot lies past the rows read (below the band round the row
#: tried), the print found stands as measured (another trial reads the lower rows), but
#: FRAMED is among its doubts all the same: a face stands on the floor, and under the row
#: tried lies no floor but a margin of the colour flanking the print, running on down to
#: a foot of its own; the row is the print's lower edge, not a floor contact (procedural
#: 3274 hard: a brick print in a frame of the floor's shade, its lower edge 27 rows over
#: the frame's foot, answered at 0.58, 29 % short). A switch for the tests.
FRAMED_PAST_ROWS_DOUBT = True
#: ... where the margin over the print (past the RING_SKIP row) runs this many rows at
#: least: a frame's margin is a band of the face's paint; one row over the top is the
#: top edge's blend into what lies above (photo 2030 ordinary: a plain face before a
#: dark sky, the floor's grey beside it and its shadow under it read as a "ring" with 1
#: row over its top, a right answer doubted).
FRAMED_PAST_ROWS_MIN_OVER = 2
#: A top where the face's sides stop and a print's texture ends (scoring.closing_top
#: with scoring.PRINT_ENDS_TEXTURE) is not lowered to where the background seems to show
#: past a side below it (region.lower_top_to_background): under it is the print, and a
#: print's margin beside a side can match the background beyond (a switch for the tests).
CLOSED_TOP_KEPT = True
#: The face found by its texture walks its sides up too (:meth:`FusedMethod._by_texture`):
#: a print's texture stops the texture's walk at the print's top or inside it, while the
#: face's margin at both sides parts it from what is beside it up to its real top.
TEXTURE_SIDES_WALK = True
#: ... and then the face's hue (region.raise_top_by_hue, with HUE_HOLDS_TOP), as the edge
#: search's and the colour rescue's faces: a gloss on a grey face of a photographed
#: texture ends the texture's walk where the highlight starts, while the face's hue holds
#: up to its top (photo/3168 hard: the top on the highlight, -42 % with the rig and
#: without; the rig's own face, walked so, was found whole but outscored by this one).
TEXTURE_HUE_WALK = True
#: With the rig, a face found standing above the floor-contact band (farther back than
#: the sonar's range, or on an edge across the face) with no margin round it gives way to
#: the face its colour finds standing in the band (a switch for the tests)...
STANDING_BEHIND_RESCUE = True
#: Whether a face found standing above the contact band with no print round it (and no
#: colour face standing in the band: STANDING_BEHIND_RESCUE) takes the foot in the band
#: when its own colour runs on down to it (:func:`.region.face_down_to_foot`; a gloss face
#: whose lower rows, a shade darker, ended the found foot early).
FACE_DOWN_TO_FOOT = True
#: ... when that face reaches up as high, within this share of the first face's height:
#: the same face read with its foot in the band, or the box in front of an outline of
#: things behind it; a colour face reaching much lower is a print on the face found.
STANDING_TOP_SHARE = 0.25
#: With the rig, a top that the face's own seams (panel joints, plank gaps) run on past
#: together is a background line across a face in the wall's shade: the top is raised to
#: where they end (`extent.raise_top_along_seams`).
SEAMS_RAISE_TOP = True
#: ... and so where the top is decided again between the settled sides: the search's pair
#: may have been one panel whose side is itself a joint (no seam inside it to raise the
#: top), the settled sides then hold the face's other joints, which run on past a top
#: that was a joint across the face to the face's real top, where they all end
#: (procedural/3305 ordinary: a pink panel face on a pink wall, a horizontal joint 45 %
#: of the way up taken for the top, -49 %). With the rig given only (not a trial's rig
#: taken as known: there the foot read may be a frame's bottom rail, the face a strip of
#: margin, and a brick print's joints above it end at the print's top, not the face's:
#: photo/3070 ordinary with no rig -3.6 -> -88 %).
SETTLED_SEAMS_RAISE = True
#: A thin strip found at the face's foot (under THIN_STRIP_SHARE of its width high) whose
#: ends carry its colour up as a frame's sides, round a middle of another colour, is the
#: frame's bottom rail: the top is raised to where the frame's sides end
#: (`region.raise_top_along_frame`; a switch for the tests).
FRAME_RAIL_RAISE = True
#: A print lies inside its face: where the face found stands on a frame's bottom rail of
#: one colour whose side margins run up past the top found and close across over the
#: print, the top is the frame's (`region.raise_top_to_frame`; with and without the rig,
#: on the edge search's face and the settled sides' top; a switch for the tests).
FRAME_CLOSES_TOP = True
#: With the rig, a face the edges found as a thin strip at its foot (its height under
#: this share of its width: a floor line or a band's foot taken for its top, a floor-grid
#: line for a side) at under THIN_STRIP_MAX_CONFIDENCE is weighed against the face its
#: colour finds (the colour rescue otherwise runs only where the edges refuse); the
#: colour's face is taken when it is surer and reaches THIN_STRIP_TALLER times as high
#: (the strip was its foot; a face about as high is the strip's own face read again).
THIN_STRIP_SHARE = 0.3
#: A raise past the inner edges refused for ending on no line across the face
#: (``extent.RAISE_SPANS_FACE``, with the rig) is at most this share of the found face's
#: height: a piece found under a longer raise (procedural/108 hard: 11 rows, raised 88)
#: is a band or label low on the face, its top line spanning that piece only.
RAISE_SPAN_MAX_RAISE = 1.0
THIN_STRIP_MAX_CONFIDENCE = 0.15
THIN_STRIP_TALLER = 2.0


#: A frame round a print (extent.enclose_inner_frame) raises the top only where the colour
#: does not end at the print's top from side to side (region.ends_in_colour); its sides
#: stand either way. A raise under FRAME_CHECKED_RAISE of the print's height is not judged
#: (a thin top margin, a few rows: the colour bands read there lie in the edges' blur).
FRAME_KEEPS_COLOUR = True
FRAME_CHECKED_RAISE = 0.2
#: With the rig, the edge search's top is carried past a band's edge behind the face (a
#: skirting's top, where the face's sides merely lost the band's contrast) as the colour
#: rescue's is (region.raise_top_past_band), where that band runs on out past both sides
#: (``runs_on``: a skirting along the wall, not a frame's margin round a print); the walk
#: adds no evidence: the face's agreement is the lesser of the two tops' (a switch).
EDGE_SKIRTING_WALK = True
#: A face found as a piece of a print covering it is grown to the outline read from its
#: foot (:func:`.foot_outline.outline_from_foot`; with the rig only: the foot's row is the
#: one the range predicts). Session 35, branch ``wt-b-35``; a switch for the tests.
FOOT_OUTLINE = True
#: ... only for a face reported under this confidence (its doubts and pixel size applied,
#: unfloored): a face found surely is no piece of a print (with no limit, photo/2063 hard
#: at 0.41 went 0.9 -> 37 %, photo/2042 ordinary at 0.58 9.5 -> 39 %; the pieces the rule
#: is for were at 0.05-0.20).
FOOT_OUTLINE_CONFIDENCE = 0.25
#: ... its foot the found one where that is within this many rows of the predicted row.
FOOT_SAME_ROWS = 3
#: With no rig (:meth:`FusedMethod.run`'s ``rig_known`` False: a trial's camera height and
#: pitch only guessed from a floor-contact row) the outline is read too, on the trial's
#: row, where the face found stands on that row (:func:`_foot_read`). Session 35, branch
#: ``wt-c-35c``; a switch for the tests.
FOOT_OUTLINE_TRIALS = True
#: ... its found foot within this many rows of the trial's row (a row guessed at the
#: face's foot, the outline read on it as on the rig's: the trial rows step by a few
#: rows, so the foot is seldom on one exactly; at 0, procedural/2029 ordinary, 2046 hard
#: and photo/737 hard stay wrong, from 1 to 5 all are fixed; 5 as evaluated) ...
FOOT_TRIAL_ROWS = 5
#: ... round a face found at least this surely (its edges' confidence, before its
#: doubts): a weaker face in a guessed view stands on a row it merely shares with what
#: stands behind it (procedural/2162 hard: a box found at 0.08-0.10 in front of a drum
#: whose foot is a few rows above its own was grown to the drum, 2.6 -> 102 % off; most
#: trials of the prints' pieces the rule fixes found them at 0.16-0.52).
FOOT_TRIAL_MIN_CONFIDENCE = 0.15
#: With the rig given, a miss (no face, or one refused, after every channel measure's
#: _run_rig tries) where a seam's two edges took two of a side's ranked places and left
#: out the nearest peak beyond the seam is measured again with that peak a candidate
#: (search.SEAM_TAKES_TWO; session 49, helper E: on every frame the extra pairs moved
#: right answers' confidence both ways; as a rerun of each channel's own miss, it
#: pre-empted luminance's right answer: own procedural/2022 ordinary 0.2 -> 5.6 %).
SEAM_MISS_RERUN = True
#: A face found by its colour in place of the edges' face standing above the contact band
#: (STANDING_BEHIND_RESCUE), lying between that face's sides and reaching as high (its top
#: at most RESCUE_SAME_TOP_ROWS under that face's: the same face, its foot read in the
#: band), takes those sides as far as their strips rise as its own (region.sides_rising):
#: the colour's run along the foot ends at a gloss's highlight or shade, the sides' edges
#: do not. "Between" allows RESCUE_SIDES_SLACK columns past either side (the sides'
#: snapping); a colour face lower than the edges' top is a box in front of an outline of
#: what stands behind it.
RESCUE_TAKES_EDGE_SIDES = True
RESCUE_SIDES_SLACK = SNAP_COLUMNS
RESCUE_SAME_TOP_ROWS = 2
#: With the rig, the top as settled is lowered to where the face's own surface begins
#: under it when the rows between are something else from side to side, ending at an
#: edge (:func:`.region.lower_top_to_surface`): the face is one surface from its foot up
#: to its top, and a top on a background line in line above it (a rocket's or a
#: platform's edge, a wall band) has that background between (a switch for the tests).
SURFACE_UP_TO_TOP = True
#: ... without the rig too (under a floor row merely tried): the face's surface is read
#: between its own foot and top, whatever rig gave the row; the no-rig search's top up a
#: photographed rocket in line above a face was swapped in over the rig's own (photo/3026
#: ordinary +121 %) (a switch for the tests).
SURFACE_ANY_FLOOR = True
#: ... and on the colour rescue's face after its walks up, which nothing judged there: its
#: sides' walk ran up beside two posters to the image's top (photo/3109 hard, no rig,
#: +51 %) (a switch for the tests).
SURFACE_IN_RESCUE = True
#: ... and on the outline read from the face's foot (foot_outline.outline_from_foot): its
#: sides rise from the floor as far as their edges run, and a background standing in
#: line behind the face with its edges over the face's (a rocket photographed above a
#: narrow face) carries them on past the face's top; the surface rule had lowered the
#: top to where the face begins and the outline raised it back (photo/3255 hard, +85 %)
#: (a switch for the tests).
OUTLINE_SURFACE_TOP = True
#: With the rig, a top where the face's colour ends (region.stops_at_colour_top: the
#: inner edges' raise judged short, the rows above unlike those below and the face's
#: foot, from side to side) is not raised by the colour and sides walks either: their
#: looser limits (the face's spread, up to region.MAX_FACE_DISTANCE) let a print's wide
#: spread pass what stands in line behind the face (photo/2085 hard: a poster under a
#: photographed rocket, +131 -> +2 %; a switch for the tests).
COLOUR_TOP_STAYS = True
#: Every face measured (the edges', the colour's and texture's rescues', the foot
#: outline's) has its top moved down to where its sides end: a top far above them put on
#: something standing in line behind the face (region.lower_top_where_sides_end; a switch
#: for the tests).
SIDES_END_TOP = True
#: A print's thin margin line (region.margin_line_out) moves the measured face's edges
#: out to it with a rig given only: with none, the faces of the rows tried are pieces of
#: prints whose doubts choose between them, and the line moved them (procedural 144 and
#: 2033 hard: 3 -> 74 % and 6 -> 92 %, another row's piece taken).
MARGIN_LINE_RIG_GIVEN = True

#: Every walk of the face's colour along its foot (widen_by_colour) has each side it moves
#: out rise as the face's up to the face's top (region.sides_rising), not only the edge
#: search's with the rig: with no rig too (the face is one surface from its foot to its top
#: at whatever row its contact is tried; its shadow lies on the floor whatever the row), and
#: after the colour rescue's walk from the top (RESCUE_WIDEN_AT_TOP), which ran on over a
#: brick face's shadow (procedural/2099 no rig +58 -> +2 % wide; fresh procedural/2183 no
#: rig 17 -> 6 %, held-out photo 6003 hard no rig 22 -> 5 %). A switch for the tests.
RISES_EVERY_WALK = True
#: With the rig, the edge search's face's sides' walk (region.raise_top_by_sides) also
#: crosses a band up to SIDES_HOLD_BAND_SHARE of the face found where the sides lose their
#: step but the strips inside them keep the face's colour (region.HELD_BAND_ROWS_SHARE): a
#: skirting of nearly the face's colour behind it hid its sides, and the top stayed on a
#: line inside the face (a print's lower edge). A top so raised is doubted as
#: TOP_FROM_SIDES (no top edge's score chose it).
SIDES_HOLD_BAND = True
SIDES_HOLD_BAND_SHARE = 1.5
#: With the rig, the edge search's top raised past the scored top (a closing top, the
#: inner edges', seams', colour's, sides', hue's, rail's or band's walk, one after another)
#: is judged over the whole way up (session 38, branch ``wt-b-38``, a switch): each step
#: alone may be a short way that region.face_under_raised_top does not judge (a top
#: face's, a blurred top's), while together they climb into what stands behind the face in
#: line with its sides (a rocket in a photograph on the wall: photo/736 ordinary, 203 ->
#: 182 -> 147, +94 %). The scored top stands where neither the face's colour nor its hue
#: is back under the raised top, or where the raised face would be taller than
#: RAISED_FACE_MAX_M at the face's depth (:func:`_raise_stands`). Not on a rig only
#: guessed with no rig given (``FusedMethod.rig_guessed``): there it moved which trial
#: wins (photo/2003 ordinary, no rig, 16 -> 169 %) ...
WHOLE_RAISE_JUDGED = True
#: ... (m; foot_outline.RISE_REACH_M: a face the sonar ranges is seldom taller; photo/2098
#: hard's closing top up a rocket's sides behind a panel face: 1.65 m, +369 %).
RAISED_FACE_MAX_M = 1.5
#: The colour rescue's top is raised to where its sides run on up to in the gradients
#: (region.raise_top_past_inner_edges) though the face's colour is not back under there,
#: where a margin of one colour hugs both sides from the foot up to that top
#: (region.margin_up_to_raised_top): a poster's board frames its print on every side,
#: the colour walk stopped inside the print, and what stands behind a face in line with
#: its sides does not carry one colour down both of them to its foot. With the rig only
#: (a switch for the tests; photo/3297 hard: -55 % at confidence 0.40).
MARGIN_HOLDS_RAISED_TOP = True
#: With the rig, the colour rescue's top is walked on up by the face's mean colour over
#: windows of rows (region.raise_top_by_windows; a switch for the tests). Not on a rig only
#: guessed with no rig given (``FusedMethod.rig_guessed``): merged with
#: measure.SMALL_FACE_GROWN, whose rows are read on guessed rigs, it walked a small face's
#: top into the wall above it (fresh photo/2189 ordinary, no rig, 1.6 -> 195 %).
WINDOW_RESCUE_TOP = True


def _across_stripe(
    seen: npt.NDArray[Any],
    v: View,
    ay: npt.NDArray[np.float32],
    ax3: npt.NDArray[np.int16],
    rb: int,
    top: int,
    ul: int,
    ur: int,
    depth: float,
    noise: float,
    rig_known: bool,
) -> tuple[int, int]:
    """The sides past a stripe down the face (:func:`.region.bridge_stripe`), widened on
    across seams from its far edge; kept only where the face runs on past the stripe by
    at least the stripe's own width (a stripe at the face's real side is its edge)."""
    bl, br = bridge_stripe(seen, v, ay, ax3, rb, top, ul, ur, depth, noise)
    if (bl, br) == (ul, ur):
        return ul, ur
    wl, wr = widen_across_seams(ay, ax3, rb, top, bl, br, noise, rig_known)
    left = wl if bl != ul and bl - wl >= ul - bl else ul
    right = wr if br != ur and wr - br >= br - ur else ur
    if (left, right) != (ul, ur):
        log.debug("across a stripe: %d-%d -> %d-%d", ul, ur, left, right)
    return left, right


def contact_band(view: View, depth: float) -> tuple[float, float]:
    """The floor-contact row the view's rig predicts for a face at ``depth`` (working-view
    rows) and the band's half-height about it (the range's and the rig's errors)."""
    vb0 = view.cy + view.fy * view.rig.camera_height_m / depth
    return vb0, 3.0 + (vb0 - view.cy) * (0.03 + 0.01 / depth)


class FusedMethod:
    """The sonar-guided method for one camera and image size (buffers reused per frame)."""

    name = "fused"

    def __init__(
        self,
        view: View,
        min_confidence: float = DEFAULT_MIN_CONFIDENCE,
        eager_tables: bool = True,
    ) -> None:
        """``eager_tables``: the remap's table made now (a view measured frame after frame)
        rather than on the view's second frame (a view levelled for a pitch tried once)."""
        self.view = view
        self.min_confidence = min_confidence
        h, w = view.camera.height, view.camera.width
        self._kernel3 = np.ones((1, 3), np.uint8)
        self._remap = TableRemap(view, eager_tables)  # OpenCV's remap, from a table
        # the colour stages' Lab blocks remapped by the same table (OpenCV's values)
        view.use_colour_remap(self._remap.colour_block)
        # ... and their bookkeeping (which parts of a block are new) in C, when built
        view.use_uncovered(_c_uncovered)
        self._h, self._w = h, w
        # gradient buffers reused every frame: fresh large arrays cost more in page faults
        # than the filters themselves
        self._buf = np.empty((2, h, w), np.float32)  # |dy|, top edge
        self._adx = np.empty((2, h, w), np.int16)  # d/dx, made |dx| in place; its dilation
        self._dy = np.empty((h, w), np.int16)
        self._seen: npt.NDArray[Any] | None = None  # the frame the colour stages read
        #: the view's rig only guessed from the image (measure's no-rig search, its
        #: camera height and pitch taken as known): the rules for a rig given alone skip
        self.rig_guessed = False
        self._rig_given = True  # the frame's rig given (not tried, nor guessed)
        #: the search's side candidates beyond a seam (search.SEAM_TAKES_TWO): taken
        #: (``beside_seam``) in the rig path's rerun of a miss (measure's _run_rig); the
        #: peaks the searches would add, gathered while it is off (``seam_sides``)
        self.beside_seam = False
        self.seam_sides: list[int] = []

    def run(
        self,
        image: npt.NDArray[Any],
        range_m: float,
        timer: Timer,
        colour: npt.NDArray[Any] | None = None,
        rescue: bool = True,
        floor_known: bool = True,
        rig_known: bool = True,
    ) -> Measurement:
        """``colour``: the BGR frame ``image`` was made from, when ``image`` is one channel
        of it (the face's colour along its foot sets its width). ``rescue``: where the
        edges give no clear face, seek it by its colour (off for a first try that a
        caller repeats on another channel). ``floor_known``: the floor-contact
        row comes from a rig (a file, or one fitted over frames); False while a row is
        only tried with no rig, and then neither the texture search (a texture step stands
        at many rows, a tile line or a wall's foot as well), nor the preference for faces
        on the beam's axis (it lifts a face on the axis at a wrong row over the real one),
        nor the rival taken for a top edge across part of the face is used: the row
        search was tuned without them, and on the tuning rooms they moved it both ways.
        ``rig_known``: False while the camera's height and pitch are only tried (with
        ``floor_known`` too, in the no-rig search's last rounds): the colour rescue then
        leaves a contact band running past the image's foot alone."""
        # the colour stages read blocks of the frame in Lab, some inside others
        self.view.hold_colour(colour if colour is not None else image)
        try:
            return self._stages(image, range_m, timer, colour, rescue, floor_known, rig_known)
        finally:
            self.view.hold_colour(None)

    def _stages(
        self,
        image: npt.NDArray[Any],
        range_m: float,
        timer: Timer,
        colour: npt.NDArray[Any] | None = None,
        rescue: bool = True,
        floor_known: bool = True,
        rig_known: bool = True,
    ) -> Measurement:
        """:meth:`run`'s stages, the frame's colour held."""
        v = self.view
        self._seen = colour if colour is not None else image
        self._rig_given = rig_known and not self.rig_guessed
        rig = v.rig
        fail = Measurement(detected=False, method=self.name, range_m=range_m, distance_m=range_m)
        depth = rig.face_depth(range_m)
        if depth <= 0.05:
            fail.reason = "the face depth from this range and the rig is not in front of the lens"
            return fail
        h_img, w_img = self._h, self._w
        vb0, tol = contact_band(v, depth)
        r0b, r1b = int(math.floor(vb0 - tol)), int(math.ceil(vb0 + tol))
        # (no contact row in the view's last FOOT_EDGE_FLOOR_ROWS rows: its edge needs floor
        # rows below it to show)
        r0b, r1b = max(r0b, 4), min(r1b, h_img - FOOT_EDGE_FLOOR_ROWS)

        def from_view_foot(sought: bool) -> Measurement | None:
            """Where ``sought`` (PAST_FOOT_FACE, FOOT_AT_VIEW_EDGE), with the rig given and
            the colour rescue on: the face by its colour from the view's foot up, its
            height from the predicted contact row (:meth:`_past_foot`); None otherwise."""
            if not (sought and rescue and floor_known and rig_known):
                return None
            return self._past_foot(image, colour, range_m, depth, vb0, timer)

        if r0b > r1b:
            # the rig puts the face's foot below the image
            past = from_view_foot(PAST_FOOT_FACE and vb0 > h_img)
            if past is not None:
                return past
            fail.reason = (
                f"the floor-contact row predicted from the range ({vb0:.0f}) is outside the "
                "image; check the rig's camera height and pitch"
            )
            return fail
        roi_end = min(h_img, r1b + 4)
        # only the rows above the floor-contact band
        roi = v.warp(image, roi_end, self._remap)
        timer.lap("undistort")
        n = roi.shape[0]
        ay = self._buf[0, :n]
        # both 3x3 Sobels in one pass, exact in int16 (|g| <= 1020); |d/dy| as float32,
        # the same values the float Sobels give, for less than one of them costs; the
        # signed d/dy and |d/dx| stay int16 (their sums are taken in float32 where
        # needed: integers under 2**24, exact)
        ax, ax3, dy = self._adx[0, :n], self._adx[1, :n], self._dy[:n]
        cv2.spatialGradient(roi, ax, dy)
        np.abs(ax, out=ax)  # d/dx is read only as |d/dx|: one buffer less to stream
        np.abs(dy, out=ay)
        # tolerate a column of drift on vertical edges (int16: exact, and the dilation
        # and the reads cost less than in float32)
        cv2.dilate(ax, self._kernel3, dst=ax3)
        noise = median(ay[::4, ::4]) / 0.6745 + 1.0
        timer.lap("gradients")

        # candidate search and scoring, one floor-contact row at a time
        u_lo, u_hi = beam_columns(v, range_m, depth, w_img)
        u_axis = v.cx + v.fx * rig.sonar_right_m / depth
        xb0, xb1 = rig.beam_x_bounds(range_m)
        beam_half = 0.5 * v.fx * (xb1 - xb0) / depth  # the cone's half-width in columns
        rig_given = rig_known and not self.rig_guessed
        bottoms = bottom_candidates(ay, vb0, tol, r0b, r1b, u_lo, u_hi)
        # the rows searched are the rig's prediction, not cut short by the view's foot (there
        # a face's foot is FOOT_AT_VIEW_EDGE's: past the last row searched)
        foot_known = rig_given and floor_known and math.ceil(vb0 + tol) <= r1b
        best: Candidate | None = None
        cands: list[Candidate] = []
        min_w = min_width_px(v, depth)
        seen_early = colour if colour is not None else image

        def lab_rows(r0: int, r1: int) -> npt.NDArray[np.uint8] | None:
            """The working view's rows r0..r1-1 in 8-bit Lab (None for a grey frame)."""
            if seen_early.ndim != 3:
                return None
            return v.lab(seen_early, r0, r1, 0, None, 1)

        for rb, pb in bottoms:
            found = side_candidates(
                v,
                ax,
                ax3,
                rb,
                depth,
                noise,
                u_lo,
                u_hi,
                min_w,
                roi,
                lab_rows,
                rig_known,
                self.beside_seam,
                self.seam_sides if self._rig_given and not self.beside_seam else None,
            )
            if found is None:
                continue
            sides, pairs = found
            for cand in score_pairs(
                v,
                depth,
                roi,
                ax3,
                ay,
                sides,
                pairs,
                noise,
                rb,
                pb,
                foot_known and on_rigs_row(rb, vb0, tol),
            ):
                if floor_known and not cand.ul <= u_axis <= cand.ur:
                    # the beam's axis hits what the sonar ranges: of two faces at its
                    # depth (a box and a can beside it), the one on the axis
                    share = off_axis_share(cand.ul, cand.ur, u_axis, beam_half, rig_given)
                    cand = dataclasses.replace(cand, score=cand.score * share)
                cands.append(cand)
                if best is None or cand.score > best.score:
                    best = cand
            if best is not None and best.evidence > 0.8 and not best.foot_unseen:
                break  # a clear face at the most likely floor-contact row
        if FOOT_SEEN_FIRST:
            cands = foot_seen_first(cands)
        fits = VerticalFits(ax)  # the sides' fits, shared with the refinement
        best, rivals = verified(v, ax, cands, fits)
        if FOOT_SEEN_FIRST and best is not None and not best.foot_unseen:
            # nor is a pair on the rig's row alone a rival of a face on its seen foot
            rivals = [c for c in rivals if not c.foot_unseen]
        if floor_known and best is not None and _top_cover(ay, best) < TOP_COVER_MIN:
            # a top edge across part of the face only (a skirting's top between two
            # chair legs, over a face that runs on up): a rival whose top spans it
            spanning = [
                c
                for c in rivals[1:]
                if c.score >= RIVAL_SHARE * best.score and _top_cover(ay, c) >= TOP_COVER_MIN
            ]
            if spanning:
                best = spanning[0]
        outlined = False
        if floor_known and best is not None:
            # a plain piece of a print chosen inside the face's own clean outline (a doubt
            # when no top score chose the outline's top)
            # a pair closed round the piece only where its foot is on the floor the
            # range predicts: a print standing above it is _outline's (a margin's foot
            # below it)
            foot_from = int(np.ceil(vb0 - FOOT_ABOVE_SHARE * tol))
            enclosed = enclosing_outline(v, ax, ay, best, cands, fits, foot_from)
            if enclosed is not None:
                outer, own_top = enclosed
                rivals = [outer] + [c for c in rivals if not nested(c, outer)]
                best, outlined = outer, not own_top
        timer.lap("search")
        seen = colour if colour is not None else image  # the colours the extent reads

        def from_foot(
            bottom: int, top: int, left: int, right: int, found_conf: float
        ) -> tuple[Measurement, tuple[int, int, int, int]] | None:
            """An unsure face (a piece of a print, found at ``found_conf``) measured again
            on the outline read from its foot (:meth:`_foot_outline`), with that outline;
            None when there is none or it gives no detection."""
            grown = self._foot_outline(seen, dy, noise, bottom, top, left, right, depth, vb0)
            if grown is None:
                return None
            g_bottom, g_top, g_left, g_right = grown
            if SURFACE_UP_TO_TOP and OUTLINE_SURFACE_TOP:
                # the face is one surface from its foot up to its top: the outline's sides
                # rising from the floor may run on up the edges of what stands in line
                # behind it (a rocket photographed above a narrow face), past its top
                surface = lower_top_to_surface(seen, v, ay, g_bottom, g_top, g_left, g_right)
                if surface > g_top:
                    log.debug(
                        "foot outline: top %d, the face's surface starts at %d", g_top, surface
                    )
                    g_top = surface
                    grown = (g_bottom, g_top, g_left, g_right)
            sign = 1.0 if int(dy[g_top, g_left:g_right].sum()) >= 0 else -1.0
            again = self._refine(
                ax,
                ay,
                ax3,
                dy,
                g_bottom,
                g_left,
                g_right,
                g_top,
                sign,
                None,
                found_conf,
                depth,
                range_m,
                timer,
                None,
            )
            return (again, grown) if again.detected else None

        def rescue_by_colour(
            top_at_most: int | None = None, within: tuple[int, int, int] | None = None
        ) -> Measurement | None:
            """Where the edges give no face, or none clear, the face by its colour (else,
            with the floor row known, by its texture). ``top_at_most``: a face whose top
            is lower than this row is not taken. ``within``: the sides and top of the face
            the edges found, whose sides a colour face between them with the same top
            takes as far as they rise as its (RESCUE_TAKES_EDGE_SIDES)."""
            if not rescue:
                return None
            rows = (r0b, r1b)
            found = self._by_colour(seen, ay, ax3, rows, depth, noise, floor_known, rig_known)
            if found is None and floor_known:
                found = self._by_texture(seen, ay, rows, depth)
            if found is None:
                return None
            rb, vt, ul, ur, conf = found
            log.debug("rescue: face %d-%d x %d-%d", ul, ur, vt, rb)
            if top_at_most is not None and vt > top_at_most:
                return None
            if RESCUE_TAKES_EDGE_SIDES and within is not None:
                between = (
                    within[0] - RESCUE_SIDES_SLACK <= ul and ur <= within[1] + RESCUE_SIDES_SLACK
                )
                if between and vt <= within[2] + RESCUE_SAME_TOP_ROWS:
                    edge_sides = (within[0], within[1])
                    ul, ur = sides_rising(seen, v, ax3, rb, vt, (ul, ur), edge_sides)
                    log.debug("rescue: sides out to the edges' %s: %d-%d", within, ul, ur)
            sign = 1.0 if int(dy[vt, ul:ur].sum()) >= 0 else -1.0
            # a box below the lens shows its top face: the colour's top may be that face's
            # back edge, its sides the top face's receding edges; the front top edge under
            # it is the face's top when the rows between differ in colour from the front
            # (with the rig only: under a row merely tried, the horizon is a guess)
            if floor_known:
                front, front_sign = front_top(v, depth, dy, rb, ul, ur, vt, noise)
                log.debug("rescue: top %d, front top %d", vt, front)
                if front != vt and looks_like_top_face(seen, v, vt, front, ul, ur, pattern=True):
                    vt, sign = front, front_sign
            if rig_given:
                # a side on a seam: the top and the foot run on past it to the face's corner
                ul, ur = sides_past_seams(seen, v, ay, ax3, vt, rb, (ul, ur), depth)
            colour_face = self._refine(
                ax, ay, ax3, dy, rb, ul, ur, vt, sign, None, conf, depth, range_m, timer, None
            )
            if (
                FOOT_OUTLINE
                and _foot_read(floor_known, rig_known, rb, vb0, conf)
                and _unsure(colour_face)
            ):
                # a piece of a print found by its colour or texture: the face round it
                grown = from_foot(rb, vt, ul, ur, conf)
                if grown is not None:
                    return grown[0]
            return colour_face

        def at_view_edge() -> Measurement | None:
            """Where the edges give no face, or none clear, and the rig puts the face's
            foot in the view's last rows or past them (FOOT_AT_VIEW_EDGE): the face from
            the view's foot up, as PAST_FOOT_FACE's; None otherwise. (A face refused is
            under ``min_confidence``, which any face :meth:`_past_foot` gives reaches.)"""
            if not (FOOT_AT_VIEW_EDGE and foot_at_view_edge(vb0, h_img)):
                return None
            log.debug("foot %.0f at the view's edge: the face from the view's foot up", vb0)
            return from_view_foot(True)

        if best is None:
            rescued = rescue_by_colour()
            if rescued is not None:
                return rescued
            at_foot = at_view_edge()
            if at_foot is not None:
                return at_foot
            fail.reason = "no face with a floor-contact edge and two vertical sides near the range"
            return fail

        # the face's sides run on past a label's edge up to its real top: a higher top
        # candidate where they stop (scoring.closing_top), else where they end
        rb, ul, ur, vt = best.rb, best.ul, best.ur, best.vt
        closed = best.closing is not None
        print_top = closed and best.print_top and CLOSED_TOP_KEPT
        if best.closing is not None:
            vt = best.closing
        raised = raise_top_past_inner_edges(ay, ax3, rb, vt, ul, ur, noise)
        if (
            rig_known
            and vt - raised <= RAISE_SPAN_MAX_RAISE * (rb - vt)
            and not raise_spans_face(ay, vt, raised, ul, ur, noise)
        ):
            # the found top's line spans the face, the raised top's does not: the sides
            # ran on up what stands behind in line with the face (a piece under a raise
            # longer than itself is a band across the face's foot, a label, a plank: its
            # line spans the piece only, and the raise is the sides' to make)
            log.debug("top %d: the raise to %d ends on no line across the face", vt, raised)
            raised = vt
        seam_top = False  # the top where the face's own seams end
        if SEAMS_RAISE_TOP and rig_known:
            # a face in the wall's shade: its own seams run on past a background line
            by_seams = raise_top_along_seams(ay, ax3, rb, raised, ul, ur, noise)
            seam_top, raised = by_seams < raised, by_seams
        # a short way up past a top where the face's colour ends: a top face or a
        # background band of the face's width, its sides the edges of what is behind;
        # that top is the front top edge already (no top face's front below it)
        colour_top = stops_at_colour_top(seen, v, rb, vt, raised, ul, ur)
        if colour_top or not face_under_raised_top(seen, v, rb, vt, raised, ul, ur):
            raised, seam_top = vt, False
        # what lowers the reported confidence: no top edge's score chose that row
        doubts = [TOP_FROM_SIDES] if raised < vt or closed else []
        if outlined:
            doubts.append(PRINT_OUTLINE)
        if best.foot_unseen:
            doubts.append(FOOT_UNSEEN)  # the rig's contact row stood in for the foot edge
        vt = raised
        # a print on the face with a margin of the face's colour: the face is its frame
        ul, ur, frame_top = enclose_inner_frame(ay, ax3, rb, vt, ul, ur, noise)
        if not (
            FRAME_KEEPS_COLOUR
            and vt - frame_top >= FRAME_CHECKED_RAISE * (rb - vt)
            and ends_in_colour(seen, v, rb, vt, ul, ur)
        ):
            # a frame's margin keeps its colour up past the print's top, beside it too;
            # where the colour ends there from side to side, what the sides ran on past
            # is behind the face, and the print's top is the face's
            vt = frame_top
        framed = enclose_by_margin(seen, v, rb, vt, ul, ur, depth)
        if framed is None and floor_known and vb0 - rb <= FOOT_ABOVE_SHARE * tol:
            # a margin too thin for fixed strips: its own colour runs, its foot on the floor
            # (a face standing above the floor's row is _outline's, after the confidence)
            framed = enclose_by_ring(seen, v, rb, vt, ul, ur, (r0b, r1b))
            if framed is None and BESIDE_FOOT_FIRST:
                # ... or no margin under the print (its foot the face's own), the margin
                # beside it running up to the frame's top (as after the texture rescue)
                framed = enclose_beside_foot(seen, v, rb, vt, ul, ur, (r0b, r1b))
        if framed is None and MARGIN_UNDER_TRIED_ROW and not floor_known:
            # no rig: the row tried stands a print whose margin (the face's own colour)
            # runs on under it to a foot below the row: the frame is the face (where its
            # foot lies within the rows read; past them the row tried stands as it is)
            framed = margin_under_print(seen, v, rb, int(vt), ul, ur)
            if framed is not None and framed[0] >= n - 3:
                # its foot past the rows read: doubted below (the row is no foot) where the
                # margin over the print is a band, not the top edge's blend; not taken
                over = int(vt) - RING_SKIP - framed[1]  # the margin's rows over the print
                if not (FRAMED_PAST_ROWS_DOUBT and over >= FRAMED_PAST_ROWS_MIN_OVER):
                    framed = None
        if framed is not None:
            doubts.append(FRAMED)  # a print in a margin, even one running on below the rows
        if framed is not None and framed[0] >= n - 3:
            framed = None
        if framed is not None and floor_known and framed[0] > vb0 + tol:
            # a frame whose foot lies below the contact rows the rig predicts would stand
            # nearer than the range: the print found on those rows is the face, and what
            # surrounds it (floor and wall of one shade) is no margin of it
            framed = None
        if framed is not None:
            rb, vt, ul, ur = framed
        # a background line crossing the face is not its top: the face's colour runs on
        # (a frame's top margin is the front top edge of a low box's top face seen above
        # it: a short way up to where that face's back edge ends the colour is no face)
        # (with the rig, the face's colour must reach the pair's sides: they stand up from
        # the floor row the range predicts; under a row merely tried a poster face's
        # strips, unlike its middle, stopped its walk: photo/1490 hard)
        coloured = raise_top_by_colour(seen, v, ay, rb, vt, ul, ur, depth, edge_sides=rig_known)
        if COLOUR_TOP_STAYS and colour_top and rig_known:
            # the face's colour ends at this top (the sides ran on a short way only): the
            # walks up read what stands in line behind it, not the face
            coloured = vt
        if face_under_raised_top(seen, v, rb, vt, coloured, ul, ur) and not (
            framed is not None and top_face_above(seen, v, rb, vt, coloured, ul, ur)
        ):
            vt = coloured
        walked = raise_top_by_sides(seen, v, ay, rb, vt, ul, ur, depth)
        tops = [walked]  # the tops the sides' walks reached, highest first
        if SIDES_HOLD_BAND and rig_known and not (COLOUR_TOP_STAYS and colour_top):
            past_band = raise_top_by_sides(
                seen, v, ay, rb, vt, ul, ur, depth, held_band_share=SIDES_HOLD_BAND_SHARE
            )
            if past_band < walked:
                log.debug(
                    "top %d: the sides' strips hold the face's colour up to %d", walked, past_band
                )
                tops.insert(0, past_band)
        if COLOUR_TOP_STAYS and colour_top and rig_known:
            tops = [vt]
        # the held band's crossing may be refused where the plain walk's top still holds
        for k, top in enumerate(tops):
            if face_under_raised_top(seen, v, rb, vt, top, ul, ur, one_strip=True) and not (
                framed is not None and top_face_above(seen, v, rb, vt, top, ul, ur)
            ):
                vt = top
                if k < len(tops) - 1 and TOP_FROM_SIDES not in doubts:
                    doubts.append(TOP_FROM_SIDES)  # no top edge's score chose that row
                break
        if HUE_HOLDS_TOP and framed is None and not (COLOUR_TOP_STAYS and colour_top and rig_known):
            # a gloss's highlight across the face stopped both walks: the face's hue goes on
            hued = raise_top_by_hue(seen, v, ay, rb, vt, ul, ur, depth)
            if hued < vt:
                log.debug("top %d: the face's hue holds up to %d", vt, hued)
                vt = hued
        if FRAME_RAIL_RAISE and rb - vt < THIN_STRIP_SHARE * (ur - ul):
            # a thin strip at the foot: a frame's bottom rail, its sides running on above
            rail_top = raise_top_along_frame(seen, v, ay, rb, vt, ul, ur, depth)
            if rail_top != vt:
                log.debug("frame rail %d-%d: top raised to %d", vt, rb, rail_top)
            vt = rail_top
        if FRAME_CLOSES_TOP and framed is None:
            # the print's frame closes over it above the top found: the face's top
            frame_top = raise_top_to_frame(seen, v, rb, vt, ul, ur, depth)
            if frame_top < vt:
                log.debug("top %d: the print's frame closes at %d", vt, frame_top)
                vt = frame_top
                if TOP_FROM_SIDES not in doubts:
                    doubts.append(TOP_FROM_SIDES)
        band_from: int | None = None  # the top the band walk carried up ...
        band_rows = 0  # ... and by how many rows
        if EDGE_SKIRTING_WALK and rig_known:
            # a top on a band's edge behind the face (a skirting's running on along the
            # wall), where the face's sides merely lost the band's contrast: walked on up
            # while its colour holds (procedural/2033: a brick print's margin, the top
            # taken at an orange skirting's edge, height -70 %)
            band_top = raise_top_past_band(seen, v, ay, rb, vt, ul, ur, depth, runs_on=True)
            if band_top < vt:
                log.debug("top %d past a band's edge behind the face: %d", vt, band_top)
                band_from, band_rows, vt = vt, vt - band_top, band_top

        if (
            WHOLE_RAISE_JUDGED
            and rig_known
            and not self.rig_guessed
            and framed is None
            and vt < best.vt
            and not _raise_stands(seen, v, rb, best.vt, vt, ul, ur, depth)
        ):
            log.debug("top %d: the whole way up from %d refused", vt, best.vt)
            vt, print_top, seam_top = best.vt, False, False
            band_from, band_rows = None, 0
            doubts = [d for d in doubts if d != TOP_FROM_SIDES]

        # confidence
        conf = confidence(best, rivals, parts_agree=floor_known)
        reason = refusal(conf, self.min_confidence)
        rescued_first: list[Measurement | None] = []  # the rescue, tried once
        if reason is not None and PRINT_EVIDENCE and rig_known and rescue:
            # a face refused for a print of its own over it from its foot up (its texture
            # cut its evidence): weighed without that texture, in the try that rescues,
            # where the colour finds no surer face (what the refusal gives it, as before)
            printed = dataclasses.replace(best, evidence=best.print_evidence)
            again = confidence(printed, rivals, parts_agree=floor_known)
            if again > conf and refusal(again, self.min_confidence) is None:
                rescued_first.append(rescue_by_colour())
                first = rescued_first[0]
                inner = (
                    FRAME_OVER_INNER_RESCUE
                    and first is not None
                    and framed is not None
                    and _inside_frame(v, first, framed)
                )
                if inner:
                    log.debug("rescue inside the frame %s: the print again", framed)
                if first is not None and (first.confidence or 0.0) > conf and not inner:
                    return first
                log.debug("face refused at %.3f: a print of its own, %.3f", conf, again)
                conf, reason = again, None
        if reason is not None:
            rescued = rescue_by_colour()
            if rescued is not None and (rescued.confidence or 0.0) > conf:
                return rescued
            at_foot = at_view_edge()
            if at_foot is not None:
                return at_foot
            fail.confidence = round(conf, 3)
            fail.reason = reason
            return fail

        # the front top edge, then sub-pixel refinement
        found_top = vt
        undone: tuple[int, int] | None = None  # FRONT_STEP_UNDONE's top kept and step
        # a frame's top is its margin's (the print below it is no top face)
        if framed is None:
            vt, sign = front_top(v, depth, dy, rb, ul, ur, vt, noise, horizon_known=rig_given)
            if (
                colour_top
                and vt != found_top
                and not _front_ends_colour(seen, v, rb, found_top, vt, ul, ur)
            ):
                # under a top where the face's colour ends, a front top edge ends it too
                if (
                    FRONT_STEP_UNDONE_DOUBT
                    and rig_given
                    and vt - found_top >= FRONT_STEP_UNDONE_SHARE * (rb - found_top)
                    and FRONT_STEP_UNDONE not in doubts
                ):
                    # ... or the top kept is a faint top face's back edge (see the doubt)
                    log.debug("top %d: the front step at %d undone by colour", found_top, vt)
                    doubts.append(FRONT_STEP_UNDONE)
                    undone = (found_top, vt)
                vt, sign = found_top, (1.0 if int(dy[found_top, ul:ur].sum()) >= 0 else -1.0)
        else:
            sign = 1.0 if int(dy[vt, ul:ur].sum()) >= 0 else -1.0
        if not looks_like_top_face(seen, v, found_top, vt, ul, ur):
            vt, sign = found_top, (1.0 if int(dy[found_top, ul:ur].sum()) >= 0 else -1.0)
        top_row: float | None = None  # a sub-pixel front top row that needs no refining
        front = None if framed is not None else front_from_back(v, depth, ay, dy, rb, ul, ur, vt)
        if (
            colour_top
            and front is not None
            and not _front_ends_colour(seen, v, rb, vt, front[0], ul, ur)
        ):
            front = None
        if front is not None and looks_like_top_face(seen, v, vt, front[0], ul, ur):
            vt, sign, top_row = front
        across = None
        if framed is None and rig_known:
            # a seam and a tower behind in line with it taken for the sides, the top raised
            # up the tower: the face's top line crosses them, ending at its real sides
            across = top_line_across(ay, ax3, rb, int(round(vt)), ul, ur, noise)
        if across is not None and not _across_ends_colour(seen, v, across):
            log.debug(
                "top line across %d-%d at %d: no colour ends there (a joint)", ul, ur, across[0]
            )
            across = None
        if across is not None:
            log.debug("top line across %d-%d (top %.0f): %s", ul, ur, vt, across)
            vt, ul, ur = across
            sign, top_row = (1.0 if int(dy[vt, ul:ur].sum()) >= 0 else -1.0), None
        # the face's front top and bottom edges run on across seams out to its real sides
        span = (ul, ur)  # the top and bottom edges are fitted where the search found them
        ul, ur = widen_across_seams(
            ay, ax3, rb, int(round(vt)), ul, ur, noise, rig_known, narrow=rig_given, faded=rig_given
        )
        # ... and across a stripe down the face (a tape): a marking on it, not a gap
        ul, ur = _across_stripe(
            seen, v, ay, ax3, rb, int(round(vt)), ul, ur, depth, noise, rig_known
        )
        # ... and its top line runs from side to side: a side with none next to it over a
        # part of the width stands on something beside the face (extent.TOP_LINE_SPANS)
        trimmed = trim_to_top_line(ay, ax3, rb, int(round(vt)), ul, ur, noise)
        if trimmed != (ul, ur):
            log.debug("top line ends inside %d-%d: %s", ul, ur, trimmed)
            ul, ur = trimmed
        # ... and stand on the floor-contact row: no side beyond where the face's foot ends
        # (a print's frame is a margin's colour run already: its sides are that margin's)
        if framed is None:
            ul, ur = trim_to_foot(seen, v, ax3, rb, int(round(vt)), ul, ur, depth, span)
        walked_from = (ul, ur)  # the sides before the colour walk along the foot
        ul, ur = widen_by_colour(
            seen,
            v,
            ax3,
            rb,
            int(round(vt)),
            ul,
            ur,
            depth,
            foot_above=floor_known and vb0 - rb > FOOT_ABOVE_SHARE * tol,
            rising_kept=rig_known,
            outline_past=rig_given,  # the rig given, not guessed for a trial
        )

        def finish(
            top: tuple[int, float, float | None],
        ) -> tuple[int, float, float | None, float]:
            """The top lowered to the background beside the face, and the confidence its
            agreement with the face's colours leaves."""
            vt, sign, top_row = top
            # an object behind the face in line with its sides: the face's top is where
            # the background beside it shows past it
            lowered = lower_top_to_background(seen, v, rb, int(round(vt)), ul, ur)
            if lowered > vt and not print_top:
                vt, top_row = lowered, None
                sign = 1.0 if int(dy[lowered, ul:ur].sum()) >= 0 else -1.0
            elif not seam_top:
                # a top face narrower than the front, the background seen past both
                # sides above its front edge: that edge is found from there
                past = lower_top_past_top_face(seen, v, rb, int(round(vt)), ul, ur)
                if past > vt:
                    vt, sign = front_top(v, depth, dy, rb, ul, ur, past, noise)
                    top_row = None
                    log.debug("top face seen past the sides from %d: front top %d", past, vt)
            # a top that is no colour boundary may be a line on the face or behind it
            agree = top_agreement(seen, v, int(round(vt)), ul, ur)
            if band_from is not None:
                # the walk past the band adds no evidence: the lesser of the two tops'
                agree = min(agree, top_agreement(seen, v, band_from, ul, ur))
            agree *= side_agreement(seen, v, rb, int(round(vt)), ul, ur)
            return vt, sign, top_row, conf * agree

        vt, sign, top_row, face_conf = finish((vt, sign, top_row))
        refused = face_conf < self.min_confidence
        # the colour's face for a face refused here (tried once: the refusal below reads it)
        rescued_once = rescued_first
        if (
            floor_known
            and framed is None
            and (not refused or (SETTLED_REFUSED and rig_known and rescue))
            and not (SETTLED_KEEPS_ACROSS and across is not None)
            and _moved(span, (ul, ur))
        ):
            # the top was decided between the search's sides; the face's sides settled
            # far from them (one plank of a face, or a face with the background beside
            # it): its top decided again between the sides it has, taken where it moved
            # and the face under it is still one to report. A face this top refused (with
            # the rig: SETTLED_REFUSED) is decided so only where the colour finds no surer
            # face (what the refusal gives it, as before)
            if refused:
                if not rescued_once:
                    rescued_once.append(rescue_by_colour())
                first = rescued_once[0]
                if first is not None and (first.confidence or 0.0) > face_conf:
                    return first
            settled = self._settled_top(
                seen,
                ay,
                dy,
                rb,
                ul,
                ur,
                depth,
                noise,
                found_top,
                colour_top,
                seams=ax3 if rig_given and SETTLED_SEAMS_RAISE else None,
            )
            decided = finish(settled)
            log.debug("top %d between the settled sides, %d as first found", decided[0], vt)
            if (
                abs(decided[0] - vt) >= SETTLED_TOP_MOVE * (rb - vt)
                and decided[3] >= self.min_confidence
            ):
                vt, sign, top_row, face_conf = decided
        if SURFACE_UP_TO_TOP and (SURFACE_ANY_FLOOR or (rig_known and floor_known)):
            # the face is one surface from its foot up to its top: a top with something
            # else from side to side between it and the face's colour is a line behind
            surface = lower_top_to_surface(seen, v, ay, rb, int(round(vt)), ul, ur)
            if surface > vt:
                log.debug("top %d: the face's surface starts at %d", vt, surface)
                vt, top_row = surface, None
                sign = 1.0 if int(dy[surface, ul:ur].sum()) >= 0 else -1.0
        if rig_known or RISES_EVERY_WALK:
            # a side the walk moved out rises as the face's up to the top as settled (no
            # shadow's, no floor's at its foot): read under the top found for the sides the
            # walk gave (before it, a top found too high read the background up there)
            ul, ur = sides_rising(seen, v, ax3, rb, int(round(vt)), walked_from, (ul, ur))
        if rig_given:
            # a side on a seam: the top and the foot run on past it to the face's corner
            ul, ur = sides_past_seams(seen, v, ay, ax3, int(round(vt)), rb, (ul, ur), depth)
        conf = face_conf
        reason = refusal(conf, self.min_confidence)
        if reason is not None:
            rescued = rescued_once[0] if rescued_once else rescue_by_colour()
            if rescued is not None and (rescued.confidence or 0.0) > conf:
                return rescued
            at_foot = at_view_edge()
            if at_foot is not None:
                return at_foot
            fail.confidence = round(conf, 3)
            fail.reason = reason
            return fail
        if floor_known and vb0 - rb > FOOT_ABOVE_SHARE * tol:
            # standing above the floor the rig predicts: a print on the face, whose own
            # sides stand on down to the floor round it
            outline = self._outline(
                seen, ay, ax3, rb, int(round(vt)), ul, ur, (r0b, r1b), depth, noise, rig_known
            )
            if outline is not None:
                rb, vt, ul, ur = outline
                sign, top_row = (1.0 if int(dy[vt, ul:ur].sum()) >= 0 else -1.0), None
            elif STANDING_BEHIND_RESCUE:
                # no face round it: what stands at the range is on the floor the rig
                # predicts; its colour there, reaching up as high, is the face
                rescued = rescue_by_colour(
                    vt + int(STANDING_TOP_SHARE * (rb - vt)), (ul, ur, int(round(vt)))
                )
                if rescued is not None and rescued.detected:
                    log.debug("face standing above the contact band: the colour's face")
                    return rescued
            if outline is None and FACE_DOWN_TO_FOOT:
                # no print, no other face standing in the band: the face's own colour may
                # run on down to the foot the rig predicts
                down = face_down_to_foot(seen, v, ay, rb, ul, ur, (r0b, r1b), noise)
                if down is not None:
                    log.debug("foot %d: the face's colour runs down to %d", rb, down)
                    rb = down
        timer.lap("extent")
        measured = self._refine(
            ax, ay, ax3, dy, rb, ul, ur, vt, sign, top_row, conf, depth, range_m, timer, span, fits
        )
        # what the face as measured leaves in doubt (the reported confidence only)
        faced = face_doubts(
            v.camera,
            seen,
            ay,
            rb,
            ul,
            ur,
            vt,
            best,
            rivals,
            measured.lines,
            below_horizon=looks_down_on(v, vt),
        )
        measured.doubts = _kept_doubts(
            v, [*doubts, *faced, *contact_doubts(rb, vb0, tol)], measured.lines, undone
        )
        strip = measured
        if band_rows and measured.height_px is not None:
            # a thin strip carried past a band's edge is weighed as the edges found it
            strip = dataclasses.replace(measured, height_px=measured.height_px - band_rows)
        if floor_known and thin_strip(strip):
            rescued = rescue_by_colour()
            if rescued is not None and stands_for_strip(rescued, measured):
                log.debug("a thin strip at the foot: the colour's face, surer")
                return rescued
        if FOOT_OUTLINE and _foot_read(floor_known, rig_known, rb, vb0, conf) and _unsure(measured):
            # an unsure face, a piece of a print over the face: the outline round it read
            # from the face's foot
            grown = from_foot(rb, int(round(vt)), ul, ur, conf)
            if grown is not None:
                regrown, (g_bottom, g_top, g_left, g_right) = grown
                faced = face_doubts(
                    v.camera,
                    seen,
                    ay,
                    g_bottom,
                    g_left,
                    g_right,
                    g_top,
                    best,
                    rivals,
                    regrown.lines,
                    below_horizon=looks_down_on(v, g_top),
                )
                regrown.doubts = _kept_doubts(
                    v,
                    [*doubts, *faced, *contact_doubts(g_bottom, vb0, tol)],
                    regrown.lines,
                    undone,
                )
                return regrown
        return measured

    def _foot_outline(
        self,
        seen: npt.NDArray[Any],
        dy: npt.NDArray[np.int16],
        noise: float,
        rb: int,
        vt: int,
        ul: int,
        ur: int,
        depth: float,
        vb0: float,
    ) -> tuple[int, int, int, int] | None:
        """The face's outline read from its foot (:func:`.foot_outline.outline_from_foot`)
        round a face found as a piece of a print: read on the floor-contact row the rig
        predicts (the face stands there, a print's found foot may be a margin's width
        above it), the face's foot there unless the found one is within FOOT_SAME_ROWS."""
        foot = int(round(vb0))
        log.debug("foot outline from %d round %d-%d x %d-%d", foot, ul, ur, vt, rb)
        grown = outline_from_foot(seen, self.view, foot, rb, vt, ul, ur, depth)
        if grown is None:
            return None
        bottom = rb if abs(rb - foot) <= FOOT_SAME_ROWS else foot
        _, top, left, right = grown
        if top == vt:
            return bottom, top, left, right  # widened only: the found top, judged already
        # a face lower than the lens shows its top face over its front: the sides' rises
        # end at its back edge, the face's top is the front edge under it
        front, _ = front_top(self.view, depth, dy, bottom, left, right, top, noise)
        if front != top and looks_like_top_face(seen, self.view, top, front, left, right):
            log.debug("foot outline: top %d, a top face's back edge over the front %d", top, front)
            # an outline lowered to where the sides end (top > vt) grows nothing: the
            # front edge is not asked to grow the face, but the top still moves to it
            # (photo 3214 hard: 221 -> 226)
            if top < vt and not grows_face((rb, vt, ul, ur), front, left, right):
                return None
            top = front
        return bottom, top, left, right

    def _settled_top(
        self,
        seen: npt.NDArray[Any],
        ay: npt.NDArray[np.float32],
        dy: npt.NDArray[np.int16],
        rb: int,
        ul: int,
        ur: int,
        depth: float,
        noise: float,
        start: int,
        colour_top: bool,
        seams: npt.NDArray[np.int16] | None = None,
    ) -> tuple[int, float, float | None]:
        """The face's top decided again between the sides the width stages settled on:
        from ``start`` (the top before its front edge was sought), the colour's and the
        sides' raises, the front top edge and whether the rows above it look like a top
        face, each reading the face's columns as they are now (so the top may go down as
        well as up). ``colour_top``: the face's colour ended at the top the search's sides
        gave (a front top edge under it must end it too). ``seams``: the vertical
        gradients, given with the rig given (SETTLED_SEAMS_RAISE): the top is also raised to
        where the face's own seams between these sides end. Returns the row, its
        gradient's sign and, from :func:`.top.front_from_back`, a sub-pixel row or None."""
        v = self.view
        vt = raise_top_by_colour(seen, v, ay, rb, start, ul, ur, depth)
        vt = raise_top_by_sides(seen, v, ay, rb, vt, ul, ur, depth)
        if seams is not None:
            # ... and the face's own seams between these sides run on past it to its top
            by_seams = raise_top_along_seams(ay, seams, rb, vt, ul, ur, noise)
            if by_seams < vt:
                log.debug("settled top %d up the face's seams: %d", vt, by_seams)
                vt = by_seams
        if PRINT_OUTLINE_TOP:
            # ... and a print's pattern stopped both walks: up its outline (as the rescue)
            outlined = raise_top_by_outline(seen, v, ay, rb, vt, ul, ur, depth)
            if outlined < vt:
                log.debug("settled top %d up the print's outline: %d", vt, outlined)
                vt = outlined
        if FRAME_CLOSES_TOP:
            framed_top = raise_top_to_frame(seen, v, rb, vt, ul, ur, depth)
            if framed_top < vt:
                log.debug("settled top %d up to the print's frame: %d", vt, framed_top)
                vt = framed_top
        found_top = vt
        # the raises read the face's columns as they are now, up to a top face's back
        # edge or past it: its front edge is sought as far below as from a back edge
        vt, sign = front_top(v, depth, dy, rb, ul, ur, vt, noise, from_back=True)
        if (
            colour_top
            and vt != found_top
            and not _front_ends_colour(seen, v, rb, found_top, vt, ul, ur)
        ) or not looks_like_top_face(seen, v, found_top, vt, ul, ur):
            vt, sign = found_top, (1.0 if int(dy[found_top, ul:ur].sum()) >= 0 else -1.0)
        front = front_from_back(v, depth, ay, dy, rb, ul, ur, vt)
        if (
            colour_top
            and front is not None
            and not _front_ends_colour(seen, v, rb, vt, front[0], ul, ur)
        ):
            front = None
        if front is not None and looks_like_top_face(seen, v, vt, front[0], ul, ur):
            vt, sign, top_row = front
            log.debug("sides settled at %d-%d: front top %d", ul, ur, vt)
            return vt, sign, top_row
        log.debug("sides settled at %d-%d: top %d", ul, ur, vt)
        return vt, sign, None

    def _outline(
        self,
        seen: npt.NDArray[Any],
        ay: npt.NDArray[np.float32],
        ax3: npt.NDArray[np.int16],
        rb: int,
        vt: int,
        ul: int,
        ur: int,
        band: tuple[int, int],
        depth: float,
        noise: float,
        rig_known: bool = False,
    ) -> tuple[int, int, int, int] | None:
        """The face round a print found standing above the floor-contact ``band`` (with
        the rig known the face's foot is there): its foot the strongest edge in the band
        under the print, its sides where the margin of the face's colour between the two
        ends (:func:`.region.widen_along_margin`), its top where its sides and its colour
        end (with ``rig_known``, the whole way up from ``vt`` judged: WHOLE_RAISE_JUDGED);
        None when no margin of one colour encloses the print."""
        v = self.view
        nb = foot_in_band(ay, rb, ul, ur, band, noise)
        if nb is None:
            return None
        reach = max(SNAP_COLUMNS, int(OUTLINE_REACH * max(ur - ul, rb - vt)))
        far = int(v.fx * OUTLINE_FAR_M / depth)
        sides = widen_along_margin(seen, v, rb, nb, ul, ur, reach, far)
        if sides is None:
            return None
        nl, nr = sides
        nt = raise_top_past_inner_edges(ay, ax3, nb, vt, nl, nr, noise)
        nt = raise_top_by_colour(seen, v, ay, nb, nt, nl, nr, depth)
        nt = raise_top_by_sides(seen, v, ay, nb, nt, nl, nr, depth)
        nt = min(nt, vt)
        if (
            WHOLE_RAISE_JUDGED
            and rig_known
            and not self.rig_guessed
            and nt < vt
            and not _raise_stands(seen, v, nb, vt, nt, nl, nr, depth)
        ):
            log.debug("outline: the whole way up from %d to %d refused", vt, nt)
            nt = vt
        # the sides ran on up into the background: the frame closes where the margin does
        framed_top = frame_top_by_margin(seen, v, rb, nb, nt, nl, nr)
        if framed_top is not None and framed_top > nt:
            log.debug("outline: the frame's margin closes at %d, not %d", framed_top, nt)
            nt = framed_top
        log.debug("outline round a print standing at %d: %d-%d x %d-%d", rb, nl, nr, nt, nb)
        return nb, nt, nl, nr

    def _by_colour(
        self,
        seen: npt.NDArray[Any],
        ay: npt.NDArray[np.float32],
        ax3: npt.NDArray[np.int16],
        rows: tuple[int, int],
        depth: float,
        noise: float,
        floor_known: bool = True,
        rig_known: bool = True,
    ) -> tuple[int, int, int, int, float] | None:
        """The face from its colour alone (:func:`.region.face_from_colour`): (contact row,
        top, left, right, confidence), or None: where the edges gave no face or no clear
        one (a brick pattern's joints, a face the floor's shade in grey)."""
        found = face_from_colour(seen, self.view, ax3, ay, rows, depth, rig_known)
        if found is None:
            return None
        rb, vt, ul, ur, evidence = found
        if evidence < self.min_confidence or rb >= ay.shape[0] - 3:
            return None
        if RESCUE_SNAP_SIDES:
            # the foot's colour run may end on the face's shadow beside it (a face of the
            # floor's shade in grey): its sides to the strong colour steps next to them
            snapped = snap_sides_to_steps(seen, self.view, rb, vt, ul, ur, depth)
            log.debug("rescue: sides %d-%d snapped to %d-%d", ul, ur, *snapped)
            ul, ur = snapped
        # the sides, in the gradients, may run on above where the colour walk stopped (a
        # joint or a label across the face): the face's top is where they end
        raised = raise_top_past_inner_edges(ay, ax3, rb, vt, ul, ur, noise)
        # ... unless the face's colour ends at its top a short way under where they end:
        # those are the edges of what stands behind it in line (as in the edge search)
        # (with the rig only, as the front top edge in rescue_by_colour)
        # ... or where the face's colour is not back under where they end (as in the edge
        # search): sides that run on through another colour up to there are the edges of
        # what stands behind the face in line with it (a frame, a rail)
        if not (
            floor_known
            and (
                stops_at_colour_top(seen, self.view, rb, vt, raised, ul, ur)
                or (
                    RESCUE_RAISE_BY_COLOUR
                    and not face_under_raised_top(seen, self.view, rb, vt, raised, ul, ur)
                    and not (
                        MARGIN_HOLDS_RAISED_TOP
                        and rig_known
                        and margin_up_to_raised_top(seen, self.view, rb, vt, raised, ul, ur)
                    )
                )
            )
        ):
            vt = raised
        # ... and where they do not show in the gradients (a face of the background's
        # shade in grey), its colour parts it from what is beside it up to its top
        vt = raise_top_by_sides(seen, self.view, ay, rb, vt, ul, ur, depth, one_side=True)
        if HUE_HOLDS_TOP:
            # ... and past a gloss's highlight that stopped both walks: the face's hue holds
            hued = raise_top_by_hue(seen, self.view, ay, rb, vt, ul, ur, depth)
            if hued < vt:
                log.debug("rescue: top %d, the face's hue holds up to %d", vt, hued)
                vt = hued
        # ... and past a band's edge behind it (a skirting's) where its sides merely lost
        # the band's contrast against the wall above it
        # (no surer for it: the confidence is the lesser of the two tops' agreements)
        agree = top_agreement(seen, self.view, vt, ul, ur)
        if SKIRTING_WALK:
            past = raise_top_past_band(seen, self.view, ay, rb, vt, ul, ur, depth)
            if past < vt:
                log.debug("rescue: top %d past a band's edge behind the face: %d", vt, past)
                vt = past
                agree = min(agree, top_agreement(seen, self.view, vt, ul, ur))
        if PRINT_OUTLINE_TOP:
            # a print's pattern stopped the colour walks: its top is where its outline's
            # sides end, closed by the background over it
            outlined = raise_top_by_outline(seen, self.view, ay, rb, vt, ul, ur, depth)
            if outlined < vt:
                log.debug("rescue: top %d up the print's outline: %d", vt, outlined)
                vt = outlined
        if RIM_LINE_TOP and floor_known and rig_known and not self.rig_guessed:
            # a print inside a board's coloured rim stopped the walks: the rim closes it
            rimmed = raise_top_to_rim(seen, self.view, rb, vt, ul, ur, depth)
            if rimmed < vt:
                log.debug("rescue: top %d, the rim's line across the face at %d", vt, rimmed)
                vt = rimmed
        if WINDOW_RESCUE_TOP and floor_known and rig_known and not self.rig_guessed:
            # a textured face's pattern stopped the row walks: its windows' mean holds on
            windowed = raise_top_by_windows(seen, self.view, ay, rb, vt, ul, ur, depth)
            if windowed < vt:
                log.debug("rescue: top %d, the face's windows hold up to %d", vt, windowed)
                vt = windowed
        if SURFACE_UP_TO_TOP and SURFACE_IN_RESCUE:
            # the face is one surface from its foot up to its top: the walks up may have
            # run on past its top along what stands in line behind it
            surface = lower_top_to_surface(seen, self.view, ay, rb, vt, ul, ur)
            if surface > vt:
                log.debug("rescue: top %d, the face's surface starts at %d", vt, surface)
                vt = surface
                agree = min(agree, top_agreement(seen, self.view, vt, ul, ur))
        # without edges to confirm it, a face found by colour alone is never a sure one
        conf = RESCUE_MAX_CONFIDENCE * evidence * agree
        if conf < self.min_confidence:
            return None
        framed = enclose_by_ring(seen, self.view, rb, vt, ul, ur, rows)
        if framed is None and floor_known and rig_known:
            # its top and sides inside the print: the margin read from the foot up
            framed = enclose_from_foot(seen, self.view, rb, vt, ul, ur, rows)
        if framed is not None:
            # the colour found a print (its lower edge a stronger colour step than the
            # margin's foot): the face is the margin's frame, its sides the margin's
            return framed[0], framed[1], framed[2], framed[3], conf
        if RESCUE_WIDEN_AT_TOP:
            # the sides walked again along the foot, from the face's top: the first walk
            # ran from the beam's core under a made-up top, so on a face of planks or tape
            # its colour run ended at the first plank and the outline walk past it read no
            # top step (the walk may bring a side in as well, past floor at the foot).
            # Only the width moves (the top and the confidence stay the first sides':
            # read at the new ones they made sure faces of rows no rig tries)
            walked_from = (ul, ur)
            ul, ur = widen_by_colour(seen, self.view, ax3, rb, vt, ul, ur, depth)
            if RISES_EVERY_WALK:
                # ... each side it moved out rising as the face's under its top
                ul, ur = sides_rising(seen, self.view, ax3, rb, vt, walked_from, (ul, ur))
        return rb, vt, ul, ur, conf

    def _by_texture(
        self,
        seen: npt.NDArray[Any],
        ay: npt.NDArray[np.float32],
        rows: tuple[int, int],
        depth: float,
    ) -> tuple[int, int, int, int, float] | None:
        """The face from its texture alone (:func:`.texture.face_from_texture`), as
        :meth:`_by_colour`: grey bricks on grey paving, where neither edges nor colour
        part them."""
        found = face_from_texture(seen, self.view, rows, depth)
        if found is None:
            return None
        rb, vt, ul, ur, evidence = found
        if rb >= ay.shape[0] - 3 or vt >= ay.shape[0]:
            return None
        # a print covering the face is textured and the face's margin round it is not:
        # the texture's walk up stops at the print's top or inside it (a row of its
        # pattern), while both sides still part the face from what is beside it up to
        # its real top (the sides' walk, as for the colour rescue's face)
        if TEXTURE_SIDES_WALK:
            vt = raise_top_by_sides(seen, self.view, ay, rb, vt, ul, ur, depth)
        conf = TEXTURE_MAX_CONFIDENCE * evidence
        if conf < self.min_confidence:
            return None
        # (after the confidence: the walk reads rows, and does not move the confidence)
        if HUE_HOLDS_TOP and TEXTURE_HUE_WALK:
            hued = raise_top_by_hue(seen, self.view, ay, rb, vt, ul, ur, depth)
            if hued < vt:
                log.debug("texture: top %d, the face's hue holds up to %d", vt, hued)
                vt = hued
        # the texture found a print whose margin is not textured: the face is the
        # margin's frame, read from the foot the rig gives up its sides
        framed = enclose_from_foot(seen, self.view, rb, vt, ul, ur, rows)
        if framed is None:
            # ... or, its found foot the face's own, up the margin beside the print
            framed = enclose_beside_foot(seen, self.view, rb, vt, ul, ur, rows)
            log.debug("texture: frame beside the print %s", framed)
        if framed is not None:
            rb, vt, ul, ur = framed
        return rb, vt, ul, ur, conf

    def _past_foot(
        self,
        image: npt.NDArray[Any],
        colour: npt.NDArray[Any] | None,
        range_m: float,
        depth: float,
        vb0: float,
        timer: Timer,
    ) -> Measurement | None:
        """A face whose floor-contact row ``vb0`` the rig puts below the view, or in its
        last rows (:func:`.region.face_past_foot`): its top and sides from its colour, its
        height from the contact row predicted, its foot flagged clipped where that row
        lies past the view's last (:func:`foot_below_view`). None if no face so."""
        v = self.view
        seen = colour if colour is not None else image
        h_img = self._h
        roi = v.warp(image, h_img, self._remap)
        n = roi.shape[0]
        ay = self._buf[0, :n]
        dy = self._dy[:n]
        cv2.spatialGradient(roi, self._adx[0, :n], dy)
        np.abs(dy, out=ay)
        found = face_past_foot(seen, v, ay, depth)
        timer.lap("past_foot")
        if found is None:
            return None
        bottom, top, left, right, evidence = found
        conf = RESCUE_MAX_CONFIDENCE * evidence
        log.debug("past foot: face %d-%d from row %d, evidence %.2f", left, right, top, evidence)
        if conf < self.min_confidence:
            return None
        h_px, w_px = vb0 - top, float(right - left)
        height_m, width_m = h_px * depth / v.fy, w_px * depth / v.fx
        if min(height_m, width_m) < MIN_SIZE_M:
            return None
        corners = np.array([[left, vb0], [right, vb0], [right, top], [left, top]], float)
        pix = v.to_input(corners)
        w_img = self._w
        x0, x1 = (
            clamp(float(pix[:, 0].min()), 0.0, w_img - 1.0),
            clamp(float(pix[:, 0].max()), 0.0, w_img - 1.0),
        )
        y0, y1 = (
            clamp(float(pix[:, 1].min()), 0.0, h_img - 1.0),
            clamp(float(pix[:, 1].max()), 0.0, h_img - 1.0),
        )
        # the sides as far down as the view sees them (the rows read end a few rows short
        # of its foot: what those rows say of the foot is not kept), and the foot where
        # the view does not see it
        seen_part = np.array([[left, bottom], [right, bottom], [right, top], [left, top]], float)
        cut = set(v.unseen_sides(seen_part)) - {"bottom"}
        if foot_below_view(vb0, h_img):
            cut.add("bottom")
        return Measurement(
            detected=True,
            method=self.name,
            range_m=range_m,
            distance_m=range_m,
            height_m=float(height_m),
            width_m=float(width_m),
            box_px=(x0, y0, x1, y1),
            confidence=round(conf, 3),
            height_px=float(h_px),
            width_px=w_px,
            clipped=[s for s in ("left", "right", "top", "bottom") if s in cut],
        )

    def _refine(
        self,
        ax: npt.NDArray[np.int16],
        ay: npt.NDArray[np.float32],
        ax3: npt.NDArray[np.int16],
        dy: npt.NDArray[np.int16],
        rb: int,
        ul: int,
        ur: int,
        vt: int,
        sign: float,
        top_row: float | None,
        conf: float,
        depth: float,
        range_m: float,
        timer: Timer,
        span: tuple[int, int] | None,
        fits: VerticalFits | None = None,
    ) -> Measurement:
        """The chosen face measured: the top edge's gradient window, then :func:`refine`.
        TOP_FACE_TO_FRONT only where no top row was chosen for the face already
        (``top_row``: a top lowered once, by front_from_back, is not lowered again)."""
        n = ay.shape[0]
        top_row_given = top_row
        v = self.view
        if SIDES_END_TOP:
            # the face's sides end at its top: above them what is behind runs on across
            ended = lower_top_where_sides_end(self._seen, v, ay, rb, vt, ul, ur)
            if ended > vt:
                log.debug("top %d: the face's sides end at %d", vt, ended)
                vt, top_row = ended, None
                sign = 1.0 if int(dy[ended, ul:ur].sum()) >= 0 else -1.0
        # a print's thin margin line round it: the face's edges (with a rig given)
        margin = (
            margin_line_out(self._seen, v, rb, vt, ul, ur)
            if top_row is None and (self._rig_given or not MARGIN_LINE_RIG_GIVEN)
            else None
        )
        # the top edge's signed gradient, only in the 7-row window its refinement reads
        top_edge = self._buf[1, :n]
        r0 = int(clamp(vt - 3, 0, n - 7))
        win = top_edge[r0 : r0 + 7]
        np.multiply(dy[r0 : r0 + 7], np.float32(sign), out=win)
        np.maximum(win, 0.0, out=win)

        def refined(row: float | None) -> Measurement:
            # the top edge's slope stays as fitted at vt: a top face's back edge parallels
            # its front, so the re-measure from the front only moves the row
            return refine(
                v,
                self.name,
                ax,
                ay,
                ax3,
                top_edge,
                rb,
                ul,
                ur,
                vt,
                row,
                conf,
                depth,
                range_m,
                timer,
                span,
                fits,
                margin,
            )

        result = refined(top_row)
        seen = self._seen

        def to_band_end(result: Measurement, gap: float, what: str) -> Measurement:
            # the top face's band (of the face's colour, lighter) read from ``gap`` rows
            # under the top found: where it runs on under that top, measured again from
            # its end, the front top edge
            assert seen is not None
            band = top_face_band(seen, result.lines, gap=gap)
            top = result.lines[1]
            x_mid, y_mid = 0.5 * (top[0] + top[2]), 0.5 * (top[1] + top[3])
            if (
                band is not None
                and band[0] >= TOP_FACE_STEP
                and band[1] - y_mid >= TOP_FACE_MIN_MOVE_PX
            ):
                front = view_row(v, x_mid, band[1])
                log.debug("top %.1f (%s): the top face's band ends at %.1f", vt, what, front)
                return refined(front)
            return result

        if (
            TOP_FACE_TO_FRONT
            and (self._rig_given or TOP_FACE_TO_FRONT_NO_RIG)
            and seen is not None
            and top_row_given is None
            and result.lines
            and looks_down_on(v, vt)
        ):
            # the top measured on a top face's back edge: measured again from its front
            result = to_band_end(result, TOP_FACE_GAP, "found")
        elif (
            TOP_FACE_PAST_PREDICTED
            and self._rig_given
            and seen is not None
            and top_row_given is not None
            and top_row is not None
            and result.lines
        ):
            # the front top row predicted from the back edge's ends (no edge of its own)
            result = to_band_end(result, PREDICTED_TOP_GAP, "predicted")
        small = min(result.height_m or 0.0, result.width_m or 0.0)
        if small < MIN_SIZE_M:
            # a face that refined down to a sliver is no measurement (the search never
            # proposes one so small): say so rather than report it
            return Measurement(
                detected=False,
                method=self.name,
                range_m=range_m,
                distance_m=range_m,
                confidence=result.confidence,
                reason=f"the face refined to {small * 100:.1f} cm across, under the "
                f"{MIN_SIZE_M * 100:.0f} cm the method measures",
            )
        return result
