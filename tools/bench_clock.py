#!/usr/bin/env python3
"""Clock model cost per RANGE, sustained: RANGE frames at 16, 200 and 1,000 per second with
TIME_SYNC round trips at 5 Hz over a jittery simulated link (in order, 1 Mbit/s: a UART
at 115200 carries at most ~570 RANGE/s), fed as the app feeds them (each
RANGE added, then its trigger mapped). The first 35 s fill the 30 s window; the next
--measure-s seconds are timed (every add_sync, add_oneway and to_host call), divided by the
RANGE count. Target: <= 20 us per RANGE at 1,000 RANGE/s.

--reference also times the model as it was (the window sorted and its hull rebuilt at each
solve) for comparison.
"""

from __future__ import annotations

import argparse
import random
import time

from obstacle_fusion.timing.clock import ClockModel

Event = tuple[float, int, int, int, int]  # (arrival, kind 0 sync / 1 range, a, b, c)


class ReferenceModel(ClockModel):
    def _hull_line(self) -> tuple[float, float] | None:
        return self._hull_line_sorted()


def make_events(
    rate_hz: float, duration_s: float, ppm: float = 3000.0, seed: int = 1
) -> list[Event]:
    rng = random.Random(seed)
    scale = 1 + ppm * 1e-6
    host0, mcu0 = 1000.0, 50_000_000
    events: list[Event] = []
    k = 0
    last = 0.0
    while (t := k / rate_hz) < duration_s:
        trig = mcu0 + int(t * 1e6 * scale)
        end = trig + 450 + int(rng.uniform(0.05, 0.8) / rate_hz * 1e6)  # echo within the cycle
        arrival = host0 + (end - mcu0) / 1e6 / scale + 0.0017 + rng.expovariate(1000.0)
        arrival = last = max(arrival, last + 20 * 10 / 1e6)  # a link keeps order (USB, 1 Mbit/s)
        events.append((arrival, 1, trig & 0xFFFFFFFF, end & 0xFFFFFFFF, 0))
        k += 1
    t = 0.01
    while t < duration_s:
        t1 = host0 + t
        rx = mcu0 + int((t + 0.0009 + rng.expovariate(2000.0)) * 1e6 * scale)
        tx = rx + rng.randrange(40, 300)
        t4 = host0 + (tx - mcu0) / 1e6 / scale + 0.0016 + rng.expovariate(2000.0)
        events.append((t4, 0, int(t1 * 1e6), rx & 0xFFFFFFFF, tx & 0xFFFFFFFF))
        t += 0.2
    events.sort()
    return events


def run(model: ClockModel, events: list[Event], warm_s: float) -> tuple[float, int]:
    """Seconds spent in the model after warm_s, and the RANGE count in that span."""
    t0 = events[0][0] + warm_s
    spent = 0.0
    ranges = 0
    clock = time.perf_counter
    for arrival, kind, a, b, c in events:
        start = clock()
        if kind == 0:
            model.add_sync(a * 1e-6, arrival, b, c)
        else:
            model.add_oneway(arrival, b)
            model.to_host(a)
        if arrival >= t0:
            spent += clock() - start
            ranges += kind
    return spent, ranges


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rates", default="16,200,1000", help="RANGE/s, comma-separated")
    parser.add_argument("--measure-s", type=float, default=10.0)
    parser.add_argument("--reference", action="store_true", help="also time the old model")
    args = parser.parse_args()
    warm = 35.0
    print(
        f"clock model, us per RANGE sustained (window full, {args.measure_s:.0f} s timed, "
        "TIME_SYNC at 5 Hz included)"
    )
    header = f"{'RANGE/s':>8} {'us/RANGE':>9}"
    if args.reference:
        header += f" {'reference us/RANGE':>19}"
    print(header)
    for rate in (float(r) for r in args.rates.split(",")):
        events = make_events(rate, warm + args.measure_s)
        spent, n = run(ClockModel(), events, warm)
        line = f"{rate:>8.0f} {spent / n * 1e6:>9.1f}"
        if args.reference:
            ref_spent, ref_n = run(ReferenceModel(), events, warm)
            line += f" {ref_spent / ref_n * 1e6:>19.1f}"
        print(line, flush=True)


if __name__ == "__main__":
    main()
