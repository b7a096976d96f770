"""A face's sides checked against its top and bottom edges: a seam is not a side.

Receives the chosen face (floor-contact row, top row, side columns, in the levelled view)
and the view's |d/dy| and |d/dx|; returns the side columns moved outward past vertical
seams. A face is one surface at the sonar's depth: its floor-contact edge and its top edge
run along its whole width, and end at its true sides. A plank seam, a panel joint or the
edge of a poster is a strong vertical edge too, but the face's top and bottom edges run on
across it; the side search, ranking vertical edges by strength, took such seams for sides
and collapsed the width to one plank on independently made rooms.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

#: The edges count as running on while their strength stays above this share of the face's.
CONTINUE_SHARE = 0.5
#: Columns averaged when walking along an edge (one noisy column stops nothing).
WALK_WINDOW = 3
#: Columns where the edges may dip (a seam, a joint) without ending the face.
MAX_GAP = 4
#: Rows either side of an edge row searched for its peak (blur, sub-pixel position).
EDGE_ROWS = 1
#: Side columns searched for the strongest vertical edge where the walk stopped.
SNAP_COLUMNS = 6
#: The face's own edges must stand this many noise levels above the floor's texture.
MIN_EDGE_SNR = 3.0


def _edge_profile(ay: npt.NDArray[np.float32], row: int) -> npt.NDArray[np.float32]:
    """Per column, the strongest |d/dy| within EDGE_ROWS of ``row``."""
    r0 = max(0, row - EDGE_ROWS)
    r1 = min(ay.shape[0], row + EDGE_ROWS + 1)
    return np.asarray(ay[r0:r1].max(axis=0), np.float32)


def _walk(on: npt.NDArray[np.bool_], start: int, step: int) -> int:
    """Last column from ``start`` in direction ``step`` where ``on`` holds, stepping over
    gaps of up to MAX_GAP columns (a dark seam dims the top edge across it)."""
    u = start
    gap = 0
    v = start
    while 0 <= v + step < on.size and gap <= MAX_GAP:
        v += step
        if on[v]:
            u, gap = v, 0
        else:
            gap += 1
    return u


def widen_across_seams(
    ay: npt.NDArray[np.float32],
    ax: npt.NDArray[np.int16],
    bottom: int,
    top: int,
    left: int,
    right: int,
    noise: float,
) -> tuple[int, int]:
    """The face's side columns, moved out to where its top and bottom edges both end."""
    if right - left < 4 or bottom - top < 3:
        return left, right
    gb = _edge_profile(ay, bottom)
    gt = _edge_profile(ay, top)
    inner = slice(left + 1, right)
    ref_b = float(np.median(gb[inner]))
    ref_t = float(np.median(gt[inner]))
    if min(ref_b, ref_t) < MIN_EDGE_SNR * noise:
        return left, right  # too faint to tell a seam from a side
    kernel = np.ones(WALK_WINDOW, np.float32) / WALK_WINDOW
    runs_on = (np.convolve(gb, kernel, mode="same") >= CONTINUE_SHARE * ref_b) & (
        np.convolve(gt, kernel, mode="same") >= CONTINUE_SHARE * ref_t
    )
    sides = np.asarray(ax[top : bottom + 1].mean(axis=0), np.float32)
    new = []
    for side, step in ((left, -1), (right, 1)):
        end = _walk(runs_on, side, step)
        if abs(end - side) <= SNAP_COLUMNS // 2:
            new.append(side)  # the edges stop at the side: it is the face's
            continue
        lo, hi = sorted((end - step * SNAP_COLUMNS, end + step * 2))
        lo, hi = max(lo, 0), min(hi, sides.size - 1)
        new.append(int(lo + np.argmax(sides[lo : hi + 1])))
    return new[0], new[1]
