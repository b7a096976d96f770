"""Per-frame cost of undistortion with the cached fixed-point maps (one core, in-process).

python tools/bench_undistort.py
"""

from __future__ import annotations

import statistics
import time

import cv2
import numpy as np
from obstacle_fusion.vision.camera import CameraModel


def bench(width: int, height: int, repeats: int = 200) -> tuple[float, float, float]:
    camera = CameraModel.paper(width, height)
    rng = np.random.default_rng(0)
    image = rng.integers(0, 255, (height, width, 3), dtype=np.uint8)
    t0 = time.perf_counter()
    camera.undistort_maps()
    maps_ms = (time.perf_counter() - t0) * 1e3
    out = np.empty_like(image)
    grey = cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)
    grey_out = np.empty_like(grey)
    times, grey_times = [], []
    for _ in range(repeats):
        t = time.perf_counter()
        camera.undistort(image, out=out)
        times.append(time.perf_counter() - t)
        t = time.perf_counter()
        camera.undistort(grey, out=grey_out)
        grey_times.append(time.perf_counter() - t)
    return maps_ms, statistics.median(times) * 1e3, statistics.median(grey_times) * 1e3


def main() -> int:
    cv2.setNumThreads(1)
    print("| size | build maps once (ms) | undistort BGR (ms, median) | undistort grey (ms) |")
    print("|---|---|---|---|")
    for width, height in ((500, 375), (1280, 960), (2592, 1944)):
        maps_ms, bgr_ms, grey_ms = bench(width, height)
        print(f"| {width}x{height} | {maps_ms:.1f} | {bgr_ms:.3f} | {grey_ms:.3f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
