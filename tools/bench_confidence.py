#!/usr/bin/env python3
"""What the fused method's reported confidence means on the TUNING scenes, per doubt.

Measures the tuning rooms (families ``procedural`` and ``photo``, never a ``-holdout`` one:
those are the held-out check, seen only through tools/bench_rooms.py) and the generated
scenes of tools/bench_vision.py, each with its true rig and with none, and prints: of the
detections at or above ``--threshold`` (default 0.5), the share with both errors within
5 %, and how many detections within 5 % the doubts took under the threshold (their
confidence before the doubts is the reported one divided by the doubts' factors); then,
per doubt (``Measurement.doubts``, vision/fused/confidence.py), how many detections carry
it and how many of those are within 5 %. A doubt whose detections are mostly within 5 %
cuts sure faces for nothing; one under the threshold's share earns its cut.

    .venv/bin/python tools/bench_confidence.py      # rooms 100-159 and 300-359, 150 generated
    .venv/bin/python tools/bench_confidence.py --first-rooms 100 --rooms 10 --generated 20
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
from obstacle_fusion.vision.fused.confidence import DOUBT_FACTORS, SMALL_FACE, pixel_factor
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
    undoubted: float = 0.0  # the confidence before the doubts (the reported one undone)


def undoubted(
    confidence: float, doubts: list[str], height_px: float | None, width_px: float | None
) -> float:
    """The confidence before the doubts cut it: the reported one divided by their factors
    (exact but for the 3-decimal rounding, and for a confidence held at the method's
    minimum)."""
    factor = 1.0
    for name in doubts:
        factor *= pixel_factor(height_px, width_px) if name == SMALL_FACE else DOUBT_FACTORS[name]
    return confidence / factor if factor > 0.0 else confidence


def scenes(
    camera: CameraModel, first_rooms: list[int], rooms: int, generated: int, seed: int
) -> list[tuple[str, np.ndarray, float, float, float, object]]:
    """(source, image, range, true height, true width, rig) per scene."""
    out: list[tuple[str, np.ndarray, float, float, float, object]] = []
    for fam in TUNING_FAMILIES:
        for hard in (False, True):
            for s in (f + i for f in first_rooms for i in range(rooms)):
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
            conf = r.confidence or 0.0
            before = undoubted(conf, list(r.doubts), r.height_px, r.width_px)
            found.append(Detection(source, with_rig, conf, good, list(r.doubts), before))
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
            # within 5 %, sure before the doubts, not after
            lost = sum(
                d.good and d.confidence < threshold <= d.undoubted
                for d in found
                if d.with_rig == with_rig and source in ("all", d.source)
            )
            lines.append(
                f"{rig:6s} {source:9s} at >= {threshold:g}: {good}/{len(sel)} within 5 % "
                f"({share}); {lost} within 5 % taken under it by doubts"
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
    ap.add_argument(
        "--first-rooms",
        default="100,300",
        help="first tuning room seeds, comma-separated (each starts --rooms seeds)",
    )
    ap.add_argument("--rooms", type=int, default=60, help="rooms per first seed, family, kind")
    ap.add_argument("--generated", type=int, default=150, help="generated scenes")
    ap.add_argument("--seed", type=int, default=2026, help="generated scenes' seed")
    ap.add_argument("--threshold", type=float, default=0.5)
    args = ap.parse_args(argv)
    if args.rooms < 0 or args.generated < 0 or args.rooms + args.generated == 0:
        ap.error("--rooms and --generated must be >= 0, and one of them > 0")
    if not 0.0 <= args.threshold <= 1.0:
        ap.error("--threshold must be within 0..1")
    try:
        first_rooms = [int(f) for f in args.first_rooms.split(",")]
    except ValueError:
        ap.error(f"--first-rooms must be comma-separated seeds, got {args.first_rooms!r}")
    cv2.setNumThreads(1)
    camera = CameraModel.paper(500, 375)
    found = measure_all(camera, scenes(camera, first_rooms, args.rooms, args.generated, args.seed))
    print("\n".join(report(found, args.threshold)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
