#!/usr/bin/env python3
"""Fingerprint of the fused method's answers, to prove a speed change moved no result.

Measures the scenes of ``tools/bench_vision.py --ordinary 50 --hard 100 --seed 2026`` (with
their rigs) and of ``tools/bench_rooms.py --seed 6000`` (every family, ordinary and hard,
with the true rig and with none), each frame twice on one Measurer (the second call meets
the per-camera state and, with no rig, the height memory), and writes every answer's
detected, height_m, width_m, confidence, reason, box_px, clipped and camera_height_m as
JSON lines. ``--compare OLD`` then reports every answer that differs from OLD's by more
than 1e-9 (exit 1 if any does). Rendering takes minutes: ``--scenes-cache FILE`` keeps the
rendered frames (a pickle) for the next run.

    .venv/bin/python tools/vision_results.py -o /tmp/before.jsonl --scenes-cache /tmp/scenes.pkl
    .venv/bin/python tools/vision_results.py -o /tmp/after.jsonl --scenes-cache /tmp/scenes.pkl \\
        --compare /tmp/before.jsonl
"""

from __future__ import annotations

import argparse
import json
import math
import pickle
import sys
from pathlib import Path
from typing import Any

import cv2
import numpy as np
from bench_vision import random_rig  # the benchmark's rigs, drawn in its order
from obstacle_fusion.sim.room_scene import FAMILIES, render_room
from obstacle_fusion.sim.scene import SceneSpec, render_scene
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.rig import Rig

FIELDS = (
    "detected",
    "height_m",
    "width_m",
    "confidence",
    "reason",
    "box_px",
    "clipped",
    "camera_height_m",
)


def render_all(
    camera: CameraModel, n_ordinary: int, n_hard: int, seed: int, room_seed: int, rooms: int
) -> list[tuple[str, np.ndarray, float, Rig | None]]:
    """(name, image, range, rig or None) for every frame measured."""
    out: list[tuple[str, np.ndarray, float, Rig | None]] = []
    rng = np.random.default_rng(seed)
    for kind, n in (("ordinary", n_ordinary), ("hard", n_hard)):
        for i in range(n):
            rig = random_rig(rng)
            spec = SceneSpec.random(rng, kind == "hard", camera, rig)
            scene = render_scene(spec, camera, rig, int(rng.integers(1 << 31)))
            noisy = spec.distance_m * (1.0 + rng.normal(0.0, 0.003)) + rng.normal(0.0, 0.002)
            out.append((f"bench/{kind}/{i}", scene.image, float(np.clip(noisy, 0.02, 5.0)), rig))
    for fam in FAMILIES:
        for hard in (False, True):
            for s in range(room_seed, room_seed + rooms):
                image, truth, room = render_room(fam, s, hard, camera)
                name = f"rooms/{fam}/{'hard' if hard else 'ord'}/{s}"
                out.append((name + "/rig", image, float(truth["range_m"]), room.rig))
                out.append((name + "/norig", image, float(truth["range_m"]), None))
    return out


def save_scenes(path: Path, scenes: list[tuple[str, np.ndarray, float, Rig | None]]) -> None:
    with path.open("wb") as f:
        pickle.dump(scenes, f, protocol=pickle.HIGHEST_PROTOCOL)


def load_scenes(path: Path) -> list[tuple[str, np.ndarray, float, Rig | None]]:
    """Frames this tool saved itself (a pickle: read only files you wrote)."""
    with path.open("rb") as f:
        scenes: list[tuple[str, np.ndarray, float, Rig | None]] = pickle.load(f)  # noqa: S301
    return scenes


def answers(camera: CameraModel, scenes: list[tuple[str, np.ndarray, float, Rig | None]]) -> list:
    out = []
    for name, image, range_m, rig in scenes:
        m = Measurer(camera, rig)
        for call in (1, 2):
            r = m.measure(image, range_m)
            row: dict[str, Any] = {"scene": name, "call": call}
            row.update({f: getattr(r, f) for f in FIELDS})  # unrounded
            if r.box_px is not None:
                row["box_px"] = [float(v) for v in r.box_px]
            out.append(row)
    return out


def _differs(a: Any, b: Any) -> bool:
    if isinstance(a, float) and isinstance(b, float):
        if math.isnan(a) and math.isnan(b):
            return False
        return abs(a - b) > 1e-9
    if isinstance(a, list) and isinstance(b, list):
        return len(a) != len(b) or any(_differs(x, y) for x, y in zip(a, b, strict=True))
    return bool(a != b)


def compare(old: list[dict], new: list[dict]) -> list[str]:
    if len(old) != len(new):
        return [f"{len(old)} answers before, {len(new)} now"]
    bad = []
    for a, b in zip(old, new, strict=True):
        for f in ("scene", "call", *FIELDS):
            if _differs(a.get(f), b.get(f)):
                bad.append(f"{b['scene']} call {b['call']}: {f} {a.get(f)!r} -> {b.get(f)!r}")
    return bad


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", type=Path, required=True, help="JSON lines written")
    ap.add_argument("--compare", type=Path, help="an earlier output to compare with")
    ap.add_argument("--scenes-cache", type=Path, help="a pickle of the rendered frames")
    ap.add_argument("--ordinary", type=int, default=50)
    ap.add_argument("--hard", type=int, default=100)
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--room-seed", type=int, default=6000)
    ap.add_argument("--rooms", type=int, default=25, help="scenes per room family and kind")
    args = ap.parse_args()
    cv2.setNumThreads(1)
    camera = CameraModel.paper(500, 375)
    if args.scenes_cache is not None and args.scenes_cache.exists():
        scenes = load_scenes(args.scenes_cache)
    else:
        scenes = render_all(camera, args.ordinary, args.hard, args.seed, args.room_seed, args.rooms)
        if args.scenes_cache is not None:
            save_scenes(args.scenes_cache, scenes)
    rows = answers(camera, scenes)
    args.output.write_text("".join(json.dumps(r) + "\n" for r in rows))
    detected = sum(1 for r in rows if r["detected"])
    print(f"{len(rows)} answers ({detected} detected) from {len(scenes)} frames -> {args.output}")
    if args.compare is None:
        return 0
    old = [json.loads(line) for line in args.compare.read_text().splitlines() if line]
    bad = compare(old, rows)
    for line in bad[:40]:
        print(line)
    print(f"{len(bad)} differences from {args.compare}" if bad else "identical")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
