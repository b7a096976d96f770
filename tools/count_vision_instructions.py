#!/usr/bin/env python3
"""Instructions per frame of a vision method, counted by valgrind's callgrind.

Wall times on a shared machine move by 2x from run to run; the instruction count of the
same frames does not, so it tells whether a change made the method cheaper. The method
measures --scenes generated ordinary scenes (random rigs as in tools/bench_vision.py,
seed 2026) in one counted process, and each of them twice more in another; the difference
of the two counts over the extra frames is the per-frame figure (imports, rendering and
per-camera setup cancel out). Needs valgrind (Debian's package); takes a few minutes.

    .venv/bin/python tools/count_vision_instructions.py [--method fused|paper] [--scenes 20]
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

_EXTRA_RUNS = 2  # the second count runs every scene this many times more than the first


def _child(method: str, scenes: int, runs: int) -> None:
    """In the counted process: render the scenes, then measure each ``runs`` + 1 times."""
    import cv2
    import numpy as np
    from obstacle_fusion.sim.scene import SceneSpec, render_scene
    from obstacle_fusion.vision.camera import CameraModel
    from obstacle_fusion.vision.measure import Measurer
    from obstacle_fusion.vision.rig import Rig

    cv2.setNumThreads(1)
    camera = CameraModel.paper(500, 375)
    rng = np.random.default_rng(2026)
    work = []
    for _ in range(scenes):
        rig = Rig(
            camera_height_m=float(rng.uniform(0.12, 0.40)),
            camera_pitch_deg=float(rng.uniform(0.0, 10.0)),
            sonar_below_m=float(rng.uniform(0.0, 0.08)),
            sonar_ahead_m=float(rng.uniform(-0.02, 0.03)),
            sonar_right_m=float(rng.uniform(-0.02, 0.02)),
        )
        spec = SceneSpec.random(rng, False, camera, rig)
        scene = render_scene(spec, camera, rig, int(rng.integers(1 << 31)))
        work.append((Measurer(camera, rig, method), scene.image, spec.distance_m))
    for _ in range(runs + 1):  # the first pass builds each measurer's per-camera state
        for measurer, image, range_m in work:
            measurer.measure(image, range_m)


def _count(method: str, scenes: int, runs: int) -> int:
    out = subprocess.run(
        [
            "valgrind",
            "--tool=callgrind",
            "--callgrind-out-file=/dev/null",
            sys.executable,
            str(Path(__file__).resolve()),
            "--child",
            "--method",
            method,
            "--scenes",
            str(scenes),
            "--runs",
            str(runs),
        ],
        capture_output=True,
        text=True,
        check=True,
        # numpy's OpenBLAS starts worker threads that spin while idle: their instructions
        # are counted too and vary with the timing (+-0.7 M a frame seen); the method's
        # BLAS calls are too small for a second thread, so one thread computes the same
        env={**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"},
    )
    found = re.search(r"Collected\s*:\s*(\d+)", out.stderr)
    if found is None:
        raise RuntimeError(f"no instruction count in callgrind's output:\n{out.stderr[-2000:]}")
    return int(found.group(1))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--method", choices=("fused", "paper"), default="fused")
    ap.add_argument("--scenes", type=int, default=20)
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--runs", type=int, default=1, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.scenes < 1:
        ap.error("--scenes must be at least 1")
    if args.child:
        _child(args.method, args.scenes, args.runs)
        return 0
    if shutil.which("valgrind") is None:
        print("valgrind is not installed (apt-get install valgrind)", file=sys.stderr)
        return 2
    once = _count(args.method, args.scenes, 1)
    more = _count(args.method, args.scenes, 1 + _EXTRA_RUNS)
    per_frame = (more - once) / (_EXTRA_RUNS * args.scenes)
    print(
        f"{args.method}: {per_frame / 1e6:.2f} M instructions per 500x375 frame "
        f"({args.scenes} ordinary scenes, seed 2026)"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
