"""The confidence figure and the min-confidence decision.

Receives the chosen face candidate and its rivals (from
:func:`~obstacle_fusion.vision.fused.scoring.verified`). Returns the confidence: the face's
evidence times one minus its ambiguity (the best rival with little overlap, scoring
nearly as well, makes the choice a guess); and, for a confidence under the method's
minimum, the reason to report no detection.
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
