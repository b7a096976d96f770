"""A face's width from its colour: the columns whose foot looks like the face's.

Receives the chosen face (floor-contact row, top row, side columns, in the levelled view)
and the input BGR frame; returns the side columns moved outward to where the face's colour
ends along its foot. A face is one surface standing on the floor-contact row: just above
that row, across its whole width, it shows its own colour (plank seams, joints and tape
are a few columns of another one), and just below it the floor. Beyond its sides the rows
above the contact row show what stands farther back (the floor, the wall), which is
neither the face's colour nor, for the floor, any different from the floor below. On
photographed floors the face's edges are lost in the floor's texture, while its colour is
not: gradients alone collapsed the width to one plank there.
"""

from __future__ import annotations

from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.types import View

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
#: Columns each foot colour is averaged over.
SMOOTH_COLUMNS = 5
#: Columns of another colour crossed without ending the face (a seam, a joint, tape), metres
#: at the face.
MAX_GAP_M = 0.04
#: A side moves only when the face's colour runs on past it by this share of its width.
MIN_WIDEN_SHARE = 0.1
#: Columns either side of the colour's end searched for the strongest vertical edge.
SNAP_COLUMNS = 3


def _band(image: npt.NDArray[Any], view: View, r0: int, r1: int) -> npt.NDArray[np.float32]:
    """The view's rows r0..r1-1 of ``image`` in CIE Lab (float, 8-bit scale)."""
    band = cv2.remap(
        image,
        view.map1[r0:r1],
        view.map2[r0:r1],
        cv2.INTER_LINEAR,
        borderMode=cv2.BORDER_REPLICATE,
    )
    return np.asarray(cv2.cvtColor(band, cv2.COLOR_BGR2LAB), np.float32)


def _walk(on: npt.NDArray[np.bool_], start: int, step: int, max_gap: int) -> int:
    """Last ``on`` column from ``start`` towards ``step``, over gaps of up to max_gap."""
    u, v, gap = start, start, 0
    while 0 <= v + step < on.size and gap <= max_gap:
        v += step
        if on[v]:
            u, gap = v, 0
        else:
            gap += 1
    return u


def widen_by_colour(
    image: npt.NDArray[Any] | None,
    view: View,
    ax: npt.NDArray[np.int16],
    bottom: int,
    top: int,
    left: int,
    right: int,
    depth_m: float,
) -> tuple[int, int]:
    """The face's sides, moved out to where its colour along its foot ends."""
    if image is None or image.ndim != 3 or right - left < 6 or bottom - top < 4:
        return left, right
    h_view = view.out.shape[0]
    rows = int(np.clip(FACE_BAND_SHARE * (bottom - top), *FACE_BAND_ROWS))
    r0 = bottom - EDGE_SKIP - rows
    r1 = min(bottom + EDGE_SKIP + FLOOR_BAND_ROWS + 1, h_view)
    floor_rows = r1 - (bottom + EDGE_SKIP + 1)
    if r0 < 0 or floor_rows < 1:
        return left, right  # the face's foot at the image's edge: no floor to compare
    lab = _band(image, view, r0, r1)
    # per column, W x 3, then over SMOOTH_COLUMNS (a textured floor's grain averages out)
    face = cv2.blur(np.median(lab[:rows], axis=0)[None], (SMOOTH_COLUMNS, 1))[0]
    floor = cv2.blur(np.median(lab[-floor_rows:], axis=0)[None], (SMOOTH_COLUMNS, 1))[0]
    seed = slice(left + 2, right - 1)
    ref = np.median(face[seed], axis=0)
    d_face = np.linalg.norm(face - ref, axis=1)
    spread = float(np.median(d_face[seed]))
    limit = float(np.clip(SPREAD_FACTOR * spread, MIN_FACE_DISTANCE, MAX_FACE_DISTANCE))
    d_floor = np.linalg.norm(face - floor, axis=1)
    on = (d_face <= limit) & (d_floor >= MIN_FLOOR_STEP)
    if float(np.mean(on[seed])) < 0.5:
        return left, right  # the face's own foot is not one colour over the floor
    # the smoothing spreads a seam over SMOOTH_COLUMNS - 1 more columns
    max_gap = max(2, int(round(view.fx * MAX_GAP_M / depth_m))) + SMOOTH_COLUMNS - 1
    min_move = max(SNAP_COLUMNS, MIN_WIDEN_SHARE * (right - left))
    sides_strength = np.asarray(ax[top : bottom + 1].mean(axis=0), np.float32)
    new = []
    for side, step in ((left, -1), (right, 1)):
        end = _walk(on, side - step * 2, step, max_gap)
        if (end - side) * step <= min_move:
            new.append(side)
            continue
        lo, hi = max(end - SNAP_COLUMNS, 0), min(end + SNAP_COLUMNS, on.size - 1)
        new.append(int(lo + np.argmax(sides_strength[lo : hi + 1])))
    return new[0], new[1]
