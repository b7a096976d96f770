"""The grey image the fused method reads, turned towards the face's colour against the floor.

Receives a BGR frame, the level View and the row where the face meets the floor; returns one
8-bit channel. Plain luminance loses a green box on grey gravel (same brightness, another
colour). A patch just above the floor-contact row in the beam is the face, one just below it
the floor: projecting the colours half on luminance and half on the direction from the
floor's colour to the face's keeps every luminance edge and adds the face's own contrast.
With a frame that is grey already, or face and floor of one colour, it is plain luminance.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.fused.profiles import norm
from obstacle_fusion.vision.fused.search import SHORT_STRIP_M, line_columns
from obstacle_fusion.vision.types import View

#: Share of the face-floor colour direction in the projection (the rest is luminance).
FACE_SHARE = 0.5
#: Face and floor closer than this (8-bit BGR distance) give no direction to trust.
MIN_COLOUR_STEP = 12.0
#: The part of the face-floor colour step luminance does not see must reach this (8-bit
#: BGR distance) for the turn to be worth its cost; below it, plain luminance.
MIN_CHROMA_STEP = 15.0
#: Rows above and below the contact row sampled for the face and the floor (view rows).
SAMPLE_ROWS = (5.0, 8.0, 11.0)
#: Half the sampled width at the face, metres (the beam's core).
SAMPLE_HALF_M = 0.03

#: Rows below the contact row the method may read beyond its search band (3 px +
#: (3 % + 1 cm / D) of the row's distance below the horizon), with a margin.
BAND_ROWS = 12.0

_LUMA = np.array([0.114, 0.587, 0.299])  # BGR weights of OpenCV's grey

_c_project3: Callable[[Any, float, float, float, float, Any], None] | None
try:  # the optional C accelerator (setup.py)
    from obstacle_fusion.vision.fused._cmiddle import project3 as _c_project3
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_project3 = None

#: A row and colours on which OpenCV's 3-to-1 transform rounds otherwise when its build
#: here multiplies and adds in one step (fused multiply-adds, as the C projection does)
#: than when it rounds each product: where OpenCV does not answer as the C projection
#: does, the C projection is not used.
_PROBE_ROW = (0.3, 0.6, -0.2, 51.0)
_PROBE_BGR = ((219, 3, 0), (239, 3, 0), (217, 4, 0), (237, 4, 0), (229, 8, 0), (12, 9, 0))


def _c_project_agrees() -> bool:
    """Whether the C projection gives OpenCV's integers for the probe colours (and one row
    of every 8-bit value on each channel)."""
    if _c_project3 is None:  # pragma: no cover - only where the extension did not build
        return False
    ramp = np.arange(256, dtype=np.uint8)
    image = np.concatenate(
        [np.array(_PROBE_BGR, np.uint8), np.stack([ramp, ramp[::-1], ramp[::3].repeat(3)[:256]], 1)]
    )[None]
    matrix = np.array([_PROBE_ROW], np.float32)
    mine = np.empty(image.shape[:2], np.uint8)
    a, b, c, d = (float(v) for v in matrix[0])
    _c_project3(image, a, b, c, d, mine)
    return bool(np.array_equal(mine, cv2.transform(image, matrix)))


if _c_project3 is not None and not _c_project_agrees():  # pragma: no cover - another build
    _c_project3 = None


def _mean_colours(
    image: npt.NDArray[Any], pts: npt.NDArray[np.float64], groups: int
) -> list[npt.NDArray[Any] | None]:
    """Mean colour of the 3x3 patches around the points that lie inside the image, for
    each of ``groups`` equal consecutive groups of ``pts`` (None: none inside), from one
    gather: np.mean of 8-bit values is their integer sum, exact in float64, over the count,
    so the grouping changes no value."""
    h, w = image.shape[:2]
    x = np.rint(pts[:, 0]).astype(int)
    y = np.rint(pts[:, 1]).astype(int)
    keep = (x >= 1) & (x < w - 1) & (y >= 1) & (y < h - 1)
    xs, ys = np.where(keep, x, 1), np.where(keep, y, 1)  # out-of-image points not summed
    patches = image[ys[:, None, None] + _PATCH[0], xs[:, None, None] + _PATCH[1]]
    sums = patches.reshape(len(pts), -1, image.shape[2]).sum(axis=1, dtype=np.int64)
    per = len(pts) // groups
    out: list[npt.NDArray[Any] | None] = []
    for g in range(groups):
        k = keep[g * per : (g + 1) * per]
        n = int(np.count_nonzero(k))
        # np.mean of the kept patches: their integer sum (exact in float64) over the count
        out.append(None if n == 0 else sums[g * per : (g + 1) * per][k].sum(axis=0) / (9 * n))
    return out


_PATCH = np.mgrid[-1:2, -1:2]  # row and column offsets of a 3x3 patch
#: The sample offsets (du units across, rows) around the contact row's centre column.
_OFFSETS = np.array([(a, r) for a in (-1.0, 0.0, 1.0) for r in SAMPLE_ROWS])
_LUMA_LEN = float(np.linalg.norm(_LUMA))
_LUMA_UNIT = _LUMA / _LUMA_LEN


def _sample_points(
    view: View, contact_row: float, depth_m: float
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """The view points sampled for the face (SAMPLE_ROWS above the contact row) and for
    the floor (as far below it), across the beam's core (SAMPLE_HALF_M either side of the
    centre column, at least 3 px): the channels read the face's colour at the same place."""
    du = max(3.0, view.fx * SAMPLE_HALF_M / depth_m)
    offsets = _OFFSETS * [du, 1.0]  # (a du, r): the same products
    centre = np.array([view.cx, contact_row])
    return centre + offsets * [1.0, -1.0], centre + offsets


def face_floor_grey(
    image: npt.NDArray[Any], view: View, contact_row: float, depth_m: float
) -> npt.NDArray[Any]:
    """One channel for the fused method: ``image`` itself when it is grey already."""
    if image.ndim != 3:
        return image
    above, below = _sample_points(view, contact_row, depth_m)
    # the face's samples above the contact row, the floor's below it: one projection
    pts = view.to_input(np.concatenate([above, below]))
    face, floor = _mean_colours(image, pts, 2)
    if face is None or floor is None:
        return image
    return _turned(image, view, face - floor, contact_row, depth_m)


#: Heights above the contact row (metres at the face) of the rows whose median colour,
#: across the frame, is taken for what stands beside the face: the wall or the floor
#: farther back, seen past its sides (a face wider than the frame's half is its own median,
#: and then no direction is added).
BACKGROUND_ROWS_M = (0.1, 0.2, 0.3)


def face_background_grey(
    image: npt.NDArray[Any], view: View, contact_row: float, depth_m: float
) -> npt.NDArray[Any] | None:
    """One channel turned towards the face's colour against what stands beside it, or
    None where luminance sees that step already (or the frame is grey).

    A face in the lightness of the wall or floor behind it shows its sides in hue only (a
    grey box against a blue wall), while its seams and prints are luminance lines: the
    luminance and face-floor channels then find a pair of seams, or no face. The face's
    colour is the beam's core just above the contact row (as :func:`face_floor_grey`);
    the background's, the median colour of the rows BACKGROUND_ROWS_M above that row
    across the frame."""
    if image.ndim != 3:
        return None
    above, _ = _sample_points(view, contact_row, depth_m)
    (face,) = _mean_colours(image, view.to_input(above), 1)
    heights = np.array([[view.cx, contact_row - view.fy * m / depth_m] for m in BACKGROUND_ROWS_M])
    rows = [int(round(r)) for r in view.to_input(heights)[:, 1]]
    rows = [r for r in rows if 0 <= r < image.shape[0]]
    if face is None or not rows:
        return None
    background = np.median(image[rows].reshape(-1, image.shape[2]), axis=0)
    turned = _turned(image, view, face - background, contact_row, depth_m)
    return None if turned is image else turned


#: The rows over which a side found on that channel is checked for a seam: this many metres
#: (at the face) just above its foot: the side search's short strip ...
SEAM_STRIP_M = SHORT_STRIP_M
#: ... at the side's column and this many either side of it (the box's sub-pixel side).
SEAM_SIDE_COLUMNS = 1


def side_on_seam(
    grey: npt.NDArray[Any], box: tuple[float, float, float, float], view: View, depth_m: float
) -> bool:
    """Whether a side of the face ``box`` (x0, y0, x1, y1 in ``grey``) found on the
    background channel is a thin line on one shade just above its foot (see
    :func:`~obstacle_fusion.vision.fused.search.line_columns`): a seam or joint the face
    runs on past, not a side. The last try's face is not taken then: its colour against
    the background shows the face's sides, and a seam's pair is a part of the face."""
    x0, _, x1, y1 = box
    foot = int(round(y1))
    rows = max(3, int(round(view.fy * SEAM_STRIP_M / depth_m)))
    strip = grey[max(0, foot - 1 - rows) : max(0, foot - 1)]
    d = SEAM_SIDE_COLUMNS
    cols = [int(round(x)) + k for x in (x0, x1) for k in range(-d, d + 1)]
    return bool(line_columns(strip, cols))


def _turned(
    image: npt.NDArray[Any],
    view: View,
    step: npt.NDArray[Any],
    contact_row: float,
    depth_m: float,
) -> npt.NDArray[Any]:
    """``image`` projected half on luminance, half on the colour ``step`` (the face's
    colour less what it is told from), down to the rows the method reads; ``image``
    itself where luminance sees that step already."""
    size = norm(step)
    luma_unit = _LUMA_UNIT
    chroma = norm(step - float(step @ luma_unit) * luma_unit)
    if size < MIN_COLOUR_STEP or chroma < MIN_CHROMA_STEP:
        return image  # luminance sees the step already: nothing to add
    towards = step / size
    if float(towards @ _LUMA) < 0.0:
        towards = -towards
    luma_len = _LUMA_LEN
    weights = (1.0 - FACE_SHARE) * _LUMA / luma_len + FACE_SHARE * towards
    weights *= luma_len / norm(weights)
    # black stays at or above 0 whatever the signs of the weights
    offset = -255.0 * float(np.minimum(weights, 0.0).sum())
    matrix = np.array([[*weights, offset]], np.float32)
    # only the rows the method's levelled view reads: down to its floor-contact band
    band = contact_row + BAND_ROWS + max(0.0, contact_row - view.cy) * (0.03 + 0.01 / depth_m)
    k = view.input_rows(int(np.ceil(band)))
    out = np.zeros(image.shape[:2], np.uint8)
    if _c_project3 is not None:
        try:  # OpenCV's integers, faster (checked at import, _c_project_agrees)
            a, b, c, d = (float(v) for v in matrix[0])
            _c_project3(image[:k], a, b, c, d, out[:k])
            return out
        except ValueError:  # pixels not packed, or weights it does not take: OpenCV
            pass
    cv2.transform(image[:k], matrix, dst=out[:k])
    return out
