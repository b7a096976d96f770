"""The confidence figure and the min-confidence decision.

Receives the chosen face candidate and its rivals (from
:func:`~obstacle_fusion.vision.fused.scoring.verified`). Returns the confidence: the face's
evidence times one minus its ambiguity (the best rival with little overlap, scoring
nearly as well, makes the choice a guess); and, for a confidence under the method's
minimum, the reason to report no detection. Then the confidence a detection is reported
with (:func:`reported_confidence`, applied by :class:`~obstacle_fusion.vision.measure.Measurer`
after every decision is taken): that figure cut by the doubts the stages recorded about
how the face's size was reached.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused.profiles import upper_middles_u8
from obstacle_fusion.vision.fused.scoring import Candidate

log = logging.getLogger(__name__)


#: A rival whose top and bottom rows are within this many rows of the face's ...
SAME_FACE_ROWS = 2
#: ... and whose columns reach within this many of the face's is a part of the same face.
SAME_FACE_GAP = 3


def same_face(c: Candidate, best: Candidate) -> bool:
    """Whether ``c`` is a part of the face ``best`` (or the face with more of it): the same
    top and bottom edges over columns that meet or overlap.

    A face of panels or planks gives a candidate per panel and per run of panels, all on
    the same top and floor-contact rows; they are one face with another choice of sides
    (the seams are crossed later, :func:`.extent.widen_across_seams`), not another face,
    and counting them as rivals refused faces whose top and bottom were found right."""
    return (
        abs(c.vt - best.vt) <= SAME_FACE_ROWS
        and abs(c.rb - best.rb) <= SAME_FACE_ROWS
        and c.ul <= best.ur + SAME_FACE_GAP
        and c.ur >= best.ul - SAME_FACE_GAP
    )


def confidence(best: Candidate, rivals: list[Candidate], parts_agree: bool = False) -> float:
    """0..1: the face's evidence, cut by how nearly a different face scores as well.

    ``parts_agree``: parts of the same face (:func:`same_face`) are no rivals; only with
    the floor-contact row known (a rig): while rows are only tried, with no rig, a strip
    along the floor (a print's lower margin, a shadow beside it) gives such parts too,
    and their agreement lifted wrong rows over the face's."""
    # a different face (little overlap) scoring nearly as well makes the choice a guess
    rival = max(
        (
            c.score
            for c in rivals
            if c.overlap(best) < 0.5 and not (parts_agree and same_face(c, best))
        ),
        default=0.0,
    )
    ambiguity = min(1.0, rival / best.score) if best.score > 0.0 else 1.0
    conf = best.evidence * (1.0 - ambiguity)
    log.debug(
        "face %d-%d x %d-%d: evidence %.3f, ambiguity %.2f",
        best.ul,
        best.ur,
        best.vt,
        best.rb,
        best.evidence,
        ambiguity,
    )
    return conf


def refusal(conf: float, min_confidence: float) -> str | None:
    """Why a face of this confidence is not reported (None: it is)."""
    if conf < min_confidence:
        return (
            f"no clear face: the best candidate's confidence {conf:.3f} is under "
            f"{min_confidence:g} (weak edges, or another face almost as likely)"
        )
    return None


# --- doubts: what makes a detection less sure than its edges say -----------------------
#
# The figure above is how clearly the edges show one face. Some ways the face's size was
# reached are known to go wrong more often than that figure says; each is a named doubt,
# recorded on the measurement (``Measurement.doubts``) by the stage that took that way,
# and each scales the reported confidence down by a fixed factor
# (:func:`reported_confidence`). On the tuning scenes (procedural and photo rooms, seeds
# 100-159, ordinary and hard, and the 150 generated scenes of tools/bench_vision.py seed
# 2026) the share of detections at 0.5 or above with both errors within 5 % went from
# 92.3 to 95.8 % with the rig and from 83.6 to 96.6 % with none; 9 of 191 and 41 of 127
# good detections fell under 0.5. Doubts only move the figure, never the measured size.

#: The face's top was moved up past a horizontal edge between its sides, to where the
#: sides end (:func:`~obstacle_fusion.vision.fused.extent.raise_top_past_inner_edges`): no
#: top edge chose that row, the sides' fading did (a side running on in front of a
#: background of the face's shade carries the top too far; half of such sure faces on the
#: tuning scenes had a height error over 5 %).
TOP_FROM_SIDES = "top_from_sides"
#: A margin of one colour surrounds the face found, a print's frame
#: (:func:`~obstacle_fusion.vision.fused.region.enclose_by_margin`, with no rig also
#: :func:`~obstacle_fusion.vision.fused.region.margin_under_print`; taken as the face, or
#: refused because it runs on below the floor-contact rows). With the floor contact found
#: in the image (no rig) the print's own lower edge passes for the floor contact and the
#: print for the face, and nothing ties either to the floor (six of the eight such faces
#: on the tuning rooms with no rig were 8-25 % small). With a rig the contact row is
#: predicted from the range: the doubt is recorded but cuts nothing (:data:`NO_RIG_ONLY`).
FRAMED = "framed_print"
#: The face chosen lay inside a clean outline on its floor-contact row (a piece of a
#: print), and the outline was taken as the face
#: (:func:`~obstacle_fusion.vision.fused.scoring.enclosing_outline`), its top a row that
#: the outline's pair's own top score did not choose.
PRINT_OUTLINE = "print_outline"
#: No rig: the face's sides gave no pitch (too short or too close to read a lean, or a
#: side with no clear edge), so the face was measured as seen by a level camera, or at a
#: pitch guessed from a near-horizon contact row. The pitch read from the sides is the one
#: check that the floor-contact row the method guessed is the face's; without it a step
#: on the floor or a stripe across the face stands unchecked.
PITCH_UNREAD = "pitch_unread"
#: No rig: measured again in the view levelled for the pitch its sides gave, the face
#: came out another size (or was not found): the size reported is the level view's one
#: scaled, from two measurements that disagree.
PITCH_RERUN_DISAGREES = "pitch_rerun_disagrees"
#: No rig: another trial of the floor-contact search (a neighbouring row, another guessed
#: pitch, so another guessed camera height) found a different sure face beside this one,
#: standing on its own foot (little shared width): which face is measured depends on the
#: camera height and pitch the method could only guess, and the beam holds both.
TRIAL_RIVAL = "trial_rival"
#: A face whose image height or width (working view) is under SMALL_FACE_PX: its size is
#: only as sure as its share of that (see :func:`pixel_factor`).
SMALL_FACE = "small_face"

# The doubts below are read off the face as measured (:func:`face_doubts`, called once by
# the fused method on the face it reports). Each marks a face whose top, outline or foot
# could as well be another: on the tuning scenes (procedural and photo rooms, seeds
# 100-159 and 300-359, ordinary and hard, with the true rig and with none, and the 150
# generated scenes) about half (near_rivals, top_runs_on) to all (foot_off_floor,
# floor_in_face) of the detections carrying one were off by more than 5 %, at any
# confidence; a sure face must be within 5 % 95 times in 100. With them the detections at
# 0.5 or above within 5 % went from 95.3 to 96.9 % with the rig and from 96.7 to 98.6 %
# with none; 16 of 264 and 2 of 146 right ones fell under 0.5 (tools/bench_confidence.py).

#: A horizontal edge inside the face, just under its top (within SECOND_TOP_REACH of the
#: face's height), at least SECOND_TOP_SHARE as strong as the top: a lid's edge, a label's
#: or a print's, a band of the face; either could be the top (:func:`top_edge_doubts`).
SECOND_TOP = "second_top_edge"
#: The top edge runs on beside the face on both sides at TOP_RUNS_ON_SHARE of its strength
#: or more: a line of the background (a skirting, a shelf, a wall's joint) at the top's
#: row, which may be what was taken for the top (:func:`top_edge_doubts`).
TOP_RUNS_ON = "top_runs_on"
#: The face's left and right sides differ in height by more than UNEVEN_SIDES_SHARE (in the
#: undistorted image, where a face square to the beam has equal sides at any pitch): a
#: side or a corner is off, or the face is turned more than the method measures
#: (:func:`outline_doubts`).
UNEVEN_SIDES = "uneven_sides"
#: The face's top and bottom edges' slopes differ by more than SKEWED_SLOPE (undistorted
#: image: parallel for a face square to the beam at any pitch or roll): one of them is
#: not the face's (:func:`outline_doubts`).
SKEWED_EDGES = "skewed_edges"
#: More than NEAR_RIVALS_MAX other face candidates score at least NEAR_RIVAL_SHARE of the
#: face's score, overlapping it or not: the face's extent is one of several comparable
#: readings (the ambiguity in :func:`confidence` counts only rivals with little overlap).
NEAR_RIVALS = "near_rivals"
#: What lies just under the face's bottom edge differs more from the floor beside the face
#: (same rows) than from the face itself: the face does not stand on the floor at that row;
#: the edge taken for its floor contact is a band or a print's edge on the face, or a
#: plinth's (:func:`foot_doubts`).
FOOT_OFF_FLOOR = "foot_off_floor"
#: The face's lowest band looks more like what lies under its bottom edge than like the
#: face (FLOOR_IN_FACE_SHARE): floor taken into the face, the floor contact taken too low
#: (a seam or a plank's edge on the floor) (:func:`foot_doubts`).
FLOOR_IN_FACE = "floor_in_face"
#: The face's top band (just under its top edge) differs in colour from both the face's
#: middle and its lowest band TOP_BAND_MARGIN times more than from what lies just above
#: the top edge (and by more than TOP_BAND_MIN_STEP): the upper part of the face found
#: looks more like the background than like the face standing on the floor. A poster or
#: an object behind the face, in line with its sides, extends the face upwards; its edge
#: against the wall passes for the face's top, and the face's real top is a step inside
#: it (:func:`top_band_doubts`). The face's own print or a lid of another colour looks so
#: too; either could be the top.
TOP_BAND_UNLIKE_FACE = "top_band_unlike_face"

#: The lens looks down on the face's top (it lies below the horizon), and just under the top
#: found runs a band of the face's own colour, lighter (TOP_FACE_STEP): a box's top face,
#: lit from above, between its back edge (taken for the top) and the front top edge; the
#: face is measured a band too tall (:func:`top_face_doubts`).
TOP_FACE_UNDER_TOP = "top_face_under_top"

#: With a rig, the face's floor-contact row lies above the one the rig and the range
#: predict by more than FOOT_ABOVE_SHARE of the search band's half-width (the band allows
#: for the rig's own error): the edge taken for the foot is on the face (a print's lower
#: edge in a margin of the face's colour, a brick course), or the face stands farther back
#: than the sonar's range (set by :meth:`FusedMethod._stages`).
FOOT_ABOVE_CONTACT = "foot_above_contact"

#: With a rig, the face passed the pair gate only with the contact row the rig and the
#: range predict standing in for a foot edge too faint to see (a face of the floor's own
#: shade: :data:`~obstacle_fusion.vision.fused.scoring.FOOT_FROM_RIG`): its height rests on
#: the rig's row alone, unchecked by the image. Photo 3520 ordinary (new11, rig): a pink
#: board on a pink floor, refused at 0.045 before. Session 50, branch ``wt-e-50``.
FOOT_UNSEEN = "foot_unseen"

#: The face's top edge and its floor-contact edge both run on past one of its sides, at the
#: same rows, as lines (FACE_RUNS_ON_LINE times the rows off them: a textured floor or a
#: photographed background is no line) at FACE_RUNS_ON_SHARE of the face's own strength
#: or more (:func:`face_runs_on_doubts`): what stands beside that side has the face's top
#: and foot, at its range and of its height: the face goes on there, and the side found
#: is a seam on it (a plank's, a panel's). A line of the background meets one of the two
#: rows now and then, both only where the face goes on. With the rig only (RIG_ONLY): the
#: contact row is then the range's; with no rig the trials' choice reads the confidence,
#: and the doubt was not weighed there. Procedural 3423 ordinary (new9, rig): one plank
#: of three taken for the face, -62 % wide at confidence 0.71. Session 48, branch
#: ``wt-a-48``.
FACE_RUNS_ON = "face_runs_on"

#: One colour runs in a thin band over the face's top and under its foot (inside its
#: sides), unlike the face and unlike what lies beside each band (:func:`frame_doubts`):
#: the face found is the inner panel of a frame (a plinth and a lid, a print's border),
#: and the thing itself reaches out to the frame's outer edges; a wall over a face's top
#: is the wall beside it as well, and a floor under its foot the floor beside it.
#: Procedural 3400 ordinary (new9, no rig): a brick panel in a green frame, the panel
#: measured -8.0 % high and -7.1 % wide at confidence 0.955. Session 48, branch
#: ``wt-a-48``.
FRAME_ROUND = "frame_round_face"

#: With the rig given, under the top found where the face's colour ends, the signed
#: gradient holds a front top edge (a step of its own, :func:`top.front_top`) whose move
#: the colour did not bear out (too faint a shade between, ``method._front_ends_colour``),
#: and the two tops differ by FRONT_STEP_UNDONE_SHARE of the face's height or more: the
#: top kept may be a top face's back edge (its band of the face's hue a level or two
#: lighter) as well as the front top edge; the two readings differ by more than the 5 %
#: promised. New10 photo 3476 hard with the rig: a lilac box's top face 2.3 levels lighter
#: than its front, its front edge found 4 rows under the top and undone, +7.0 % at 0.96.
#: Set by the fused method; a switch for the tests (``method.FRONT_STEP_UNDONE_DOUBT``).
FRONT_STEP_UNDONE = "front_step_undone"
FRONT_STEP_UNDONE_SHARE = 0.05

#: What one doubt leaves of the confidence: a doubt alone takes the surest face (1.0)
#: under the 0.5 that means "sure" (halving would leave it at 0.5 exactly).
DOUBT_FACTOR = 0.45
#: The factor each doubt scales the confidence by.
DOUBT_FACTORS: dict[str, float] = {
    TOP_FROM_SIDES: DOUBT_FACTOR,
    FRAMED: DOUBT_FACTOR,
    PRINT_OUTLINE: DOUBT_FACTOR,
    PITCH_UNREAD: DOUBT_FACTOR,
    PITCH_RERUN_DISAGREES: DOUBT_FACTOR,
    SECOND_TOP: DOUBT_FACTOR,
    TOP_RUNS_ON: DOUBT_FACTOR,
    UNEVEN_SIDES: DOUBT_FACTOR,
    SKEWED_EDGES: DOUBT_FACTOR,
    NEAR_RIVALS: DOUBT_FACTOR,
    FOOT_OFF_FLOOR: DOUBT_FACTOR,
    FLOOR_IN_FACE: DOUBT_FACTOR,
    TOP_BAND_UNLIKE_FACE: DOUBT_FACTOR,
    FOOT_ABOVE_CONTACT: DOUBT_FACTOR,
    FOOT_UNSEEN: DOUBT_FACTOR,
    TRIAL_RIVAL: DOUBT_FACTOR,
    TOP_FACE_UNDER_TOP: DOUBT_FACTOR,
    FACE_RUNS_ON: DOUBT_FACTOR,
    FRAME_ROUND: DOUBT_FACTOR,
    FRONT_STEP_UNDONE: DOUBT_FACTOR,
}

#: Doubts that cut the confidence only when the floor contact was found in the image.
NO_RIG_ONLY = frozenset({FRAMED, TRIAL_RIVAL})
#: ... and only when it was predicted from a rig file (with no rig the contact row is the
#: trial's own guess, and the horizon a guessed pitch's).
RIG_ONLY = frozenset({FOOT_ABOVE_CONTACT, TOP_FACE_UNDER_TOP, FACE_RUNS_ON})

#: A face side of this many pixels or more is measured well enough for a 5 % bound: a
#: size is the distance between two edges, each found to about half a pixel (the tuning
#: scenes: median size error 0.6 px, 1.1-1.4 px at the 75th percentile, over 2 px at the
#: 90th); 2 px are 5 % of 40 px. A smaller side is as sure as its share of this.
SMALL_FACE_PX = 40.0


#: SECOND_TOP: rows searched under the top (after a gap of SECOND_TOP_GAP rows clear of the
#: top's own blur), as a share of the face's height, at least SECOND_TOP_MIN_ROWS ...
SECOND_TOP_REACH = 0.15
SECOND_TOP_MIN_ROWS = 4
SECOND_TOP_GAP = 3
#: ... and how strong (mean |d/dy| over the face's columns) such a row must be, against
#: the top's.
SECOND_TOP_SHARE = 0.8
#: TOP_RUNS_ON: the columns read beside each side (half the face's width, at least
#: TOP_RUNS_ON_MIN_COLUMNS), and the share of the top's strength both must reach.
TOP_RUNS_ON_REACH = 0.5
TOP_RUNS_ON_MIN_COLUMNS = 8
TOP_RUNS_ON_SHARE = 0.75
#: FACE_RUNS_ON: a switch for the tests; the columns read past each side (after a gap of
#: FACE_RUNS_ON_GAP columns clear of the side's own blur; half the face's width, at least
#: FACE_RUNS_ON_MIN_COLUMNS), and the share of the face's own top and foot strength both
#: rows must keep there.
FACE_RUNS_ON_DOUBT = True
FACE_RUNS_ON_GAP = 3
FACE_RUNS_ON_REACH = 0.5
FACE_RUNS_ON_MIN_COLUMNS = 8
FACE_RUNS_ON_SHARE = 0.4
#: ... and how many times the rows off the line (FACE_RUNS_ON_GAP to FACE_RUNS_ON_BAND
#: above and below) the run-on must be.
FACE_RUNS_ON_LINE = 3.0
FACE_RUNS_ON_BAND = 8
#: FRAME_ROUND: a switch for the tests; the bands read over the top and under the foot
#: (input rows: FRAME_GAP rows off the edge, clear of most of its blur, FRAME_ROWS rows
#: high: a frame's band is a few rows), over the face's columns but FOOT_INNER_SHARE of
#: its width off each side, and beside each band over FOOT_BESIDE_SHARE of the width ...
FRAME_ROUND_DOUBT = True
FRAME_GAP = 2.0
FRAME_ROWS = 3.0
#: ... the two bands' colour distance, against the least of each band's distance to the
#: face's middle and to what lies beside it, under which they are one frame ...
FRAME_SHARE = 0.5
#: ... where that least distance is at least this many levels (in a room of one shade no
#: band is told from another).
FRAME_MIN_STEP = 10.0
#: UNEVEN_SIDES: the left and right heights' difference, as a share of their mean.
UNEVEN_SIDES_SHARE = 0.04
#: SKEWED_EDGES: the top's slope minus the bottom's (rows per column).
SKEWED_SLOPE = 0.03
#: NEAR_RIVALS: a rival's score against the face's, and how many such rivals pass.
NEAR_RIVAL_SHARE = 0.5
NEAR_RIVALS_MAX = 2
#: FLOOR_IN_FACE: the face's lowest band's colour distance to what lies under the bottom
#: edge, against its distance to the face's middle, under which the doubt holds.
FLOOR_IN_FACE_SHARE = 0.5
#: The bands :func:`foot_doubts` compares (input-image rows and columns): a band is
#: FOOT_BAND_SHARE of the face's height high (at least FOOT_BAND_MIN_ROWS), FOOT_BAND_GAP
#: rows clear of the bottom edge's blur, over the face's columns but FOOT_INNER_SHARE of
#: its width off each side; the face's middle is its rows FOOT_MIDDLE_ROWS (shares of its
#: height from the top); the floor beside spans FOOT_BESIDE_SHARE of the face's width on
#: each side.
FOOT_BAND_SHARE = 0.08
FOOT_BAND_MIN_ROWS = 3.0
FOOT_BAND_GAP = 3.0
FOOT_INNER_SHARE = 0.2
FOOT_MIDDLE_ROWS = (0.3, 0.7)
FOOT_BESIDE_SHARE = 0.5
#: TOP_BAND_UNLIKE_FACE: the least colour distance (BGR or grey levels) from the top band
#: to the face's middle and lowest bands that counts as unlike (a gloss's or a shading's
#: gradient across a face of the background's own shade is no step).
TOP_BAND_MIN_STEP = 10.0
#: ... and how many times the top band's distance to what lies above the top edge it must
#: be: a gloss or a light's fall-off across the face shifts its top band's shade by about
#: as much as the face differs from the wall (a glossy face on the tuning rooms: 1.04
#: times); a poster in line with the face's sides is clearly nearer the wall's colour
#: than the face's (the one sure face found so, 69 % off on seeds 900-999: 2.0 times).
TOP_BAND_MARGIN = 1.5
#: TOP_FACE_UNDER_TOP (a switch for the tests): the rows searched under the top, from
#: TOP_FACE_GAP rows under the top line (clear of its own blur row) down to
#: TOP_FACE_REACH of the face's height under the line (at least TOP_FACE_MIN_ROWS rows read,
#: on a small face) ...
TOP_FACE_UNDER_TOP_DOUBT = True
TOP_FACE_GAP = 1.5
TOP_FACE_REACH = 0.15
TOP_FACE_MIN_ROWS = 3
#: ... a row's colour counts as the face's own scaled while its distance from that is
#: under this share of its distance from the blur's mixes ...
TOP_FACE_CHROMA_SHARE = 0.5
#: ... and the band must be this many levels lighter than the face and off the mixes
#: (a median over the face's columns varies by a level or two with the noise; the right
#: answers with their top below the horizon on seeds 3050-3149 read up to 4.3).
TOP_FACE_STEP = 5.0
#: ... read one row past TOP_FACE_REACH: a band's end is a step between two rows, seen
#: only with the row under it read (and the face's colour read under that). A top face
#: ending on the reach's last row was read as a band that does not end (photo 3217
#: ordinary: a top face 6 rows of a 42-row face, its step between rows 231 and 232, the
#: reach ending at 231; +19.6 % at 0.68). The row is added to the reach only, not to
#: the TOP_FACE_MIN_ROWS floor that small faces (under ~27 rows) read to: the floor was
#: set and checked as it is, reading a row more there moves the face's colour, read under
#: the last row, down a small face unchecked (session 44, helper G; a band ending on the
#: floor's last row stays unread, ``test_top_face_past_predicted``). A switch for the
#: tests.
TOP_FACE_PAST_REACH = True
#: ... and just inside each side (this share of the face's width) the face's middle rows
#: must be of the face's colour, not the band's (:func:`_band_ends_at_sides`).
TOP_FACE_SIDE_SHARE = 0.08
#: ... at least this many columns (a small face's strip clear of its sides' blur) ...
TOP_FACE_SIDE_MIN_COLUMNS = 3.0
#: ... over which the middle rows' median is not nearer the band than the face, nor in
#: any one column (a margin may be a few columns wide: the strip's median then reads the
#: print) within this share of the band's step (band to face) of the band's colour:
#: nearer the band than the face two to one. At a half a photo's side columns, in the
#: blur's tail or a plank's seam (0.41-0.6 of the step), took right moves (photo 158,
#: 2006); a drawn margin lies at 0.
TOP_FACE_SIDE_AGREE = 1.0 / 3.0
#: ... and the strip's median counts as a margin of the band's colour only where it is
#: nearer the band than the face's own inner columns over the same middle rows too: a
#: stripe or a tape across the face (its middle rows mixed with the stripe's colour) sits
#: in the side strips as in the middle, and a strip that reads like the face's middle is
#: the face, not a margin running down its sides (new11 photo 3506 hard with the rig: a
#: cyan tape across a magenta face left the strip 12.69 from the band, 12.73 from the face
#: read under it, and the top face's band was refused, +12.4 % at 0.61). A switch for the
#: tests.
TOP_FACE_SIDE_VS_MIDDLE = True
#: A band read over fewer of the face's inner columns than this is too narrow to read.
TOP_FACE_MIN_COLUMNS = 3
#: Samples per band and axis at most (a band's colour is a median of a strided sample).
FOOT_SAMPLES_ROWS = 16
FOOT_SAMPLES_COLUMNS = 32


def top_edge_doubts(ay: npt.NDArray[np.float32], rb: int, ul: int, ur: int, vt: int) -> list[str]:
    """SECOND_TOP and TOP_RUNS_ON for the face with floor-contact row ``rb``, sides ``ul``,
    ``ur`` and top row ``vt`` in the working view; ``ay`` is that view's |d/dy| (its rows
    down to at least the contact row). The top's strength is the strongest of the mean
    |d/dy| over the face's inner columns (a tenth of its width off each side) at rows
    vt-1..vt+1."""
    n, w = ay.shape
    height, width = rb - vt, ur - ul
    if height < 6 or width < 6 or vt < 3 or vt + 1 >= n:
        return []
    m = max(1, width // 10)
    cols = ay[:, ul + m : ur - m + 1]
    top = _edge_strength(ay, vt, ul, ur)
    if top <= 0.0:
        return []
    doubts = []
    reach = max(SECOND_TOP_MIN_ROWS, int(SECOND_TOP_REACH * height))
    below = cols[vt + SECOND_TOP_GAP : min(n, vt + reach + 1)]
    if below.size and float(below.mean(axis=1).max()) > SECOND_TOP_SHARE * top:
        doubts.append(SECOND_TOP)
    k = max(TOP_RUNS_ON_MIN_COLUMNS, int(TOP_RUNS_ON_REACH * width))
    beside = []
    for c0, c1 in ((ul - k, ul - 2), (ur + 3, ur + k + 1)):
        c0, c1 = max(0, c0), min(w, c1)
        if c1 - c0 >= 3:
            beside.append(float(ay[vt - 1 : vt + 2, c0:c1].max(axis=0).mean()))
    if beside and min(beside) > TOP_RUNS_ON_SHARE * top:
        doubts.append(TOP_RUNS_ON)
    return doubts


def _edge_strength(ay: npt.NDArray[np.float32], r: int, ul: int, ur: int) -> float:
    """A face edge's strength on row ``r``: the strongest mean |d/dy| over the face's inner
    columns (a tenth of its width off each side, away from the corners' blur) at rows
    r-1..r+1 (the edge found to a row). Shared by the top's doubts and FACE_RUNS_ON, so
    that both weigh what lies past a side against the same strength."""
    m = max(1, (ur - ul) // 10)
    return float(ay[r - 1 : r + 2, ul + m : ur - m + 1].mean(axis=1).max())


def face_runs_on_doubts(
    ay: npt.NDArray[np.float32], rb: int, ul: int, ur: int, vt: int
) -> list[str]:
    """FACE_RUNS_ON for the face with floor-contact row ``rb``, sides ``ul``, ``ur`` and top
    row ``vt`` in the working view (``ay``: its |d/dy|, rows down to at least ``rb`` + 1).
    The face's top and foot strengths are the strongest mean |d/dy| over its inner columns
    (a tenth of its width off each side) at rows vt-1..vt+1 and rb-1..rb+1; past a side,
    each row's is the mean over the columns read of the strongest of those three rows."""
    if not FACE_RUNS_ON_DOUBT:
        return []
    n, w = ay.shape
    height, width = rb - vt, ur - ul
    if height < 6 or width < 6 or vt < 1 or rb + 2 > n:
        return []
    own = [_edge_strength(ay, r, ul, ur) for r in (vt, rb)]
    if min(own) <= 0.0:
        return []
    k = max(FACE_RUNS_ON_MIN_COLUMNS, int(FACE_RUNS_ON_REACH * width))
    g = FACE_RUNS_ON_GAP
    for c0, c1 in ((ul - g - k + 1, ul - g + 1), (ur + g, ur + g + k)):
        c0, c1 = max(0, c0), min(w, c1)
        if c1 - c0 < k:
            continue  # the side is too near the view's edge to read what goes on past it
        if all(_runs_on(ay, r, c0, c1, o) for r, o in zip((vt, rb), own, strict=True)):
            return [FACE_RUNS_ON]
    return []


def _runs_on(ay: npt.NDArray[np.float32], r: int, c0: int, c1: int, own: float) -> bool:
    """Whether the face's edge on row ``r`` (``own``: its strength) runs on over columns
    ``c0``..``c1``: a line there (each column's strongest of rows r-1..r+1, their mean)
    at FACE_RUNS_ON_SHARE of ``own`` and FACE_RUNS_ON_LINE times what the same columns
    show FACE_RUNS_ON_GAP to FACE_RUNS_ON_BAND rows above and below (a textured floor or
    background is as strong off the row as on it)."""
    line = float(ay[r - 1 : r + 2, c0:c1].max(axis=0).mean())
    n = ay.shape[0]
    g, b = FACE_RUNS_ON_GAP, FACE_RUNS_ON_BAND
    rows = [*range(max(0, r - b), max(0, r - g + 1)), *range(min(n, r + g), min(n, r + b + 1))]
    off = float(np.median(ay[rows, c0:c1].mean(axis=1))) if rows else 0.0
    return line > FACE_RUNS_ON_SHARE * own and line > FACE_RUNS_ON_LINE * off


def outline_doubts(
    camera: CameraModel, lines: Sequence[tuple[float, float, float, float]]
) -> list[str]:
    """UNEVEN_SIDES and SKEWED_EDGES from the face's outline as reported
    (``Measurement.lines``: bottom, top, left, right, input-image pixels; a left or right
    line runs from its bottom corner to its top corner)."""
    if len(lines) != 4:
        return []
    pts = camera.undistort_points(np.asarray(lines, dtype=np.float64).reshape(-1, 2))
    bottom, top, left, right = pts.reshape(4, 4)
    doubts = []
    h_left, h_right = left[1] - left[3], right[1] - right[3]
    if abs(h_left - h_right) > UNEVEN_SIDES_SHARE * max(1.0, 0.5 * (h_left + h_right)):
        doubts.append(UNEVEN_SIDES)
    slope_top = (top[3] - top[1]) / max(1.0, top[2] - top[0])
    slope_bottom = (bottom[3] - bottom[1]) / max(1.0, bottom[2] - bottom[0])
    if abs(slope_top - slope_bottom) > SKEWED_SLOPE:
        doubts.append(SKEWED_EDGES)
    return doubts


def _dist(a: npt.NDArray[np.float32], b: npt.NDArray[np.float32]) -> float:
    """The distance between two colours (or greys), as the colour doubts compare bands."""
    return float(np.linalg.norm(a - b))


def _band_colour(
    image: npt.NDArray[np.uint8], r0: float, r1: float, c0: float, c1: float
) -> npt.NDArray[np.float32] | None:
    """Median colour (or grey) of image rows r0..r1, columns c0..c1 (a strided sample);
    None when the band is under 2 rows or 3 columns inside the image."""
    h, w = image.shape[:2]
    a, b = max(0, int(r0)), min(h, int(r1))
    c, d = max(0, int(c0)), min(w, int(c1))
    if b - a < 2 or d - c < 3:
        return None
    sy, sx = max(1, (b - a) // FOOT_SAMPLES_ROWS), max(1, (d - c) // FOOT_SAMPLES_COLUMNS)
    channels = image.shape[2] if image.ndim == 3 else 1
    sample = image[a:b:sy, c:d:sx].reshape(-1, channels)
    return upper_middles_u8(sample)


@dataclass(frozen=True)
class _FaceBands:
    """Where the colour doubts read a face's bands: its columns inside the sides, its top
    and bottom rows, the band height and the gap kept from an edge's blur."""

    x0: float
    x1: float
    c0: float
    c1: float
    vt: float
    rb: float
    height: float
    width: float
    k: float
    g: float

    @property
    def middle_rows(self) -> tuple[float, float]:
        m0, m1 = FOOT_MIDDLE_ROWS
        return self.vt + m0 * self.height, self.vt + m1 * self.height


def _face_bands(lines: Sequence[tuple[float, float, float, float]]) -> _FaceBands | None:
    """The bands of a face's outline (``lines`` as in :func:`outline_doubts`); None for a
    face too small to read."""
    if len(lines) != 4:
        return None
    bottom, top = lines[0], lines[1]
    x0, x1 = max(bottom[0], top[0]), min(bottom[2], top[2])
    rb, vt = 0.5 * (bottom[1] + bottom[3]), 0.5 * (top[1] + top[3])
    height, width = rb - vt, x1 - x0
    if height < 10.0 or width < 10.0:
        return None
    c0, c1 = x0 + FOOT_INNER_SHARE * width, x1 - FOOT_INNER_SHARE * width + 1.0
    k = max(FOOT_BAND_MIN_ROWS, FOOT_BAND_SHARE * height)
    return _FaceBands(x0, x1, c0, c1, vt, rb, height, width, k, FOOT_BAND_GAP)


def foot_doubts(
    image: npt.NDArray[np.uint8], lines: Sequence[tuple[float, float, float, float]]
) -> list[str]:
    """FOOT_OFF_FLOOR and FLOOR_IN_FACE from the colours round the face's bottom edge in
    the input image (``lines`` as in :func:`outline_doubts`; BGR or grey)."""
    bands = _face_bands(lines)
    if bands is None:
        return []
    x0, x1, c0, c1 = bands.x0, bands.x1, bands.c0, bands.c1
    rb, width, k, g = bands.rb, bands.width, bands.k, bands.g
    m_lo, m_hi = bands.middle_rows
    middle = _band_colour(image, m_lo, m_hi, c0, c1)
    lowest = _band_colour(image, rb - k - g + 1.0, rb - g + 1.0, c0, c1)
    under = _band_colour(image, rb + g, rb + g + k, c0, c1)
    if middle is None or under is None:
        return []

    doubts = []
    beside = [
        _dist(under, floor)
        for floor in (
            _band_colour(image, rb + g, rb + g + k, x0 - FOOT_BESIDE_SHARE * width, x0 - g),
            _band_colour(image, rb + g, rb + g + k, x1 + g, x1 + FOOT_BESIDE_SHARE * width),
        )
        if floor is not None
    ]
    if beside and min(beside) > max(1.0, _dist(under, middle)):
        doubts.append(FOOT_OFF_FLOOR)
    if lowest is not None:
        if _dist(lowest, under) < FLOOR_IN_FACE_SHARE * max(1.0, _dist(lowest, middle)):
            doubts.append(FLOOR_IN_FACE)
    return doubts


def frame_doubts(
    image: npt.NDArray[np.uint8], lines: Sequence[tuple[float, float, float, float]]
) -> list[str]:
    """FRAME_ROUND from the colours just over the face's top and just under its foot, in
    its middle, and beside the two bands, in the input image (``lines`` as in
    :func:`outline_doubts`; BGR or grey)."""
    bands = _face_bands(lines) if FRAME_ROUND_DOUBT else None
    if bands is None:
        return []
    x0, x1, c0, c1, g = bands.x0, bands.x1, bands.c0, bands.c1, FRAME_GAP
    reach = FOOT_BESIDE_SHARE * bands.width
    over_rows = (bands.vt - g - FRAME_ROWS, bands.vt - g)
    under_rows = (bands.rb + g, bands.rb + g + FRAME_ROWS)
    middle = _band_colour(image, *bands.middle_rows, c0, c1)
    if middle is None:
        return []
    found = []
    for r0, r1 in (over_rows, under_rows):
        band = _band_colour(image, r0, r1, c0, c1)
        beside = [
            b
            for b in (
                _band_colour(image, r0, r1, x0 - reach, x0 - FOOT_BAND_GAP),
                _band_colour(image, r0, r1, x1 + FOOT_BAND_GAP, x1 + reach),
            )
            if b is not None
        ]
        if band is None or not beside:
            return []
        found.append((band, beside))
    (over, over_beside), (under, under_beside) = found

    unlike = min(
        _dist(over, middle),
        _dist(under, middle),
        *(_dist(over, b) for b in over_beside),
        *(_dist(under, b) for b in under_beside),
    )
    if unlike >= FRAME_MIN_STEP and _dist(over, under) < FRAME_SHARE * unlike:
        return [FRAME_ROUND]
    return []


def top_band_doubts(
    image: npt.NDArray[np.uint8], lines: Sequence[tuple[float, float, float, float]]
) -> list[str]:
    """TOP_BAND_UNLIKE_FACE from the colours round the face's top edge and in its middle
    and lowest bands, in the input image (``lines`` as in :func:`outline_doubts`; BGR or
    grey). The bands are those of :func:`foot_doubts`, mirrored at the top edge."""
    bands = _face_bands(lines)
    if bands is None:
        return []
    c0, c1, vt, rb, k, g = bands.c0, bands.c1, bands.vt, bands.rb, bands.k, bands.g
    m_lo, m_hi = bands.middle_rows
    above = _band_colour(image, vt - g - k, vt - g, c0, c1)
    upper = _band_colour(image, vt + g, vt + g + k, c0, c1)
    middle = _band_colour(image, m_lo, m_hi, c0, c1)
    lowest = _band_colour(image, rb - k - g + 1.0, rb - g + 1.0, c0, c1)
    if above is None or upper is None or middle is None or lowest is None:
        return []
    unlike = min(float(np.linalg.norm(upper - middle)), float(np.linalg.norm(upper - lowest)))
    step = float(np.linalg.norm(upper - above))
    return [TOP_BAND_UNLIKE_FACE] if unlike > TOP_BAND_MARGIN * max(TOP_BAND_MIN_STEP, step) else []


def top_face_band(
    image: npt.NDArray[np.uint8],
    lines: Sequence[tuple[float, float, float, float]],
    gap: float = TOP_FACE_GAP,
) -> tuple[float, float] | None:
    """How clearly a band of the face's own colour, lighter, lies just under the top edge
    found (BGR or grey levels; ``lines`` as in :func:`outline_doubts`), and the input
    row where it ends (its step down to the face's shade, sub-pixel: the front top edge
    of a box's top face). The first: the largest, over the rows from TOP_FACE_GAP under
    the top to TOP_FACE_REACH of the face's height under it (at least
    TOP_FACE_MIN_ROWS), of the lesser of the row's lightness over the face's and its
    distance from every mix of the colours above the top and of the face (an edge's blur
    mixes those two only), counted where the row is the face's colour scaled (its
    distance from that under TOP_FACE_CHROMA_SHARE of the other). Rows are medians over
    the face's inner columns; the face's colour is read right under the rows searched.
    None for a face too small to read. ``gap``: the rows skipped under the top line
    (TOP_FACE_GAP, its own blur; a top row predicted, not found on an edge, has none
    there). The rows read run one past the reach (TOP_FACE_PAST_REACH: a band ending on
    the reach's last row shows its step), not past the TOP_FACE_MIN_ROWS floor. The
    colour above is read over FOOT_BAND_GAP to FOOT_BAND_GAP + k rows above the top line
    given: a top predicted more than FOOT_BAND_GAP rows under the band's first row reads
    the band there, and no band is found (a miss, never a move)."""
    bands = _face_bands(lines)
    if bands is None:
        return None
    c0, c1, vt, k, g = bands.c0, bands.c1, bands.vt, bands.k, bands.g
    reach = int(round(TOP_FACE_REACH * bands.height))
    first = int(np.ceil(vt + gap))
    # down to TOP_FACE_REACH of the height under the top line, TOP_FACE_MIN_ROWS read at
    # least (a face under ~27 rows reached only 1-2 rows past the line's blur), and one
    # row past that (TOP_FACE_PAST_REACH): a band's end is a step between two rows
    past = 1 if TOP_FACE_PAST_REACH else 0
    last = max(int(vt) + reach + past, first + TOP_FACE_MIN_ROWS - 1)
    above = _band_colour(image, vt - g - k, vt - g, c0, c1)
    face = _band_colour(image, last + 1.0, last + 1.0 + k, c0, c1)
    h, w = image.shape[:2]
    a, b = max(0, int(c0)), min(w, int(c1))
    if above is None or face is None or b - a < TOP_FACE_MIN_COLUMNS or last >= h or first > last:
        return None
    step = above - face
    length = float(np.linalg.norm(step))
    unit = step / max(length, 1e-6)
    norm2 = max(float(face @ face), 1e-6)
    channels = image.shape[2] if image.ndim == 3 else 1
    best, at = 0.0, first
    lightness = []
    for r in range(first, last + 1):
        colour = upper_middles_u8(np.ascontiguousarray(image[r, a:b].reshape(-1, channels)))
        d = colour - face
        t = min(max(float(d @ unit), 0.0), length)
        off = float(np.linalg.norm(d - t * unit))  # from the blur's mixes
        scaled = float(np.linalg.norm(colour - float(colour @ face) / norm2 * face))
        lighter = float(d.mean())
        lightness.append(lighter)
        if scaled < TOP_FACE_CHROMA_SHARE * off and min(lighter, off) > best:
            best, at = min(lighter, off), r
    if best <= 0.0:
        return 0.0, float(last) + 0.5
    # one band from the top line down to one step, the face's shade under it: every row
    # read down to the surest is at least half as light, and a row under it falls under
    # half, as do all the rows read after it (a band that starts lower is a line on the
    # face, a brick's mortar; one that does not end, or lightens again, a gloss)
    i = at - first
    half = 0.5 * lightness[i]
    end = next((j for j in range(i + 1, len(lightness)) if lightness[j] < half), None)
    if (
        end is None
        or any(x < half for x in lightness[:i])
        or any(x >= half for x in lightness[end:])
        or not _band_ends_at_sides(image, bands, face, at)
    ):
        return 0.0, float(last) + 0.5
    hi, lo = lightness[end - 1], lightness[end]
    front = first + end - 1 + (hi - half) / max(hi - lo, 1e-6)
    return best, front


def _band_ends_at_sides(
    image: npt.NDArray[np.uint8], bands: _FaceBands, face: npt.NDArray[np.float32], row: int
) -> bool:
    """Whether the band's colour (its row ``row``) ends at the sides too: in no column
    just inside each side (TOP_FACE_SIDE_SHARE of the face's width, at least
    TOP_FACE_SIDE_MIN_COLUMNS, past the sides' blur) are the face's middle rows nearer the
    band's colour than the face's colour ``face`` over the strip (a median), nor in any one
    column within TOP_FACE_SIDE_AGREE of the band's step of the band's colour. A top face
    ends at the front top edge from side to side; a print's margin of that colour runs on
    down along the sides, and may be only a few columns wide (a median over the strip
    then reads the print)."""
    h, w = image.shape[:2]
    if not 0 <= row < h:
        return True
    s = max(TOP_FACE_SIDE_MIN_COLUMNS, TOP_FACE_SIDE_SHARE * bands.width)
    x0, x1, g = bands.x0, bands.x1, bands.g
    band = _band_colour(image, row, row + 2, bands.c0, bands.c1)
    m_lo, m_hi = bands.middle_rows
    if band is None:
        return True
    channels = image.shape[2] if image.ndim == 3 else 1
    r0, r1 = max(0, int(m_lo)), min(h, int(m_hi))
    if r1 - r0 < 2:
        return True
    sy = max(1, (r1 - r0) // FOOT_SAMPLES_ROWS)
    agree = TOP_FACE_SIDE_AGREE * float(np.linalg.norm(band - face))
    # the face's inner columns over the same rows (TOP_FACE_SIDE_VS_MIDDLE)
    middle = (
        _band_colour(image, m_lo, m_hi, bands.c0, bands.c1) if TOP_FACE_SIDE_VS_MIDDLE else None
    )
    for c0, c1 in ((x0 + g, x0 + g + s), (x1 - g - s, x1 - g)):
        strip = _band_colour(image, m_lo, m_hi, c0, c1)
        if (
            strip is not None
            and np.linalg.norm(strip - band) < np.linalg.norm(strip - face)
            and not (
                middle is not None
                and np.linalg.norm(strip - middle) <= np.linalg.norm(strip - band)
            )
        ):
            return False  # the strip as a whole nearer the band: a wide margin, shaded
        a, b = max(0, int(c0)), min(w, int(c1))
        for c in range(a, b):
            column = upper_middles_u8(
                np.ascontiguousarray(image[r0:r1:sy, c].reshape(-1, channels))
            )
            if np.linalg.norm(column - band) < agree:
                return False
    return True


def top_face_doubts(
    image: npt.NDArray[np.uint8],
    lines: Sequence[tuple[float, float, float, float]],
    below_horizon: bool,
) -> list[str]:
    """TOP_FACE_UNDER_TOP for a face whose top lies below the horizon (``below_horizon``:
    the lens looks down on it, so a box's top face shows above its front top edge)."""
    if not TOP_FACE_UNDER_TOP_DOUBT or not below_horizon:
        return []
    band = top_face_band(image, lines)
    return [TOP_FACE_UNDER_TOP] if band is not None and band[0] >= TOP_FACE_STEP else []


#: FOOT_ABOVE_CONTACT: the found contact row lies above the predicted one by more than this
#: share of the search band's half-width (chosen on the tuning rooms with the rig: at
#: confidence >= 0.5 it took 2 wrong faces and no right one under 0.5 there, 2 wrong and 2
#: right on seeds 500-559 and 900-959).
FOOT_ABOVE_SHARE = 0.5


def contact_doubts(rb: int, vb0: float, tol: float) -> list[str]:
    """FOOT_ABOVE_CONTACT for a face found standing on row ``rb`` where the rig and the
    range predict ``vb0``, within a search band of half-width ``tol`` (working view rows;
    the doubt counts only when the rig is given: :data:`RIG_ONLY`)."""
    return [FOOT_ABOVE_CONTACT] if vb0 - rb > FOOT_ABOVE_SHARE * tol else []


def rival_doubts(best: Candidate, rivals: list[Candidate]) -> list[str]:
    """NEAR_RIVALS: the other candidates (any overlap) scoring NEAR_RIVAL_SHARE of ``best``."""
    near = sum(1 for c in rivals if c is not best and c.score >= NEAR_RIVAL_SHARE * best.score)
    return [NEAR_RIVALS] if near > NEAR_RIVALS_MAX else []


def face_doubts(
    camera: CameraModel,
    image: npt.NDArray[np.uint8],
    ay: npt.NDArray[np.float32],
    rb: int,
    ul: int,
    ur: int,
    vt: float,
    best: Candidate,
    rivals: list[Candidate],
    lines: Sequence[tuple[float, float, float, float]],
    below_horizon: bool = False,
) -> list[str]:
    """The doubts read off the face the fused method reports (``image``: the input frame,
    BGR or grey; the face's working-view rows and columns before the refinement, the
    candidate it came from and its rivals, and its refined outline):
    :func:`top_edge_doubts`, :func:`outline_doubts`, :func:`foot_doubts`,
    :func:`top_band_doubts`, :func:`rival_doubts`, :func:`top_face_doubts` (``below_horizon``:
    the face's top lies below the view's horizon). They move the reported confidence
    only, never the face."""
    return [
        *top_edge_doubts(ay, rb, ul, ur, int(round(vt))),
        *face_runs_on_doubts(ay, rb, ul, ur, int(round(vt))),
        *outline_doubts(camera, lines),
        *foot_doubts(image, lines),
        *top_band_doubts(image, lines),
        *frame_doubts(image, lines),
        *rival_doubts(best, rivals),
        *top_face_doubts(image, lines, below_horizon),
    ]


def pixel_factor(height_px: float | None, width_px: float | None) -> float:
    """0..1: how well the face's image size allows a 5 % measurement (one factor of
    ``min(1, size / SMALL_FACE_PX)`` per dimension; 1 when a size is unknown)."""
    f = 1.0
    for size in (height_px, width_px):
        if size is not None:
            f *= min(1.0, max(0.0, size) / SMALL_FACE_PX)
    return f


def reported_confidence(
    conf: float,
    doubts: list[str],
    height_px: float | None,
    width_px: float | None,
    min_confidence: float,
    rig_given: bool,
) -> tuple[float, list[str]]:
    """The confidence a detection is reported with, and the doubts that cut it.

    ``conf`` is the confidence the method decided with (the face passed
    ``min_confidence`` with it); ``doubts`` those the stages recorded (names from
    :data:`DOUBT_FACTORS`); ``rig_given``: the floor contact was predicted from a rig, not
    found in the image, and the :data:`NO_RIG_ONLY` doubts do not apply. Each doubt's
    factor and :func:`pixel_factor` scale the confidence down, but never under
    ``min_confidence`` (a reported face stays a detection; the doubts decide how sure it
    is, not whether it is seen). Rounded to 3 decimals, as the method's own figure."""
    applied = [
        d
        for d in dict.fromkeys(doubts)
        if d in DOUBT_FACTORS
        and not (rig_given and d in NO_RIG_ONLY)
        and not (not rig_given and d in RIG_ONLY)
    ]
    factor = 1.0
    for d in applied:
        factor *= DOUBT_FACTORS[d]
    pixels = pixel_factor(height_px, width_px)
    if pixels < 1.0:
        applied.append(SMALL_FACE)
        factor *= pixels
    if not applied:
        return conf, []
    floor = min(conf, min_confidence)
    return round(max(floor, conf * factor), 3), applied
