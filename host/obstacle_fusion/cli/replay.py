"""`obstacle-fusion replay FILE.mcap`: re-run the fusion offline on a recording.

The recording keeps raw sonar values (echo ticks, the timer's rate, MCU stamps mapped to
host time) and the camera frames with their capture instants, so pairing, conversion (at
another temperature, with a median filter) and measurement (with another method) can all
be redone. Messages are fed in the order the host received them, with the fusion's clock
set to each message's receipt time, so frames wait for their ranges exactly as they did.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from obstacle_fusion.errors import UserError


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = subparsers.add_parser(
        "replay",
        help="re-run the fusion on an MCAP recording and print JSON lines",
        description="Read a recording made by `obstacle-fusion run --record`, pair its frames "
        "with its sonar ranges again, measure, and print one JSON line per frame.",
    )
    p.add_argument("recording", type=Path, help="FILE.mcap")
    p.add_argument("--method", choices=("fused", "paper"), help="default: the recorded one")
    p.add_argument("--temperature", type=float, help="re-convert ranges at this air temperature")
    p.add_argument("--median", type=int, default=1, help="median filter over N ranges")
    p.add_argument("--calib", type=Path, help="camera calibration (default: the recorded one)")
    p.add_argument("--rig", type=Path, help="rig file (default: the recorded one)")
    p.add_argument("--stop-distance", type=float, metavar="M", help="alert below this")
    p.add_argument("--pair-tolerance-ms", type=float, default=50.0)
    p.set_defaults(func=run)


_STATUS_CODES = {"ok": 0, "no_echo": 1, "timeout": 2, "out_of_range": 3, "too_close": 0}


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from obstacle_fusion.fusion import Fusion, RangePairer
    from obstacle_fusion.outputs.jsonl import JsonLinesWriter
    from obstacle_fusion.outputs.mcap_file import (
        TOPIC_IMAGE,
        TOPIC_RANGE,
        decode_image,
        read_recording,
    )
    from obstacle_fusion.protocol.generated import Range
    from obstacle_fusion.sonar import SonarConverter
    from obstacle_fusion.sources import Frame
    from obstacle_fusion.vision.camera import CameraModel
    from obstacle_fusion.vision.measure import Measurer
    from obstacle_fusion.vision.rig import Rig

    if args.median < 1:
        raise UserError(f"--median must be at least 1, got {args.median}")
    rec = read_recording(args.recording)
    meta = rec.metadata.get("run", {})
    msgs = [m for m in rec.messages if m.topic in (TOPIC_IMAGE, TOPIC_RANGE)]
    if not msgs:
        if not rec.complete:
            raise UserError(f"{args.recording}: {rec.problem}; no frame or range before the cut")
        raise UserError(f"{args.recording} holds no camera frames or sonar ranges to replay")
    temperature = (
        args.temperature
        if args.temperature is not None
        else float(meta.get("temperature_c", "20") or 20)
    )
    half_spacing = float(meta.get("half_spacing_m", "0.013") or 0.013)
    method = args.method or meta.get("method") or "fused"
    if args.rig is not None:
        rig = Rig.load(args.rig)
    elif meta.get("rig"):
        rig = Rig(**json.loads(meta["rig"]))
    else:
        rig = Rig()
    camera: Any = None
    if args.calib is not None:
        camera = CameraModel.load(args.calib)
    elif meta.get("camera") and meta["camera"] != "null":
        c = json.loads(meta["camera"])
        camera = CameraModel(
            np.array(c["camera_matrix"]), np.array(c["dist_coeffs"]), c["width"], c["height"]
        )
    stop = args.stop_distance
    if stop is None and meta.get("stop_distance_m") not in (None, "None", ""):
        stop = float(meta["stop_distance_m"])

    now = [0.0]
    measurer: Any = None
    converters: dict[int, SonarConverter] = {}
    fusion = Fusion(
        measurer=None,
        pairer=RangePairer(tolerance_s=args.pair_tolerance_ms / 1e3),
        stop_distance_m=stop,
        method=method,
        clock=lambda: now[0],
    )
    out = JsonLinesWriter(sys.stdout)
    index = 0
    bad_images = 0
    for m in sorted(msgs, key=lambda m: m.log_time_ns):
        now[0] = m.log_time_ns / 1e9
        d = m.data
        if m.topic == TOPIC_RANGE:
            hz = int(d.get("timer_hz") or 2_000_000)
            conv = converters.get(hz)
            if conv is None:
                conv = converters[hz] = SonarConverter(
                    timer_hz=hz,
                    temperature_c=temperature,
                    median_window=args.median,
                    half_spacing_m=half_spacing,
                )
            raw = Range(
                d["measurement"],
                d["sensor_id"],
                d["trigger_us"],
                d["echo_ticks"],
                _STATUS_CODES.get(d["status"], 255),
            )
            reading = conv.convert(
                raw,
                d.get("t_trigger_host"),
                d.get("t_receipt"),
                time_scale=float(d.get("time_scale") or 1.0),
            )
            records = fusion.add_reading(reading)

        else:
            image = decode_image(d)
            if image is None:
                bad_images += 1
                continue
            if measurer is None:
                cam = camera
                if cam is None:
                    from obstacle_fusion.synthetic_camera import synthetic_camera_model

                    cam = synthetic_camera_model(image.shape[1], image.shape[0])
                measurer = Measurer(cam, rig, method)
                fusion.measurer = measurer
            frame = Frame(image, m.publish_time_ns / 1e9, index, str(d.get("frame_id", "")))
            index += 1
            records = fusion.add_frame(frame)
        for r in records:
            out.write(r)
    for r in fusion.flush():
        out.write(r)
    s = fusion.stats
    print(
        f"obstacle-fusion replay: {s.published} records from {index} frames and {s.readings} "
        f"ranges; {s.paired} paired, {s.unpaired} unpaired, {s.detected} measured"
        + (f", {bad_images} undecodable frames" if bad_images else ""),
        file=sys.stderr,
    )
    if not rec.complete:
        raise UserError(
            f"{args.recording}: {rec.problem}. The {len(msgs)} messages before the cut were "
            "replayed above; anything after it is lost"
        )
    return 0
