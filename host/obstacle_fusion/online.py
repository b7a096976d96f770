"""The rig and the camera's latency, re-estimated from the run's own detections.

Every confident detection (detected, confidence >= 0.5) gives two things:

* its floor-contact row at the sonar's depth (:mod:`obstacle_fusion.vision.rig_estimator`):
  over many frames at varied depths, the camera's height and pitch;
* its face's image height at its frame stamp (:mod:`obstacle_fusion.timing.latency`):
  aligned with the range series, the camera's latency.

:class:`OnlineCalibration` is what the run loop (:mod:`obstacle_fusion.app`) and `replay`
feed: ``frame_in`` (each frame, before pairing: the raw stamp is remembered and, once the
latency is known and not given, the frame is re-dated), ``reading_in`` (each converted
sonar reading), ``measured`` (the fusion's observer: each frame's measurement) and
``update`` (now and then: re-fit, warn). Nothing here changes a measurement; it only
reports, re-dates frames for pairing, and exposes ``rig_estimate`` for whoever measures
without a rig file. OpenCV is only touched through the camera model, for undistorting the
floor-contact points.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from collections import OrderedDict, deque
from collections.abc import Callable
from typing import Any

from obstacle_fusion.sonar import SonarReading
from obstacle_fusion.sources.frames import Frame
from obstacle_fusion.timing.latency import CameraLatencyEstimator, LatencyEstimate
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.rig_estimator import OnlineRigEstimator, RigEstimate

log = logging.getLogger(__name__)

#: Detections at least this confident feed the estimators.
MIN_CONFIDENCE = 0.5
#: The online rig disagrees with the rig file beyond these: warn.
RIG_HEIGHT_TOLERANCE_M = 0.02
RIG_PITCH_TOLERANCE_DEG = 1.0
#: The rig fit must rest on this many detections before it may contradict a file.
MIN_DETECTIONS_TO_WARN = 30
#: The latency estimate re-dates frames only when at least this confident.
MIN_LATENCY_CONFIDENCE = 0.8


def bottom_row(camera: Any, measurement: Any) -> float | None:
    """The face's floor-contact row in the undistorted (not levelled) image, or None.

    The fused method's first line is the bottom edge (input pixels): both of its ends are
    undistorted and averaged (a floor line at one depth is one undistorted row). Otherwise
    the bottom of ``box_px`` at its middle column.
    """
    import numpy as np

    lines = getattr(measurement, "lines", None) or []
    if getattr(measurement, "method", "") == "fused" and lines:
        x0, y0, x1, y1 = lines[0]
        pts = np.array([[x0, y0], [x1, y1]], np.float64)
    else:
        box = getattr(measurement, "box_px", None)
        if box is None:
            return None
        pts = np.array([[(box[0] + box[2]) / 2.0, box[3]]], np.float64)
    rows = camera.undistort_points(pts)[:, 1]
    value = float(rows.mean())
    return value if math.isfinite(value) else None


class OnlineCalibration:
    """Online rig and latency estimates for one run.

    ``rig``: the rig the measurement uses; ``rig_source``: "file" (a --rig was given:
    disagreements are warned about), "default" or "none" (the measurer has no rig; ``rig``
    then only gives the sonar's offsets). ``latency_given_s``: the camera latency
    the user gave (None: estimate it and re-date frames by it once confident);
    ``stamp_shift_s``: a fixed amount to subtract from every stamp here (for a source that
    does not do it itself). ``camera_of(width, height)``: the camera model at a frame size
    (None until the measurer knows it).
    """

    def __init__(
        self,
        rig: Rig,
        *,
        rig_source: str = "default",
        latency_given_s: float | None = None,
        stamp_shift_s: float = 0.0,
        camera_of: Callable[[int, int], Any] | None = None,
        update_every_s: float = 2.0,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.rig = rig
        self.rig_source = rig_source
        self.latency_given_s = latency_given_s
        self.stamp_shift_s = stamp_shift_s
        self.camera_of = camera_of
        self.update_every_s = update_every_s
        self.clock = clock
        self.latency = CameraLatencyEstimator(depth_offset_m=rig.sonar_ahead_m)
        self.rig_estimator: OnlineRigEstimator | None = None
        self.rig_estimate: RigEstimate | None = None
        self.latency_estimate: LatencyEstimate | None = None
        self.applied_latency_s = 0.0  # re-dating frames by the estimate (when not given)
        self.warnings: list[str] = []
        self.detections = 0
        self._raw_t: OrderedDict[int, float] = OrderedDict()
        self._last_update = -math.inf
        self._fitted_at = -1  # detections seen at the last fit
        self._warned_rig = False
        self._camera: Any = None
        self._camera_size: tuple[int, int] | None = None
        self._rows: deque[tuple[float, float]] = deque(maxlen=1000)  # (raw stamp, row)
        self._ranges: deque[tuple[float, float]] = deque(maxlen=4000)  # (t, range)

    # ------------------------------------------------------------------ inputs
    def frame_in(self, frame: Frame) -> Frame:
        """Remember the raw stamp; the frame re-dated by the latency in use."""
        self._raw_t[frame.index] = frame.t_host
        while len(self._raw_t) > 256:
            self._raw_t.popitem(last=False)
        shift = self.stamp_shift_s + self.applied_latency_s
        if shift == 0.0:
            return frame
        return dataclasses.replace(frame, t_host=frame.t_host - shift)

    def reading_in(self, reading: SonarReading) -> None:
        if reading.ok and reading.t_host is not None and reading.distance_m is not None:
            self.latency.add_range(reading.t_host, reading.distance_m)
            self._ranges.append((reading.t_host, reading.distance_m))

    def measured(self, frame: Frame, range_m: float, measurement: Any) -> None:
        """The fusion's observer: one frame's measurement at its paired range."""
        if not getattr(measurement, "detected", False):
            return
        confidence = getattr(measurement, "confidence", None)
        if confidence is None or confidence < MIN_CONFIDENCE:
            return
        self.detections += 1
        raw_t = self._raw_t.get(frame.index, frame.t_host) - self.stamp_shift_s
        h_px = getattr(measurement, "height_px", None)
        if h_px is not None:
            self.latency.add_frame(raw_t, float(h_px))
        camera = self._camera_for(frame.width, frame.height)
        if camera is None:
            return
        row = bottom_row(camera, measurement)
        if row is not None:
            # the depth is looked up at fit time, at the instant the latency then known says
            # the frame shows: a range paired 100 ms off at 0.5 m/s would bend the fit
            self._rows.append((raw_t, row))

    def _camera_for(self, width: int, height: int) -> Any:
        if self._camera_size != (width, height) and self.camera_of is not None:
            self._camera = self.camera_of(width, height)
            if self._camera is not None:
                self._camera_size = (width, height)
                self._rows.clear()  # rows of another size are another view
        return self._camera

    def _fit_rig(self) -> None:
        """Rebuild the rig fit from the stored rows at the depths the latency now says."""
        if self._camera is None or not self._rows or len(self._ranges) < 2:
            return
        import numpy as np

        rt = np.array([t for t, _ in self._ranges])
        rd = np.array([d for _, d in self._ranges])
        order = np.argsort(rt)
        rt, rd = rt[order], rd[order]
        est = OnlineRigEstimator(self._camera.fy, self._camera.cy)
        lag = self.applied_latency_s
        lat = self.latency_estimate
        if self.latency_given_s is not None and lat is not None:
            # a given latency that leaves some behind: the rows still show the scene earlier
            lag = lat.latency_s if lat.confidence >= MIN_LATENCY_CONFIDENCE else 0.0
        obs = np.array(self._rows)
        when = obs[:, 0] - lag
        i = np.clip(np.searchsorted(rt, when), 1, len(rt) - 1)
        ok = (when > rt[0]) & (when < rt[-1]) & (rt[i] - rt[i - 1] <= 0.25)
        for row, d in zip(obs[ok, 1], np.interp(when[ok], rt, rd), strict=True):
            est.add(float(row), self.rig.face_depth(float(d)))
        self.rig_estimator = est
        self.rig_estimate = est.estimate()

    # ------------------------------------------------------------------ estimates
    def update(self, now: float | None = None, force: bool = False) -> list[str]:
        """Re-fit at most every ``update_every_s``; the new warnings (also logged)."""
        now = self.clock() if now is None else now
        if not force and (
            now - self._last_update < self.update_every_s or self.detections == self._fitted_at
        ):
            return []
        self._last_update = now
        self._fitted_at = self.detections
        new: list[str] = []
        self.latency_estimate = self.latency.estimate()
        lat = self.latency_estimate
        # until the latency (or what a given one leaves) is known, depths may be paired off:
        # no warning about the rig before that
        settled = lat is not None and lat.confidence >= MIN_LATENCY_CONFIDENCE
        if self.latency_given_s is None and lat is not None and settled:
            self.applied_latency_s = lat.latency_s
        self._fit_rig()
        est = self.rig_estimate
        if (
            est is not None
            and settled
            and self.rig_source == "file"
            and est.n_used >= MIN_DETECTIONS_TO_WARN
            and not self._warned_rig
        ):
            dh = est.height_m - self.rig.camera_height_m
            dp = est.pitch_deg - self.rig.camera_pitch_deg
            if abs(dh) > RIG_HEIGHT_TOLERANCE_M or abs(dp) > RIG_PITCH_TOLERANCE_DEG:
                self._warned_rig = True
                new.append(
                    f"the rig file says camera {self.rig.camera_height_m:.3f} m high, pitched "
                    f"{self.rig.camera_pitch_deg:+.2f} deg, but {est.n_used} detections put it "
                    f"at {est.height_m:.3f} m, {est.pitch_deg:+.2f} deg (off by {100 * dh:+.1f} "
                    f"cm, {dp:+.2f} deg): check the rig (obstacle-fusion calibrate-rig)"
                )
        for text in new:
            log.warning("%s", text)
        self.warnings += new
        return new

    def estimated_rig(self) -> Rig | None:
        """The rig with the online height and pitch (the sonar's offsets and beam kept), for
        measuring without a rig file; None until the fit exists."""
        est = self.rig_estimate
        if est is None:
            return None
        return dataclasses.replace(
            self.rig, camera_height_m=est.height_m, camera_pitch_deg=est.pitch_deg
        )

    def rig_text(self) -> str:
        est = self.rig_estimate
        if est is None:
            why = self.rig_estimator.why_not if self.rig_estimator is not None else "no detection"
            return f"online rig: not yet ({why})"
        text = (
            f"online rig: camera {est.height_m:.3f} m high, pitch {est.pitch_deg:+.2f} deg from "
            f"{est.n_used} detections (rms {est.residual_px:.2f} px)"
        )
        if self.rig_source == "none":
            return text + "; no rig file"
        return (
            f"{text}; {self.rig_source} rig {self.rig.camera_height_m:.3f} m, "
            f"{self.rig.camera_pitch_deg:+.2f} deg"
        )

    def latency_text(self) -> str:
        lat = self.latency_estimate
        if lat is None:
            return f"camera latency: not yet ({self.latency.why_not})"
        use = (
            f"given {1e3 * self.latency_given_s:.0f} ms (this is what remains)"
            if self.latency_given_s is not None
            else (
                f"pairing uses {1e3 * self.applied_latency_s:.1f} ms"
                if self.applied_latency_s
                else "not used for pairing (not confident enough)"
            )
        )
        return (
            f"camera latency: {1e3 * lat.latency_s:.1f} ms +- {1e3 * lat.std_error_s:.1f} "
            f"(confidence {lat.confidence:.2f}, {lat.n_frames} frames); {use}"
        )

    def summary(self) -> dict[str, Any]:
        est, lat = self.rig_estimate, self.latency_estimate
        return {
            "detections": self.detections,
            "rig_source": self.rig_source,
            "rig_estimate": None
            if est is None
            else {
                "camera_height_m": round(est.height_m, 5),
                "camera_pitch_deg": round(est.pitch_deg, 4),
                "n_used": est.n_used,
                "residual_px": round(est.residual_px, 4),
            },
            "camera_latency": None
            if lat is None
            else {
                "latency_s": round(lat.latency_s, 5),
                "confidence": round(lat.confidence, 3),
                "std_error_s": round(lat.std_error_s, 5),
                "n_frames": lat.n_frames,
            },
            "latency_given_s": self.latency_given_s,
            "latency_applied_s": round(self.applied_latency_s, 5),
            "warnings": list(self.warnings),
        }
