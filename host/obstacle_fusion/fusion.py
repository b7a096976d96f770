"""Pair every camera frame with the sonar range of its capture instant, measure, publish.

As ROS message_filters' ApproximateTime does for two streams, but with the answer a robot
needs: the range *at* the frame's instant. Two ways to get it:

* ``predicted`` (the default): the frame is published at once with the range a
  constant-velocity Kalman filter over each sonar's recent readings predicts for the
  frame's instant, and that prediction's standard deviation (``range_sigma_m``). Only a
  filter with at least two recent good readings predicts, and never further ahead of its
  last reading than ``max_extrapolation_s``; otherwise the frame falls back to waiting, as
  below.
* ``interpolated``: the frame waits (briefly, bounded) for the reading after it, because
  that reading is still in flight when the frame arrives, then takes the range interpolated
  between the two good readings around it when they are close enough together.

Either way, when neither works, the nearest reading within a tolerance is used; otherwise the
frame is published as unpaired and counted. A pairing is never silently made with a reading
that is too old. With several sonars, each has its own readings and filter, every record
carries every sonar's range, and the distance is the one of the sonar whose beam covers the
obstacle the image shows (without an image box: the nearest valid range).
"""

from __future__ import annotations

import bisect
import logging
import math
import time
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field, replace
from enum import StrEnum
from typing import Any, Protocol

from obstacle_fusion.errors import UserError
from obstacle_fusion.sonar import SonarReading, SonarStatus
from obstacle_fusion.sources.frames import Frame

log = logging.getLogger(__name__)


class PairKind(StrEnum):
    PREDICTED = "predicted"
    INTERPOLATED = "interpolated"
    NEAREST = "nearest"
    NONE = "none"


class PairingMode(StrEnum):
    """How a frame gets its range: at once from the filter, or after the next echo."""

    PREDICTED = "predicted"
    INTERPOLATED = "interpolated"


class ObstacleStatus(StrEnum):
    """What a published record means."""

    OK = "ok"  # paired, and the vision found the obstacle: distance, height and width
    NOT_DETECTED = "not_detected"  # paired, the sonar sees something, the image shows no box
    CLEAR = "clear"  # the sonar hears nothing in range (no echo / out of range)
    SONAR_ERROR = "sonar_error"  # the nearest reading failed (timeout, too close)
    UNPAIRED = "unpaired"  # no reading near enough in time: nothing claimed
    VISION_ERROR = "vision_error"  # paired, but the vision refused or failed: nothing claimed
    RANGE = "range"  # sonar only (no camera): a distance, no height or width


SONAR_ONLY_SOURCE = "sonar"  # a range record's `source` (no frame: frame_index is -1)


@dataclass(frozen=True, slots=True)
class Pairing:
    kind: PairKind
    distance_m: float | None
    sonar_status: SonarStatus | None
    dt_s: float | None  # frame time minus the nearest reading's time
    readings: tuple[SonarReading, ...]
    reason: str | None = None
    sigma_m: float | None = None  # the prediction's standard deviation (predicted only)


class MeasurerLike(Protocol):
    def measure(self, image: Any, range_m: float) -> Any: ...


class BeamChooser(Protocol):
    """Which sonar's beam covers the obstacle an image box shows (several sonars)."""

    def in_view(self, sensors: Sequence[int]) -> list[int]:
        """Those of ``sensors`` whose beam reaches into the camera's view, in order."""
        ...

    def choose(
        self, box_px: tuple[float, float, float, float], depth_m: float, sensors: Sequence[int]
    ) -> int | None: ...


@dataclass(frozen=True, slots=True)
class ObstacleRecord:
    """The published result for one frame. Times are host-monotonic seconds."""

    t_host: float  # the frame's capture instant
    distance_m: float | None  # sonar range at t_host
    height_m: float | None
    width_m: float | None
    confidence: float
    status: str
    alert: bool
    frame_index: int
    source: str
    pairing: str
    pair_dt_s: float | None
    sonar_status: str | None
    measurements: tuple[int, ...]  # the sonar measurement numbers used
    trigger_us: tuple[int, ...]  # their raw MCU trigger stamps (source time)
    box_px: tuple[float, float, float, float] | None = None
    depth_m: float | None = None  # the measurer's depth along the optical axis, if it reports one
    method: str | None = None
    vision_ms: float | None = None
    t_published: float | None = None
    reason: str | None = None
    range_sigma_m: float | None = None  # standard deviation of a predicted distance
    sensor_id: int | None = None  # the sonar the distance comes from
    ranges: tuple[tuple[int, float | None], ...] = ()  # every sonar's range at t_host
    #: the image edges the method chose (x0, y0, x1, y1 px), for drawing; not in to_dict()
    edges_px: tuple[tuple[float, float, float, float], ...] = ()

    @property
    def latency_s(self) -> float | None:
        return None if self.t_published is None else self.t_published - self.t_host

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["measurements"] = list(self.measurements)
        d["trigger_us"] = list(self.trigger_us)
        d["box_px"] = list(self.box_px) if self.box_px is not None else None
        d["ranges"] = {str(k): v for k, v in self.ranges}
        d["latency_s"] = self.latency_s
        del d["edges_px"]
        return d


class RangePairer:
    """Recent sonar readings ordered by host time, and the pairing rule."""

    def __init__(
        self, tolerance_s: float = 0.05, max_gap_s: float = 0.2, history_s: float = 10.0
    ) -> None:
        self.tolerance_s = tolerance_s
        self.max_gap_s = max_gap_s
        self.history_s = history_s
        self._times: list[float] = []
        self._readings: list[SonarReading] = []
        self.dropped_unmapped = 0  # readings without a host time (clock not ready)

    def __len__(self) -> int:
        return len(self._readings)

    @property
    def newest_t(self) -> float | None:
        return self._times[-1] if self._times else None

    @property
    def newest(self) -> SonarReading | None:
        return self._readings[-1] if self._readings else None

    def add(self, reading: SonarReading) -> None:
        t = reading.t_host
        if t is None or not math.isfinite(t):
            self.dropped_unmapped += 1
            return
        i = bisect.bisect_right(self._times, t)
        self._times.insert(i, t)
        self._readings.insert(i, reading)
        cut = bisect.bisect_left(self._times, self._times[-1] - self.history_s)
        if cut > 0:
            del self._times[:cut]
            del self._readings[:cut]

    def ready(self, t: float) -> bool:
        """True once a reading later than t has arrived (or one cannot be useful any more)."""
        newest = self.newest_t
        return newest is not None and newest > t

    def pair(self, t: float) -> Pairing:
        i = bisect.bisect_right(self._times, t)
        before = self._readings[i - 1] if i > 0 else None
        after = self._readings[i] if i < len(self._readings) else None
        if (
            before is not None
            and after is not None
            and before.ok
            and after.ok
            and after.t_host is not None
            and before.t_host is not None
            and after.t_host - before.t_host <= self.max_gap_s
        ):
            # bisect_right: before.t_host <= t < after.t_host, so the span is positive.
            frac = (t - before.t_host) / (after.t_host - before.t_host)
            assert before.distance_m is not None and after.distance_m is not None
            distance = before.distance_m + frac * (after.distance_m - before.distance_m)
            near = before if frac <= 0.5 else after
            assert near.t_host is not None
            return Pairing(
                PairKind.INTERPOLATED,
                distance,
                SonarStatus.OK,
                t - near.t_host,
                (before, after),
            )
        # Every stored reading has a host time (add() keeps no other): self._times holds it.
        candidates = [(self._times[k], self._readings[k]) for k in (i - 1, i) if 0 <= k < len(self)]
        if not candidates:
            return Pairing(PairKind.NONE, None, None, None, (), "no sonar reading yet")
        t_near, nearest = min(candidates, key=lambda c: abs(t - c[0]))
        dt = t - t_near
        if abs(dt) > self.tolerance_s:
            return Pairing(
                PairKind.NONE,
                None,
                nearest.status,
                dt,
                (),
                f"nearest sonar reading is {abs(dt) * 1e3:.0f} ms away "
                f"(tolerance {self.tolerance_s * 1e3:.0f} ms)",
            )
        return Pairing(PairKind.NEAREST, nearest.distance_m, nearest.status, dt, (nearest,))


@dataclass(frozen=True, slots=True)
class TrackSettings:
    """The constant-velocity filter's model and its limits."""

    measurement_sigma_m: float = 0.003  # one reading's noise (the HC-SR04's few millimetres)
    accel_psd: float = 0.5  # white-noise acceleration spectral density, m^2/s^3
    speed_sigma_mps: float = 2.0  # prior on the speed when a track starts
    max_extrapolation_s: float = 0.2  # never predict further past the last reading
    max_gap_s: float = 0.2  # good readings further apart start a new track
    gate_sigmas: float = 5.0  # a reading this far off the prediction starts a new track...
    gate_min_m: float = 0.10  # ...and at least this far (another obstacle, not motion)


@dataclass(frozen=True, slots=True)
class Prediction:
    distance_m: float
    sigma_m: float
    speed_mps: float  # d(range)/dt: negative when the obstacle comes closer
    reading: SonarReading  # the newest reading the filter used


class RangeTrack:
    """A constant-velocity Kalman filter over one sonar's good readings: (range, speed).

    State x = (r, v) with covariance P; between readings r' = r + v dt and P grows with the
    white-noise acceleration model (Q = q [dt^3/3, dt^2/2; dt^2/2, dt]). A failed reading
    stops predictions until a good one arrives; a gap longer than ``max_gap_s`` or a reading
    outside the gate (another obstacle stepped in) starts the track again.
    """

    def __init__(self, settings: TrackSettings | None = None) -> None:
        self.s = settings or TrackSettings()
        self.restarts = 0
        self.reset()

    def reset(self) -> None:
        self.t: float | None = None  # host time of the newest good reading used
        self.r = 0.0
        self.v = 0.0
        self.p00 = self.p01 = self.p11 = 0.0
        self.updates = 0
        self.last: SonarReading | None = None
        self.failed_t: float | None = None  # a failed reading after the last good one

    def _propagate(self, dt: float) -> tuple[float, float, float, float, float]:
        q = self.s.accel_psd
        a = abs(dt)
        return (
            self.r + self.v * dt,
            self.v,
            self.p00 + 2.0 * dt * self.p01 + dt * dt * self.p11 + q * a**3 / 3.0,
            self.p01 + dt * self.p11 + q * dt * a / 2.0,
            self.p11 + q * a,
        )

    def _start(self, t: float, z: float, reading: SonarReading) -> None:
        if self.updates:
            self.restarts += 1
        self.t = t
        self.r, self.v = z, 0.0
        self.p00 = self.s.measurement_sigma_m**2
        self.p01 = 0.0
        self.p11 = self.s.speed_sigma_mps**2
        self.updates = 1
        self.last = reading
        self.failed_t = None

    def add(self, reading: SonarReading) -> None:
        t = reading.t_host
        if t is None or not math.isfinite(t):
            return
        if self.t is not None and t <= self.t:
            return  # older than what the filter holds: out of order, not used
        if not reading.ok:
            self.failed_t = t
            return
        z = reading.distance_m
        assert z is not None
        if self.t is None or t - self.t > self.s.max_gap_s:
            self._start(t, z, reading)
            return
        r, v, p00, p01, p11 = self._propagate(t - self.t)
        s_var = p00 + self.s.measurement_sigma_m**2
        y = z - r
        if abs(y) > max(self.s.gate_sigmas * math.sqrt(s_var), self.s.gate_min_m):
            self._start(t, z, reading)
            return
        k0, k1 = p00 / s_var, p01 / s_var
        self.r, self.v = r + k0 * y, v + k1 * y
        self.p00, self.p01, self.p11 = (1.0 - k0) * p00, (1.0 - k0) * p01, p11 - k1 * p01
        self.t = t
        self.updates += 1
        self.last = reading
        self.failed_t = None

    def predict(self, t: float) -> tuple[Prediction | None, str]:
        """The range at host time t and its standard deviation, or None and why not."""
        if self.updates < 2:
            return None, "the range filter has fewer than two good readings in a row"
        assert self.t is not None and self.last is not None
        if self.failed_t is not None:
            return None, "the newest sonar reading failed"
        h = t - self.t
        if h > self.s.max_extrapolation_s:
            return None, (
                f"the last good reading is {h * 1e3:.0f} ms old (extrapolation limit "
                f"{self.s.max_extrapolation_s * 1e3:.0f} ms)"
            )
        r, v, p00, _, _ = self._propagate(h)
        if r <= 0.0:
            return None, f"the predicted range {r:.3f} m is not positive"
        return Prediction(r, math.sqrt(max(p00, 0.0)), v, self.last), ""


@dataclass(slots=True)
class FusionStats:
    frames: int = 0
    published: int = 0
    paired: int = 0
    predicted: int = 0
    interpolated: int = 0
    nearest: int = 0
    unpaired: int = 0
    detected: int = 0
    not_detected: int = 0
    clear: int = 0
    sonar_errors: int = 0
    vision_errors: int = 0
    alerts: int = 0
    forced: int = 0  # frames decided before the reading after them arrived (wait expired)
    readings: int = 0

    @property
    def paired_fraction(self) -> float:
        return self.paired / self.published if self.published else 0.0

    def as_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["paired_fraction"] = self.paired_fraction
        return d


@dataclass
class Fusion:
    """Frames and readings in (any interleaving), obstacle records out, in frame order."""

    measurer: MeasurerLike | None = None
    pairer: RangePairer = field(default_factory=RangePairer)  # sonar 0's; others copy it
    stop_distance_m: float | None = None
    max_wait_s: float = 0.25  # longest a frame waits for the reading after it
    max_pending: int = 32
    method: str | None = None
    clock: Callable[[], float] = time.monotonic
    stats: FusionStats = field(default_factory=FusionStats)
    vision_errors: int = 0
    pairing: PairingMode = PairingMode.PREDICTED
    track: TrackSettings = field(default_factory=TrackSettings)
    beams: BeamChooser | None = None  # several sonars: which beam covers the image's box
    stale_sensor_s: float = 1.0  # a sonar silent this long (others speaking) is left out
    #: called with (frame, range_m, measurement) after each measurement (online estimates)
    observer: Callable[[Frame, float, Any], None] | None = None
    _pending: deque[tuple[Frame, float]] = field(default_factory=deque)
    _pairers: dict[int, RangePairer] = field(default_factory=dict)
    _tracks: dict[int, RangeTrack] = field(default_factory=dict)
    _last_range_t: float = -math.inf  # the newest sonar-only record's time

    def __post_init__(self) -> None:
        self.pairing = PairingMode(self.pairing)

    def pairer_of(self, sensor_id: int) -> RangePairer:
        if sensor_id == 0:
            return self.pairer
        p = self._pairers.get(sensor_id)
        if p is None:
            t = self.pairer
            p = self._pairers[sensor_id] = RangePairer(t.tolerance_s, t.max_gap_s, t.history_s)
        return p

    def track_of(self, sensor_id: int) -> RangeTrack:
        tr = self._tracks.get(sensor_id)
        if tr is None:
            tr = self._tracks[sensor_id] = RangeTrack(self.track)
        return tr

    @property
    def newest_t(self) -> float | None:
        times = [t for t in (p.newest_t for p in self._all_pairers().values()) if t is not None]
        return max(times) if times else None

    def _all_pairers(self) -> dict[int, RangePairer]:
        return {0: self.pairer, **self._pairers}

    def sensors(self) -> list[int]:
        """The sonars that speak: each has a reading within stale_sensor_s of the newest."""
        newest = {sid: p.newest_t for sid, p in self._all_pairers().items()}
        known = [t for t in newest.values() if t is not None]
        if not known:
            return []
        latest = max(known)
        return sorted(
            sid for sid, t in newest.items() if t is not None and latest - t <= self.stale_sensor_s
        )

    def ready_for_frames(self) -> bool:
        """Readings flow (and, when predicting, a filter can predict): start the camera."""
        if self.newest_t is None:
            return False
        if self.pairing is PairingMode.INTERPOLATED:
            return True
        return any(tr.updates >= 2 for tr in self._tracks.values())

    def add_reading(self, reading: SonarReading) -> list[ObstacleRecord]:
        self.stats.readings += 1
        self.pairer_of(reading.sensor_id).add(reading)
        if reading.t_host is not None:
            self.track_of(reading.sensor_id).add(reading)
        return self.poll()

    def add_frame(self, frame: Frame) -> list[ObstacleRecord]:
        self.stats.frames += 1
        self._pending.append((frame, self.clock()))
        return self.poll()

    @property
    def pending(self) -> int:
        return len(self._pending)

    def poll(self, now: float | None = None) -> list[ObstacleRecord]:
        """Publish every waiting frame whose pairing can be decided now."""
        out: list[ObstacleRecord] = []
        now = self.clock() if now is None else now
        while self._pending:
            frame, t_arrived = self._pending[0]
            final = now - t_arrived >= self.max_wait_s or len(self._pending) > self.max_pending
            pairings = self._decide(frame.t_host, final)
            if pairings is None:
                break
            self._pending.popleft()
            out.append(self._publish(frame, pairings))
        return out

    def flush(self) -> list[ObstacleRecord]:
        """Decide every waiting frame with what is known (end of run)."""
        out = []
        while self._pending:
            frame, _ = self._pending.popleft()
            pairings = self._decide(frame.t_host, final=True)
            assert pairings is not None
            out.append(self._publish(frame, pairings))
        return out

    def _decide(self, t: float, final: bool) -> dict[int, Pairing] | None:
        """Every speaking sonar's pairing for a frame at t, or None to wait for more."""
        sensors = self.sensors()
        if not sensors:
            if not final:
                return None
            self.stats.forced += 1
            return {0: self.pairer.pair(t)}
        out: dict[int, Pairing] = {}
        forced = False
        for sid in sensors:
            pairer = self.pairer_of(sid)
            if pairer.ready(t):
                out[sid] = pairer.pair(t)
                continue
            why = ""
            if self.pairing is PairingMode.PREDICTED:
                predicted, why = self._predict(sid, t)
                if predicted is not None:
                    out[sid] = predicted
                    continue
            if not final:
                return None
            forced = True
            pairing = pairer.pair(t)
            if pairing.kind is PairKind.NONE and why:
                pairing = replace(pairing, reason=f"{pairing.reason}; no prediction: {why}")
            out[sid] = pairing
        if forced:
            self.stats.forced += 1
        return out

    def _predict(self, sid: int, t: float) -> tuple[Pairing | None, str]:
        pred, why = self.track_of(sid).predict(t)
        if pred is not None:
            assert pred.reading.t_host is not None
            return (
                Pairing(
                    PairKind.PREDICTED,
                    pred.distance_m,
                    SonarStatus.OK,
                    t - pred.reading.t_host,
                    (pred.reading,),
                    sigma_m=pred.sigma_m,
                ),
                "",
            )
        newest = self.pairer_of(sid).newest
        if newest is not None and not newest.ok:
            # The newest reading failed (no echo, timeout): it is what is known now.
            pairing = self.pairer_of(sid).pair(t)
            if pairing.kind is PairKind.NEAREST:
                return pairing, ""
        return None, why

    @staticmethod
    def _nearest_valid(pairings: dict[int, Pairing]) -> list[int]:
        """Sonars with a distance, nearest first (ties: the lower id)."""
        valid = [(p.distance_m, sid) for sid, p in pairings.items() if p.distance_m is not None]
        return [sid for _, sid in sorted(valid)]

    def _primary(self, pairings: dict[int, Pairing]) -> int:
        valid = self._nearest_valid(pairings)
        if valid and self.beams is not None and self.measurer is not None:
            valid = self.beams.in_view(valid) or valid  # the image can only see those
        if valid:
            return valid[0]
        paired = [sid for sid, p in sorted(pairings.items()) if p.kind is not PairKind.NONE]
        return paired[0] if paired else min(pairings)

    def _measure(self, frame: Frame, range_m: float) -> tuple[Any, str | None, float]:
        """(measurement or None, reason when None, milliseconds spent)."""
        assert self.measurer is not None
        t0 = time.perf_counter()
        m: Any = None
        reason = None
        # A refusal or a crash is not "nothing there": a robot must not drive on it.
        try:
            m = self.measurer.measure(frame.image, range_m)
        except UserError as exc:  # e.g. a range outside what the vision accepts
            reason = f"vision refused: {exc}"
        except Exception as exc:  # one bad frame must not end a robot's run
            self.vision_errors += 1
            if self.vision_errors <= 3:
                log.exception("vision failed on frame %d", frame.index)
            reason = f"vision failed: {exc!r}"
        return m, reason, (time.perf_counter() - t0) * 1e3

    def _measure_choosing(
        self, frame: Frame, pairings: dict[int, Pairing], first: int
    ) -> tuple[int, Any, str | None, float]:
        """Measure with the sonar whose beam covers the box the image shows.

        One sonar: its range. Several in the camera's view: nearest first; a box found with
        a range is kept when it lies in that sonar's beam; when it lies in another's, that
        one's range is measured next; when none is found, the next sonar's range is tried.
        Returns (sonar, measurement or None, reason, milliseconds)."""
        valid = self._nearest_valid(pairings)
        cands = valid
        if self.beams is not None:
            cands = self.beams.in_view(valid) or valid
        order = [first] + [c for c in cands if c != first]
        tried: dict[int, tuple[Any, str | None]] = {}
        total_ms = 0.0
        while order:
            sid = order.pop(0)
            if sid in tried:
                continue
            distance = pairings[sid].distance_m
            assert distance is not None
            m, reason, ms = self._measure(frame, distance)
            total_ms += ms
            tried[sid] = (m, reason)
            if self.beams is None or len(cands) < 2:
                return sid, m, reason, total_ms
            if m is None or not m.detected or m.box_px is None:
                continue
            box = tuple(float(v) for v in m.box_px)
            covering = self.beams.choose(box, distance, cands)  # type: ignore[arg-type]
            if covering is None or covering == sid:
                return sid, m, reason, total_ms
            if covering not in tried:
                order.insert(0, covering)
            elif tried[covering][0] is not None and tried[covering][0].detected:
                return covering, tried[covering][0], tried[covering][1], total_ms
            else:
                return sid, m, reason, total_ms
        m, reason = tried[first]
        return first, m, reason, total_ms

    def _publish(self, frame: Frame, pairings: dict[int, Pairing]) -> ObstacleRecord:
        sid = self._primary(pairings)
        pairing = pairings[sid]
        stats = self.stats
        height = width = depth = vision_ms = None
        box = None
        edges: tuple[tuple[float, float, float, float], ...] = ()
        confidence = 0.0
        method = self.method
        reason = pairing.reason
        if pairing.kind is PairKind.NONE:
            status = ObstacleStatus.UNPAIRED
            stats.unpaired += 1
        else:
            if pairing.distance_m is None:
                if pairing.sonar_status in (SonarStatus.NO_ECHO, SonarStatus.OUT_OF_RANGE):
                    status = ObstacleStatus.CLEAR
                    stats.clear += 1
                else:
                    status = ObstacleStatus.SONAR_ERROR
                    stats.sonar_errors += 1
                    reason = f"sonar reading: {pairing.sonar_status}"
            elif self.measurer is None:
                status = ObstacleStatus.NOT_DETECTED
                stats.not_detected += 1
                reason = "no measurer configured"
            else:
                sid, m, reason, vision_ms = self._measure_choosing(frame, pairings, sid)
                pairing = pairings[sid]
                if m is not None and self.observer is not None:
                    assert pairing.distance_m is not None
                    self.observer(frame, pairing.distance_m, m)
                if m is None:
                    status = ObstacleStatus.VISION_ERROR
                    stats.vision_errors += 1
                elif m.detected:
                    method = m.method
                    status = ObstacleStatus.OK
                    stats.detected += 1
                    height, width, depth = m.height_m, m.width_m, m.distance_m
                    confidence = float(m.confidence or 0.0)  # None: the method has none
                    box = None if m.box_px is None else tuple(float(v) for v in m.box_px)
                    edges = tuple(
                        (float(a), float(b), float(c), float(d))
                        for a, b, c, d in (getattr(m, "lines", None) or ())
                    )
                else:
                    method = m.method
                    status = ObstacleStatus.NOT_DETECTED
                    stats.not_detected += 1
                    reason = m.reason or "no obstacle found in the image"
            stats.paired += 1
            if pairing.kind is PairKind.PREDICTED:
                stats.predicted += 1
            elif pairing.kind is PairKind.INTERPOLATED:
                stats.interpolated += 1
            else:
                stats.nearest += 1
        distance = pairing.distance_m
        nearest = [p.distance_m for p in pairings.values() if p.distance_m is not None]
        alert = (
            self.stop_distance_m is not None
            and bool(nearest)
            and min(nearest) <= self.stop_distance_m  # any sonar: the robot must stop
        )
        if alert:
            stats.alerts += 1
        stats.published += 1
        return ObstacleRecord(
            t_host=frame.t_host,
            distance_m=distance,
            height_m=height,
            width_m=width,
            confidence=confidence,
            status=str(status),
            alert=bool(alert),
            frame_index=frame.index,
            source=frame.source,
            pairing=str(pairing.kind),
            pair_dt_s=pairing.dt_s,
            sonar_status=str(pairing.sonar_status) if pairing.sonar_status else None,
            measurements=tuple(r.measurement for r in pairing.readings),
            trigger_us=tuple(r.trigger_us for r in pairing.readings),
            box_px=box,  # type: ignore[arg-type]
            depth_m=depth,
            method=method,
            vision_ms=vision_ms,
            t_published=self.clock(),
            reason=reason,
            range_sigma_m=pairing.sigma_m,
            sensor_id=sid if pairing.kind is not PairKind.NONE else None,
            ranges=tuple((k, p.distance_m) for k, p in sorted(pairings.items())),
            edges_px=edges,
        )

    def range_record(self, reading: SonarReading) -> ObstacleRecord:
        """A record for one reading alone: the sonar-only mode, with no camera to pair.

        Its instant is the reading's reflection time (or, before the clock model is
        ready, its receipt time; records never go back in time, so the first mapped one
        after those may be held at the last receipt time, a few ms late); the status says
        what the sonar heard (RANGE with a distance, CLEAR, or SONAR_ERROR); the alert is
        the same rule."""
        stats = self.stats
        stats.readings += 1
        reason = None
        if reading.distance_m is not None and reading.status is SonarStatus.OK:
            status = ObstacleStatus.RANGE
        elif reading.status in (SonarStatus.NO_ECHO, SonarStatus.OUT_OF_RANGE):
            status = ObstacleStatus.CLEAR
            stats.clear += 1
        else:
            status = ObstacleStatus.SONAR_ERROR
            stats.sonar_errors += 1
            reason = f"sonar reading: {reading.status}"
        distance = reading.distance_m if status is ObstacleStatus.RANGE else None
        alert = (
            self.stop_distance_m is not None
            and distance is not None
            and (distance <= self.stop_distance_m)
        )
        if alert:
            stats.alerts += 1
        stats.published += 1
        t = reading.t_host if reading.t_host is not None else self.clock()
        # in order: a reading before the clock model was ready carries its receipt time,
        # later than its instant, and the next one, mapped, must not go back before it
        t = max(t, self._last_range_t)
        self._last_range_t = t
        return ObstacleRecord(
            t_host=t,
            distance_m=distance,
            height_m=None,
            width_m=None,
            confidence=1.0 if distance is not None else 0.0,
            status=str(status),
            alert=bool(alert),
            frame_index=-1,
            source=SONAR_ONLY_SOURCE,
            pairing=str(PairKind.NONE),
            pair_dt_s=None,
            sonar_status=str(reading.status),
            measurements=(reading.measurement,),
            trigger_us=(reading.trigger_us,),
            t_published=self.clock(),
            reason=reason,
        )
