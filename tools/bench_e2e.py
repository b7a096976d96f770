#!/usr/bin/env python3
"""End-to-end latency and sustained frame rate of `obstacle-fusion run` on the emulated robot.

The whole host pipeline runs as in production: the real firmware under simavr (wall-clock
paced) -> pty -> link thread -> clock model -> sonar conversion -> pairing -> fused
measurement -> JSON lines (to /dev/null) and an MCAP recording. The only change is the
camera: the scenario's frames are rendered before the run (rendering is the synthetic
camera's cost, not the host's), and the source hands out the frame of the current scene
instant at the requested rate, stamped with its capture time.

Latency = obstacle record published - frame captured (host monotonic), which includes the
wait for the sonar reading *after* the frame (interpolated pairing, the default). The
"no wait" rows pair with the nearest reading at once instead (max wait 0).
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
from obstacle_fusion.link.connection import Link
from obstacle_fusion.outputs.jsonl import JsonLinesWriter
from obstacle_fusion.outputs.mcap_file import McapRecorder
from obstacle_fusion.sim.emulated_robot import EmulatedRobot
from obstacle_fusion.sim.scenario import demo_scenario
from obstacle_fusion.sim.scene import renderer_for
from obstacle_fusion.sim.synthetic_camera import SyntheticCamera, synthetic_camera_model
from obstacle_fusion.sources.frames import Frame, FrameSource
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.rig import Rig


class PrerenderedScenario(FrameSource):
    """The scenario's frames rendered ahead on a grid of scene times, served live."""

    def __init__(self, robot: EmulatedRobot, width: int, height: int, seconds: float) -> None:
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


def run_once(width: int, height: int, fps: float, seconds: float, max_wait_s: float) -> dict:
    robot = EmulatedRobot(demo_scenario()).start()
    try:
        source = PrerenderedScenario(robot, width, height, seconds)
        source.fps = fps
        with tempfile.TemporaryDirectory() as tmp:
            recorder = McapRecorder(Path(tmp) / "bench.mcap")
            app = App(
                RunSettings(duration_s=seconds, max_wait_s=max_wait_s, mode="bench"),
                Link(robot.port),
                source,
                Measurer(source.camera, Rig(), "fused"),
                jsonl=JsonLinesWriter(io.StringIO()),
                recorder=recorder,
                robot=robot,
            )
            records: list = []
            publish = app._publish

            def keep(batch: list) -> None:
                records.extend(batch)
                publish(batch)

            app._publish = keep  # type: ignore[method-assign,assignment]
            t0 = time.monotonic()
            result = app.run()
            wall = time.monotonic() - t0
            recorder.close()
    finally:
        robot.stop()
    lat = sorted(r.latency_s for r in records if r.latency_s is not None)
    vision = sorted(r.vision_ms for r in records if r.vision_ms is not None)
    span = records[-1].t_host - records[0].t_host if len(records) > 1 else wall
    return {
        "records": len(records),
        "rate": (len(records) - 1) / span if span > 0 else 0.0,
        "lat_p50_ms": 1e3 * statistics.median(lat),
        "lat_p95_ms": 1e3 * lat[int(0.95 * (len(lat) - 1))],
        "vision_p50_ms": statistics.median(vision) if vision else float("nan"),
        "dropped": result.stats["frames_dropped"],
        "paired": result.stats["fusion"]["paired_fraction"],
        "measured": result.stats["fusion"]["detected"],
    }


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=10.0)
    args = ap.parse_args()
    rows = []
    for width, height in ((500, 375), (1280, 720)):
        for label, fps, wait in (
            ("15 fps, interpolated pairing", 15.0, 0.25),
            ("15 fps, no wait (nearest)", 15.0, 0.0),
            ("sustained (source asks 120 fps)", 120.0, 0.25),
        ):
            r = run_once(width, height, fps, args.seconds, wait)
            rows.append((f"{width}x{height}", label, r))
            print(
                f"{width}x{height:<4} {label:<34} records {r['records']:4d}  "
                f"rate {r['rate']:6.1f}/s  latency p50 {r['lat_p50_ms']:6.1f} ms  "
                f"p95 {r['lat_p95_ms']:6.1f} ms  vision p50 {r['vision_p50_ms']:5.2f} ms  "
                f"dropped {r['dropped']:4d}  paired {100 * r['paired']:5.1f}%",
                flush=True,
            )
    print()
    print("| resolution | mode | frames/s | latency median | latency p95 | vision median |")
    print("|---|---|---|---|---|---|")
    for res, label, r in rows:
        print(
            f"| {res} | {label} | {r['rate']:.1f} | {r['lat_p50_ms']:.1f} ms | "
            f"{r['lat_p95_ms']:.1f} ms | {r['vision_p50_ms']:.2f} ms |"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
