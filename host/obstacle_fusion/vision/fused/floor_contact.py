"""Where the obstacle meets the floor, found in the image when the rig is not known.

Receives a frame, the face depth from the sonar and a level View (pitch taken as 0); returns
candidate rows of that view, lowest first, where the floor in front of the robot stops: a
step in the colour of a narrow band of columns around the beam's axis, with the rows above it
staying off the floor's colour (a tile joint or plank seam is a line, not a step). Each row
is one hypothesis of the camera's height, h = (row - cy) D / fy, that the measurement then
tries; the JSON says ``rig_source: estimated``.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.fused.profiles import median_of, row_norms
from obstacle_fusion.vision.types import View

STEP_ROWS = 5  # rows averaged on each side of a candidate step
MIN_STEP_GREY = 10.0  # a step smaller than this (colour distance, 8-bit) is floor texture
NOISE_FACTOR = 5.0  # a step must stand this many median steps above the floor's own
MAX_CANDIDATES = 8
# steps under the noise bars tried when no candidate stands a face (gravel near the lens
# steps a dozen times under a far face's foot: 12 stopped short of photo 1181's)
MAX_WEAK_CANDIDATES = 24
FLOOR_NOISE_ROWS = 20  # rows below a step whose own steps give the floor's texture
BAND_HALF_M = 0.04  # half-width of the column band at the face, metres
MIN_BAND_COLUMNS = 3  # a band (moved beside the axis) narrower than this in view is not read


def band_columns(view: View, depth_m: float, shift: int = 0) -> tuple[int, int]:
    """The columns (first, past the last) of the narrow band around the beam's axis, moved
    by ``shift`` band widths (negative to the left)."""
    half = max(3, int(view.fx * BAND_HALF_M / depth_m))
    u0 = int(round(view.cx)) + shift * (2 * half + 1)
    return max(0, u0 - half), min(view.camera.width, u0 + half + 1)


def band_rows(
    image: npt.NDArray[np.uint8], view: View, depth_m: float, shift: int = 0
) -> npt.NDArray[np.float32]:
    """Mean colour (or grey) of each row of the view over a narrow band around the beam axis
    (``shift``: the band moved by that many band widths, negative to the left)."""
    x0, x1 = band_columns(view, depth_m, shift)
    m1 = view.map1[:, x0:x1]
    m2 = view.map2[:, x0:x1]
    band = cv2.remap(image, m1, m2, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    rows = band.astype(np.float32).mean(axis=1)
    return rows.reshape(rows.shape[0], -1)


def contact_rows(
    image: npt.NDArray[np.uint8],
    view: View,
    depth_m: float,
    above_px: float = 0.0,
    shift: int = 0,
) -> list[int]:
    """Candidate floor-contact rows (view rows), lowest first; empty when none stands out
    of the band's steps nor of the floor's own texture below it.

    ``above_px``: how far above the view's centre row the floor may still show (a camera
    pitched down lifts the horizon); with no pitch the floor lies below the horizon.
    ``shift``: the band read that many band widths beside the beam's axis."""
    found = _band_steps(image, view, depth_m, above_px, shift)
    if found is None:
        return []
    rows, v, step, top = found
    band_threshold = NOISE_FACTOR * float(median_of(step))
    out = _steps(rows, v, step, top, band_threshold, None)
    if not out:
        # no step stands out of the whole band's (the wall and the face count there too:
        # a busy room hides a clear foot on gravel): each against the floor's own texture
        # below it
        out = _steps(rows, v, step, top, band_threshold, FLOOR_NOISE_ROWS)
    return out


def weak_contact_rows(image: npt.NDArray[np.uint8], view: View, depth_m: float) -> list[int]:
    """Every step of the band's colour that could be a floor contact, lowest first, up to
    MAX_WEAK_CANDIDATES: at least MIN_STEP_GREY, with the rows above it off the floor's
    colour, however much of the band's (or the floor's) texture is as strong. For when no
    row of :func:`contact_rows` stands a face: a foot of a face little apart from the floor
    (a purple face on grey gravel) steps less than the gravel does."""
    found = _band_steps(image, view, depth_m, 0.0)
    if found is None:
        return []
    rows, v, step, top = found
    return _steps(rows, v, step, top, 0.0, None, MAX_WEAK_CANDIDATES)


def _band_steps(
    image: npt.NDArray[np.uint8], view: View, depth_m: float, above_px: float, shift: int = 0
) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.int64], npt.NDArray[np.float64], int] | None:
    """The band's row colours, the rows a step is read at, the step there (colour distance
    of the STEP_ROWS rows above and below) and the highest row the floor may show; None
    when too few rows lie below it, or the band (moved by ``shift``) lies outside the view
    (a face so near that the band beside the axis is past the image's edge)."""
    x0, x1 = band_columns(view, depth_m, shift)
    if x1 - x0 < MIN_BAND_COLUMNS:
        return None
    rows = band_rows(image, view, depth_m, shift)
    n = rows.shape[0]
    k = STEP_ROWS
    top = max(k, int(view.cy - above_px) + 2)
    if n - top < 4 * k:
        return None
    cs = np.vstack(
        [np.zeros((1, rows.shape[1]), np.float64), np.cumsum(rows, axis=0, dtype=np.float64)]
    )
    v = np.arange(top + k, n - k)
    above = (cs[v] - cs[v - k]) / k
    below = (cs[v + k] - cs[v]) / k
    return rows, v, row_norms(above - below), top


def _steps(
    rows: npt.NDArray[np.float32],
    v: npt.NDArray[np.int64],
    step: npt.NDArray[np.float64],
    top: int,
    band_threshold: float,
    floor_rows: int | None,
    max_candidates: int = MAX_CANDIDATES,
) -> list[int]:
    """The steps of :func:`contact_rows`, lowest first, at most ``max_candidates``: over
    ``band_threshold``, or with ``floor_rows``, over NOISE_FACTOR times the median step of
    that many rows below (at least half of them there to read)."""
    k = STEP_ROWS
    out: list[int] = []
    for i in range(len(step) - 2, 0, -1):  # from the bottom up
        s = step[i]
        if s < MIN_STEP_GREY or s < step[i - 1] or s < step[i + 1]:
            continue
        if floor_rows is None:
            if s < band_threshold:
                continue
        else:
            below = step[i + k : i + k + floor_rows]
            if len(below) < floor_rows // 2 or s < NOISE_FACTOR * float(median_of(below)):
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
        if len(out) >= max_candidates:
            break
    return out


#: The share of a side's height, from its foot up, whose colour step the foot check reads.
FOOT_SHARE = 0.2
#: A side stands on its foot when the colour step across it near the foot is at least
#: this (8-bit BGR distance; the floor beside the foot differs from the face less than the
#: wall beside its middle does, so the middle's step is no measure).
MIN_FOOT_STEP = 12.0
#: Columns either side of a side line whose colours are compared (from, to; pixels).
ACROSS_PX = (2, 5)


def _step_across(
    image: npt.NDArray[np.uint8], line: tuple[float, float, float, float], t0: float, t1: float
) -> float:
    """Median colour step across a side line (x0, y0 at its foot, x1, y1 at its top) over
    the part of it between shares t0 and t1 of its length."""
    x0, y0, x1, y1 = line
    h, w = image.shape[:2]
    n = max(3, int(abs(y1 - y0) * (t1 - t0)))
    t = np.linspace(t0, t1, n)
    ys = np.clip(np.round(y0 + (y1 - y0) * t).astype(np.int64), 0, h - 1)
    xs = np.round(x0 + (x1 - x0) * t).astype(np.int64)
    a, b = ACROSS_PX
    if xs.min() - b < 0 or xs.max() + b >= w:
        return float("nan")  # a side at the border: the other side decides
    pix = image.reshape(h, w, -1).astype(np.float32)
    left = np.mean([pix[ys, xs - d] for d in range(a, b + 1)], axis=0)
    right = np.mean([pix[ys, xs + d] for d in range(a, b + 1)], axis=0)
    return float(np.median(np.linalg.norm(left - right, axis=1)))


def sides_reach_foot(
    image: npt.NDArray[np.uint8], lines: list[tuple[float, float, float, float]]
) -> bool:
    """Whether a face found on a tried floor-contact row stands on it: at least one of its
    sides still steps in colour near that row. A row below the face (a floor line, a
    plank's seam) stands a face whose sides end above it, over floor that is one colour
    across them.

    ``lines``: the face's outline as :class:`Measurement` gives it (bottom, top, left side,
    right side; input pixels)."""
    if len(lines) < 4:
        return True
    steps = [_step_across(image, side, 0.0, FOOT_SHARE) for side in lines[2:4]]
    read = [step >= MIN_FOOT_STEP for step in steps if not math.isnan(step)]  # nan: at the border
    return not read or any(read)


#: A taller reading's side runs on above a shorter reading's top (the short top a line
#: on the face, a print's edge or the wall's line behind, not the face's top) when the
#: colour step across it is at least MIN_FOOT_STEP on this share of the rows between
#: the two tops, on each side not at the image's border.
RUN_UP_SHARE = 0.8
#: Rows next to either top left out of that check (the top's own blur), pixels.
RUN_UP_SKIP_PX = 3
#: ... and the strip just inside one side (pixels inward, from, to) has the same colour
#: above the short top as below it, median Lab within RUN_UP_MATCH (the full faces taken
#: on the fresh photo rooms: 1.0-7.0 on the nearer side; a print on the wall in line with
#: a planked box's sides, photo 1065: 30.5). The same strips and match judge the rows a
#: face read higher adds (:func:`face_runs_above`).
RUN_UP_COLUMNS = (2, 8)
RUN_UP_MATCH = 15.0


def side_steps(
    image: npt.NDArray[np.uint8], line: tuple[float, float, float, float], y_lo: float, y_hi: float
) -> npt.NDArray[np.float32] | None:
    """The colour step across a side line (x0, y0 at its foot, x1, y1 at its top; input
    pixels) on each of its rows between image rows ``y_hi`` and ``y_lo`` (``y_hi`` the
    higher); None when the side lies at the border or no row is left."""
    x0, y0, x1, y1 = line
    h, w = image.shape[:2]
    if abs(y0 - y1) < 1.0 or y_lo - y_hi < 1.0:
        return None
    first = int(math.ceil(max(y_hi, min(y0, y1), 0)))
    ys = np.arange(first, int(min(y_lo, max(y0, y1), h - 1)) + 1)
    if len(ys) == 0:
        return None
    xs = np.round(x0 + (x1 - x0) * (ys - y0) / (y1 - y0)).astype(np.int64)
    a, b = ACROSS_PX
    if xs.min() - b < 0 or xs.max() + b >= w:
        return None
    pix = image.reshape(h, w, -1).astype(np.float32)
    left = np.mean([pix[ys, xs - d] for d in range(a, b + 1)], axis=0)
    right = np.mean([pix[ys, xs + d] for d in range(a, b + 1)], axis=0)
    return np.linalg.norm(left - right, axis=1).astype(np.float32)


def sides_run_up(
    image: npt.NDArray[np.uint8], lines: list[tuple[float, float, float, float]], short_top: float
) -> bool:
    """Whether a face's sides (``lines`` as :class:`Measurement` gives them: bottom, top,
    left side, right side; input pixels) run on, straight and at their own columns, from a
    shorter reading's top row ``short_top`` up to the face's own top: on RUN_UP_SHARE of
    those rows each side not at the border still steps in colour (MIN_FOOT_STEP), and the
    face's colour just inside a side runs on past that row (:func:`_margin_runs_up`). Then
    the short top is a line on the face (a print's edge, a tape, a line of the picture),
    not where the face ends; a box under a print on the wall has none there (the print's
    sides elsewhere, or its colour above the box's top). False with no side read, and
    when a side read has under 2 x RUN_UP_SKIP_PX rows between the two tops (too short a
    way up to tell a line from the face's end)."""
    if len(lines) < 4:
        return False
    on = _sides_step_on(
        image,
        lines,
        lambda side: (short_top - RUN_UP_SKIP_PX, min(side[1], side[3]) + RUN_UP_SKIP_PX),
        RUN_UP_SHARE,
    )
    return on and _margin_runs_up(image, lines, short_top)


#: A lower reading's sides run on below a higher reading's foot (that foot a line across
#: the face: a panel joint, a label's or a band's lower edge, not the floor contact) when
#: the colour step across each side not at the border is at least MIN_FOOT_STEP on this
#: share of the rows between the two feet (the rows next to either foot left out:
#: RUN_UP_SKIP_PX).
RUN_DOWN_SHARE = 0.8


def sides_run_down(
    image: npt.NDArray[np.uint8], lines: list[tuple[float, float, float, float]], upper_foot: float
) -> bool:
    """Whether a face's sides (``lines`` as :class:`Measurement` gives them: bottom, top,
    left side, right side; input pixels) run on, at their own columns, from a higher
    reading's foot row ``upper_foot`` down to the face's own foot: on RUN_DOWN_SHARE of
    those rows each side not at the border still steps in colour (MIN_FOOT_STEP). A face
    whose sides end at that row (a floor patch or a shadow under it, one colour across
    the side's column) does not. False with no side read, and when a side read has under
    2 x RUN_UP_SKIP_PX rows between the two feet."""
    if len(lines) < 4:
        return False
    return _sides_step_on(
        image,
        lines,
        lambda side: (max(side[1], side[3]) - RUN_UP_SKIP_PX, upper_foot + RUN_UP_SKIP_PX),
        RUN_DOWN_SHARE,
    )


def _sides_step_on(
    image: npt.NDArray[np.uint8],
    lines: list[tuple[float, float, float, float]],
    span: Callable[[tuple[float, float, float, float]], tuple[float, float]],
    min_share: float,
) -> bool:
    """Whether each side read (``lines[2:4]``) steps in colour (MIN_FOOT_STEP) on
    ``min_share`` of the rows ``span(side)`` gives (lower row, upper row): one check for
    sides running up past a top and down past a foot. False with no side read, and when
    a side read has under 2 x RUN_UP_SKIP_PX rows."""
    read = 0
    for side in lines[2:4]:
        lower, upper = span(side)
        steps = side_steps(image, side, lower, upper)
        if steps is None:
            continue
        if len(steps) < 2 * RUN_UP_SKIP_PX:
            return False
        if float(np.mean(steps >= MIN_FOOT_STEP)) < min_share:
            return False
        read += 1
    return read > 0


def _margin_runs_up(
    image: npt.NDArray[np.uint8], lines: list[tuple[float, float, float, float]], short_top: float
) -> bool:
    """Whether the strip just inside one of a face's sides (:func:`_inside_side`) has the
    same colour (:func:`_colour_runs_on`) above a shorter reading's top ``short_top`` as
    below it (each past the tops' and the foot's blur, RUN_UP_SKIP_PX): the face's own
    colour or margin runs on past that line. A box under a print on the wall in line with
    its sides has the print's colour above its top on both sides. A grey image tells no
    colours apart: False."""
    if image.ndim != 3:
        return False
    for k, side in enumerate(lines[2:4]):
        x = 0.5 * (side[0] + side[2])
        foot, top = max(side[1], side[3]), min(side[1], side[3])
        above = _inside_side(image, top + RUN_UP_SKIP_PX, short_top - RUN_UP_SKIP_PX, x, k)
        below = _inside_side(image, short_top + RUN_UP_SKIP_PX, foot - RUN_UP_SKIP_PX, x, k)
        if _colour_runs_on(above, [below]):
            return True
    return False


def _inside_side(
    image: npt.NDArray[np.uint8], y0: float, y1: float, x: float, k: int
) -> npt.NDArray[np.float32]:
    """The Lab pixels of the strip just inside a side at column ``x`` (``k`` 0 the left
    side, 1 the right; RUN_UP_COLUMNS inward) over the rows ``y0`` to ``y1``."""
    a, z = RUN_UP_COLUMNS
    x0, x1 = (x + a, x + z) if k == 0 else (x - z, x - a)
    return _lab_pixels(image, y0, y1, x0, x1)


def _colour_runs_on(above: npt.NDArray[np.float32], below: list[npt.NDArray[np.float32]]) -> bool:
    """Whether the pixels ``above`` a line across a face have the colour (median Lab within
    RUN_UP_MATCH) of any of the reads ``below`` it: the face's own colour (or its margin's)
    runs on past that line. False where a read holds no pixel."""
    if not len(above):
        return False
    a_m = np.median(above, axis=0)
    return any(
        len(px) and float(np.linalg.norm(a_m - np.median(px, axis=0))) <= RUN_UP_MATCH
        for px in below
    )


#: A face found on a lower row covers one found higher when its sides lie within this
#: share of the higher face's width outside it (or further out).
COVER_SHARE = 0.1
#: ... and its foot lies at least this many pixels lower (a strip of a row between them).
MIN_DROP_PX = 4
#: The strip between the two feet shows the margin beside the higher face when their
#: colours (median Lab) are at most this far apart ...
MARGIN_MATCH = 15.0
#: ... and is not floor when it stands this far from the floor's colour below the lower
#: foot ...
FLOOR_APART = 25.0
#: ... and the margin beside the higher face stands this far from that floor colour too.
MARGIN_FLOOR_APART = 20.0
#: Pixels beside the higher face read as its margin (from, to).
MARGIN_COLUMNS = (2, 6)
#: Whether, where no margin shows beside the higher face (thinner than MARGIN_COLUMNS),
#: the margin above it counts (:func:`face_runs_below`): the lower face's top at least
#: MIN_ABOVE_PX above the higher face's, the rows between them the strip's colour (and
#: apart from the floor's, as the margin beside must be).
MARGIN_ABOVE_PRINT = True
#: ... (and a face read higher adds at least this many rows past both tops' blur,
#: RUN_UP_SKIP_PX at each, to read its colour on: :func:`face_runs_above`).
MIN_ABOVE_PX = 4
#: A face's middle read over the columns past this share of its width from each side (the
#: strip between two feet and the rows above a print, :func:`face_runs_below`; the rows a
#: face read higher adds, :func:`face_runs_above`).
MIDDLE_SHARE = 0.2


def _lab_pixels(
    image: npt.NDArray[np.uint8], y0: float, y1: float, x0: float, x1: float
) -> npt.NDArray[np.float32]:
    """The Lab pixels (N x 3) of a box of the image, clipped to it (maybe none)."""
    h, w = image.shape[:2]
    r0, r1 = max(0, int(y0)), min(h, int(y1))
    c0, c1 = max(0, int(x0)), min(w, int(x1))
    if r1 <= r0 or c1 <= c0:
        return np.zeros((0, 3), np.float32)
    lab = cv2.cvtColor(np.ascontiguousarray(image[r0:r1, c0:c1]), cv2.COLOR_BGR2Lab)
    return lab.reshape(-1, 3).astype(np.float32)


def _face_middle(
    image: npt.NDArray[np.uint8], y0: float, y1: float, left: float, right: float
) -> npt.NDArray[np.float32]:
    """The Lab pixels of a face's middle (past MIDDLE_SHARE of its width from each side,
    ``left`` to ``right``) over the rows ``y0`` to ``y1``."""
    w = right - left
    return _lab_pixels(image, y0, y1, left + MIDDLE_SHARE * w, right - MIDDLE_SHARE * w)


def face_runs_below(
    image: npt.NDArray[np.uint8],
    upper: tuple[float, float, float, float],
    lower: tuple[float, float, float, float],
) -> bool:
    """Whether a face found on a higher tried row is the print of one found on a lower
    row (input pixel boxes x0, y0, x1, y1): the lower face covers it, and the strip between
    their feet has the colour of the margin beside the higher face, a colour the floor
    below the lower foot does not have. A print on a box with a margin of the box's own
    colour is a face of its own, surer than the box, standing on the print's lower edge.
    Where the margin beside fails (MARGIN_ABOVE_PRINT: thinner than MARGIN_COLUMNS, the
    room read there), the rows above the print up to the lower face's top stand for it.
    A grey image tells no colours apart: False."""
    if image.ndim != 3:
        return False
    left, top, right, foot = upper
    low_left, _, low_right, low_foot = lower
    w = right - left
    if w <= 0 or not (low_left <= left + COVER_SHARE * w and low_right >= right - COVER_SHARE * w):
        return False
    if low_foot < foot + MIN_DROP_PX:
        return False
    a, z = MARGIN_COLUMNS
    mid = 0.5 * (top + foot)
    strip = _face_middle(image, foot + 2, low_foot - 1, left, right)
    margin = np.vstack(
        [
            _lab_pixels(image, mid, foot, x0, x1)
            for x0, x1 in ((left - z, left - a), (right + a, right + z))
        ]
    )
    floor = _lab_pixels(image, low_foot + 3, low_foot + 9, left, right)
    if not (len(strip) and len(margin) and len(floor)):
        return False
    s_m, m_m, f_m = (np.median(px, axis=0) for px in (strip, margin, floor))
    if np.linalg.norm(s_m - f_m) < FLOOR_APART:
        return False
    if (
        np.linalg.norm(s_m - m_m) <= MARGIN_MATCH
        and np.linalg.norm(m_m - f_m) >= MARGIN_FLOOR_APART
    ):
        return True
    if not MARGIN_ABOVE_PRINT:
        return False
    # a margin too thin beside the print to read (the room beyond it in those columns):
    # the face's colour runs on above the print too, up to the lower face's top (one
    # surface round the print on its rows above and below it)
    low_top = lower[1]
    if top - low_top < MIN_ABOVE_PX:
        return False
    above = _face_middle(image, low_top + 2, top - 1, left, right)
    if not len(above):
        return False
    a_m = np.median(above, axis=0)
    return bool(
        np.linalg.norm(a_m - s_m) <= MARGIN_MATCH
        and np.linalg.norm(a_m - f_m) >= MARGIN_FLOOR_APART
    )


def face_runs_above(
    image: npt.NDArray[np.uint8],
    found: tuple[float, float, float, float],
    raised: tuple[float, float, float, float],
) -> bool:
    """Whether the rows a face read higher (``raised``, input pixel boxes x0, y0, x1, y1)
    adds over ``found``'s top are ``found``'s own surface: past both tops' blur
    (RUN_UP_SKIP_PX at each) at least MIN_ABOVE_PX rows, their middle's colour
    (:func:`_face_middle`) running on (:func:`_colour_runs_on`, RUN_UP_MATCH) from
    ``found``'s middle or from the strips just inside its sides (:func:`_inside_side`),
    each read past ``found``'s top and foot blur. The face is one surface up to its top:
    over a line across it (a brick course, a tape) it goes on in its colour, a frame round
    a print in its margin's, while a top read on what stands behind it adds the
    background's colour (a wall seen above the face). A grey image tells no colours
    apart: False."""
    if image.ndim != 3:
        return False
    x0, y0, x1, y1 = found
    hi, lo = raised[1] + RUN_UP_SKIP_PX, y0 - RUN_UP_SKIP_PX
    if x1 <= x0 or lo - hi < MIN_ABOVE_PX:
        return False
    f0, f1 = y0 + RUN_UP_SKIP_PX, y1 - RUN_UP_SKIP_PX
    sides = np.vstack([_inside_side(image, f0, f1, x, k) for k, x in enumerate((x0, x1))])
    return _colour_runs_on(
        _face_middle(image, hi, lo, x0, x1), [_face_middle(image, f0, f1, x0, x1), sides]
    )


#: A print's line taken for a face's foot (:func:`print_runs_below`): the strip between the
#: two feet is the print running on when its grey spread (standard deviation) is at least
#: this share of the spread of the band just above the higher foot (as tall as the strip) ...
PRINT_TEXTURE_SHARE = 0.5
#: ... and at least this many times the spread of the floor under the lower foot ...
PRINT_FLOOR_TEXTURE = 3.0
#: ... and at least this (8-bit grey levels): a plain strip is no print, whatever the
#: floor's spread.
PRINT_MIN_SPREAD = 8.0
#: Rows under the lower foot read as the floor there (from, to).
PRINT_FLOOR_PX = (3, 9)
#: The lower foot at least this many rows under the higher one (the strip read between
#: them, 2 rows clear of the line and 1 of the foot, two rows at least).
PRINT_MIN_DROP_PX = 5


def print_runs_below(
    image: npt.NDArray[np.uint8],
    upper: tuple[float, float, float, float],
    lower: tuple[float, float, float, float],
) -> bool:
    """Whether a face found on a higher tried row stands on a line inside its own print (a
    row of a photograph's pattern, a brick course) and the face found on a lower row is the
    same face standing on the floor (input pixel boxes x0, y0, x1, y1): the lower face
    covers the higher one, and the strip between their feet (the middle three fifths of
    the columns) is as textured as the higher face just above its foot
    (PRINT_TEXTURE_SHARE of its grey spread) and far more than the floor under the
    lower foot (PRINT_FLOOR_TEXTURE): the print runs on under the line, the floor does not.
    Colour alone does not tell it: a dark print's mean matches a dark floor's."""
    left, _, right, foot = upper
    low_left, _, low_right, low_foot = lower
    w = right - left
    if w <= 0 or not (low_left <= left + COVER_SHARE * w and low_right >= right - COVER_SHARE * w):
        return False
    drop = low_foot - foot
    if drop < PRINT_MIN_DROP_PX:
        return False
    c0, c1 = left + 0.2 * w, right - 0.2 * w
    grey = image if image.ndim == 2 else cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)
    a, z = PRINT_FLOOR_PX

    def spread(y0: float, y1: float) -> float | None:
        h_img, w_img = grey.shape[:2]
        r0, r1 = max(0, int(y0)), min(h_img, int(y1))
        q0, q1 = max(0, int(c0)), min(w_img, int(c1))
        if r1 - r0 < 2 or q1 <= q0:
            return None
        return float(np.std(grey[r0:r1, q0:q1].astype(np.float32)))

    strip = spread(foot + 2, low_foot - 1)
    band = spread(foot - drop, foot - 1)
    floor = spread(low_foot + a, low_foot + z)
    if strip is None or band is None or floor is None:
        return False
    return (
        strip >= PRINT_MIN_SPREAD
        and strip >= PRINT_TEXTURE_SHARE * band
        and strip >= PRINT_FLOOR_TEXTURE * floor
    )


# a face of its own colour, not a patch of the floor before a face: its middle (the middle
# share FACE_MIDDLE of its box each way) this far (Lab, 8-bit) from the floor under its foot
# (a gravel patch read as a face stood 6 apart; boxes on the fresh rooms 30-49)
FACE_FLOOR_APART = 15.0
FACE_MIDDLE = 0.6
FLOOR_UNDER_PX = (3, 9)  # the rows under a face's foot read as the floor there


def face_apart_from_floor(
    image: npt.NDArray[np.uint8], box: tuple[float, float, float, float]
) -> bool:
    """Whether a face box (input pixels x0, y0, x1, y1) has a colour of its own: the median
    Lab colour of its middle at least FACE_FLOOR_APART from the floor's just under its foot
    (the same columns). A patch of the floor taken for a face (a stretch of gravel between
    a face's foot and a line nearer the lens) has the floor's colour. A grey image, or a
    foot at the image's lower border: False."""
    if image.ndim != 3:
        return False
    left, top, right, foot = box
    w, h = right - left, foot - top
    if w <= 0 or h <= 0:
        return False
    m = 0.5 * (1.0 - FACE_MIDDLE)
    middle = _lab_pixels(image, top + m * h, foot - m * h, left + m * w, right - m * w)
    a, z = FLOOR_UNDER_PX
    floor = _lab_pixels(image, foot + a, foot + z, left, right)
    if not (len(middle) and len(floor)):
        return False
    return bool(
        np.linalg.norm(np.median(middle, axis=0) - np.median(floor, axis=0)) >= FACE_FLOOR_APART
    )
