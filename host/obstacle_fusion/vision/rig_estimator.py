"""The camera's height and pitch from the run itself: where obstacles meet the floor.

A face square to the robot at depth D stands on the floor line y = h (robot frame: x right,
y down, z forward, origin at the lens; see :mod:`obstacle_fusion.vision.rig`). Through a
camera pitched down by p that floor point lies at camera coordinates
y_c = h cos p - D sin p, z_c = h sin p + D cos p, so in the undistorted image (not levelled)
its row is

    v = cy + fy (h cos p - D sin p) / (h sin p + D cos p) = cy + fy tan(atan(h / D) - p),

whatever its column (the whole floor line at depth D images onto one row). With p = 0 this
is the levelled view's v = cy + fy h / D. Each confident detection gives one (v, D); two
unknowns need depths that differ (1/D spread: the slope is h, the offset p). Dividing by
cos p gives a relation linear in (h, tan p, h tan p):

    h - D tan p - y (h tan p) = y D,    y = (v - cy) / fy,

so three observations fix a candidate exactly: RANSAC over such triples finds the inliers,
then Gauss-Newton on the pixel residuals refines (h, p) over all of them. No OpenCV here.
"""

from __future__ import annotations

import math
from collections import deque
from typing import NamedTuple

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]


class RigEstimate(NamedTuple):
    """The fit: (height_m, pitch_deg, n_used, residual_px) also unpacks as a tuple."""

    height_m: float
    pitch_deg: float
    n_used: int  # inliers the fit used
    residual_px: float  # RMS pixel residual over those inliers


def floor_row(fy: float, cy: float, height_m: float, pitch_deg: float, depth_m: float) -> float:
    """Undistorted-image row of the floor line ``depth_m`` ahead (the model above)."""
    return cy + fy * math.tan(math.atan2(height_m, depth_m) - math.radians(pitch_deg))


class OnlineRigEstimator:
    """Floor-contact rows at known depths in; camera height and pitch out.

    ``fy``, ``cy``: the undistorted camera view the rows are measured in. Observations are
    kept in a window of the newest ``max_points``. ``estimate()`` is None until at least
    ``min_points`` observations spanning depths in a ratio of ``min_depth_ratio`` agree.
    """

    def __init__(
        self,
        fy: float,
        cy: float,
        *,
        min_points: int = 15,
        min_depth_ratio: float = 1.3,
        inlier_px: float | None = None,
        max_points: int = 1000,
        iterations: int = 200,
        seed: int = 0,
    ) -> None:
        if not (math.isfinite(fy) and fy > 0 and math.isfinite(cy)):
            raise ValueError(f"need a positive focal length and a finite centre: {fy}, {cy}")
        self.fy = float(fy)
        self.cy = float(cy)
        self.min_points = max(3, int(min_points))
        self.min_depth_ratio = float(min_depth_ratio)
        # a floor-contact row is good to about a pixel at 500 px wide; scale with the lens
        self.inlier_px = float(inlier_px) if inlier_px is not None else max(1.5, 0.004 * fy)
        self.iterations = int(iterations)
        self.seed = seed
        self._rows: deque[float] = deque(maxlen=max_points)
        self._depths: deque[float] = deque(maxlen=max_points)
        self.why_not = "no observation yet"

    def __len__(self) -> int:
        return len(self._rows)

    def add(self, bottom_row_px: float, depth_m: float) -> None:
        """One floor-contact row (undistorted image) of a face ``depth_m`` ahead of the lens."""
        if not (math.isfinite(bottom_row_px) and math.isfinite(depth_m) and depth_m > 0.05):
            return
        self._rows.append(float(bottom_row_px))
        self._depths.append(float(depth_m))

    # ------------------------------------------------------------------ the fit
    def _predict(self, h: float, p: float, depth: FloatArray) -> FloatArray:
        out: FloatArray = self.cy + self.fy * np.tan(np.arctan2(h, depth) - p)
        return out

    def _ransac(self, y: FloatArray, depth: FloatArray, rows: FloatArray) -> npt.NDArray[np.bool_]:
        n = len(y)
        rng = np.random.default_rng(self.seed)
        picks = rng.integers(0, n, (self.iterations, 3))
        distinct = (
            (picks[:, 0] != picks[:, 1])
            & (picks[:, 0] != picks[:, 2])
            & (picks[:, 1] != picks[:, 2])
        )
        picks = picks[distinct]
        a = np.stack([np.ones((len(picks), 3)), -depth[picks], -y[picks]], axis=2)
        b = y[picks] * depth[picks]
        det = np.linalg.det(a)
        ok = np.abs(det) > 1e-12
        best = np.zeros(n, bool)
        if not ok.any():
            return best
        sol = np.linalg.solve(a[ok], b[ok][:, :, None])[:, :, 0]
        h, t = sol[:, 0], sol[:, 1]
        sane = (h > 0.0) & (h < 5.0) & (np.abs(t) < math.tan(math.radians(60)))
        if not sane.any():
            return best
        h, p = h[sane], np.arctan(t[sane])
        # every candidate's pixel residuals at once (candidates x observations)
        pred = self.cy + self.fy * np.tan(np.arctan2(h[:, None], depth[None, :]) - p[:, None])
        resid = np.abs(pred - rows[None, :])
        # MSAC: inliers cost their squared residual, outliers the threshold's
        cost = np.minimum(resid, self.inlier_px) ** 2
        inl = resid < self.inlier_px
        total = np.where(inl.sum(axis=1) >= 3, cost.sum(axis=1), math.inf)
        j = int(np.argmin(total))
        if math.isfinite(float(total[j])):
            best = inl[j]
        return best

    def _refine(
        self, h: float, p: float, depth: FloatArray, rows: FloatArray
    ) -> tuple[float, float]:
        for _ in range(10):
            theta = np.arctan2(h, depth) - p
            sec2 = 1.0 / np.cos(theta) ** 2
            r = self._predict(h, p, depth) - rows
            jh = self.fy * sec2 * depth / (depth**2 + h**2)
            jp = -self.fy * sec2
            jac = np.stack([jh, jp], axis=1)
            step, *_ = np.linalg.lstsq(jac, -r, rcond=None)
            h, p = h + float(step[0]), p + float(step[1])
            if abs(step[0]) < 1e-7 and abs(step[1]) < 1e-8:
                break
        return h, p

    def estimate(self) -> RigEstimate | None:
        """The robust fit, or None (``why_not`` says why)."""
        if len(self._rows) < self.min_points:
            self.why_not = f"{len(self._rows)} of the {self.min_points} detections needed"
            return None
        rows = np.asarray(self._rows, np.float64)
        depth = np.asarray(self._depths, np.float64)
        if depth.max() / depth.min() < self.min_depth_ratio:
            self.why_not = (
                f"depths {depth.min():.2f}-{depth.max():.2f} m: too alike to tell height "
                "from pitch (they must differ by a ratio of "
                f"{self.min_depth_ratio:g})"
            )
            return None
        y = (rows - self.cy) / self.fy
        inliers = self._ransac(y, depth, rows)
        if inliers.sum() < self.min_points:
            self.why_not = f"only {int(inliers.sum())} detections agree on one floor"
            return None
        # start from the linear least squares over the inliers, then refine in pixels
        a = np.stack([np.ones(int(inliers.sum())), -depth[inliers], -y[inliers]], axis=1)
        (h0, t0, _), *_ = np.linalg.lstsq(a, y[inliers] * depth[inliers], rcond=None)
        h, p = self._refine(float(h0), math.atan(float(t0)), depth[inliers], rows[inliers])
        for _ in range(2):  # the refined model may take in or let go a few borderline points
            inliers = np.abs(self._predict(h, p, depth) - rows) < self.inlier_px
            if inliers.sum() < self.min_points:
                self.why_not = f"only {int(inliers.sum())} detections agree on one floor"
                return None
            h, p = self._refine(h, p, depth[inliers], rows[inliers])
        d_in = depth[inliers]
        if d_in.max() / d_in.min() < self.min_depth_ratio:
            self.why_not = "the agreeing detections all lie at one depth"
            return None
        if not (0.0 < h < 5.0 and math.isfinite(p)):
            self.why_not = "the fit is not a camera above a floor"
            return None
        resid = self._predict(h, p, d_in) - rows[inliers]
        self.why_not = ""
        return RigEstimate(
            float(h), math.degrees(p), int(inliers.sum()), float(np.sqrt(np.mean(resid**2)))
        )
