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

import numpy as np

from obstacle_fusion.vision.camera import CameraModel

Line = tuple[float, float, float, float]

#: Sides shorter than this (pixels, undistorted) give no pitch: their slopes are noise.
MIN_SIDE_PX = 40.0
#: Sides closer together than this (pixels) give no pitch.
MIN_SEPARATION_PX = 40.0
#: Per-pixel scatter of a fitted side's edge points (pixels), for the expected error.
EDGE_NOISE_PX = 0.3
#: An estimate whose expected error exceeds this (degrees) is not used.
MAX_SIGMA_DEG = 0.5
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
    (ul0, vl0), (ul1, vl1), (ur0, vr0), (ur1, vr1) = pts.tolist()
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
    fy = camera.fy
    pitch = pitch_from_slopes(s_l, s_r, u_l, u_r, v, fy, camera.cy)
    # a fitted line's slope scatters by noise * sqrt(12 / n) / n over n rows; the two
    # sides' difference, over their separation, times fy is the pitch's (small angles)
    slope_sigma = math.hypot(*(EDGE_NOISE_PX * math.sqrt(12.0 / n) / n for n in (len_l, len_r)))
    sigma = math.degrees(fy * slope_sigma / sep)
    deg = math.degrees(pitch)
    if abs(deg) > MAX_PITCH_DEG or sigma > MAX_SIGMA_DEG:
        return None
    return PitchEstimate(deg, sigma, side, sep)


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
