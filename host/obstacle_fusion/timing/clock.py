"""MCU microseconds to host monotonic seconds: offset, drift and how sure we are.

Two kinds of evidence, as in the literature the house plan points to:

* TIME_SYNC round trips (PX4 timesync): the host sends at t1, the MCU stamps the request's
  last byte at rx_us and queues its reply at tx_us, the host reads it at t4. The MCU's clock,
  mapped to the host, must put rx_us after t1 + the request's wire time and tx_us before
  t4 - the reply's wire time; the middle of that interval is the estimate and half its width
  bounds the error. Only the round trips with the lowest slack are kept.
* One-way RANGE arrivals (TICSync): an echo ends at a known MCU instant and its frame
  reaches the host some unknown but bounded-below delay later. The lower convex hull of
  (MCU time, arrival time) over a window is a line shifted by the minimum delay; its slope
  is the crystal's drift, found from dozens of frames a second with no request at all.

The slope comes from the hull when it spans enough time (dense, one-sided jitter is exactly
what a hull ignores), else from a fit through the best round trips; the offset comes from the
round trips, or from the hull minus the frame's wire time when the firmware never answered.
"""

from __future__ import annotations

import logging
import math
from collections import deque
from dataclasses import dataclass

from obstacle_fusion.protocol.generated import Range, TimeSync, TimeSyncReply

log = logging.getLogger(__name__)

_WRAP = 1 << 32
_HALF = 1 << 31


def frame_bytes(msg_cls: type) -> int:
    """Bytes on the wire for a fixed-length message: COBS(id, seq, payload, crc) + 0x00."""
    body = 2 + int(msg_cls.MIN_LEN) + 2  # type: ignore[attr-defined]
    return body + 1 + (body // 254) + 1


class Unwrapper:
    """A 32-bit microsecond counter made monotonic; values a little older than the newest
    (a RANGE trigger behind a TIME_SYNC reply) unwrap to the past, not 71 minutes ahead."""

    def __init__(self) -> None:
        self._last_raw: int | None = None
        self._last = 0

    def reset(self) -> None:
        self._last_raw = None
        self._last = 0

    def __call__(self, raw: int) -> int:
        raw &= 0xFFFFFFFF
        if self._last_raw is None:
            self._last_raw = raw
            self._last = raw
            return raw
        delta = (raw - self._last_raw) & 0xFFFFFFFF
        if delta >= _HALF:
            delta -= _WRAP
        value = self._last + delta
        if delta > 0:
            self._last_raw = raw
            self._last = value
        return value


@dataclass(frozen=True, slots=True)
class ClockEstimate:
    """host_s = offset_s + slope * (mcu_us - ref_us) / 1e6."""

    slope: float
    offset_s: float
    ref_us: int
    uncertainty_s: float
    source: str  # "sync+oneway", "sync", "oneway" or "none"
    n_sync: int
    n_oneway: int
    min_oneway_delay_s: float | None  # hull offset minus the round-trip line, when both exist

    @property
    def drift_ppm(self) -> float:
        """How fast the MCU's crystal runs relative to the host (positive: MCU fast)."""
        return (1.0 / self.slope - 1.0) * 1e6 if self.slope else 0.0

    def map_us(self, mcu_us: int) -> float:
        return self.offset_s + self.slope * (mcu_us - self.ref_us) * 1e-6


@dataclass(slots=True)
class _Sync:
    x: float  # MCU seconds since ref, middle of rx/tx
    y: float  # host seconds, middle of the admissible interval
    span_mcu: float  # (tx - rx) in MCU seconds
    lo: float  # earliest host time the MCU could have received (t1 + request wire time)
    hi: float  # latest host time the MCU could have sent (t4 - reply wire time)


def _lower_hull(points: list[tuple[float, float]]) -> list[tuple[float, float]]:
    hull: list[tuple[float, float]] = []
    for p in points:
        while len(hull) >= 2:
            (x1, y1), (x2, y2) = hull[-2], hull[-1]
            if (x2 - x1) * (p[1] - y1) - (y2 - y1) * (p[0] - x1) <= 0:
                hull.pop()
            else:
                break
        hull.append(p)
    return hull


def _weighted_median(values: list[float], weights: list[float]) -> float:
    pairs = sorted(zip(values, weights, strict=True))
    half = sum(weights) / 2.0
    acc = 0.0
    for value, weight in pairs:
        acc += weight
        if acc >= half:
            return value
    return pairs[-1][0]


class ClockModel:
    """Feed it round trips and one-way arrivals; ask it to map MCU times.

    A reset (the MCU rebooted: a new HELLO, or its clock jumped backwards) forgets
    everything, because the new counter has nothing to do with the old one.
    """

    def __init__(
        self,
        baud: int = 115200,
        bits_per_byte: float = 10.0,
        window_s: float = 30.0,
        min_hull_span_s: float = 2.0,
        oneway_extra_latency_s: float = 0.0,
    ) -> None:
        self.byte_s = bits_per_byte / baud
        self.window_s = window_s
        self.min_hull_span_s = min_hull_span_s
        self.oneway_extra_latency_s = oneway_extra_latency_s
        self.request_wire_s = frame_bytes(TimeSync) * self.byte_s
        self.reply_wire_s = frame_bytes(TimeSyncReply) * self.byte_s
        self.range_wire_s = frame_bytes(Range) * self.byte_s
        self.unwrap = Unwrapper()
        self.resets = 0
        self.jumps = 0
        self._backjumps = 0
        self.fast_round_trips = 0
        self._ref_us: int | None = None
        self._syncs: deque[_Sync] = deque()
        self._oneway: deque[tuple[float, float]] = deque()
        self._estimate: ClockEstimate | None = None
        self._dirty = False

    BACKJUMPS_TO_RESET = 3

    def reset(self) -> None:
        self._backjumps = 0
        self.unwrap.reset()
        self._ref_us = None
        self._syncs.clear()
        self._oneway.clear()
        self._estimate = None
        self._dirty = False
        self.resets += 1

    # ------------------------------------------------------------------ evidence
    def _behind(self, x: float) -> bool:
        """True for a stamp seconds older than the newest one: a stray, or a rebooted MCU
        whose HELLO was lost; a few in a row mean the latter."""
        newest = max(
            self._oneway[-1][0] if self._oneway else -math.inf,
            self._syncs[-1].x if self._syncs else -math.inf,
        )
        if x < newest - 2.0:
            self._backjumps += 1
            return True
        self._backjumps = 0
        return False

    def _restart_after_jump(self) -> None:
        log.warning("the MCU clock went back in time (a reset without HELLO?): starting over")
        self.jumps += 1
        self.reset()

    def _x(self, raw_us: int) -> float:
        value = self.unwrap(raw_us)
        if self._ref_us is None:
            self._ref_us = value
        return (value - self._ref_us) * 1e-6

    def add_sync(self, t_send: float, t_recv: float, rx_us: int, tx_us: int) -> None:
        """One TIME_SYNC round trip: host send/receive instants and the MCU's two stamps."""
        x_rx = self._x(rx_us)
        if self._behind(x_rx):
            if self._backjumps < self.BACKJUMPS_TO_RESET:
                return
            self._restart_after_jump()
            x_rx = self._x(rx_us)
        x_tx = self._x(tx_us)
        if x_tx < x_rx or t_recv < t_send:
            log.debug("discarding inconsistent round trip")
            return
        lo = t_send + self.request_wire_s
        hi = t_recv - self.reply_wire_s
        if hi < lo:  # faster than the wire allows (a pty, a USB board): use the raw bounds
            lo, hi = t_send, t_recv
            self.fast_round_trips += 1
        newest = (x_rx + x_tx) / 2
        self._syncs.append(_Sync(newest, (lo + hi) / 2, x_tx - x_rx, lo, hi))
        while self._syncs[0].x < newest - self.window_s:
            self._syncs.popleft()
        self._dirty = True

    def add_oneway(self, t_arrival: float, event_us: int) -> None:
        """A frame read at t_arrival that the MCU sent just after event_us (an echo's end)."""
        x = self._x(event_us)
        if self._behind(x):
            if self._backjumps < self.BACKJUMPS_TO_RESET:
                return
            self._restart_after_jump()
            x = self._x(event_us)
        self._oneway.append((x, t_arrival))
        while self._oneway[0][0] < x - self.window_s:
            self._oneway.popleft()
        self._dirty = True

    # ------------------------------------------------------------------ estimate
    @property
    def ready(self) -> bool:
        return bool(self._syncs or len(self._oneway) >= 2)

    def estimate(self) -> ClockEstimate | None:
        if self._dirty:
            self._estimate = self._solve()
            self._dirty = False
        return self._estimate

    def to_host(self, mcu_us: int) -> float | None:
        """Host monotonic seconds for an MCU microsecond stamp (raw 32-bit), or None if unknown."""
        est = self.estimate()
        if est is None or self._ref_us is None:
            return None
        return est.map_us(self.unwrap(mcu_us))

    def _hull_line(self) -> tuple[float, float] | None:
        pts = sorted(self._oneway)
        if len(pts) < 8 or pts[-1][0] - pts[0][0] < self.min_hull_span_s:
            return None
        hull = _lower_hull(pts)
        mean_x = sum(p[0] for p in pts) / len(pts)
        for (x1, y1), (x2, y2) in zip(hull, hull[1:], strict=False):
            if x1 <= mean_x <= x2 and x2 > x1:
                slope = (y2 - y1) / (x2 - x1)
                return slope, y1 - slope * x1
        return None

    def _best_syncs(self) -> list[_Sync]:
        """The round trip with the least slack in each second, minus the poor ones."""
        buckets: dict[int, _Sync] = {}
        for s in self._syncs:
            key = math.floor(s.x)
            best = buckets.get(key)
            if best is None or (s.hi - s.lo) < (best.hi - best.lo):
                buckets[key] = s
        chosen = sorted(buckets.values(), key=lambda s: s.x)
        if not chosen:
            return chosen
        widths = sorted(s.hi - s.lo for s in chosen)
        limit = 2.0 * widths[len(widths) // 2] + 2e-4
        return [s for s in chosen if s.hi - s.lo <= limit]

    def _solve(self) -> ClockEstimate | None:
        if self._ref_us is None:
            return None
        syncs = self._best_syncs()
        hull = self._hull_line()
        slope: float | None = None
        if hull is not None:
            slope = hull[0]
        elif len(syncs) >= 3 and syncs[-1].x - syncs[0].x >= 1.0:
            n = len(syncs)
            mx = sum(s.x for s in syncs) / n
            my = sum(s.y for s in syncs) / n
            sxx = sum((s.x - mx) ** 2 for s in syncs)
            slope = sum((s.x - mx) * (s.y - my) for s in syncs) / sxx
        if slope is None or not 0.9 < slope < 1.1:
            slope = 1.0  # no drift evidence yet (or nonsense): assume none
        if syncs:
            halves = [max((s.hi - s.lo - slope * s.span_mcu) / 2, 0.0) for s in syncs]
            offsets = [s.y - slope * s.x for s in syncs]
            # A weighted median: one impossible round trip (faster than the wire, as when a
            # board or emulator was still starting) cannot drag the line; the floor keeps a
            # lucky near-zero slack from taking all the weight.
            floor = max(sorted(halves)[len(halves) // 2] * 0.5, 1e-4)
            weights = [1.0 / (h + floor) ** 2 for h in halves]
            offset = _weighted_median(offsets, weights)
            wsum = sum(weights)
            spread = math.sqrt(
                sum(w * (o - offset) ** 2 for w, o in zip(weights, offsets, strict=True)) / wsum
            )
            best_half = min(max((s.hi - s.lo) / 2, 0.0) for s in syncs)
            uncertainty = math.hypot(spread, best_half / math.sqrt(3.0))
            min_delay = hull[1] - offset if hull is not None else None
            return ClockEstimate(
                slope=slope,
                offset_s=offset,
                ref_us=self._ref_us,
                uncertainty_s=uncertainty,
                source="sync+oneway" if hull is not None else "sync",
                n_sync=len(self._syncs),
                n_oneway=len(self._oneway),
                min_oneway_delay_s=min_delay,
            )
        if len(self._oneway) >= 2:
            if hull is not None:
                base = hull[1]
            else:
                base = min(y - slope * x for x, y in self._oneway)
            offset = base - self.range_wire_s - self.oneway_extra_latency_s
            return ClockEstimate(
                slope=slope,
                offset_s=offset,
                ref_us=self._ref_us,
                # Nothing bounds the delay from below but the wire: say so with a wide band.
                uncertainty_s=max(self.range_wire_s, 1e-3),
                source="oneway",
                n_sync=0,
                n_oneway=len(self._oneway),
                min_oneway_delay_s=None,
            )
        return None
