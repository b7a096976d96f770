#!/usr/bin/env python3
"""Held-out accuracy of the fused method on textured rooms (host/obstacle_fusion/sim/room_scene.py).

Rooms come from a second renderer (textures by homography, real photographs, clutter,
shadows, random rigs), not the generator the method was tuned on. Families ending in
``-holdout`` use materials and photographs never looked at while tuning: report them.

For each family and scene kind (ordinary / hard) it prints, over the scenes whose face lies
whole in the image: mean and median height/width error of the detected ones, missed (not
detected), gross (an error over 25 %), with the true rig (``--rig file``) and with no rig
(the floor contact and the camera pitch estimated from the image; the no-rig rows add
how many faces gave a pitch and its error against the true rig). Clipped scenes are
counted apart: they must come back flagged (``clipped``), never as a full width. Then the
reliability table: of the detections at or above each confidence, the share with both
errors within 5 %.

    .venv/bin/python tools/bench_rooms.py                      # 25 + 25 scenes per family
    .venv/bin/python tools/bench_rooms.py --families photo-holdout --scenes 50 --seed 100
"""

from __future__ import annotations

import argparse
import statistics
import sys
from dataclasses import dataclass

import cv2
from obstacle_fusion.sim.room_scene import FAMILIES, TextureMissing, render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.measure import Measurer

CONF_STEPS = (0.0, 0.3, 0.5, 0.7)


@dataclass
class Outcome:
    family: str
    hard: bool
    with_rig: bool
    detected: bool
    clipped_truth: bool
    flagged: bool
    err_h: float = float("nan")
    err_w: float = float("nan")
    confidence: float = 0.0
    ms: float = 0.0
    pitch_err: float | None = None  # estimated minus true camera pitch (no rig, levelled)


def run_family(family: str, scenes: int, seed: int, camera: CameraModel) -> list[Outcome]:
    out = []
    for hard in (False, True):
        for s in range(seed, seed + scenes):
            image, truth, spec = render_room(family, s, hard, camera)
            for with_rig in (True, False):
                m = Measurer(camera, spec.rig if with_rig else None)
                r = m.measure(image, truth["range_m"])
                # per-frame time: the maps built once per camera and rig are not the frame's
                ms = r.timings_ms.get("total", 0.0) - r.timings_ms.get("setup", 0.0)
                o = Outcome(
                    family,
                    hard,
                    with_rig,
                    r.detected,
                    bool(truth["clipped"]),
                    bool(r.clipped),
                    confidence=r.confidence or 0.0,
                    ms=ms,
                )
                if not with_rig and r.camera_pitch_deg:  # 0: the pitch was not read
                    o.pitch_err = r.camera_pitch_deg - spec.rig.camera_pitch_deg
                if r.detected and r.height_m is not None and r.width_m is not None:
                    o.err_h = abs(r.height_m - truth["height_m"]) / truth["height_m"]
                    o.err_w = abs(r.width_m - truth["width_m"]) / truth["width_m"]
                out.append(o)
    return out


def _pct(values: list[float], stat: str) -> float:
    if not values:
        return float("nan")
    return 100 * (statistics.fmean(values) if stat == "mean" else statistics.median(values))


def summary(rows: list[Outcome]) -> str:
    whole = [o for o in rows if not o.clipped_truth]
    det = [o for o in whole if o.detected]
    if not whole:
        return "no scenes"
    eh = [o.err_h for o in det]
    ew = [o.err_w for o in det]
    gross = sum(1 for o in det if max(o.err_h, o.err_w) > 0.25)
    clipped = [o for o in rows if o.clipped_truth]
    flagged = sum(1 for o in clipped if o.flagged or not o.detected)
    pitch = ""
    errs = sorted(abs(o.pitch_err) for o in rows if o.pitch_err is not None)
    if errs:
        p90 = errs[min(len(errs) - 1, int(0.9 * len(errs)))]
        pitch = (
            f" pitch read {len(errs)}, |error| median {statistics.median(errs):.2f} "
            f"p90 {p90:.2f} max {errs[-1]:.2f} deg"
        )
    return (
        f"h {_pct(eh, 'mean'):5.1f}% w {_pct(ew, 'mean'):5.1f}% "
        f"(median {_pct(eh, 'median'):4.1f} / {_pct(ew, 'median'):4.1f}) "
        f"missed {len(whole) - len(det):2d}/{len(whole):2d} gross {gross:2d} "
        f"clipped flagged-or-refused {flagged}/{len(clipped)} "
        f"ms {statistics.median([o.ms for o in rows]):.1f}{pitch}"
    )


def reliability(rows: list[Outcome]) -> list[str]:
    det = [o for o in rows if o.detected and not o.clipped_truth]
    lines = ["| confidence >= | detections | both errors <= 5 % |", "|---|---|---|"]
    for c in CONF_STEPS:
        sel = [o for o in det if o.confidence >= c]
        good = sum(1 for o in sel if max(o.err_h, o.err_w) <= 0.05)
        share = f"{100 * good / len(sel):.0f} %" if sel else "n/a"
        lines.append(f"| {c:.1f} | {len(sel)} | {share} |")
    return lines


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument(
        "--families",
        default=",".join(FAMILIES),
        help=f"comma-separated, from {', '.join(FAMILIES)}",
    )
    ap.add_argument("--scenes", type=int, default=25, help="scenes per family and kind")
    ap.add_argument("--seed", type=int, default=1000, help="first scene seed")
    args = ap.parse_args(argv)
    families = [f for f in args.families.split(",") if f]
    bad = [f for f in families if f not in FAMILIES]
    if bad or args.scenes < 1:
        ap.error(f"unknown families {bad}" if bad else "--scenes must be at least 1")
    cv2.setNumThreads(1)
    camera = CameraModel.paper(500, 375)
    allrows: list[Outcome] = []
    print(
        f"seed {args.seed}, {args.scenes} ordinary + {args.scenes} hard scenes per family, "
        "500x375, one core"
    )
    for fam in families:
        try:
            rows = run_family(fam, args.scenes, args.seed, camera)
        except TextureMissing as exc:
            print(f"{fam}: skipped ({exc})", file=sys.stderr)
            return 2
        allrows += rows
        for with_rig in (True, False):
            for hard in (False, True):
                sel = [o for o in rows if o.hard == hard and o.with_rig == with_rig]
                label = (
                    f"{fam:19s} {'rig   ' if with_rig else 'no rig'} {'hard' if hard else 'ord '}"
                )
                print(f"{label} {summary(sel)}")
    for with_rig in (True, False):
        print(f"\nreliability, {'with the rig' if with_rig else 'no rig'}, all families above:")
        print("\n".join(reliability([o for o in allrows if o.with_rig == with_rig])))
    return 0


if __name__ == "__main__":
    sys.exit(main())
