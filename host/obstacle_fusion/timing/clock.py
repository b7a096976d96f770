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


# ClockEstimate's fields in order: slope, offset_s, ref_us, uncertainty_s, source, n_sync,
# n_oneway, min_oneway_delay_s.
_Params = tuple[float, float, int, float, str, int, int, float | None]


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


class WindowHull:
    """The lower convex hull of a sliding window of points whose x only grows: points come
    in on the right and leave on the left, amortised O(1) each, and ``segment_at`` finds the
    hull's edge above an x in O(log n) plus a short walk.

    A queue made of two stacks: the back stack's hull is the monotone chain of the points
    appended since the last move (no point ever leaves it); when the front runs out, the back
    moves to the front, whose hull is built from the right with an undo record per point, so
    removing its leftmost point restores the hull of the rest exactly. The window's hull is
    the front's hull, the bridge between the two (a common tangent, found by walking from the
    last one), and the back's hull. Same vertices as ``_lower_hull`` of the sorted points.
    """

    MAX_WALK = 10_000  # a safety net for the bridge walk; never reached on a convex chain

    def __init__(self) -> None:
        self.clear()

    def clear(self) -> None:
        self._front: list[tuple[float, float]] = []
        self._fpos = 0  # the first point of _front still in the window
        self._fstack: list[tuple[float, float]] = []  # rightmost vertex at 0, leftmost on top
        self._fn = 0  # live length of _fstack (entries above are kept for the undo)
        self._undo: list[tuple[int, tuple[float, float] | None, int]] = []
        self._back: list[tuple[float, float]] = []
        self._bhull: list[tuple[float, float]] = []
        self._u = 0  # the bridge's ends at the last query: index into the front's chain
        self._v = 0  # and into the back's hull

    def __len__(self) -> int:
        return len(self._front) - self._fpos + len(self._back)

    def append(self, p: tuple[float, float]) -> None:
        """Add a point to the right of every point in the window."""
        self._back.append(p)
        hull = self._bhull
        px, py = p
        while len(hull) >= 2:
            (x1, y1), (x2, y2) = hull[-2], hull[-1]
            if (x2 - x1) * (py - y1) - (y2 - y1) * (px - x1) <= 0:
                hull.pop()
            else:
                break
        hull.append(p)

    def popleft(self) -> None:
        """Remove the leftmost point of the window."""
        if self._fpos == len(self._front):
            self._move_back_to_front()
        if self._fpos == len(self._front):
            return
        k, old, old_n = self._undo[self._fpos]
        stack = self._fstack
        if old is None:
            stack.pop()
        else:
            stack[k] = old
        self._fn = old_n
        self._fpos += 1

    def _move_back_to_front(self) -> None:
        pts = self._back
        stack: list[tuple[float, float]] = []
        undo: list[tuple[int, tuple[float, float] | None, int]] = [(0, None, 0)] * len(pts)
        n = 0
        for i in range(len(pts) - 1, -1, -1):
            before = n
            ax, ay = pts[i]
            # Pop (logically) the vertices that the new left point puts on or above the chain.
            while n >= 2:
                bx, by = stack[n - 1]
                cx, cy = stack[n - 2]
                if (bx - ax) * (cy - ay) - (by - ay) * (cx - ax) <= 0:
                    n -= 1
                else:
                    break
            if n == len(stack):
                undo[i] = (n, None, before)
                stack.append(pts[i])
            else:
                undo[i] = (n, stack[n], before)
                stack[n] = pts[i]
            n += 1
        self._front = pts
        self._fpos = 0
        self._fstack = stack
        self._fn = n
        self._undo = undo
        self._back = []
        self._bhull = []
        self._u = self._v = 0

    def segment_at(self, m: float) -> tuple[tuple[float, float], tuple[float, float]] | None:
        """The hull edge (left vertex, right vertex) over x = m: the first edge whose right
        end is at or beyond m, as ``ClockModel`` reads the sorted hull."""
        stack, fn, back = self._fstack, self._fn, self._bhull
        nb = len(back)
        if fn == 0:
            return _first_reaching(back, 0, nb, m)
        if nb == 0:
            return _first_reaching_rev(stack, fn, 0, fn, m)
        u, v = self._bridge()
        ux = stack[fn - 1 - u][0]
        if m <= ux:
            seg = _first_reaching_rev(stack, fn, 0, u + 1, m)
            if seg is not None:
                return seg
        if m <= back[v][0]:
            return stack[fn - 1 - u], back[v]
        return _first_reaching(back, v, nb, m)

    def _bridge(self) -> tuple[int, int]:
        """The lower common tangent of the front's and the back's hulls (front chain index,
        back hull index): every point of both lies on or above the line through them."""
        stack, fn, back = self._fstack, self._fn, self._bhull
        nb = len(back)
        u = min(self._u, fn - 1)
        v = min(self._v, nb - 1)
        for _ in range(self.MAX_WALK):
            moved = False
            ux, uy = stack[fn - 1 - u]
            # v: the back vertex of least slope seen from u (the rightmost of equals).
            vx, vy = back[v]
            while v + 1 < nb:
                wx, wy = back[v + 1]
                if (wy - uy) * (vx - ux) <= (vy - uy) * (wx - ux):
                    v += 1
                    vx, vy = wx, wy
                    moved = True
                else:
                    break
            while v > 0:
                wx, wy = back[v - 1]
                if (wy - uy) * (vx - ux) < (vy - uy) * (wx - ux):
                    v -= 1
                    vx, vy = wx, wy
                    moved = True
                else:
                    break
            # u: the front vertex of greatest slope towards v (the leftmost of equals).
            while u > 0:
                wx, wy = stack[fn - u]  # chain index u - 1
                if (vy - wy) * (vx - ux) >= (vy - uy) * (vx - wx):
                    u -= 1
                    ux, uy = wx, wy
                    moved = True
                else:
                    break
            while u + 1 < fn:
                wx, wy = stack[fn - 2 - u]  # chain index u + 1
                if (vy - wy) * (vx - ux) > (vy - uy) * (vx - wx):
                    u += 1
                    ux, uy = wx, wy
                    moved = True
                else:
                    break
            if not moved:
                break
        self._u, self._v = u, v
        return u, v


def _first_reaching(
    chain: list[tuple[float, float]], lo: int, hi: int, m: float
) -> tuple[tuple[float, float], tuple[float, float]] | None:
    """Edge (chain[j-1], chain[j]) for the least j in (lo, hi) with chain[j].x >= m."""
    a, b = lo + 1, hi
    while a < b:
        mid = (a + b) // 2
        if chain[mid][0] >= m:
            b = mid
        else:
            a = mid + 1
    if a >= hi:
        return None
    return chain[a - 1], chain[a]


def _first_reaching_rev(
    stack: list[tuple[float, float]], fn: int, lo: int, hi: int, m: float
) -> tuple[tuple[float, float], tuple[float, float]] | None:
    """As _first_reaching over the chain stack[fn-1], stack[fn-2], ... (left to right)."""
    a, b = lo + 1, hi
    while a < b:
        mid = (a + b) // 2
        if stack[fn - 1 - mid][0] >= m:
            b = mid
        else:
            a = mid + 1
    if a >= hi:
        return None
    return stack[fn - a], stack[fn - 1 - a]


def _weighted_median(values: list[float], weights: list[float]) -> float:
    pairs = sorted(zip(values, weights, strict=True))
    half = sum(weights) / 2.0
    acc = 0.0
    for value, weight in pairs:
        acc += weight
        if acc >= half:
            return value
    return pairs[-1][0]


def _sync_offset(syncs: list[_Sync], slope: float) -> tuple[float, float]:
    """The round trips' offset for this slope, and how sure it is."""
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
    return offset, math.hypot(spread, best_half / math.sqrt(3.0))


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
        self._params: _Params | None = None  # ClockEstimate's fields, built into one on demand
        self._dirty = False
        # The one-way window's hull, kept as points come and go (see WindowHull), with the
        # sum of their x in whole microseconds for the mean. It holds while the window's x
        # strictly grow; a stamp out of order (count below) falls back to sorting.
        self._hull = WindowHull()
        self._oneway_us: deque[int] = deque()  # the window's x in whole microseconds
        self._sum_us = 0
        self._inversions = 0
        self._hull_stale = False
        # The round trips' part of the solution, kept until a round trip comes or the slope
        # changes (the hull's edge over the window's middle moves only now and then).
        self._sync_version = 0
        self._best_cache: tuple[int, list[_Sync]] | None = None
        self._sync_cache: tuple[int, float, float, float] | None = None

    BACKJUMPS_TO_RESET = 3

    def reset(self) -> None:
        self._backjumps = 0
        self.unwrap.reset()
        self._ref_us = None
        self._syncs.clear()
        self._oneway.clear()
        self._estimate = None
        self._params = None
        self._dirty = False
        self._hull.clear()
        self._oneway_us.clear()
        self._sum_us = 0
        self._inversions = 0
        self._hull_stale = False
        self._sync_version += 1
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
        self._sync_version += 1
        self._dirty = True

    def add_oneway(self, t_arrival: float, event_us: int) -> None:
        """A frame read at t_arrival that the MCU sent just after event_us (an echo's end)."""
        value = self.unwrap(event_us)
        if self._ref_us is None:
            self._ref_us = value
        rel_us = value - self._ref_us
        x = rel_us * 1e-6
        if self._behind(x):
            if self._backjumps < self.BACKJUMPS_TO_RESET:
                return
            self._restart_after_jump()
            x = self._x(event_us)
            rel_us = 0
        oneway = self._oneway
        point = (x, t_arrival)
        if oneway and x <= oneway[-1][0]:
            self._inversions += 1
            self._hull_stale = True
        oneway.append(point)
        self._oneway_us.append(rel_us)
        self._sum_us += rel_us
        stale = self._hull_stale
        if not stale:
            self._hull.append(point)
        while oneway[0][0] < x - self.window_s:
            old = oneway.popleft()
            self._sum_us -= self._oneway_us.popleft()
            if oneway[0][0] <= old[0]:
                self._inversions -= 1
            if not stale:
                self._hull.popleft()
        self._dirty = True

    # ------------------------------------------------------------------ estimate
    @property
    def ready(self) -> bool:
        return bool(self._syncs or len(self._oneway) >= 2)

    def estimate(self) -> ClockEstimate | None:
        if self._dirty:
            self._params = self._solve()
            self._dirty = False
            self._estimate = None
        if self._estimate is None and self._params is not None:
            self._estimate = ClockEstimate(*self._params)
        return self._estimate

    def to_host(self, mcu_us: int) -> float | None:
        """Host monotonic seconds for an MCU microsecond stamp (raw 32-bit), or None if unknown."""
        if self._dirty:
            self._params = self._solve()
            self._dirty = False
            self._estimate = None
        p = self._params
        if p is None or self._ref_us is None:
            return None
        # ClockEstimate.map_us, without building the estimate at every RANGE.
        return p[1] + p[0] * (self.unwrap(mcu_us) - p[2]) * 1e-6

    def _hull_line(self) -> tuple[float, float] | None:
        """The lower hull's edge over the window's mean x: (slope, intercept)."""
        oneway = self._oneway
        if self._inversions:
            return self._hull_line_sorted()
        n = len(oneway)
        if n < 8 or oneway[-1][0] - oneway[0][0] < self.min_hull_span_s:
            return None
        if self._hull_stale:  # the window is in order again: rebuild the hull once
            self._hull.clear()
            for point in oneway:
                self._hull.append(point)
            self._hull_stale = False
        seg = self._hull.segment_at(self._sum_us / n * 1e-6)
        if seg is None:
            return None
        (x1, y1), (x2, y2) = seg
        slope = (y2 - y1) / (x2 - x1)
        return slope, y1 - slope * x1

    def _hull_line_sorted(self) -> tuple[float, float] | None:
        """The same from scratch: sort the window, build the hull (stamps out of order)."""
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
        cache = self._best_cache
        if cache is not None and cache[0] == self._sync_version:
            return cache[1]
        best = self._select_syncs()
        self._best_cache = (self._sync_version, best)
        return best

    def _select_syncs(self) -> list[_Sync]:
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

    def _solve(self) -> _Params | None:
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
            cached = self._sync_cache
            if cached is not None and cached[0] == self._sync_version and cached[1] == slope:
                offset, uncertainty = cached[2], cached[3]
            else:
                offset, uncertainty = _sync_offset(syncs, slope)
                self._sync_cache = (self._sync_version, slope, offset, uncertainty)
            min_delay = hull[1] - offset if hull is not None else None
            return (
                slope,
                offset,
                self._ref_us,
                uncertainty,
                "sync+oneway" if hull is not None else "sync",
                len(self._syncs),
                len(self._oneway),
                min_delay,
            )
        if len(self._oneway) >= 2:
            if hull is not None:
                base = hull[1]
            else:
                base = min(y - slope * x for x, y in self._oneway)
            offset = base - self.range_wire_s - self.oneway_extra_latency_s
            # Nothing bounds the delay from below but the wire: say so with a wide band.
            uncertainty = max(self.range_wire_s, 1e-3)
            return (slope, offset, self._ref_us, uncertainty, "oneway", 0, len(self._oneway), None)
        return None
