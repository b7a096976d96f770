"""`obstacle-fusion run`: the live job, on the emulated robot by default or on a real one."""

from __future__ import annotations

import argparse
import dataclasses
import json
import logging
import signal
import sys
from pathlib import Path
from types import FrameType
from typing import Any

from obstacle_fusion.api import LazyMeasurer as _LazyMeasurer  # noqa: F401 - kept for tests
from obstacle_fusion.cli import _args
from obstacle_fusion.errors import UserError

log = logging.getLogger(__name__)


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = subparsers.add_parser(
        "run",
        help="fuse sonar and camera live: distance, height and width of the obstacle ahead",
        description="Pair every camera frame with the sonar range of its capture instant and "
        "measure the obstacle. With no --port and no --camera it runs the emulated robot: the "
        "real firmware under simavr with a virtual HC-SR04 playing a demo scene, and a "
        "synthetic camera filming the same scene. With --port and no --camera it runs on the "
        "sonar alone: one range record per reading, no vision.",
    )
    hw = p.add_argument_group("hardware (omit both for the emulated robot)")
    hw.add_argument(
        "--port",
        help="the board's serial port (default with --camera: auto-find; alone: sonar only)",
    )
    hw.add_argument("--baud", type=_args.positive_int, default=115200)
    hw.add_argument(
        "--camera", help="camera index or /dev/videoN, a video file, or a folder of images"
    )
    hw.add_argument(
        "--width", type=_args.frame_side_px, help="frame width to ask the camera for (16..8192)"
    )
    hw.add_argument(
        "--height", type=_args.frame_side_px, help="frame height to ask the camera for (16..8192)"
    )
    hw.add_argument("--fps", type=_args.positive_float, help="frame rate (camera; demo: 15)")
    hw.add_argument(
        "--camera-latency-ms",
        type=_args.camera_latency_ms,
        help="exposure-to-read delay to subtract (0..2000); default: estimated during the run "
        "(the face's image height against the sonar's range) and used for pairing once sure",
    )
    hw.add_argument("--calib", type=Path, help="camera calibration (obstacle-fusion calibrate)")
    hw.add_argument("--rig", type=Path, help="rig file: camera height, pitch, sonar offsets")
    proc = p.add_argument_group("processing")
    proc.add_argument("--method", choices=("fused", "paper"), default="fused")
    proc.add_argument(
        "--temperature",
        type=_args.temperature_c,
        help="air temperature, celsius, -50..80 (default 20; demo: the scenario's)",
    )
    _args.add_processing_args(proc)
    proc.add_argument(
        "--half-spacing-mm",
        type=float,
        default=13.0,
        help="half the transducer spacing for formula (6); 0 = formula (7) only",
    )
    proc.add_argument(
        "--pairing",
        choices=("predicted", "interpolated"),
        default="predicted",
        help="predicted (default): each frame at once with the range a constant-velocity "
        "filter predicts for its instant; interpolated: wait for the echo after the frame "
        "and interpolate (about 40-70 ms later)",
    )
    proc.add_argument(
        "--max-extrapolation-ms",
        type=float,
        default=200.0,
        help="never predict further than this past a sonar's last good reading (10..1000)",
    )
    proc.add_argument(
        "--max-wait-ms",
        type=float,
        default=250.0,
        help="longest a frame waits for the range after it when it is not predicted (0: "
        "nearest range at once, lower latency, fewer frames paired)",
    )
    proc.add_argument(
        "--sensors",
        type=int,
        help="number of sonars to range, 1..4 (SET_CONFIG sensor_mask after each handshake; "
        "default: the rig's sonars when it lists several, else the board's setting)",
    )
    out = p.add_argument_group("outputs")
    out.add_argument(
        "--duration", type=_args.positive_float, help="seconds to run (demo: the scene's)"
    )
    out.add_argument("--json", action="store_true", help="JSON lines on standard output")
    out.add_argument("--record", type=Path, metavar="FILE.mcap", help="MCAP recording")
    out.add_argument(
        "--video", type=Path, metavar="OUT.mp4", help="annotated video (H.264 MP4; .avi: MJPEG)"
    )
    out.add_argument(
        "--foxglove",
        metavar="[HOST:]PORT",
        help="serve the run live to Foxglove over WebSocket (host default 127.0.0.1; "
        "e.g. 8765, or 0.0.0.0:8765 for other machines)",
    )
    out.add_argument(
        "--ros2-bag",
        type=Path,
        metavar="OUT",
        help="write a ROS 2 bag folder (MCAP storage): Range, CompressedImage, CameraInfo, "
        "Detection3DArray, tf_static",
    )
    out.add_argument(
        "--stop-distance", type=_args.stop_distance_m, metavar="M", help="alert below this"
    )
    out.add_argument(
        "--exit-on-alert",
        type=_args.exit_code,
        metavar="CODE",
        help="exit with CODE (1..125) at the first alert",
    )
    out.add_argument(
        "--overwrite",
        action="store_true",
        help="replace an existing --record, --video or --ros2-bag output",
    )
    out.add_argument("--quiet", action="store_true", help="no live console view")
    emu = p.add_argument_group("emulated robot")
    emu.add_argument("--clock-ppm", type=float, default=0.0, help="emulated crystal error")
    emu.add_argument(
        "--scenario", type=Path, help="TOML scenario for the emulated robot (default: the demo)"
    )
    emu.add_argument(
        "--emulated-latency-ms",
        type=_args.camera_latency_ms,
        default=0.0,
        help="the synthetic camera lags the scene by this much (0..2000), as a USB camera does",
    )
    p.set_defaults(func=run)


class _Terminated(KeyboardInterrupt):
    """SIGTERM: stop as for Ctrl-C, but exit 143 (128 + 15) as a service manager expects."""


def _sigterm(signum: int, frame: FrameType | None) -> None:
    raise _Terminated


def run(args: argparse.Namespace) -> int:
    from obstacle_fusion.api import ObstacleSensor

    if args.video is not None and args.port and not args.camera:
        raise UserError("--video needs --camera: with --port alone the run is sonar only")
    if not 0.0 <= args.max_wait_ms <= 5000.0:
        raise UserError(f"--max-wait-ms must be within 0..5000, got {args.max_wait_ms}")
    if not 10.0 <= args.max_extrapolation_ms <= 1000.0:
        raise UserError(
            f"--max-extrapolation-ms must be within 10..1000, got {args.max_extrapolation_ms}"
        )
    if args.sensors is not None and not 1 <= args.sensors <= 4:
        raise UserError(f"--sensors must be within 1..4, got {args.sensors}")
    if not 0.0 <= args.half_spacing_mm <= 50.0:
        raise UserError(f"--half-spacing-mm must be within 0..50, got {args.half_spacing_mm}")
    if args.exit_on_alert is not None and args.stop_distance is None:
        raise UserError("--exit-on-alert needs --stop-distance M (the alert's threshold)")
    if args.scenario is not None and (args.port or args.camera):
        raise UserError("--scenario is for the emulated robot; leave out --port and --camera")
    if args.emulated_latency_ms and (args.port or args.camera):
        raise UserError(
            "--emulated-latency-ms is for the emulated robot; leave out --port and --camera"
        )
    if args.record is not None and args.record.suffix.lower() != ".mcap":
        raise UserError(f"--record {args.record}: the recording must be a .mcap file")
    if args.camera and (args.width or args.height) and Path(args.camera).exists():
        if not str(args.camera).startswith("/dev/"):  # a folder or a video file
            log.warning(
                "--width/--height only ask a camera for a size; %s plays at its own size",
                args.camera,
            )
    _args.refuse_overwrite(args.record, "--record", args.overwrite)
    _args.refuse_overwrite(args.video, "--video", args.overwrite)
    _args.refuse_overwrite(args.ros2_bag, "--ros2-bag", args.overwrite)
    demo = not args.port and not args.camera
    scenario = None
    if demo:
        from obstacle_fusion.sim.scenario import demo_scenario, load_scenario

        scenario = load_scenario(args.scenario) if args.scenario else demo_scenario()
        if args.temperature is not None and args.temperature != scenario.temperature_c:
            print(
                f"obstacle-fusion run: --temperature {args.temperature:g} C replaces the "
                f"scenario's {scenario.temperature_c:g} C, for the emulated air and the "
                "host's conversion alike",
                file=sys.stderr,
            )
            scenario = dataclasses.replace(scenario, temperature_c=args.temperature)
    # the sensor checks its outputs (a taken --foxglove port, a missing extra, a video it
    # cannot write) here, before anything starts
    sensor = ObstacleSensor(
        port=args.port,
        camera=args.camera,
        calib=args.calib,
        rig=args.rig,
        baud=args.baud,
        method=args.method,
        stop_distance=args.stop_distance,
        exit_on_alert=args.exit_on_alert,
        temperature=args.temperature,
        median=args.median,
        half_spacing_mm=args.half_spacing_mm,
        pair_tolerance_ms=args.pair_tolerance_ms,
        max_wait_ms=args.max_wait_ms,
        width=args.width,
        height=args.height,
        fps=args.fps,
        camera_latency_ms=args.camera_latency_ms,
        scenario=scenario,
        emulated_latency_ms=args.emulated_latency_ms,
        clock_ppm=args.clock_ppm,
        duration=args.duration,
        record=args.record,
        video=args.video,
        foxglove=args.foxglove,
        ros2_bag=args.ros2_bag,
        overwrite=args.overwrite,
        json_stream=sys.stdout if args.json else None,
        console=None if args.quiet else sys.stderr,
        pairing=args.pairing,
        max_extrapolation_ms=args.max_extrapolation_ms,
        sensors=args.sensors,
    )
    if scenario is not None:
        print(
            "obstacle-fusion run: no --port or --camera given: running the emulated robot "
            "(the real Uno firmware under simavr, a virtual HC-SR04 and a synthetic camera "
            f"playing the '{scenario.name}' scene, {scenario.duration_s:g} s, "
            f"{scenario.temperature_c:g} C)",
            file=sys.stderr,
        )
    elif not args.camera:
        print(
            f"obstacle-fusion run: no --camera given: sonar only on {args.port} (one range "
            "record per reading, no height or width)",
            file=sys.stderr,
        )
    if signal.getsignal(signal.SIGTERM) is signal.SIG_DFL:
        signal.signal(signal.SIGTERM, _sigterm)
    try:
        result = sensor.run(on_ready=_say_ready)
    except KeyboardInterrupt as exc:
        print("obstacle-fusion run: stopped; outputs closed", file=sys.stderr)
        return 143 if isinstance(exc, _Terminated) else 130
    summary = result.stats
    f, link = summary["fusion"], summary["link"]
    link_text = (
        f"link: {link['frames']} frames, {link['crc_errors']} CRC errors, {link['seq_gaps']} "
        f"lost, {link['reconnects']} reconnects"
    )
    if sensor.mode == "sonar-only":
        ranges = f["published"] - f["clear"] - f["sonar_errors"]
        print(
            f"obstacle-fusion run: {f['published']} range records, {ranges} with a distance, "
            f"{f['clear']} clear, {f['sonar_errors']} sonar errors, {f['alerts']} alerts; "
            f"{link_text}",
            file=sys.stderr,
        )
    else:
        print(
            f"obstacle-fusion run: {f['published']} records, {f['paired']} paired "
            f"({100 * f['paired_fraction']:.1f}%), {f['unpaired']} unpaired, "
            f"{f['detected']} measured, {f['vision_errors']} vision errors, {f['alerts']} "
            f"alerts; {link_text}",
            file=sys.stderr,
        )
    online = sensor.online
    if online is not None:
        print(f"obstacle-fusion run: {online.rig_text()}", file=sys.stderr)
        print(f"obstacle-fusion run: {online.latency_text()}", file=sys.stderr)
        for text in online.warnings:
            print(f"obstacle-fusion run: warning: {text}", file=sys.stderr)
    log.info("summary: %s", json.dumps(summary))
    recorder = sensor.app.recorder if sensor.app is not None else None
    if recorder is not None and recorder.failed is not None:
        print(
            f"obstacle-fusion run: recording failed: {recorder.failed}; "
            f"{recorder.dropped} messages not recorded (exit {EXIT_RECORDING_FAILED})",
            file=sys.stderr,
        )
        if result.exit_code == 0:
            return EXIT_RECORDING_FAILED
    return result.exit_code


EXIT_RECORDING_FAILED = 4  # the run went on to its end, but --record stopped early


def _say_ready(sensor: Any) -> None:
    """Once everything is open: where the emulated robot runs (a test kills it by this pid)
    and where the live Foxglove view is served."""
    if sensor.robot is not None:
        print(
            f"obstacle-fusion run: emulator pid {sensor.robot.pid} on {sensor.robot.port()}",
            file=sys.stderr,
            flush=True,
        )
    if sensor.live is not None:
        print(
            f"obstacle-fusion run: Foxglove live on {sensor.live.url} (Foxglove: Open connection "
            "-> Foxglove WebSocket)",
            file=sys.stderr,
            flush=True,
        )
