"""`obstacle-fusion replay FILE.mcap`: re-run the fusion offline on a recording.

The recording keeps raw sonar values (echo ticks, the timer's rate, MCU stamps mapped to
host time) and the camera frames with their capture instants, so pairing, conversion (at
another temperature, with a median filter) and measurement (with another method) can all
be redone. Messages are fed in the order the host received them, with the fusion's clock
set to each message's receipt time, so frames wait for their ranges exactly as they did.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import logging
import sys
from pathlib import Path
from typing import Any

from obstacle_fusion.cli import _args
from obstacle_fusion.errors import UserError

log = logging.getLogger(__name__)


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = subparsers.add_parser(
        "replay",
        help="re-run the fusion on an MCAP recording and print JSON lines",
        description="Read a recording made by `obstacle-fusion run --record`, pair its frames "
        "with its sonar ranges again, measure, and print one JSON line per frame.",
    )
    p.add_argument("recording", type=Path, help="FILE.mcap (a file: replay needs to seek)")
    p.add_argument("--method", choices=("fused", "paper"), help="default: the recorded one")
    p.add_argument(
        "--temperature",
        type=_args.temperature_c,
        help="re-convert ranges at this air temperature, celsius (-50..80)",
    )
    _args.add_processing_args(p)
    p.add_argument(
        "--pairing",
        choices=("predicted", "interpolated"),
        help="default: the recorded one (interpolated for recordings that do not say: "
        "they were made before predicted pairing)",
    )
    p.add_argument("--calib", type=Path, help="camera calibration (default: the recorded one)")
    p.add_argument("--rig", type=Path, help="rig file (default: the recorded one)")
    p.add_argument(
        "--stop-distance", type=_args.stop_distance_m, metavar="M", help="alert below this"
    )
    p.add_argument(
        "--ros2-bag",
        type=Path,
        metavar="OUT",
        help="also write a ROS 2 bag folder (MCAP storage): the recorded ranges and images, "
        "CameraInfo, and the replayed detections as vision_msgs/Detection3DArray",
    )
    p.add_argument("--overwrite", action="store_true", help="replace an existing --ros2-bag")
    p.add_argument(
        "--camera-latency-ms",
        type=_args.camera_latency_ms,
        help="subtract this from the recorded frame stamps (0..2000); default: estimated from "
        "the recording (image heights against ranges; one extra pass) and used when confident",
    )
    p.set_defaults(func=run)


_STATUS_CODES = {"ok": 0, "no_echo": 1, "timeout": 2, "out_of_range": 3, "too_close": 0}
# Exit code when the recording was damaged in the middle: everything intact was replayed,
# but messages were lost (a file cut short is reported as an error, exit 2, as before).
EXIT_DAMAGED = 3
_RANGE_INTS = ("measurement", "sensor_id", "trigger_us", "echo_ticks")


def _range_fields(d: dict[str, Any]) -> tuple[int, int, int, int, str] | None:
    """The raw values of a /sonar/range message this tool wrote, or None for another's."""
    values = [d.get(k) for k in _RANGE_INTS]
    status = d.get("status")
    if not all(isinstance(v, int) and not isinstance(v, bool) for v in values):
        return None
    if not isinstance(status, str):
        return None
    return values[0], values[1], values[2], values[3], status  # type: ignore[return-value]


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from obstacle_fusion.fusion import Fusion, PairingMode, RangePairer, TrackSettings
    from obstacle_fusion.outputs.foxglove_schemas import (
        FoxgloveTopics,
        recording_monotonic_to_unix_ns,
        recording_unix_offset_ns,
    )
    from obstacle_fusion.outputs.jsonl import JsonLinesWriter
    from obstacle_fusion.outputs.mcap_file import (
        TOPIC_IMAGE,
        TOPIC_OBSTACLE,
        TOPIC_RANGE,
        decode_image,
        read_recording,
    )
    from obstacle_fusion.sonar import SonarConverter
    from obstacle_fusion.vision.camera import CameraModel, CameraModelError
    from obstacle_fusion.vision.rig import Rig

    if str(args.recording) == "-":
        raise UserError("replay reads a file, not standard input: save the recording first")
    _args.refuse_overwrite(args.ros2_bag, "--ros2-bag", args.overwrite)
    if args.ros2_bag is not None:
        from obstacle_fusion.outputs.ros2_bag import require_rosbags

        require_rosbags()
    rec = read_recording(args.recording)
    # New recordings hold Unix-epoch times; the fusion runs on the host-monotonic ones.
    offset_ns = recording_unix_offset_ns(rec.metadata)
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
        rig = rig_from_metadata(meta["rig"], args.recording)
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
    first_image = next(
        (img for m in msgs if m.topic == TOPIC_IMAGE and (img := decode_image(m.data)) is not None),
        None,
    )
    if camera is not None and first_image is not None:
        h, w = first_image.shape[:2]
        try:
            camera.scaled_to(w, h)
        except CameraModelError as exc:
            which = f"--calib {args.calib}" if args.calib is not None else "the recorded camera"
            raise UserError(f"{which} does not fit the recording's {w}x{h} frames: {exc}") from None
    stop = args.stop_distance
    if stop is None and meta.get("stop_distance_m") not in (None, "None", ""):
        stop = float(meta["stop_distance_m"])

    from obstacle_fusion.online import MIN_LATENCY_CONFIDENCE, OnlineCalibration

    rig_source = "file" if args.rig is not None else str(meta.get("rig_source", "default"))
    now = [0.0]

    span = _meta_number(meta, "sensors", 1.0, 1.0, 4.0)
    extrapolation = _meta_number(meta, "max_extrapolation_s", 0.2, 0.01, 1.0)
    recorded_pairing = meta.get("pairing")
    pairing = PairingMode(
        args.pairing
        or (recorded_pairing if recorded_pairing in ("predicted", "interpolated") else None)
        or "interpolated"  # recorded before predicted pairing existed
    )

    def fresh(shift_s: float, given_s: float | None) -> tuple[Any, OnlineCalibration]:
        online = OnlineCalibration(
            rig,
            rig_source=rig_source,
            latency_given_s=given_s,
            stamp_shift_s=shift_s,
            clock=lambda: now[0],
        )
        fusion = Fusion(
            measurer=None,
            pairer=RangePairer(tolerance_s=args.pair_tolerance_ms / 1e3, max_gap_s=0.2 * span),
            stop_distance_m=stop,
            method=method,
            clock=lambda: now[0],
            observer=online.measured,
            pairing=pairing,
            track=TrackSettings(max_extrapolation_s=extrapolation * span, max_gap_s=0.2 * span),
        )
        return fusion, online

    given = None if args.camera_latency_ms is None else args.camera_latency_ms / 1e3
    shift = given or 0.0
    if given is None:  # a first pass, with no output, only to estimate the latency
        fusion, online = fresh(0.0, None)
        _replay(
            args, msgs, offset_ns, now, fusion, _NoOutput(), None, {}, temperature,
            half_spacing, camera, rig, method, online,
        )  # fmt: skip
        online.update(now=now[0], force=True)
        lat = online.latency_estimate
        if lat is not None and lat.confidence >= MIN_LATENCY_CONFIDENCE:
            shift = lat.latency_s
            note = f"pairing with the frames {1e3 * shift:.1f} ms earlier"
        else:
            note = "frames paired as recorded"
        print(f"obstacle-fusion replay: {online.latency_text()}; {note}", file=sys.stderr)
    converters: dict[int, SonarConverter] = {}
    fusion, online = fresh(shift, shift if given is None else given)
    out = JsonLinesWriter(sys.stdout)
    # The live run's frame numbers (a camera may have skipped some), from its records.
    recorded_index: dict[int, int] = {}
    for m in rec.messages:
        data = m.data if isinstance(m.data, dict) else {}
        if m.topic == TOPIC_OBSTACLE and isinstance(data.get("frame_index"), int):
            recorded_index[m.publish_time_ns] = data["frame_index"]
    ros2: Any = None
    if args.ros2_bag is not None:
        from obstacle_fusion.outputs.ros2_bag import Ros2BagWriter

        topics = FoxgloveTopics(
            rig=rig, camera=camera, unix_offset_ns=recording_monotonic_to_unix_ns(rec.metadata)
        )
        ros2 = Ros2BagWriter(args.ros2_bag, topics=topics, overwrite=args.overwrite)
    try:
        index, bad_images, foreign_ranges = _replay(
            args,
            msgs,
            offset_ns,
            now,
            fusion,
            out,
            ros2,
            converters,
            temperature,
            half_spacing,
            camera,
            rig,
            method,
            online,
            recorded_index=recorded_index,
        )
    finally:
        if ros2 is not None:
            ros2.close()
    online.update(now=now[0], force=True)
    s = fusion.stats
    print(
        f"obstacle-fusion replay: {s.published} records from {index} frames and {s.readings} "
        f"ranges; {s.paired} paired, {s.unpaired} unpaired, {s.detected} measured, "
        f"{s.vision_errors} vision errors",
        file=sys.stderr,
    )
    print(f"obstacle-fusion replay: {online.rig_text()}", file=sys.stderr)
    if given is not None:
        print(f"obstacle-fusion replay: {online.latency_text()}", file=sys.stderr)
    for text in online.warnings:
        print(f"obstacle-fusion replay: warning: {text}", file=sys.stderr)
    if ros2 is not None:
        print(
            f"obstacle-fusion replay: wrote the ROS 2 bag {args.ros2_bag} ("
            + ", ".join(f"{n} on {t}" for t, n in ros2.counts.items())
            + ")",
            file=sys.stderr,
        )
    skipped = dict(rec.skipped)
    if bad_images:
        skipped[f"{TOPIC_IMAGE} (no image data)"] = bad_images
    if foreign_ranges:
        skipped[f"{TOPIC_RANGE} (not an obstacle-fusion range)"] = foreign_ranges
    what = ", ".join(f"{n} on {t}" for t, n in sorted(skipped.items()))
    if index == 0 and s.readings == 0:
        raise UserError(
            f"{args.recording} holds no camera frames or sonar ranges this tool can replay"
            + (
                f" (skipped {what}); was it written by `obstacle-fusion run --record`?"
                if what
                else ""
            )
        )
    if skipped:
        print(
            f"obstacle-fusion replay: warning: skipped {sum(skipped.values())} messages it "
            f"cannot replay: {what}",
            file=sys.stderr,
        )
    if not rec.complete:
        raise UserError(
            f"{args.recording}: {rec.problem}"
            + (f" and damaged ({rec.damage})" if rec.damage else "")
            + f". The {len(msgs)} messages before the cut were replayed above; anything "
            "after it is lost (`obstacle-fusion recover` writes what is left as a whole file)"
        )
    if rec.damage:
        print(
            f"obstacle-fusion replay: error: {args.recording} lost data: {rec.damage}; every "
            f"intact message was replayed (exit {EXIT_DAMAGED})",
            file=sys.stderr,
        )
        return EXIT_DAMAGED
    return 0


def _replay(
    args: argparse.Namespace,
    msgs: list[Any],
    offset_ns: int,
    now: list[float],
    fusion: Any,
    out: Any,
    ros2: Any,
    converters: dict[int, Any],
    temperature: float,
    half_spacing: float,
    camera: Any,
    rig: Any,
    method: str,
    online: Any,
    recorded_index: dict[int, int] | None = None,
) -> tuple[int, int, int]:
    import base64

    from obstacle_fusion.outputs.mcap_file import TOPIC_RANGE, decode_image
    from obstacle_fusion.protocol.generated import Range
    from obstacle_fusion.sonar import SonarConverter
    from obstacle_fusion.sources.frames import Frame
    from obstacle_fusion.vision.measure import STREAM_RIG_CHECK, Measurer

    measurer: Any = None
    index = 0
    bad_images = 0
    foreign_ranges = 0
    for m in sorted(msgs, key=lambda m: m.log_time_ns):
        now[0] = (m.log_time_ns - offset_ns) / 1e9
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
            fields = _range_fields(d)
            t_trigger, t_receipt = d.get("t_trigger_host"), d.get("t_receipt")
            scale = d.get("time_scale") or 1.0
            if fields is None or not all(
                v is None or isinstance(v, int | float) for v in (t_trigger, t_receipt, scale)
            ):
                foreign_ranges += 1
                continue
            measurement, sensor_id, trigger_us, echo_ticks, status = fields
            raw = Range(
                measurement, sensor_id, trigger_us, echo_ticks, _STATUS_CODES.get(status, 255)
            )
            reading = conv.convert(raw, t_trigger, t_receipt, time_scale=float(scale))
            online.reading_in(reading)
            records = fusion.add_reading(reading)
            if ros2 is not None:
                ros2.write_range(reading, log_t=now[0])

        else:
            image = decode_image(d)
            if image is None:
                bad_images += 1
                continue
            if measurer is None:
                cam = camera
                if cam is None:
                    from obstacle_fusion.sim.synthetic_camera import synthetic_camera_model

                    cam = synthetic_camera_model(image.shape[1], image.shape[0])
                measurer = Measurer(cam, rig, method)
                measurer.rig_check = STREAM_RIG_CHECK  # as `run` measured the stream
                fusion.measurer = measurer
                online.camera_of = lambda w, h, c=cam: c.scaled_to(w, h)
                if ros2 is not None:
                    ros2.topics.set_camera(cam)
            t_frame = (m.publish_time_ns - offset_ns) / 1e9
            if ros2 is not None:
                h, w = image.shape[:2]
                jpeg = base64.b64decode(d["data"])
                ros2.write_image(jpeg, str(d.get("format", "jpeg")), w, h, t_frame, now[0])
            frame = Frame(
                image,
                t_frame,
                (recorded_index or {}).get(m.publish_time_ns, index),
                str(d.get("frame_id", "")),
            )
            index += 1
            records = fusion.add_frame(online.frame_in(frame))
        for r in records:
            out.write(r)
            if ros2 is not None:
                ros2.write_record(r)
    for r in fusion.flush():
        out.write(r)
        if ros2 is not None:
            ros2.write_record(r)
    return index, bad_images, foreign_ranges


def _meta_number(meta: dict[str, str], key: str, default: float, lo: float, hi: float) -> float:
    """A recorded setting, or the default when it is missing or not a sensible number."""
    try:
        value = float(meta.get(key, default))
    except (TypeError, ValueError):
        return default
    return value if lo <= value <= hi else default


class _NoOutput:
    """Where the estimation pass's records go."""

    def write(self, record: Any, extra: Any = None) -> None:
        return None


def rig_from_metadata(text: str, recording: Path) -> Any:
    """The recorded rig; keys a newer version added are skipped with a warning."""
    from obstacle_fusion.vision.rig import Rig

    try:
        values = json.loads(text)
    except json.JSONDecodeError as exc:
        raise UserError(
            f"{recording}: the recorded rig is not valid JSON ({exc}); pass --rig FILE"
        ) from None
    if not isinstance(values, dict):
        raise UserError(f"{recording}: the recorded rig is not a JSON object; pass --rig FILE")
    known = {f.name for f in dataclasses.fields(Rig)}
    unknown = sorted(set(values) - known)
    if unknown:
        log.warning(
            "%s: ignoring rig values this version does not know: %s",
            recording,
            ", ".join(unknown),
        )
    try:
        return Rig(**{k: v for k, v in values.items() if k in known})
    except UserError as exc:
        raise UserError(
            f"{recording}: the recorded rig is unusable: {exc}; pass --rig FILE"
        ) from None
