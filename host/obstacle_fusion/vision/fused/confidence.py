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

from obstacle_fusion.vision.fused.scoring import Candidate

log = logging.getLogger(__name__)


def confidence(best: Candidate, rivals: list[Candidate]) -> float:
    """0..1: the face's evidence, cut by how nearly a different face scores as well."""
    # a different face (little overlap) scoring nearly as well makes the choice a guess
    rival = max((c.score for c in rivals if c.overlap(best) < 0.5), default=0.0)
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
#: (:func:`~obstacle_fusion.vision.fused.region.enclose_by_margin`; taken as the face, or
#: refused because it runs on below the floor-contact rows). With the floor contact found
#: in the image (no rig) the print's own lower edge passes for the floor contact and the
#: print for the face, and nothing ties either to the floor (six of the eight such faces
#: on the tuning rooms with no rig were 8-25 % small). With a rig the contact row is
#: predicted from the range: the doubt is recorded but cuts nothing (:data:`NO_RIG_ONLY`).
FRAMED = "framed_print"
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
#: A face whose image height or width (working view) is under SMALL_FACE_PX: its size is
#: only as sure as its share of that (see :func:`pixel_factor`).
SMALL_FACE = "small_face"

#: What one doubt leaves of the confidence: a doubt alone takes the surest face (1.0)
#: under the 0.5 that means "sure" (halving would leave it at 0.5 exactly).
DOUBT_FACTOR = 0.45
#: The factor each doubt scales the confidence by.
DOUBT_FACTORS: dict[str, float] = {
    TOP_FROM_SIDES: DOUBT_FACTOR,
    FRAMED: DOUBT_FACTOR,
    PITCH_UNREAD: DOUBT_FACTOR,
    PITCH_RERUN_DISAGREES: DOUBT_FACTOR,
}

#: Doubts that cut the confidence only when the floor contact was found in the image.
NO_RIG_ONLY = frozenset({FRAMED})

#: A face side of this many pixels or more is measured well enough for a 5 % bound: a
#: size is the distance between two edges, each found to about half a pixel (the tuning
#: scenes: median size error 0.6 px, 1.1-1.4 px at the 75th percentile, over 2 px at the
#: 90th); 2 px are 5 % of 40 px. A smaller side is as sure as its share of this.
SMALL_FACE_PX = 40.0


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
        if d in DOUBT_FACTORS and not (rig_given and d in NO_RIG_ONLY)
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
