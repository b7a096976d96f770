#!/usr/bin/env python3
"""End-to-end latency and sustained frame rate of `obstacle-fusion run` on the emulated robot.

The whole host pipeline runs as in production: the real firmware under simavr (wall-clock
paced) -> pty -> link thread -> clock model -> sonar conversion -> pairing -> fused
measurement -> JSON lines (to /dev/null) and an MCAP recording. The only change is the
camera: the scenario's frames are rendered before the run (rendering is the synthetic
camera's cost, not the host's), and the source hands out the frame of the current scene
instant at the requested rate, stamped with its capture time.

Latency = obstacle record published - frame captured (host monotonic). Pairing modes:
"predicted" (the default: each frame at once, with the range a constant-velocity filter
predicts for its instant), "interpolated" (each frame waits for the sonar reading after
it), and "no wait" (interpolated pairing with max wait 0: the nearest reading at once).
For predicted records the range the interpolation between the readings around the frame
gives (computed afterwards from every reading) is the reference: the p95 of
|predicted - interpolated|, over frames at least 0.15 s from a step of the scene (a new
obstacle), at constant approach speeds of 0.3, 0.6 and 1.0 m/s (a saw-tooth scene: the
box comes from 3.0 m to 0.8 m at that speed, then the next one appears at 3.0 m).
Sustained rate = records published per second with the source asking for more than the
host can take (frames it cannot take are dropped at the source, counted).

Usage: .venv/bin/python tools/bench_e2e.py [--seconds 10]
"""

from __future__ import annotations

import argparse
import io
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from obstacle_fusion.app import App, RunSettings
from obstacle_fusion.fusion import PairKind, RangePairer
from obstacle_fusion.link.connection import Link
from obstacle_fusion.outputs.jsonl import JsonLinesWriter
from obstacle_fusion.outputs.mcap_file import McapRecorder
from obstacle_fusion.sim.emulated_robot import EmulatedRobot
from obstacle_fusion.sim.scenario import BOX_A, BOX_B, Scenario, Segment, demo_scenario
from obstacle_fusion.sim.scene import renderer_for
from obstacle_fusion.sim.synthetic_camera import SyntheticCamera, synthetic_camera_model
from obstacle_fusion.sources.frames import Frame, FrameSource
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.rig import Rig


class PrerenderedScenario(FrameSource):
    """The scenario's frames rendered ahead on a grid of scene times, served live."""

    def __init__(self, robot: EmulatedRobot, width: int, height: int, seconds: float) -> None:
        # Rendered for every scene instant the run can reach (it starts a few seconds in).
        super().__init__(f"prerendered:{width}x{height}")
        self.robot = robot
        self.step = 1.0 / 15.0
        camera = synthetic_camera_model(width, height)
        cam = SyntheticCamera(robot.scenario, camera, Rig(), realtime=False)
        renderer = renderer_for(camera, Rig(), 2)
        rng = np.random.default_rng(1)
        n = int((seconds + 6.0) / self.step)
        self.images = [renderer.render(cam.spec_at(k * self.step), rng).image for k in range(n)]
        self.camera = camera
        self.frame_size = (width, height)
        self.fps = 15.0
        self._next = 0.0
        self._k = 0

    def _capture(self) -> Frame | None:
        now = time.monotonic()
        if self._next > now:
            time.sleep(self._next - now)
        elif now - self._next > 1.0 / self.fps:
            self._next = now  # behind (the host could not take more): no burst
        t = self._next
        self._next = t + 1.0 / self.fps
        scene_t = self.robot.scene_time(t) or 0.0
        k = min(max(int(round(scene_t / self.step)), 0), len(self.images) - 1)
        self._k += 1
        return self._frame(self.images[k], t, self._k)


def sawtooth(speed: float, seconds: float, far: float = 3.0, near: float = 0.8) -> Scenario:
    """Boxes approaching at ``speed`` m/s from ``far`` to ``near``, one after the other."""
    ramp = (far - near) / speed
    segs = []
    t = 0.0
    k = 0
    while t < seconds:
        segs.append(Segment(t, t + ramp, BOX_A if k % 2 == 0 else BOX_B, far, near))
        t += ramp
        k += 1
    return Scenario(tuple(segs), 20.0, f"sawtooth-{speed:g}")


def q(values: list[float], p: float) -> float:
    v = sorted(values)
    return v[int(p * (len(v) - 1))] if v else float("nan")


def run_once(
    width: int,
    height: int,
    fps: float,
    seconds: float,
    pairing: str = "predicted",
    max_wait_s: float = 0.25,
    scenario: Scenario | None = None,
) -> dict:
    scenario = scenario or demo_scenario()
    robot = EmulatedRobot(scenario).start()
    try:
        source = PrerenderedScenario(robot, width, height, seconds)
        source.fps = fps
        with tempfile.TemporaryDirectory() as tmp:
            recorder = McapRecorder(Path(tmp) / "bench.mcap")
            app = App(
                RunSettings(
                    duration_s=seconds, max_wait_s=max_wait_s, mode="bench", pairing=pairing
                ),
                Link(robot.port),
                source,
                Measurer(source.camera, Rig(), "fused"),
                jsonl=JsonLinesWriter(io.StringIO()),
                recorder=recorder,
                robot=robot,
            )
            records: list = []
            publish = app._publish
            reference = RangePairer(history_s=1e9)
            add_reading = app.fusion.add_reading

            def keep(batch: list) -> None:
                records.extend(batch)
                publish(batch)

            def also_keep(reading):  # type: ignore[no-untyped-def]
                reference.add(reading)
                return add_reading(reading)

            app._publish = keep  # type: ignore[method-assign,assignment]
            app.fusion.add_reading = also_keep  # type: ignore[method-assign]
            t0 = time.monotonic()
            result = app.run()
            wall = time.monotonic() - t0
            recorder.close()
    finally:
        robot.stop()
    steps = [seg.t0 for seg in scenario.segments[1:]]
    diffs: list[float] = []
    truth_err: list[float] = []
    excluded = 0
    for r in records:
        if r.pairing != "predicted" or r.distance_m is None:
            continue
        scene_t = robot.scene_time(r.t_host)
        if scene_t is None or any(abs(scene_t - b) < 0.15 for b in steps):
            excluded += 1
            continue
        ref = reference.pair(r.t_host)
        if ref.kind is not PairKind.INTERPOLATED or ref.distance_m is None:
            excluded += 1
            continue
        diffs.append(abs(r.distance_m - ref.distance_m))
        truth = scenario.distance_at(scene_t)
        if truth is not None:
            truth_err.append(abs(r.distance_m - truth))
    lat = [r.latency_s for r in records if r.latency_s is not None]
    vision = [r.vision_ms for r in records if r.vision_ms is not None]
    span = records[-1].t_host - records[0].t_host if len(records) > 1 else wall
    fusion = result.stats["fusion"]
    return {
        "records": len(records),
        "rate": (len(records) - 1) / span if span > 0 else 0.0,
        "lat_p50_ms": 1e3 * statistics.median(lat),
        "lat_p95_ms": 1e3 * q(lat, 0.95),
        "vision_p50_ms": statistics.median(vision) if vision else float("nan"),
        "dropped": result.stats["frames_dropped"],
        "paired": fusion["paired_fraction"],
        "predicted": fusion["predicted"] / max(fusion["published"], 1),
        "measured": fusion["detected"],
        "diff_p95_mm": 1e3 * q(diffs, 0.95),
        "diff_max_mm": 1e3 * max(diffs) if diffs else float("nan"),
        "truth_p95_mm": 1e3 * q(truth_err, 0.95),
        "compared": len(diffs),
        "excluded": excluded,
    }


def _line(res: str, label: str, r: dict) -> str:
    return (
        f"{res:<9} {label:<34} records {r['records']:4d}  rate {r['rate']:6.1f}/s  latency p50 "
        f"{r['lat_p50_ms']:6.1f} ms  p95 {r['lat_p95_ms']:6.1f} ms  vision p50 "
        f"{r['vision_p50_ms']:5.2f} ms  dropped {r['dropped']:4d}  paired "
        f"{100 * r['paired']:5.1f}%  predicted {100 * r['predicted']:5.1f}%"
    )


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--quick", action="store_true", help="500x375 only, no sustained rows")
    args = ap.parse_args()
    rows = []
    sizes = ((500, 375),) if args.quick else ((500, 375), (1280, 720))
    for width, height in sizes:
        modes = [
            ("15 fps, predicted (default)", 15.0, "predicted", 0.25),
            ("15 fps, interpolated (waits)", 15.0, "interpolated", 0.25),
            ("15 fps, no wait (nearest)", 15.0, "interpolated", 0.0),
        ]
        if not args.quick:
            modes.append(("sustained (source asks 120 fps)", 120.0, "predicted", 0.25))
        for label, fps, pairing, wait in modes:
            r = run_once(width, height, fps, args.seconds, pairing, wait)
            rows.append((f"{width}x{height}", label, r))
            print(_line(f"{width}x{height}", label, r), flush=True)
    speed_rows = []
    for speed in (0.3, 0.6, 1.0):
        r = run_once(500, 375, 15.0, args.seconds, scenario=sawtooth(speed, args.seconds + 10.0))
        speed_rows.append((speed, r))
        print(
            _line("500x375", f"{speed:g} m/s saw-tooth, predicted", r)
            + f"  |pred-interp| p95 {r['diff_p95_mm']:.2f} mm max {r['diff_max_mm']:.2f} mm"
            f" ({r['compared']} frames, {r['excluded']} near steps); |pred-truth| p95 "
            f"{r['truth_p95_mm']:.2f} mm",
            flush=True,
        )
    print()
    print(
        "| resolution | mode | frames/s | latency median | latency p95 | paired | vision median |"
    )
    print("|---|---|---|---|---|---|---|")
    for res, label, r in rows:
        print(
            f"| {res} | {label} | {r['rate']:.1f} | {r['lat_p50_ms']:.1f} ms | "
            f"{r['lat_p95_ms']:.1f} ms | {100 * r['paired']:.1f} % | {r['vision_p50_ms']:.2f} ms |"
        )
    print()
    print(
        "| approach speed | latency median / p95 | paired | predicted "
        "| \\|predicted - interpolated\\| p95 (max) | \\|predicted - truth\\| p95 |"
    )
    print("|---|---|---|---|---|---|")
    for speed, r in speed_rows:
        print(
            f"| {speed:g} m/s | {r['lat_p50_ms']:.1f} / {r['lat_p95_ms']:.1f} ms | "
            f"{100 * r['paired']:.1f} % | {100 * r['predicted']:.1f} % | "
            f"{r['diff_p95_mm']:.2f} mm ({r['diff_max_mm']:.2f} mm) | {r['truth_p95_mm']:.2f} mm |"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
