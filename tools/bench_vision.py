#!/usr/bin/env python3
"""Vision benchmark: the paper's Table 1 for both methods on generated scenes, plus timing.

Every scene gets its own random rig (camera 0.12-0.40 m high, pitch 0-10 deg, sonar offsets)
and a simulated HC-SR04 range (true range + 0.3 % + 2 mm noise). Errors are mean relative
errors over the detected scenes; "missed" counts scenes with no detection, "gross" those
detected with a height or width error above 25 %. Times: median per frame, in-process,
one core (cv2.setNumThreads(1)).

    .venv/bin/python tools/bench_vision.py [--ordinary 50] [--hard 100] [--seed 2026]
    .venv/bin/python tools/bench_vision.py --seeds 2026,7,123,11,99   # one row per seed
    .venv/bin/python tools/bench_vision.py --speed --ordinary 100     # the speed line only

Each scene is timed --repeat times (default 3) and its median kept, so one hiccup of a
shared machine does not stand for the frame; the table shows the median over scenes.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time

import cv2
import numpy as np
from obstacle_fusion.sim.scene import HARD_TRAITS, SceneSpec, render_scene
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.rig import Rig

PAPER_ROW = (
    "| paper (published, 50 real obstacles) | 6.41% | 8.25% | 5.74% | n/a | 17.7 ms (Matlab) |"
)


def random_rig(rng: np.random.Generator) -> Rig:
    return Rig(
        camera_height_m=float(rng.uniform(0.12, 0.40)),
        camera_pitch_deg=float(rng.uniform(0.0, 10.0)),
        sonar_below_m=float(rng.uniform(0.0, 0.08)),
        sonar_ahead_m=float(rng.uniform(-0.02, 0.03)),
        sonar_right_m=float(rng.uniform(-0.02, 0.02)),
    )


def hd_camera() -> CameraModel:
    """A 1280x720 camera with the paper's lens (its focal length in proportion to width)."""
    paper = CameraModel.paper(1280, 960)
    k = paper.camera_matrix.copy()
    k[1, 2] = 359.5
    return CameraModel(k, paper.dist_coeffs, 1280, 720)


def make_set(
    rng: np.random.Generator, n: int, hard: bool, camera: CameraModel, render_ms: list | None = None
) -> list:
    out = []
    for _ in range(n):
        rig = random_rig(rng)
        spec = SceneSpec.random(rng, hard, camera, rig)
        seed = int(rng.integers(1 << 31))
        render_scene(spec, camera, rig, seed)  # per-camera/rig state outside the timing
        t0 = time.perf_counter()
        scene = render_scene(spec, camera, rig, seed)
        if render_ms is not None:
            render_ms.append((time.perf_counter() - t0) * 1e3)
        noisy = spec.distance_m * (1.0 + rng.normal(0.0, 0.003)) + rng.normal(0.0, 0.002)
        out.append((scene, rig, float(np.clip(noisy, 0.02, 5.0))))
    return out


def evaluate(
    camera: CameraModel, scenes: list, method: str, trait: str | None = None, repeat: int = 3
) -> dict:
    eh, ew, ed, times = [], [], [], []
    missed = gross = 0
    if trait is not None:
        scenes = [s for s in scenes if trait in s[0].spec.traits]
    for scene, rig, range_m in scenes:
        m = Measurer(camera, rig, method)
        m.measure(scene.image, range_m)  # build per-camera state outside the timing
        runs = []
        for _ in range(max(1, repeat)):
            t0 = time.perf_counter()
            res = m.measure(scene.image, range_m)
            runs.append((time.perf_counter() - t0) * 1e3)
        times.append(statistics.median(runs))
        t = scene.truth
        if not res.detected:
            missed += 1
            continue
        e_h = abs(res.height_m / t.height_m - 1.0)
        e_w = abs(res.width_m / t.width_m - 1.0)
        eh.append(e_h)
        ew.append(e_w)
        ed.append(abs(res.distance_m / t.distance_m - 1.0))
        gross += int(e_h > 0.25 or e_w > 0.25)

    def mean(v: list[float]) -> float:
        return 100.0 * float(np.mean(v)) if v else float("nan")

    def med(v: list[float]) -> float:
        return 100.0 * float(np.median(v)) if v else float("nan")

    return {
        "h": mean(eh),
        "w": mean(ew),
        "h_med": med(eh),
        "w_med": med(ew),
        "d": mean(ed),
        "missed": missed,
        "gross": gross,
        "n": len(scenes),
        "ms": statistics.median(times) if times else float("nan"),
    }


def speed_line(ms: dict[str, float]) -> str:
    """The speed comparison of one run: median ms per ordinary frame of each method."""
    ratio = ms["paper"] / ms["fused"] if ms["fused"] > 0 else 0.0
    return (
        "speed, ordinary scenes at 500x375, one core, this run: "
        f"fused {ms['fused']:.2f} ms, the paper's pipeline in OpenCV "
        f"{ms['paper']:.2f} ms: fused is {ratio:.1f}x as fast"
    )


def seed_list(text: str) -> list[int]:
    try:
        seeds = [int(part) for part in text.split(",") if part.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"not a comma-separated list of integers: {text!r}"
        ) from None
    if not seeds:
        raise argparse.ArgumentTypeError("give at least one seed")
    return seeds


def per_seed(seeds: list[int], n_ordinary: int, n_hard: int, repeat: int) -> int:
    """One row per seed for fused (ordinary and hard) and the paper (ordinary), then all."""
    cam = CameraModel.paper(500, 375)
    print(f"{n_ordinary} ordinary + {n_hard} hard scenes per seed at 500x375; one core\n")
    print(
        "| seed | fused ordinary h / w (missed, gross) | fused hard h / w (missed, gross) "
        "| fused ms ordinary / hard | paper ordinary h / w (missed) |"
    )
    print("|---|---|---|---|---|")
    pooled: dict[str, list] = {"ordinary": [], "hard": []}
    for seed in seeds:
        t0 = time.perf_counter()
        rng = np.random.default_rng(seed)
        ordinary = make_set(rng, n_ordinary, False, cam)
        hard = make_set(rng, n_hard, True, cam)
        pooled["ordinary"] += ordinary
        pooled["hard"] += hard
        fo = evaluate(cam, ordinary, "fused", repeat=repeat)
        fh = evaluate(cam, hard, "fused", repeat=repeat)
        po = evaluate(cam, ordinary, "paper", repeat=1)
        print(
            f"| {seed} | {fo['h']:.2f}% / {fo['w']:.2f}% ({fo['missed']}, {fo['gross']}) "
            f"| {fh['h']:.2f}% / {fh['w']:.2f}% ({fh['missed']}, {fh['gross']}) "
            f"| {fo['ms']:.2f} / {fh['ms']:.2f} "
            f"| {po['h']:.1f}% / {po['w']:.1f}% ({po['missed']}) |",
            flush=True,
        )
        print(f"seed {seed} took {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    if len(seeds) > 1:
        fo = evaluate(cam, pooled["ordinary"], "fused", repeat=1)
        fh = evaluate(cam, pooled["hard"], "fused", repeat=1)
        print(
            f"| all {len(seeds)} ({fo['n']} + {fh['n']} scenes) "
            f"| {fo['h']:.2f}% / {fo['w']:.2f}% ({fo['missed']}, {fo['gross']}) "
            f"| {fh['h']:.2f}% / {fh['w']:.2f}% ({fh['missed']}, {fh['gross']}) | | |"
        )
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ordinary", type=int, default=50)
    ap.add_argument("--hard", type=int, default=100)
    ap.add_argument("--hd", type=int, default=20, help="scenes for the 1280x720 timing")
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument(
        "--seeds", type=seed_list, help="comma-separated seeds: one summary row per seed"
    )
    ap.add_argument("--repeat", type=int, default=3, help="timed runs per scene (median kept)")
    ap.add_argument(
        "--speed",
        action="store_true",
        help="only time both methods on the ordinary scenes and print the speed line",
    )
    args = ap.parse_args()
    if args.repeat < 1:
        ap.error("--repeat must be at least 1")
    cv2.setNumThreads(1)
    if args.seeds:
        return per_seed(args.seeds, args.ordinary, args.hard, args.repeat)
    rng = np.random.default_rng(args.seed)
    cam = CameraModel.paper(500, 375)
    if args.speed:
        # the same ordinary scenes as the full run (they are drawn first from the seed)
        scenes = make_set(rng, args.ordinary, False, cam)
        times = {m: evaluate(cam, scenes, m, repeat=args.repeat)["ms"] for m in ("paper", "fused")}
        print(speed_line(times))
        return 0
    t0 = time.perf_counter()
    render_ms: list[float] = []
    ordinary = make_set(rng, args.ordinary, False, cam, render_ms)
    hard = make_set(rng, args.hard, True, cam, render_ms)
    hd_cam = hd_camera()
    hd = make_set(rng, args.hd, False, hd_cam)
    took = time.perf_counter() - t0
    print(f"rendered {len(ordinary) + len(hard) + len(hd)} scenes in {took:.1f} s", file=sys.stderr)
    print(
        f"seed {args.seed}; {args.ordinary} ordinary + {args.hard} hard scenes at 500x375; "
        f"{args.hd} at 1280x720 for timing; one core\n"
    )
    print(
        "| method / scenes | height err (median) | width err (median) | distance err "
        "| missed (gross > 25 %) | median ms 500x375 / 1280x720 |"
    )
    print("|---|---|---|---|---|---|")
    ordinary_ms: dict[str, float] = {}
    for method in ("paper", "fused"):
        hd_ms = evaluate(hd_cam, hd, method, repeat=args.repeat)["ms"]
        for name, scenes in (("ordinary", ordinary), ("hard", hard)):
            r = evaluate(cam, scenes, method, repeat=args.repeat)
            if name == "ordinary":
                ordinary_ms[method] = r["ms"]
            print(
                f"| {method} / {name} | {r['h']:.2f}% ({r['h_med']:.2f}%) "
                f"| {r['w']:.2f}% ({r['w_med']:.2f}%) | {r['d']:.2f}% "
                f"| {r['missed']}/{r['n']} ({r['gross']}) | {r['ms']:.2f} / {hd_ms:.2f} |"
            )
    print(PAPER_ROW)
    print("\n" + speed_line(ordinary_ms))
    r_med, r_90 = statistics.median(render_ms), float(np.percentile(render_ms, 90))
    print(
        f"\nscene renderer at 500x375 (supersample 4): median {r_med:.1f} ms, "
        f"90th percentile {r_90:.1f} ms per frame"
    )
    print("\nfused on the hard scenes by trait (a scene counts under each of its traits):\n")
    print("| trait | scenes | height err (median) | width err (median) | missed (gross) |")
    print("|---|---|---|---|---|")
    for trait in HARD_TRAITS:
        r = evaluate(cam, hard, "fused", trait, repeat=1)
        print(
            f"| {trait} | {r['n']} | {r['h']:.2f}% ({r['h_med']:.2f}%) "
            f"| {r['w']:.2f}% ({r['w_med']:.2f}%) | {r['missed']} ({r['gross']}) |"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
