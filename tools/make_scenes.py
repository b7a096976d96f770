#!/usr/bin/env python3
"""Write N synthetic obstacle scenes (PNG) and their ground truth (JSON) to a folder.

    .venv/bin/python tools/make_scenes.py OUT_DIR [-n 50] [--hard-fraction 0.5] [--seed 1]
        [--calib camera.yaml] [--rig rig.toml] [--random-rig]

Each scene i gets scene_i.png and scene_i.json {"truth", "spec", "rig", "range_m"}; an
index.json lists them all. --random-rig varies camera height and pitch per scene (then each
JSON holds the rig to measure with).
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import asdict
from pathlib import Path

import cv2
import numpy as np
from obstacle_fusion.sim.scene import SceneSpec, render_scene
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.rig import Rig


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("-n", type=int, default=50)
    ap.add_argument("--hard-fraction", type=float, default=0.5)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--calib", help="camera file (default: the paper's camera at 500x375)")
    ap.add_argument("--rig", help="rig TOML (default: Rig())")
    ap.add_argument("--random-rig", action="store_true")
    args = ap.parse_args()
    if args.n < 1 or not 0.0 <= args.hard_fraction <= 1.0:
        print("make_scenes: -n must be >= 1 and --hard-fraction in 0..1", file=sys.stderr)
        return 2
    camera = CameraModel.load(args.calib) if args.calib else CameraModel.paper()
    base_rig = Rig.load(args.rig) if args.rig else Rig()
    args.out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(args.seed)
    index = []
    for i in range(args.n):
        rig = base_rig
        if args.random_rig:
            rig = Rig(
                camera_height_m=float(rng.uniform(0.12, 0.4)),
                camera_pitch_deg=float(rng.uniform(0.0, 10.0)),
                sonar_below_m=base_rig.sonar_below_m,
                sonar_ahead_m=base_rig.sonar_ahead_m,
                sonar_right_m=base_rig.sonar_right_m,
                beam_width_deg=base_rig.beam_width_deg,
            )
        hard = bool(rng.random() < args.hard_fraction)
        spec = SceneSpec.random(rng, hard, camera, rig)
        scene = render_scene(spec, camera, rig, int(rng.integers(1 << 31)))
        name = f"scene_{i:04d}"
        cv2.imwrite(str(args.out / f"{name}.png"), scene.image)
        record = {
            "image": f"{name}.png",
            "range_m": spec.distance_m,
            "truth": scene.truth.to_dict(),
            "spec": spec.to_dict(),
            "rig": asdict(rig),
            "camera": {"width": camera.width, "height": camera.height},
        }
        (args.out / f"{name}.json").write_text(json.dumps(record, indent=1))
        index.append(record)
    (args.out / "index.json").write_text(json.dumps(index, indent=1))
    print(f"wrote {args.n} scenes to {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
