"""Where the obstacle meets the floor, found in the image when the rig is not known.

Receives a frame, the face depth from the sonar and a level View (pitch taken as 0); returns
candidate rows of that view, lowest first, where the floor in front of the robot stops: a
step in the colour of a narrow band of columns around the beam's axis, with the rows above it
staying off the floor's colour (a tile joint or plank seam is a line, not a step). Each row
is one hypothesis of the camera's height, h = (row - cy) D / fy, that the measurement then
tries; the JSON says ``rig_source: estimated``.
"""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.fused.profiles import median_of, row_norms
from obstacle_fusion.vision.types import View

STEP_ROWS = 5  # rows averaged on each side of a candidate step
MIN_STEP_GREY = 10.0  # a step smaller than this (colour distance, 8-bit) is floor texture
NOISE_FACTOR = 5.0  # a step must stand this many median steps above the floor's own
MAX_CANDIDATES = 8
BAND_HALF_M = 0.04  # half-width of the column band at the face, metres


def band_rows(image: npt.NDArray[np.uint8], view: View, depth_m: float) -> npt.NDArray[np.float32]:
    """Mean colour (or grey) of each row of the view over a narrow band around the beam axis."""
    half = max(3, int(view.fx * BAND_HALF_M / depth_m))
    u0 = int(round(view.cx))
    x0, x1 = max(0, u0 - half), min(view.camera.width, u0 + half + 1)
    m1 = view.map1[:, x0:x1]
    m2 = view.map2[:, x0:x1]
    band = cv2.remap(image, m1, m2, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    rows = band.astype(np.float32).mean(axis=1)
    return rows.reshape(rows.shape[0], -1)


def contact_rows(
    image: npt.NDArray[np.uint8], view: View, depth_m: float, above_px: float = 0.0
) -> list[int]:
    """Candidate floor-contact rows (view rows), lowest first; empty when none stands out.

    ``above_px``: how far above the view's centre row the floor may still show (a camera
    pitched down lifts the horizon); with no pitch the floor lies below the horizon."""
    rows = band_rows(image, view, depth_m)
    n = rows.shape[0]
    k = STEP_ROWS
    top = max(k, int(view.cy - above_px) + 2)
    if n - top < 4 * k:
        return []
    cs = np.vstack(
        [np.zeros((1, rows.shape[1]), np.float64), np.cumsum(rows, axis=0, dtype=np.float64)]
    )
    v = np.arange(top + k, n - k)
    above = (cs[v] - cs[v - k]) / k
    below = (cs[v + k] - cs[v]) / k
    step = row_norms(above - below)
    threshold = max(MIN_STEP_GREY, NOISE_FACTOR * float(median_of(step)))
    out: list[int] = []
    for i in range(len(step) - 2, 0, -1):  # from the bottom up
        s = step[i]
        if s < threshold or s < step[i - 1] or s < step[i + 1]:
            continue
        row = int(v[i])
        # the floor's colour below the step, robust to a seam line right under it
        floor = median_of(rows[row + 2 : row + 2 + 2 * k], axis=0)
        higher = rows[max(top, row - 4 * k) : row - 1]
        if len(higher) == 0:
            continue
        # the rows above stay off the floor's colour: a step, not a seam line
        if float(median_of(row_norms(higher - floor))) < MIN_STEP_GREY:
            continue
        out.append(row)
        if len(out) >= MAX_CANDIDATES:
            break
    return out
