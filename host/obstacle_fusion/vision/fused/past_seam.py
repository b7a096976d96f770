"""A side on a seam: the face's top and foot edges run on past it to the face's corner.

The face is one surface at the sonar's depth, square to the beam. Its top edge and its
foot (the floor-contact row) are straight lines that end where the surface ends, at its
two sides. A plank seam, tape or a print's inner edge up the face is a vertical line too,
and the side search can take it for a side (a face of planks measured as one or two
planks, a poster's frame measured to the photograph's edge inside it). A careful reader
follows the top edge and the foot out past such a side: where both run on at their own
rows, with the face's colour under the top and over the foot, the side was a seam; the
face ends where both stop together, at a vertical edge.
"""

from __future__ import annotations

import logging
from typing import Any

import numpy as np
import numpy.typing as npt
from numpy.linalg import norm

from obstacle_fusion.vision.types import View

log = logging.getLogger(__name__)

#: The rule's switch (with the rig given, in :class:`FusedMethod` after the settled top).
SIDES_PAST_SEAMS = True
#: An edge runs on at a column where its |d/dy| (strongest of its row +-1) holds this
#: share of its median along the face.
RUN_ON_SHARE = 0.5
#: Columns in a row under that share crossed (a seam's own dip, a blurred corner).
RUN_GAP = 2
#: The least run past the side that is read (columns): shorter is the side's own blur.
MIN_RUN = 4
#: The top's and the foot's runs end together (columns apart) at the face's corner.
ENDS_APART = 3  # (the top may run on farther: a line behind it)
#: The strips under the top and over the foot read for the face's colour (rows clear of
#: the edge, rows deep) and the columns inside the side they are matched against.
STRIP_SKIP = 2
STRIP_ROWS = 4
INSIDE_COLUMNS = 8
#: The strips past the side are the face's when this near the strips inside (8-bit Lab).
SAME_SURFACE = 15.0
#: The lightness's weight in those distances: planks and a print's parts differ in shade.
SHADE_WEIGHT = 0.3
#: ... or at most this share of its distance to the strip past the corner.
NEARER_SHARE = 0.5
#: The columns at the side left out of the colour strips (the seam's own line).
SIDE_SKIP = 2
#: The corner's vertical edge (its mean |d/dx| over the face's rows, strongest of the
#: SNAP columns either side of the foot's end) against the median column of the face.
SIDE_OVER_FACE = 3.0
SNAP = 3
#: The corner must be seen: a foot running on to within VIEW_MARGIN columns of the view's
#: edge moves nothing (new10 photo/3474 ordinary: a faint top and the floor's line ran to
#: the edge, w +55 %).
IN_VIEW = True
VIEW_MARGIN = 4
#: The widest face the move may give (metres at the face's depth).
MAX_WIDTH_M = 1.5


def _edge_along(ay: npt.NDArray[np.float32], row: int) -> npt.NDArray[np.float32]:
    """|d/dy| along ``row``, the strongest of the row and its two neighbours per column."""
    r0, r1 = max(row - 1, 0), min(row + 2, ay.shape[0])
    return np.asarray(ay[r0:r1].max(axis=0), np.float32)


def _run_end(edge: npt.NDArray[np.float32], start: int, step: int, level: float) -> int:
    """The last column from ``start`` (``step`` outwards) where ``edge`` holds ``level``,
    crossing at most RUN_GAP columns under it; ``start - step`` where it does not."""
    end, gap, col = start - step, 0, start
    while 0 <= col < edge.size:
        if edge[col] >= level:
            end, gap = col, 0
        else:
            gap += 1
            if gap > RUN_GAP:
                break
        col += step
    return end


def _snap(ax: npt.NDArray[np.int16], top: int, bottom: int, column: int) -> tuple[int, float]:
    """The column within SNAP of ``column`` whose |d/dx| is strongest over the face's rows:
    (column, that mean). The middle of the strongest columns (rounded up): the 1x3
    dilation makes an edge a plateau, whose first column (argmax's) lay one column left
    of the edge, out past a left side, in from a right one (the sides' convention: the
    left the face's first column, the right the first past it)."""
    lo, hi = max(column - SNAP, 0), min(column + SNAP + 1, ax.shape[1])
    means = ax[top:bottom, lo:hi].astype(np.float32).mean(axis=0)
    best = int(np.argmax(means))
    last = best
    while last + 1 < means.size and means[last + 1] >= means[best]:
        last += 1
    return lo + (best + last + 1) // 2, float(means[best])


def _face_grain(ax: npt.NDArray[np.int16], top: int, bottom: int, inner: slice) -> float:
    """The median column's mean |d/dx| over the face's rows (its grain, seams outvoted)."""
    return float(np.median(ax[top:bottom, inner].astype(np.float32).mean(axis=0)))


def _strip(
    image: npt.NDArray[Any], view: View, r0: int, r1: int, c0: int, c1: int
) -> npt.NDArray[np.float32] | None:
    """The median Lab colour of rows r0..r1-1, columns c0..c1-1 in the view (None when
    empty, or off the view: a strip past a corner at the view's edge is not there to
    read; one running off either edge reads its columns in view)."""
    h, w = view.out.shape
    # (clipped at both ends: a negative start once read nothing at the left edge, where
    # the right edge read the columns in view, so a corner 4-11 columns from the left
    # edge was never taken, one as near the right edge was)
    r0, r1, c0, c1 = max(r0, 0), min(r1, h), max(c0, 0), min(c1, w)
    if r1 <= r0 or c1 <= c0:
        return None
    lab = view.lab(image, r0, r1, c0, c1, 1)
    return np.asarray(np.median(lab.reshape(-1, 3).astype(np.float32), axis=0), np.float32)


def _same_surface(
    image: npt.NDArray[Any],
    view: View,
    rows: tuple[int, int],
    side: int,
    end: int,
    step: int,
) -> bool:
    """The strip ``rows`` past ``side`` (to ``end``) is the face's: near the strip just
    inside the side (planks differ in shade: or nearer it than what lies past ``end``)."""
    if step > 0:
        past = (side + SIDE_SKIP + 1, end - SIDE_SKIP + 1)
        inside = (side - SIDE_SKIP - INSIDE_COLUMNS, side - SIDE_SKIP)
        beyond = (end + SIDE_SKIP + 1, end + SIDE_SKIP + 1 + INSIDE_COLUMNS)
    else:
        past = (end + SIDE_SKIP, side - SIDE_SKIP)
        inside = (side + SIDE_SKIP + 1, side + SIDE_SKIP + 1 + INSIDE_COLUMNS)
        beyond = (end - SIDE_SKIP - INSIDE_COLUMNS, end - SIDE_SKIP)
    a = _strip(image, view, rows[0], rows[1], *past)
    b = _strip(image, view, rows[0], rows[1], *inside)
    c = _strip(image, view, rows[0], rows[1], *beyond)
    if a is None or b is None or c is None:
        return False
    w = np.array([SHADE_WEIGHT, 1.0, 1.0], np.float32)
    to_inside, to_beyond = float(norm(w * (a - b))), float(norm(w * (a - c)))
    log.debug(
        "strip %s past %d: %.1f from inside, %.1f from beyond", rows, side, to_inside, to_beyond
    )
    # never nearer what lies past the corner than the face (new10 photo/3458 ordinary: a
    # faint top over the wall's colour, 9.6 from the face and 0.2 from the wall past it)
    return to_inside < to_beyond and (
        to_inside <= SAME_SURFACE or to_inside <= NEARER_SHARE * to_beyond
    )


def _side_past_seam(
    image: npt.NDArray[Any],
    view: View,
    ay: npt.NDArray[np.float32],
    ax: npt.NDArray[np.int16],
    top: int,
    bottom: int,
    sides: tuple[int, int],
    step: int,
    max_width: float,
) -> int:
    """One side moved out (``step``) to where the top and the foot stop together, or kept."""
    left, right = sides
    side = right if step > 0 else left
    top_edge, foot_edge = _edge_along(ay, top), _edge_along(ay, bottom)
    inner = slice(left + SIDE_SKIP + 1, right - SIDE_SKIP)
    if inner.stop - inner.start < 2 * INSIDE_COLUMNS:
        return side
    top_level = RUN_ON_SHARE * float(np.median(top_edge[inner]))
    foot_level = RUN_ON_SHARE * float(np.median(foot_edge[inner]))
    start = side + step * (SIDE_SKIP + 1)
    top_end = _run_end(top_edge, start, step, top_level)
    foot_end = _run_end(foot_edge, start, step, foot_level)
    run = step * (foot_end - side)
    log.debug(
        "side %d: top runs to %d (level %.0f), foot to %d (level %.0f)",
        side,
        top_end,
        top_level,
        foot_end,
        foot_level,
    )
    if run < MIN_RUN or step * (top_end - foot_end) < -ENDS_APART:
        return side
    # the corner: the strongest vertical edge at the foot's end, standing up the face
    if IN_VIEW and not VIEW_MARGIN <= foot_end < ax.shape[1] - VIEW_MARGIN:
        # the foot runs on out of the view: no corner is seen (a floor line, the face
        # running out of sight), the side is not moved to the view's edge
        log.debug("side %d: the foot runs on out of the view", side)
        return side
    end, strength = _snap(ax, top, bottom, foot_end)
    grain = _face_grain(ax, top, bottom, inner)
    together = abs(top_end - foot_end) <= ENDS_APART
    if step * (end - side) < MIN_RUN or not (together or strength >= SIDE_OVER_FACE * grain):
        log.debug(
            "side %d: top and foot run on to %d, no side there (%.0f, grain %.0f)",
            side,
            end,
            strength,
            grain,
        )
        return side
    new_width = (end - left) if step > 0 else (right - end)
    if new_width > max_width:
        return side
    under_top = (top + STRIP_SKIP + 1, top + STRIP_SKIP + 1 + STRIP_ROWS)
    over_foot = (bottom - STRIP_SKIP - STRIP_ROWS, bottom - STRIP_SKIP)
    if not (
        _same_surface(image, view, under_top, side, end, step)
        and _same_surface(image, view, over_foot, side, end, step)
    ):
        log.debug("side %d: top and foot run on to %d, another surface", side, end)
        return side
    log.debug("side %d: a seam, the top and foot run on to %d", side, end)
    return end


def sides_past_seams(
    image: npt.NDArray[Any],
    view: View,
    ay: npt.NDArray[np.float32],
    ax: npt.NDArray[np.int16],
    top: int,
    bottom: int,
    sides: tuple[int, int],
    depth: float,
) -> tuple[int, int]:
    """The face's sides, each moved out to where its top and foot edges stop together when
    both run on past it over the face's colour (SIDES_PAST_SEAMS); as given otherwise."""
    if not SIDES_PAST_SEAMS or image.ndim != 3 or not 0 <= top < bottom < ay.shape[0]:
        return sides
    max_width = MAX_WIDTH_M * view.fx / depth
    left = _side_past_seam(image, view, ay, ax, top, bottom, sides, -1, max_width)
    right = _side_past_seam(image, view, ay, ax, top, bottom, (left, sides[1]), 1, max_width)
    return left, right
