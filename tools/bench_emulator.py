#!/usr/bin/env python3
"""Benchmark the firmware emulator: speed in fast mode and echo-timing error.

Prints
- simulated seconds per wall second in fast mode, the real Uno firmware ranging at its
  default 60 ms cycle (idle between measurements) while a host reads every frame
  (target: at least 5x real time), and the same for a firmware that never sleeps;
- real-time pacing (should be 1.000);
- the echo-timing error in timer ticks, RANGE.echo_ticks minus the truth log's width, over
  many measurements spread across 0.02..4 m.

Usage: .venv/bin/python tools/bench_emulator.py [--measurements N] [--seconds S]
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import tempfile
import time
from pathlib import Path

import serial
from obstacle_fusion.protocol import StreamDecoder
from obstacle_fusion.protocol.generated import Range
from obstacle_fusion.sim.emulator import (
    REPO_ROOT,
    Emulator,
    EmulatorConfig,
    check_built,
    firmware_elf,
)

TARGET_SPEED = 5.0


def drain(port: serial.Serial, decoder: StreamDecoder, seconds: float) -> list[Range]:
    """Read the port like a host for `seconds` of wall time; return RANGE frames."""
    out: list[Range] = []
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        data = port.read(port.in_waiting or 1)
        if data:
            out.extend(m for m in decoder.feed(data) if isinstance(m, Range))
    return out


def speed(elf: Path, seconds: float, fast: bool) -> float:
    """Simulated seconds per wall second, measured after start-up."""
    with Emulator(config=EmulatorConfig(elf=elf, fast=fast, distance_m=1.0)) as emu:
        port = serial.Serial(emu.pty_path, 115200, timeout=0.01)
        try:
            dec = StreamDecoder()
            drain(port, dec, 0.3)
            s0, w0 = emu.control.sim_time(), time.monotonic()
            drain(port, dec, seconds)
            s1, w1 = emu.control.sim_time(), time.monotonic()
        finally:
            port.close()
    return (s1 - s0) / (w1 - w0)


def timing_error(elf: Path, measurements: int) -> tuple[list[float], int]:
    """echo_ticks - truth over a distance sweep; also returns frames lost (seq gaps)."""
    with tempfile.TemporaryDirectory() as tmp:
        scene = Path(tmp) / "sweep.txt"
        # A saw-tooth over the whole range, so widths take every phase against the timer.
        period_s = 0.06 * 97
        lines = []
        t = 0.0
        while t < measurements * 0.06 + 1.0:
            lines += [f"{t:.3f} 0.02", f"{t + period_s - 0.001:.3f} 4.0"]
            t += period_s
        scene.write_text("\n".join(lines) + "\n")
        with Emulator(config=EmulatorConfig(elf=elf, fast=True, scene=scene)) as emu:
            port = serial.Serial(emu.pty_path, 115200, timeout=0.01)
            dec = StreamDecoder()
            ranges: list[Range] = []
            deadline = time.monotonic() + 120.0
            try:
                while len(ranges) < measurements and time.monotonic() < deadline:
                    ranges.extend(drain(port, dec, 0.1))
            finally:
                port.close()
            time.sleep(0.1)
            truth = sorted(emu.truth.read(), key=lambda r: r.trigger_s)
    if not ranges or not truth:
        raise SystemExit("bench_emulator: no measurements arrived; is the firmware ranging?")
    offset = ranges[0].trigger_us - truth[0].trigger_s * 1e6
    starts = [r.trigger_s * 1e6 + offset for r in truth]
    errors = []
    j = 0
    for r in ranges:

        def miss(k: int, r: Range = r) -> float:
            return abs(starts[k] - r.trigger_us)

        while j + 1 < len(truth) and miss(j + 1) < miss(j):
            j += 1
        if miss(j) > 4 or truth[j].echo_distance_m is None:
            continue
        errors.append(r.echo_ticks - truth[j].echo_ticks)
    return errors, dec.stats.seq_gaps


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--measurements", type=int, default=1000)
    parser.add_argument("--seconds", type=float, default=3.0, help="wall time per speed run")
    args = parser.parse_args()
    elf, _ = check_built(firmware_elf())
    busy = REPO_ROOT / "tools" / "emulator" / "build" / "testfw" / "quirks_test.elf"

    fast = speed(elf, args.seconds, fast=True)
    real = speed(elf, min(args.seconds, 2.0), fast=False)
    busy_fast = speed(busy, args.seconds, fast=True) if busy.is_file() else math.nan
    errors, gaps = timing_error(elf, args.measurements)
    abs_err = [abs(e) for e in errors]

    print("emulator benchmark (of-emulator, simavr 1.6, Uno firmware)")
    print(f"  firmware: {elf.relative_to(REPO_ROOT) if elf.is_relative_to(REPO_ROOT) else elf}")
    print(
        f"  fast mode, firmware ranging every 60 ms : {fast:8.1f} x real time "
        f"(target >= {TARGET_SPEED:.0f}x: {'met' if fast >= TARGET_SPEED else 'NOT met'})"
    )
    print(f"  fast mode, firmware never sleeping      : {busy_fast:8.1f} x real time")
    print(f"  real-time mode                          : {real:8.3f} x real time")
    print(
        f"  echo timing over {len(errors)} measurements, 0.02..4 m "
        f"(RANGE.echo_ticks - truth, 0.5 us ticks):"
    )
    print(
        f"    max |error| {max(abs_err):.3f} ticks, mean {statistics.fmean(errors):+.3f}, "
        f"rms {math.sqrt(statistics.fmean(e * e for e in errors)):.3f}; "
        f"within 1 tick: {sum(a <= 1.0 for a in abs_err)}/{len(errors)}; "
        f"frames lost: {gaps}"
    )
    ok = fast >= TARGET_SPEED and max(abs_err) <= 1.0 and gaps == 0
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
