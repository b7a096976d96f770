"""The face found by its texture, where neither its edges nor its colour give it.

A face of grey bricks on grey paving, or of grained wood on gravel, has no side edge
stronger than its own joints and no colour step to its surroundings; what differs is its
texture: how strong its vertical and horizontal detail is over a few centimetres. Receives
the frame, the view, the face depth and the band of likely floor-contact rows (from the
sonar range and the rig); returns (contact row, top row, left, right, evidence) in the
view, or None.

The texture is read as three smoothed maps, each over a window of TEXTURE_WINDOW_M at the
face: the log of |d/dx| and of |d/dy| and the grey level (scaled so that GREY_SCALE grey
levels weigh as much as a factor of e in detail). Just above the contact row, in the
beam's core, is the face; just below it, the floor: the contact row is where those two
differ most. The face then runs sideways and up as far as the texture stays nearer the
face's than half that step.
"""

from __future__ import annotations

import logging
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.fused.profiles import clamp, median_of, row_norms, walk_on
from obstacle_fusion.vision.types import View

log = logging.getLogger(__name__)

#: The texture window, metres at the face (a brick course and its joint).
TEXTURE_WINDOW_M = 0.10
#: Grey levels that weigh as much as a factor of e in the detail's strength.
GREY_SCALE = 20.0
#: The foot's texture step (face against floor) must reach this to seek a face at all.
MIN_FOOT_STEP = 0.8
#: ... and gives full evidence at this.
FULL_FOOT_STEP = 1.6
#: A face's sides must part its texture from what stands beside by this for full evidence.
FULL_SIDE_STEP = 1.0
#: Rows whose foot step is within this share of the largest make its plateau.
PLATEAU_SHARE = 0.9
#: The face's texture must run up at least this far (metres) to be a face.
MIN_HEIGHT_M = 0.05
#: Half the beam's core sampled for the face's texture, metres at the face.
CORE_HALF_M = 0.04


#: A gloss's highlight is light added on the face: its rows are lighter than the face's
#: foot while their detail (the |d/dx| and |d/dy| features) stays the face's, and above
#: it the face's texture comes back (photo/3213 hard: a grey gloss face on grey gravel,
#: the highlight's rows 0.8 grey units over the foot's, their detail within 0.5 of it
#: under a tolerance of 0.63: the walk stopped under the highlight, height -54 %). Such
#: rows are crossed where the face's own texture resumes above them, over at most as many
#: rows as the walk had climbed to them (a highlight lies inside the face, its upper part
#: at most: the generator puts its centre 0.1-0.5 of the face from its top). A switch for
#: the tests.
GLOSS_CROSSED = True
#: ... where above the crossed rows the face's shade comes back: the rows of its texture
#: there no lighter than this share of the highlight's greatest rise (their median; a
#: highlight is a hump of light on one surface, 3213 hard: 0.1-0.2 of a rise of 0.82; a
#: poster's lighter upper part stays light, photo/2085 hard with no rig: 1.1-1.2 of 1.4,
#: just under the tolerance, the walk carried 18 rows up it, +94 % where the face was
#: refused).
GLOSS_FALL_SHARE = 0.5


def _past_highlight(
    diff: npt.NDArray[np.float32], on_rows: list[bool], tol: float, start: int, top: int, gap: int
) -> int:
    """The top of the texture's walk from ``start`` up, carried past a gloss's highlight
    (GLOSS_CROSSED): ``diff`` the rows' features less the face's (detail x, detail y,
    grey), ``on_rows`` the rows of the face's texture, ``top`` the walk's end over gaps
    of ``gap`` rows."""
    lit = (row_norms(diff[:, :2]) <= tol) & (diff[:, 2] > 0.0)
    both = [a or bool(b) for a, b in zip(on_rows, lit.tolist(), strict=True)]
    far = walk_on(both, start, -1, gap)
    while far < top and not on_rows[far]:
        far += 1  # the walk ends on the face's own texture, not inside the highlight
    gap_rows = [r for r in range(far, top) if not on_rows[r]]
    if far >= top or len(gap_rows) > start - top:
        return top
    # ... and above it the face's own shade comes back: a highlight is a hump of light
    resumed = [r for r in range(far, gap_rows[0]) if on_rows[r]]
    lit_rows = [r for r in gap_rows if lit[r]]  # the highlight's own, not a bridged row
    if not resumed or not lit_rows:
        return top
    rise = float(diff[lit_rows, 2].max())
    if float(np.median(diff[resumed, 2])) > GLOSS_FALL_SHARE * rise:
        return top
    crossed = len(gap_rows)
    log.debug("texture: top %d past a highlight of %d rows: %d", top, crossed, far)
    return far


def _features(image: npt.NDArray[Any], view: View, rows: int, k: int) -> npt.NDArray[np.float32]:
    """The view's top ``rows`` rows as rows x columns x 3 texture features."""
    grey = cv2.cvtColor(image, cv2.COLOR_BGR2GRAY) if image.ndim == 3 else image
    seen = cv2.remap(
        grey, view.map1[:rows], view.map2[:rows], cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE
    )
    dx = np.empty(seen.shape, np.int16)
    dy = np.empty(seen.shape, np.int16)
    cv2.spatialGradient(seen, dx, dy)
    out = np.empty((*seen.shape, 3), np.float32)
    for i, a in enumerate((np.abs(dx), np.abs(dy))):
        out[..., i] = np.log1p(cv2.blur(a.astype(np.float32), (k, k)))
    out[..., 2] = cv2.blur(seen.astype(np.float32), (k, k)) / GREY_SCALE
    return out


def face_from_texture(
    image: npt.NDArray[Any] | None,
    view: View,
    rows: tuple[int, int],
    depth_m: float,
) -> tuple[int, int, int, int, float] | None:
    """The face by its texture: (contact row, top row, left, right, evidence 0..1), or
    None when no texture step stands at the foot or it makes no face shape."""
    if image is None:
        return None
    h, w = view.out.shape
    k = int(clamp(round(view.fx * TEXTURE_WINDOW_M / depth_m), 5, 31)) | 1
    half = k // 2 + 2  # a window's centre clear of the contact row
    r0, r1 = rows
    core = max(2, int(round(view.fx * CORE_HALF_M / depth_m)))
    c0, c1 = int(view.cx) - core, int(view.cx) + core + 1
    n = min(h, r1 + half + 1)
    if r0 - half - k < 0 or r1 + half >= n or c0 < 0 or c1 > w:
        return None
    feat = _features(image, view, n, k)
    prof = median_of(feat[:, c0:c1], axis=1)  # per row, the beam core's texture
    steps = row_norms(prof[r0 - half : r1 - half + 1] - prof[r0 + half : r1 + half + 1])
    best_step = float(steps.max()) if steps.size else 0.0
    # the smoothed step is a plateau a few rows wide about the contact: its middle
    near = (steps >= PLATEAU_SHARE * best_step).nonzero()[0]
    contact = r0 + int(round(float(near.mean()))) if near.size else -1
    log.debug("texture: contact %d, foot step %.2f (window %d)", contact, best_step, k)
    if contact < 0 or best_step < MIN_FOOT_STEP:
        return None
    seed = slice(max(0, contact - half - k), contact - half + 1)
    face = median_of(prof[seed], axis=0)
    # sideways: each column's texture over the rows just above the foot
    cols = median_of(feat[seed], axis=0)  # columns x 3
    tol = 0.5 * best_step  # nearer the face's texture than the floor's
    on_cols = (row_norms(cols - face) <= tol).tolist()
    log.debug("texture: core %d-%d on %d, tol %.2f", c0, c1, sum(on_cols[c0:c1]), tol)
    left = walk_on(on_cols, c0, -1, half)
    right = walk_on(on_cols, c1 - 1, 1, half) + 1
    log.debug("texture: sides %d-%d", left, right)
    if right - left < 2 * k:
        return None
    # up: each row's texture across the face, clear of its sides' blur
    inner = slice(left + half, right - half)
    up = median_of(feat[:contact, inner], axis=1)
    on_rows = (row_norms(up - face) <= tol).tolist()
    top = walk_on(on_rows, contact - half, -1, half)
    if GLOSS_CROSSED:
        top = _past_highlight(up - face, on_rows, tol, contact - half, top, half)
    log.debug("texture: top %d", top)
    if (contact - top) * depth_m / view.fy < MIN_HEIGHT_M or top <= 0:
        return None  # no face shape, or it runs out of the image: not a face to measure
    mid = slice(top + (contact - top) // 4, contact - (contact - top) // 4)
    beside = []
    for a, b in ((left - half - k, left - half), (right + half, right + half + k)):
        if a < 0 or b > w:
            return None  # a side at the image's border: not measured whole
        beside.append(
            float(np.linalg.norm(median_of(feat[mid, a:b].reshape(-1, 3), axis=0) - face))
        )
    log.debug("texture: beside %s", [round(b, 2) for b in beside])
    evidence = min(1.0, best_step / FULL_FOOT_STEP) * min(1.0, min(beside) / FULL_SIDE_STEP)
    return contact, int(top), int(left), int(right), evidence
