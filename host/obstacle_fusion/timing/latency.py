"""The camera's latency from the run itself: the face's image height against the sonar.

A face at depth D images h_px = fy H / D pixels tall, so h_px(t) D(t) is constant while one
obstacle is seen. A camera stamps a frame when it is read, a latency tau after the scene it
shows; the frame stamped t shows the obstacle at D(t - tau). The tau that makes
log h_px(t_i) + log D(t_i - tau) most nearly constant (per obstacle: per segment of
consecutive detections) is the latency: the scene-to-stamp delay a USB camera adds
(50-150 ms; at 1 m/s, 100 ms pairs a range 10 cm off). It needs motion: with the robot
and the obstacle still, every tau fits and the confidence is 0.

The search: every 2 ms over 0..``max_latency_s``, then every 0.1 ms around the best, then a
parabola through the three best samples. Frames whose ratio stays off after a first fit
(a wrong detection) are dropped and the search repeated. The standard error comes from the
residual scatter and the spread of d log D / dt over the frames; confidence =
1 / (1 + (se / 5 ms)^2). No OpenCV here.
"""

from __future__ import annotations

import logging
import math
from collections import deque
from typing import NamedTuple

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]

log = logging.getLogger(__name__)

#: A standard error of this much halves the confidence.
CONFIDENCE_SCALE_S = 0.005


class LatencyEstimate(NamedTuple):
    """``latency_s, confidence = estimator.estimate()`` unpacks the first two."""

    latency_s: float
    confidence: float  # 0..1, 1 / (1 + (se / 5 ms)^2); 0 when the best shift is at a bound
    std_error_s: float
    n_frames: int


class CameraLatencyEstimator:
    """Face image heights (frame stamps) and sonar ranges (reading instants) in; tau out.

    ``depth_offset_m`` is added to the ranges (the rig's sonar_ahead_m: the face depth from
    the lens is what h_px scales with). ``max_gap_s``: a frame whose shifted instant is not
    between two ranges at most this far apart is not used. ``segment_gap_s``: a pause in
    the detections this long starts a new segment (another obstacle, another constant).
    """

    def __init__(
        self,
        *,
        max_latency_s: float = 0.3,
        depth_offset_m: float = 0.0,
        max_gap_s: float = 0.25,
        segment_gap_s: float = 0.6,
        min_frames: int = 20,
        max_frames: int = 1500,
        min_motion_m: float = 0.1,
    ) -> None:
        if not (math.isfinite(max_latency_s) and 0.0 < max_latency_s <= 2.0):
            raise ValueError(f"max_latency_s must be within (0, 2], got {max_latency_s}")
        self.max_latency_s = float(max_latency_s)
        self.depth_offset_m = float(depth_offset_m)
        self.max_gap_s = float(max_gap_s)
        self.segment_gap_s = float(segment_gap_s)
        self.min_frames = int(min_frames)
        self.min_motion_m = float(min_motion_m)
        self._frames: deque[tuple[float, float]] = deque(maxlen=max_frames)
        self._ranges: deque[tuple[float, float]] = deque(maxlen=max_frames * 4)
        self.why_not = "no frame yet"

    @property
    def n_frames(self) -> int:
        return len(self._frames)

    def add_frame(self, t: float, h_px: float) -> None:
        """A frame stamped ``t`` (host seconds) whose obstacle face is ``h_px`` tall."""
        if math.isfinite(t) and math.isfinite(h_px) and h_px > 1.0:
            self._frames.append((float(t), float(h_px)))

    def add_range(self, t: float, distance_m: float) -> None:
        """A good sonar range (metres) at its reflection instant ``t``."""
        if math.isfinite(t) and math.isfinite(distance_m) and distance_m > 0.0:
            self._ranges.append((float(t), float(distance_m)))

    # ------------------------------------------------------------------ the search
    def _series(self) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray] | None:
        if len(self._frames) < self.min_frames:
            self.why_not = f"{len(self._frames)} of the {self.min_frames} detections needed"
            return None
        if len(self._ranges) < 4:
            self.why_not = "too few sonar ranges"
            return None
        fr = np.array(sorted(self._frames))
        rg = np.array(sorted(self._ranges))
        tr = rg[:, 0]
        log_d = np.log(rg[:, 1] + self.depth_offset_m)
        tf, log_h = fr[:, 0], np.log(fr[:, 1])

        # only frames whose every shifted instant lies between two close ranges
        def bracketed(t: FloatArray) -> npt.NDArray[np.bool_]:
            i = np.searchsorted(tr, t)
            ok = (i > 0) & (i < len(tr))
            ic = np.clip(i, 1, len(tr) - 1)
            return ok & (tr[ic] - tr[ic - 1] <= self.max_gap_s)

        ok = np.ones(len(tf), bool)
        for tau in np.arange(0.0, self.max_latency_s + 1e-9, 0.05):
            ok &= bracketed(tf - tau)
        tf, log_h = tf[ok], log_h[ok]
        if len(tf) < self.min_frames:
            self.why_not = f"{len(tf)} detections with sonar ranges around them"
            return None
        return tf, log_h, tr, log_d

    @staticmethod
    def _segments(tf: FloatArray, gap: float) -> npt.NDArray[np.int64]:
        seg: npt.NDArray[np.int64] = np.concatenate([[0], np.cumsum(np.diff(tf) > gap)])
        return seg

    @staticmethod
    def _costs(
        taus: FloatArray,
        tf: FloatArray,
        log_h: FloatArray,
        tr: FloatArray,
        log_d: FloatArray,
        seg: npt.NDArray[np.int64],
        n_seg: int,
    ) -> FloatArray:
        """The mean squared residual at every shift at once (as :meth:`_cost`)."""
        shifted = (tf[None, :] - taus[:, None]).ravel()
        k = log_h[None, :] + np.interp(shifted, tr, log_d).reshape(len(taus), len(tf))
        onehot = np.zeros((len(tf), n_seg))
        onehot[np.arange(len(tf)), seg] = 1.0
        means = (k @ onehot) / np.maximum(onehot.sum(axis=0), 1.0)
        r = k - means[:, seg]
        out: FloatArray = np.mean(r**2, axis=1)
        return out

    @staticmethod
    def _cost(
        tau: float,
        tf: FloatArray,
        log_h: FloatArray,
        tr: FloatArray,
        log_d: FloatArray,
        seg: npt.NDArray[np.int64],
        n_seg: int,
    ) -> tuple[float, FloatArray]:
        k = log_h + np.interp(tf - tau, tr, log_d)
        means = np.bincount(seg, k, n_seg) / np.maximum(np.bincount(seg, None, n_seg), 1)
        r = k - means[seg]
        return float(np.mean(r**2)), r

    def estimate(self) -> LatencyEstimate | None:
        """The best shift, or None (``why_not`` says why)."""
        series = self._series()
        if series is None:
            return None
        tf, log_h, tr, log_d = series
        seg = self._segments(tf, self.segment_gap_s)
        keep = np.ones(len(tf), bool)
        tau = 0.0
        for _round in range(3):
            t_k, h_k, s_k = tf[keep], log_h[keep], seg[keep]
            _, s_k = np.unique(s_k, return_inverse=True)
            counts = np.bincount(s_k)
            good = counts[s_k] >= 5  # a segment of a few frames says nothing of the slope
            t_k, h_k, s_k = t_k[good], h_k[good], s_k[good]
            if len(t_k) < self.min_frames:
                self.why_not = f"{len(t_k)} detections in runs long enough to use"
                return None
            _, s_k = np.unique(s_k, return_inverse=True)
            n_seg = int(s_k.max()) + 1
            grid = np.arange(0.0, self.max_latency_s + 1e-9, 0.002)
            costs = self._costs(grid, t_k, h_k, tr, log_d, s_k, n_seg)
            best = int(np.argmin(costs))
            fine = np.arange(grid[best] - 0.003, grid[best] + 0.003 + 1e-9, 0.0001)
            fine = fine[(fine >= 0.0) & (fine <= self.max_latency_s)]
            fcost = self._costs(fine, t_k, h_k, tr, log_d, s_k, n_seg)
            j = int(np.argmin(fcost))
            tau = float(fine[j])
            if 0 < j < len(fine) - 1:  # a parabola through the three best samples
                c0, c1, c2 = fcost[j - 1], fcost[j], fcost[j + 1]
                den = c0 - 2 * c1 + c2
                if den > 0:
                    tau += 0.0001 * 0.5 * (c0 - c2) / den
            log.debug("round %d: tau %.4f from %d frames", _round, tau, len(t_k))
            if _round < 2:
                # residuals of every frame about its segment's median over the kept frames
                k_all = log_h + np.interp(tf - tau, tr, log_d)
                centre = np.zeros(len(tf))
                for sid in np.unique(seg):
                    mask = seg == sid
                    kept = mask & keep
                    centre[mask] = np.median(k_all[kept] if kept.any() else k_all[mask])
                r_all = k_all - centre
                sigma = 1.4826 * float(np.median(np.abs(r_all[keep])))
                new_keep = np.abs(r_all) <= max(3.5 * sigma, 1e-4)
                if np.array_equal(new_keep, keep):
                    break
                keep = new_keep
        cost_min, r = self._cost(tau, t_k, h_k, tr, log_d, s_k, n_seg)
        # standard error: residual variance over the (per-segment centred) slope energy
        eps = 0.05  # wide enough that the sonar's millimetre noise is no "motion"
        slope = (np.interp(t_k - tau + eps, tr, log_d) - np.interp(t_k - tau - eps, tr, log_d)) / (
            2 * eps
        )
        means = np.bincount(s_k, slope, n_seg) / np.bincount(s_k, None, n_seg)
        energy = float(np.sum((slope - means[s_k]) ** 2))
        dof = max(len(t_k) - n_seg - 1, 1)
        sigma2 = cost_min * len(t_k) / dof
        se = math.sqrt(sigma2 / energy) if energy > 0 else math.inf
        at_bound = tau <= 0.001 or tau >= self.max_latency_s - 0.001
        confidence = (
            0.0 if (at_bound and tau > 0.001) else 1.0 / (1.0 + (se / CONFIDENCE_SCALE_S) ** 2)
        )
        depth_seen = np.exp(np.interp(t_k - tau, tr, log_d))
        if energy <= 0 or not math.isfinite(se) or np.ptp(depth_seen) < self.min_motion_m:
            self.why_not = (
                f"the range changed by {100 * float(np.ptp(depth_seen)):.1f} cm while the "
                f"obstacle was seen: too little motion to align (>= {100 * self.min_motion_m:g} "
                "cm needed)"
            )
            confidence = 0.0
        else:
            self.why_not = ""
        return LatencyEstimate(tau, float(confidence), float(se), int(len(t_k)))
