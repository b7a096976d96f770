#!/usr/bin/env python3
"""What the fused method's reported confidence means on the TUNING scenes, per doubt.

Measures the tuning rooms (families ``procedural`` and ``photo``, never a ``-holdout`` one:
those are the held-out check, seen only through tools/bench_rooms.py) and the generated
scenes of tools/bench_vision.py, each with its true rig and with none, and prints: of the
detections at or above ``--threshold`` (default 0.5), the share with both errors within
5 %; then, per doubt (``Measurement.doubts``, vision/fused/confidence.py), how many
detections carry it and how many of those are within 5 %. A doubt whose detections are
mostly within 5 % cuts sure faces for nothing; one under the threshold's share earns its
cut.

    .venv/bin/python tools/bench_confidence.py                 # rooms 100-159, 150 generated
    .venv/bin/python tools/bench_confidence.py --rooms 10 --generated 20
"""

from __future__ import annotations

import argparse
import sys
from collections import defaultdict
from dataclasses import dataclass, field

import cv2
import numpy as np
from bench_vision import random_rig  # the benchmark's rigs, drawn in its order
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.sim.scene import SceneSpec, render_scene
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.measure import Measurer

#: The families this tool measures: the tuning ones only.
TUNING_FAMILIES = ("procedural", "photo")
GOOD = 0.05  # both errors within this share


@dataclass
class Detection:
    source: str  # rooms / generated
    with_rig: bool
    confidence: float
    good: bool
    doubts: list[str] = field(default_factory=list)


def scenes(
    camera: CameraModel, first_room: int, rooms: int, generated: int, seed: int
) -> list[tuple[str, np.ndarray, float, float, float, object]]:
    """(source, image, range, true height, true width, rig) per scene."""
    out: list[tuple[str, np.ndarray, float, float, float, object]] = []
    for fam in TUNING_FAMILIES:
        for hard in (False, True):
            for s in range(first_room, first_room + rooms):
                image, truth, room = render_room(fam, s, hard, camera)
                if truth["clipped"]:
                    continue  # a clipped face's width is a lower bound, not a measurement
                out.append(
                    (
                        "rooms",
                        image,
                        truth["range_m"],
                        truth["height_m"],
                        truth["width_m"],
                        room.rig,
                    )
                )
    rng = np.random.default_rng(seed)
    for i in range(generated):
        rig = random_rig(rng)
        spec = SceneSpec.random(rng, i >= generated // 3, camera, rig)
        sc = render_scene(spec, camera, rig, int(rng.integers(1 << 31)))
        noisy = spec.distance_m * (1.0 + rng.normal(0.0, 0.003)) + rng.normal(0.0, 0.002)
        rng_m = float(np.clip(noisy, 0.02, 5.0))
        out.append(("generated", sc.image, rng_m, sc.truth.height_m, sc.truth.width_m, rig))
    return out


def measure_all(camera: CameraModel, frames: list) -> list[Detection]:
    found = []
    for source, image, range_m, h, w, rig in frames:
        for with_rig in (True, False):
            r = Measurer(camera, rig if with_rig else None).measure(image, range_m)
            if not r.detected or r.height_m is None or r.width_m is None:
                continue
            good = abs(r.height_m / h - 1.0) <= GOOD and abs(r.width_m / w - 1.0) <= GOOD
            found.append(Detection(source, with_rig, r.confidence or 0.0, good, list(r.doubts)))
    return found


def report(found: list[Detection], threshold: float) -> list[str]:
    lines = []
    for with_rig in (True, False):
        rig = "rig" if with_rig else "no rig"
        for source in ("rooms", "generated", "all"):
            sel = [
                d
                for d in found
                if d.with_rig == with_rig
                and source in ("all", d.source)
                and d.confidence >= threshold
            ]
            good = sum(d.good for d in sel)
            share = f"{100 * good / len(sel):.1f} %" if sel else "n/a"
            lines.append(
                f"{rig:6s} {source:9s} at >= {threshold:g}: {good}/{len(sel)} within 5 % ({share})"
            )
        per: dict[str, list[Detection]] = defaultdict(list)
        for d in found:
            if d.with_rig == with_rig:
                for name in d.doubts:
                    per[name].append(d)
        for name, ds in sorted(per.items()):
            good = sum(d.good for d in ds)
            lines.append(f"{rig:6s}   doubt {name:22s} {len(ds):4d} detections, {good} within 5 %")
    return lines


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--first-room", type=int, default=100, help="first tuning room seed")
    ap.add_argument("--rooms", type=int, default=60, help="rooms per family and kind")
    ap.add_argument("--generated", type=int, default=150, help="generated scenes")
    ap.add_argument("--seed", type=int, default=2026, help="generated scenes' seed")
    ap.add_argument("--threshold", type=float, default=0.5)
    args = ap.parse_args(argv)
    if args.rooms < 0 or args.generated < 0 or args.rooms + args.generated == 0:
        ap.error("--rooms and --generated must be >= 0, and one of them > 0")
    if not 0.0 <= args.threshold <= 1.0:
        ap.error("--threshold must be within 0..1")
    cv2.setNumThreads(1)
    camera = CameraModel.paper(500, 375)
    found = measure_all(
        camera, scenes(camera, args.first_room, args.rooms, args.generated, args.seed)
    )
    print("\n".join(report(found, args.threshold)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
