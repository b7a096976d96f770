"""Pair every camera frame with the sonar range of its capture instant, measure, publish.

As ROS message_filters' ApproximateTime does for two streams, but with the answer a robot
needs: the range *at* the frame's instant. When the frame falls between two good readings
close enough together, the range is interpolated; otherwise the nearest reading within a
tolerance is used; otherwise the frame is published as unpaired and counted. A frame waits
(briefly, bounded) for the reading after it, because that reading is still in flight when
the frame arrives; a pairing is never silently made with a reading that is too old.
"""

from __future__ import annotations

import bisect
import logging
import math
import time
from collections import deque
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from enum import StrEnum
from typing import Any, Protocol

from obstacle_fusion.errors import UserError
from obstacle_fusion.sonar import SonarReading, SonarStatus
from obstacle_fusion.sources.frames import Frame

log = logging.getLogger(__name__)


class PairKind(StrEnum):
    INTERPOLATED = "interpolated"
    NEAREST = "nearest"
    NONE = "none"


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


class MeasurerLike(Protocol):
    def measure(self, image: Any, range_m: float) -> Any: ...


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
            span = after.t_host - before.t_host
            frac = (t - before.t_host) / span if span > 0 else 0.0
            assert before.distance_m is not None and after.distance_m is not None
            distance = before.distance_m + frac * (after.distance_m - before.distance_m)
            near = before if frac <= 0.5 else after
            assert near.t_host is not None
            return Pairing(
                PairKind.INTERPOLATED, distance, SonarStatus.OK, t - near.t_host, (before, after)
            )
        candidates = [r for r in (before, after) if r is not None and r.t_host is not None]
        if not candidates:
            return Pairing(PairKind.NONE, None, None, None, (), "no sonar reading yet")
        nearest = min(candidates, key=lambda r: abs(t - (r.t_host or 0.0)))
        assert nearest.t_host is not None
        dt = t - nearest.t_host
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


@dataclass(slots=True)
class FusionStats:
    frames: int = 0
    published: int = 0
    paired: int = 0
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
    pairer: RangePairer = field(default_factory=RangePairer)
    stop_distance_m: float | None = None
    max_wait_s: float = 0.25  # longest a frame waits for the reading after it
    max_pending: int = 32
    method: str | None = None
    clock: Callable[[], float] = time.monotonic
    stats: FusionStats = field(default_factory=FusionStats)
    vision_errors: int = 0
    #: called with (frame, range_m, measurement) after each measurement (online estimates)
    observer: Callable[[Frame, float, Any], None] | None = None
    _pending: deque[tuple[Frame, float]] = field(default_factory=deque)

    def add_reading(self, reading: SonarReading) -> list[ObstacleRecord]:
        self.stats.readings += 1
        self.pairer.add(reading)
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
            ready = self.pairer.ready(frame.t_host)
            expired = now - t_arrived >= self.max_wait_s or len(self._pending) > self.max_pending
            if not (ready or expired):
                break
            self._pending.popleft()
            if not ready:
                self.stats.forced += 1
            out.append(self._publish(frame))
        return out

    def flush(self) -> list[ObstacleRecord]:
        """Decide every waiting frame with what is known (end of run)."""
        out = []
        while self._pending:
            frame, _ = self._pending.popleft()
            if not self.pairer.ready(frame.t_host):
                self.stats.forced += 1
            out.append(self._publish(frame))
        return out

    def _publish(self, frame: Frame) -> ObstacleRecord:
        pairing = self.pairer.pair(frame.t_host)
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
            stats.paired += 1
            if pairing.kind is PairKind.INTERPOLATED:
                stats.interpolated += 1
            else:
                stats.nearest += 1
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
                t0 = time.perf_counter()
                m: Any = None
                # A refusal or a crash is not "nothing there": a robot must not drive on it.
                try:
                    m = self.measurer.measure(frame.image, pairing.distance_m)
                except UserError as exc:  # e.g. a range outside what the vision accepts
                    reason = f"vision refused: {exc}"
                except Exception as exc:  # one bad frame must not end a robot's run
                    self.vision_errors += 1
                    if self.vision_errors <= 3:
                        log.exception("vision failed on frame %d", frame.index)
                    reason = f"vision failed: {exc!r}"
                vision_ms = (time.perf_counter() - t0) * 1e3
                method = getattr(m, "method", method)
                if m is not None and self.observer is not None:
                    self.observer(frame, pairing.distance_m, m)
                if m is None:
                    status = ObstacleStatus.VISION_ERROR
                    stats.vision_errors += 1
                elif getattr(m, "detected", False):
                    status = ObstacleStatus.OK
                    stats.detected += 1
                    height = getattr(m, "height_m", None)
                    width = getattr(m, "width_m", None)
                    depth = getattr(m, "distance_m", None)
                    confidence = float(getattr(m, "confidence", 1.0) or 0.0)
                    raw_box = getattr(m, "box_px", None)
                    box = tuple(float(v) for v in raw_box) if raw_box is not None else None
                    edges = tuple(
                        (float(a), float(b), float(c), float(d))
                        for a, b, c, d in (getattr(m, "lines", None) or ())
                    )
                else:
                    status = ObstacleStatus.NOT_DETECTED
                    stats.not_detected += 1
                    reason = getattr(m, "reason", None) or "no obstacle found in the image"
        distance = pairing.distance_m
        alert = (
            self.stop_distance_m is not None
            and distance is not None
            and distance <= self.stop_distance_m
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
            edges_px=edges,
        )

    def range_record(self, reading: SonarReading) -> ObstacleRecord:
        """A record for one reading alone: the sonar-only mode, with no camera to pair.

        Its instant is the reading's reflection time; the status says what the sonar heard
        (RANGE with a distance, CLEAR, or SONAR_ERROR); the alert is the same rule."""
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
        alert = self.stop_distance_m is not None and distance is not None and (
            distance <= self.stop_distance_m
        )
        if alert:
            stats.alerts += 1
        stats.published += 1
        t = reading.t_host if reading.t_host is not None else self.clock()
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
