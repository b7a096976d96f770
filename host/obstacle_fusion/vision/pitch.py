"""The camera's pitch from one frame: the face's two vertical sides converge with pitch.

Receives the measured face's side lines (input-image pixels, as a
:class:`~obstacle_fusion.vision.types.Measurement` holds them) and the camera model; returns
a :class:`PitchEstimate` (pitch in degrees, positive looking down as in
:class:`~obstacle_fusion.vision.rig.Rig`, with its expected error) or None when the sides
are too short or too close together to tell.

Geometry, in the undistorted image of a camera pitched down by p about its x axis (no roll):
the world's vertical direction, robot (0, 1, 0), is (0, cos p, sin p) in the camera frame,
so every vertical edge points at the vanishing point (cx, v_vp) with
v_vp = cy + fy / tan p (below the image when looking down). A line through (u, v) and that
point has the slope du/dv = (u - cx) / (v - v_vp); two sides u_l, u_r at the same row v thus
differ in slope by (u_r - u_l) / (v - v_vp). With k = (slope_r - slope_l) / (u_r - u_l):
v_vp = v - 1 / k and tan p = fy / (v_vp - cy) = fy k / (k (v - cy) - 1). Roll adds nearly the
same slope to both sides (it cancels in the difference); yaw does not tilt vertical lines.

Only the camera height is then found from the floor-contact row ``v_c`` of the pitch-0 view
(:func:`camera_height_for_row`): the ray to the contact point leaves the level at
atan((v_c - cy) / fy) + p, so h = D tan(atan((v_c - cy) / fy) + p).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.camera import CameraModel

Line = tuple[float, float, float, float]

#: Sides shorter than this (pixels, undistorted) give no pitch: their slopes are noise.
MIN_SIDE_PX = 40.0
#: Sides closer together than this (pixels) give no pitch.
MIN_SEPARATION_PX = 40.0
#: Per-pixel scatter of a fitted side's edge points (pixels), for the expected error.
EDGE_NOISE_PX = 0.3
#: An estimate whose expected error exceeds this (degrees) is not used (0.5 left a tenth
#: of the tuning rooms' faces unlevelled for no fewer wrong estimates).
MAX_SIGMA_DEG = 0.8
#: The side refit looks this many pixels either side of the line found.
REFIT_HALF_PX = 4
#: ... over this many rounds, each centred on the last fit.
REFIT_ROUNDS = 2
#: ... leaving out this share of the side's length at each end (corners, the top face).
REFIT_MARGIN_SHARE = 0.1
#: ... on rows whose gradient peak (8-bit, central difference, summed over the channels)
#: is at least this.
REFIT_MIN_GRADIENT = 12.0
#: ... and only when its ends stay within this many pixels of the side found (the lean
#: the method's fit misses moves an end by a pixel or two; more is another edge).
REFIT_MAX_SHIFT_PX = 2.5
#: ... and only when at least this share of the side's rows show the edge.
REFIT_MIN_SHARE = 0.6
#: An estimate beyond this (degrees) is refused: a robot camera tilted further is not a
#: reading of the face's sides but of a side that is no vertical edge (a seam, a shadow).
MAX_PITCH_DEG = 10.0


@dataclass(frozen=True)
class PitchEstimate:
    """A pitch read from the face's sides: degrees (positive down) and its expected error."""

    pitch_deg: float
    sigma_deg: float
    side_px: float  # the shorter side's length
    separation_px: float  # the sides' distance at their middle row


def pitch_from_slopes(
    slope_left: float,
    slope_right: float,
    u_left: float,
    u_right: float,
    v: float,
    fy: float,
    cy: float,
) -> float:
    """Pitch (radians, positive looking down) from two vertical edges' slopes du/dv and
    their columns ``u_left``, ``u_right`` at row ``v`` (undistorted pixels, no skew)."""
    sep = u_right - u_left
    if sep == 0.0:
        raise ValueError("the two sides must be apart")
    k = (slope_right - slope_left) / sep
    denominator = k * (v - cy) - 1.0  # zero only for a vanishing point on the centre row
    if denominator == 0.0:
        return math.copysign(math.pi / 2, -k)
    return math.atan(fy * k / denominator)


def pitch_from_sides(left: Line, right: Line, camera: CameraModel) -> PitchEstimate | None:
    """The pitch from the face's left and right sides (input-image pixels, any direction),
    or None when the sides are too short, too close, or give a pitch beyond
    :data:`MAX_PITCH_DEG` or an expected error above :data:`MAX_SIGMA_DEG`."""
    pts = camera.undistort_points(np.array([left, right], dtype=np.float64).reshape(-1, 2))
    l0, l1, r0, r1 = (tuple(p) for p in pts.tolist())
    return pitch_from_undistorted((*l0, *l1), (*r0, *r1), camera.fy, camera.cy)


def pitch_from_undistorted(left: Line, right: Line, fy: float, cy: float) -> PitchEstimate | None:
    """:func:`pitch_from_sides` for sides already in undistorted pixels (u0, v0, u1, v1)."""
    ul0, vl0, ul1, vl1 = left
    ur0, vr0, ur1, vr1 = right
    len_l, len_r = abs(vl1 - vl0), abs(vr1 - vr0)
    side = min(len_l, len_r)
    if side < MIN_SIDE_PX:
        return None
    s_l = (ul1 - ul0) / (vl1 - vl0)
    s_r = (ur1 - ur0) / (vr1 - vr0)
    v = 0.25 * (vl0 + vl1 + vr0 + vr1)
    u_l = 0.5 * (ul0 + ul1) + s_l * (v - 0.5 * (vl0 + vl1))
    u_r = 0.5 * (ur0 + ur1) + s_r * (v - 0.5 * (vr0 + vr1))
    sep = u_r - u_l
    if sep < MIN_SEPARATION_PX:
        return None
    pitch = pitch_from_slopes(s_l, s_r, u_l, u_r, v, fy, cy)
    # a fitted line's slope scatters by noise * sqrt(12 / n) / n over n rows; the two
    # sides' difference, over their separation, times fy is the pitch's (small angles)
    slope_sigma = math.hypot(*(EDGE_NOISE_PX * math.sqrt(12.0 / n) / n for n in (len_l, len_r)))
    sigma = math.degrees(fy * slope_sigma / sep)
    deg = math.degrees(pitch)
    if abs(deg) > MAX_PITCH_DEG or sigma > MAX_SIGMA_DEG:
        return None
    return PitchEstimate(deg, sigma, side, sep)


def refit_side(image: npt.NDArray[Any], side: Line) -> Line | None:
    """A vertical edge fitted again in ``image`` (undistorted, grey or colour: the colour
    difference across the edge, summed over the channels, is its gradient; a face and a
    wall of one brightness still differ in hue), free to lean: ``side``
    (u0, v0, u1, v1) is where it was found. Per row, the peak of the horizontal gradient
    within :data:`REFIT_HALF_PX` of the line (sub-pixel), a line through them with the
    outliers dropped, :data:`REFIT_ROUNDS` times over, each round centred on the last fit;
    the ends' rows are kept. None when too few rows show the edge.

    The method's own side fit looks within a column or so of the column its search found,
    which pulls a leaning side towards the vertical (an estimate of -4 degrees read -2.5)."""
    u0, v0, u1, v1 = side
    if v1 < v0:
        u0, v0, u1, v1 = u1, v1, u0, v0
    h, w = image.shape[:2]
    margin = REFIT_MARGIN_SHARE * (v1 - v0)
    rows = np.arange(int(math.ceil(v0 + margin)), int(math.floor(v1 - margin)) + 1)
    rows = rows[(rows >= 0) & (rows < h)]
    if rows.size < MIN_SIDE_PX / 2:
        return None
    slope = (u1 - u0) / (v1 - v0) if v1 != v0 else 0.0
    a = u0 - slope * v0
    offsets = np.arange(-REFIT_HALF_PX, REFIT_HALF_PX + 1)
    img = image.astype(np.float32).reshape(h, w, -1)
    vf = rows.astype(np.float64)
    for _ in range(REFIT_ROUNDS):
        centre = np.rint(a + slope * vf).astype(np.int64)
        cols = centre[:, None] + offsets[None, :]
        ok = (cols.min(axis=1) >= 2) & (cols.max(axis=1) < w - 2)
        if np.count_nonzero(ok) < MIN_SIDE_PX / 2:
            return None
        r, c, cen = rows[ok], cols[ok], centre[ok]
        grad = np.abs(img[r[:, None], c + 1] - img[r[:, None], c - 1]).sum(axis=2)
        k = np.argmax(grad, axis=1)
        k = np.clip(k, 1, grad.shape[1] - 2)
        i = np.arange(len(k))
        g0, g1, g2 = grad[i, k - 1], grad[i, k], grad[i, k + 1]
        denom = g0 - 2.0 * g1 + g2
        off = np.where(denom < 0.0, 0.5 * (g0 - g2) / np.where(denom < 0.0, denom, -1.0), 0.0)
        u = cen + offsets[k] + np.clip(off, -0.5, 0.5)
        strong = g1 >= REFIT_MIN_GRADIENT
        x, y = r[strong].astype(np.float64), u[strong]
        if x.size < max(MIN_SIDE_PX / 2, REFIT_MIN_SHARE * rows.size):
            return None  # the edge fades along the side: its lean is not read
        slope, a = np.polyfit(x, y, 1)
        res = np.abs(y - (a + slope * x))
        keep = res <= max(0.75, 2.5 * float(np.median(res)))
        if np.count_nonzero(keep) < MIN_SIDE_PX / 2:
            return None
        slope, a = np.polyfit(x[keep], y[keep], 1)
    ends = (float(a + slope * v0), float(a + slope * v1))
    if max(abs(ends[0] - u0), abs(ends[1] - u1)) > REFIT_MAX_SHIFT_PX:
        return None  # drifted onto another edge (a seam, the wall's, a shadow's)
    return (ends[0], float(v0), ends[1], float(v1))


def pitch_from_lines(lines: Sequence[Line], camera: CameraModel) -> PitchEstimate | None:
    """The pitch from a measured face's four edges (bottom, top, left, right, as the fused
    method reports them in ``Measurement.lines``), or None."""
    if len(lines) != 4:
        return None
    return pitch_from_sides(lines[2], lines[3], camera)


def camera_height_for_row(
    row: float, depth_m: float, pitch_deg: float, fy: float, cy: float
) -> float:
    """Camera height above the floor whose contact at depth ``depth_m`` images at ``row``
    of the pitch-0 (undistorted, not levelled) view, for a camera pitched ``pitch_deg``
    down."""
    return depth_m * math.tan(math.atan((row - cy) / fy) + math.radians(pitch_deg))


def pitch_for_row(row: float, depth_m: float, height_m: float, fy: float, cy: float) -> float:
    """The pitch (degrees down) that puts a camera ``height_m`` up over the floor contact
    at depth ``depth_m`` imaged at ``row`` of the pitch-0 (undistorted, not levelled)
    view: :func:`camera_height_for_row` solved for the pitch."""
    return math.degrees(math.atan(height_m / depth_m) - math.atan((row - cy) / fy))


def level_scales(
    lines: Sequence[Line], camera: CameraModel, pitch_deg: float
) -> tuple[float, float]:
    """How much the face's pixel height and width grow when its four corners (from the
    bottom and top edges of ``lines``, input-image pixels) are seen in the view levelled
    for ``pitch_deg`` instead of the pitch-0 view: (height scale, width scale)."""
    bottom, top = lines[0], lines[1]
    corners = np.array([bottom[:2], bottom[2:], top[:2], top[2:]], dtype=np.float64)
    rays = camera.unproject(corners)  # camera frame, z = 1
    p = math.radians(pitch_deg)
    c, s = math.cos(p), math.sin(p)
    level = rays @ np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])  # R p_c, rows
    sizes = []
    for pts in (rays, level):
        u = pts[:, 0] / pts[:, 2]
        v = pts[:, 1] / pts[:, 2]
        height = 0.5 * ((v[0] - v[2]) + (v[1] - v[3]))  # normalised units: fy, fx cancel
        width = 0.5 * ((u[1] + u[3]) - (u[0] + u[2]))
        sizes.append((height, width))
    (h0, w0), (h1, w1) = sizes
    if h0 <= 0.0 or w0 <= 0.0:
        return (1.0, 1.0)
    return (h1 / h0, w1 / w0)
