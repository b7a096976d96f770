"""The rig and the camera latency: how well they come back, with the figures printed.

python tools/bench_rig.py

1. calibrate-rig on rendered floor photos (800x600, a strongly distorted lens, one photo per
   rig at the nearest distance the whole board is in view): height / pitch / roll errors.
2. The online rig estimator: 100 floor-contact rows at 0.6-2.5 m, 0.5 px noise, 20 %
   outliers, 20 random rigs: worst height and pitch errors.
3. The camera latency estimator on modelled series (15 fps, 20 Hz sonar, 0.3 px height
   noise, 10 % wrong heights), 80 ms: approach-stop-back off and a steady approach at
   0.3 / 0.6 / 1.0 m/s.
"""

from __future__ import annotations

from functools import partial

import numpy as np
from obstacle_fusion.sim.floor_boards import FloorRig, nearest_placement, render_floor_board
from obstacle_fusion.timing.latency import CameraLatencyEstimator
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.chessboard import BoardRenderer, BoardSpec
from obstacle_fusion.vision.rig_calibration import calibrate_rig
from obstacle_fusion.vision.rig_estimator import OnlineRigEstimator, floor_row

RIGS = [
    FloorRig(0.12, -5.0, 0.0),
    FloorRig(0.15, 12.0, 0.4),
    FloorRig(0.22, 0.0, 0.8),
    FloorRig(0.35, 6.0, 1.5),
    FloorRig(0.50, 15.0, 2.0),
    FloorRig(0.25, -3.0, 1.2),
    FloorRig(0.40, 10.0, 0.0),
]


def bench_calibrate_rig() -> None:
    w, h = 800, 600
    k = np.array([[0.9 * w, 0, w / 2 + 3.3], [0, 0.9 * w * 0.998, h / 2 - 2.1], [0, 0, 1]])
    camera = CameraModel(k, np.array([-0.18, 0.09, 0.0008, -0.0006, -0.01]), w, h)
    board = BoardSpec(9, 6, 0.025)
    renderer = BoardRenderer(camera, board, supersample=2)
    print("calibrate-rig, rendered floor photos (target: 5 mm, 0.2 deg)")
    print("  rig (height, pitch, roll)   board at   height err   pitch err   roll err")
    for i, rig in enumerate(RIGS):
        dist = nearest_placement(camera, board, rig)
        if dist is None:
            print(f"  {rig.height_m:.2f} m {rig.pitch_deg:+5.1f} {rig.roll_deg:3.1f}   not in view")
            continue
        image = render_floor_board(renderer, rig, dist, rng=np.random.default_rng(i)).image
        res = calibrate_rig([("photo", partial(np.asarray, image))], board, camera)
        print(
            f"  {rig.height_m:.2f} m {rig.pitch_deg:+5.1f} deg {rig.roll_deg:3.1f} deg   "
            f"{dist:.2f} m   {1e3 * (res.height_m - rig.height_m):+7.2f} mm   "
            f"{res.pitch_deg - rig.pitch_deg:+7.3f}   {res.roll_deg - rig.roll_deg:+7.3f}"
            + ("   (roll warned)" if res.roll_warning else "")
        )


def bench_online_rig() -> None:
    fy, cy = 459.0, 187.0
    worst_h = worst_p = 0.0
    for seed in range(20):
        rng = np.random.default_rng(seed)
        h, p = rng.uniform(0.12, 0.5), rng.uniform(-5.0, 15.0)
        est = OnlineRigEstimator(fy, cy)
        for _ in range(100):
            d = rng.uniform(0.6, 2.5)
            v = floor_row(fy, cy, h, p, d) + rng.normal(0.0, 0.5)
            if rng.random() < 0.2:
                v += rng.choice([-1.0, 1.0]) * rng.uniform(4.0, 40.0)
            est.add(v, d)
        got = est.estimate()
        if got is None:
            print(f"  seed {seed}: no estimate ({est.why_not})")
            continue
        worst_h = max(worst_h, abs(got.height_m - h))
        worst_p = max(worst_p, abs(got.pitch_deg - p))
    print(
        "online rig, 20 rigs, 0.5 px noise, 20 % outliers (target: 1 cm, 0.5 deg): worst "
        f"{1e3 * worst_h:.2f} mm, {worst_p:.3f} deg"
    )


def _latency(keys_t: list[float], keys_d: list[float], seed: int) -> str:
    rng = np.random.default_rng(seed)
    est = CameraLatencyEstimator()
    for t in np.arange(0.0, keys_t[-1], 1 / 20) + rng.uniform(0.0, 0.01):
        est.add_range(t, float(np.interp(t, keys_t, keys_d)) + rng.normal(0.0, 0.002))
    for t in np.arange(0.3, keys_t[-1], 1 / 15):
        hp = 459.0 * 0.4 / float(np.interp(t - 0.08, keys_t, keys_d)) + rng.normal(0.0, 0.3)
        if rng.random() < 0.1:
            hp *= rng.uniform(0.6, 1.4)
        est.add_frame(t, hp)
    got = est.estimate()
    if got is None:
        return f"none ({est.why_not})"
    return (
        f"{1e3 * (got.latency_s - 0.08):+6.2f} ms (se {1e3 * got.std_error_s:.2f} ms, "
        f"confidence {got.confidence:.2f})"
    )


def bench_latency() -> None:
    print("camera latency, 80 ms, modelled series (target: 5 ms)")
    for speed in (0.3, 0.6, 1.0):
        t1 = (2.5 - 0.8) / speed
        stop_go = ([0.0, t1, t1 + 0.7, t1 + 0.7 + 1.2 / speed], [2.5, 0.8, 0.8, 2.0])
        steady = ([0.0, (2.5 - 0.7) / speed], [2.5, 0.7])
        for seed in (0, 1):
            print(f"  {speed:.1f} m/s seed {seed}: stop-and-go {_latency(*stop_go, seed)}")
        print(f"  {speed:.1f} m/s steady approach: {_latency(*steady, 4)}")


def main() -> int:
    bench_calibrate_rig()
    bench_online_rig()
    bench_latency()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
