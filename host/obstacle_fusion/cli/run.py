"""`obstacle-fusion run`: the live job, on the emulated robot by default or on a real one."""

from __future__ import annotations

import argparse
import dataclasses
import json
import logging
import signal
import sys
from contextlib import ExitStack
from pathlib import Path
from types import FrameType
from typing import Any

from obstacle_fusion.errors import UserError

log = logging.getLogger(__name__)


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be positive, got {text}")
    return value


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = subparsers.add_parser(
        "run",
        help="fuse sonar and camera live: distance, height and width of the obstacle ahead",
        description="Pair every camera frame with the sonar range of its capture instant and "
        "measure the obstacle. With no --port and no --camera it runs the emulated robot: the "
        "real firmware under simavr with a virtual HC-SR04 playing a demo scene, and a "
        "synthetic camera filming the same scene.",
    )
    hw = p.add_argument_group("hardware (omit both for the emulated robot)")
    hw.add_argument("--port", help="the board's serial port (default with --camera: auto-find)")
    hw.add_argument("--baud", type=int, default=115200)
    hw.add_argument(
        "--camera", help="camera index or /dev/videoN, a video file, or a folder of images"
    )
    hw.add_argument("--width", type=int, help="frame width to ask the camera for")
    hw.add_argument("--height", type=int, help="frame height to ask the camera for")
    hw.add_argument("--fps", type=_positive, help="frame rate (camera request; demo: 15)")
    hw.add_argument(
        "--camera-latency-ms", type=float, default=0.0, help="exposure-to-read delay to subtract"
    )
    hw.add_argument("--calib", type=Path, help="camera calibration (obstacle-fusion calibrate)")
    hw.add_argument("--rig", type=Path, help="rig file: camera height, pitch, sonar offsets")
    proc = p.add_argument_group("processing")
    proc.add_argument("--method", choices=("fused", "paper"), default="fused")
    proc.add_argument("--temperature", type=float, default=20.0, help="air temperature, celsius")
    proc.add_argument(
        "--median", type=int, default=1, help="median filter over N ranges (1 = none)"
    )
    proc.add_argument(
        "--half-spacing-mm",
        type=float,
        default=13.0,
        help="half the transducer spacing for formula (6); 0 = formula (7) only",
    )
    proc.add_argument(
        "--pair-tolerance-ms",
        type=_positive,
        default=50.0,
        help="nearest-range pairing tolerance when no interpolation is possible",
    )
    proc.add_argument(
        "--max-wait-ms",
        type=float,
        default=250.0,
        help="longest a frame waits for the range after it (0: nearest range at once, lower "
        "latency, fewer frames paired)",
    )
    out = p.add_argument_group("outputs")
    out.add_argument("--duration", type=_positive, help="seconds to run (demo: the scene's)")
    out.add_argument("--json", action="store_true", help="JSON lines on standard output")
    out.add_argument("--record", type=Path, metavar="FILE.mcap", help="MCAP recording")
    out.add_argument("--video", type=Path, metavar="OUT.mp4", help="annotated video")
    out.add_argument("--stop-distance", type=_positive, metavar="M", help="alert below this")
    out.add_argument(
        "--exit-on-alert", type=int, metavar="CODE", help="exit with CODE at the first alert"
    )
    out.add_argument("--quiet", action="store_true", help="no live console view")
    emu = p.add_argument_group("emulated robot")
    emu.add_argument("--clock-ppm", type=float, default=0.0, help="emulated crystal error")
    emu.add_argument(
        "--scenario", type=Path, help="TOML scenario for the emulated robot (default: the demo)"
    )
    p.set_defaults(func=run)


class _LazyMeasurer:
    """Builds the measurer on the first frame, when the frame size is known."""

    def __init__(self, camera: Any, rig: Any, method: str) -> None:
        self.camera = camera
        self.rig = rig
        self.method = method
        self._impl: Any = None

    def measure(self, image: Any, range_m: float) -> Any:
        if self._impl is None:
            from obstacle_fusion.synthetic_camera import synthetic_camera_model
            from obstacle_fusion.vision.measure import Measurer

            camera = self.camera
            if camera is None:
                h, w = image.shape[:2]
                log.warning(
                    "no --calib: measuring with the paper's lens at %dx%d; heights and "
                    "widths will be only as right as that guess (run obstacle-fusion calibrate)",
                    w,
                    h,
                )
                camera = synthetic_camera_model(w, h)
            self._impl = Measurer(camera, self.rig, self.method)
        return self._impl.measure(image, range_m)


def _sigterm(signum: int, frame: FrameType | None) -> None:
    raise KeyboardInterrupt


def run(args: argparse.Namespace) -> int:
    from obstacle_fusion.app import App, RunSettings
    from obstacle_fusion.link import Link, resolve_port
    from obstacle_fusion.outputs.console import ConsoleView
    from obstacle_fusion.outputs.jsonl import JsonLinesWriter
    from obstacle_fusion.outputs.mcap_file import McapRecorder
    from obstacle_fusion.outputs.video import AnnotatedVideoWriter
    from obstacle_fusion.vision.camera import CameraModel
    from obstacle_fusion.vision.rig import Rig

    if args.port and not args.camera:
        raise UserError(
            "--port needs --camera too (a camera index, /dev/videoN, a video file or an image "
            "folder); with neither, the emulated robot runs"
        )
    if args.median < 1:
        raise UserError(f"--median must be at least 1, got {args.median}")
    if not 0.0 <= args.max_wait_ms <= 5000.0:
        raise UserError(f"--max-wait-ms must be within 0..5000, got {args.max_wait_ms}")
    if not 0.0 <= args.half_spacing_mm <= 50.0:
        raise UserError(f"--half-spacing-mm must be within 0..50, got {args.half_spacing_mm}")
    if args.exit_on_alert is not None and args.stop_distance is None:
        raise UserError("--exit-on-alert needs --stop-distance M (the alert's threshold)")
    if args.scenario is not None and (args.port or args.camera):
        raise UserError("--scenario is for the emulated robot; leave out --port and --camera")
    if args.record is not None and args.record.suffix.lower() != ".mcap":
        raise UserError(f"--record {args.record}: the recording must be a .mcap file")
    rig = Rig.load(args.rig) if args.rig else Rig()
    camera = CameraModel.load(args.calib) if args.calib else None
    demo = not args.port and not args.camera
    settings = RunSettings(
        duration_s=args.duration,
        stop_distance_m=args.stop_distance,
        exit_on_alert=args.exit_on_alert,
        temperature_c=args.temperature,
        median_window=args.median,
        half_spacing_m=args.half_spacing_mm / 1e3,
        pair_tolerance_s=args.pair_tolerance_ms / 1e3,
        max_wait_s=args.max_wait_ms / 1e3,
        method=args.method,
        mode="emulator" if demo else "robot",
    )
    if signal.getsignal(signal.SIGTERM) is signal.SIG_DFL:
        signal.signal(signal.SIGTERM, _sigterm)
    with ExitStack() as stack:
        robot = None
        extra = None
        if demo:
            from obstacle_fusion.emulated_robot import EmulatedRobot
            from obstacle_fusion.scenario import demo_scenario, load_scenario
            from obstacle_fusion.synthetic_camera import SyntheticCamera, synthetic_camera_model

            scenario = load_scenario(args.scenario) if args.scenario else demo_scenario()
            print(
                "obstacle-fusion run: no --port or --camera given: running the emulated robot "
                "(the real Uno firmware under simavr, a virtual HC-SR04 and a synthetic camera "
                f"playing the '{scenario.name}' scene, {scenario.duration_s:g} s)",
                file=sys.stderr,
            )
            robot = EmulatedRobot(scenario, clock_ppm=args.clock_ppm).start()
            stack.callback(robot.stop)
            print(
                f"obstacle-fusion run: emulator pid {robot.pid} on {robot.port()}",
                file=sys.stderr,
                flush=True,
            )
            if camera is None:
                camera = synthetic_camera_model(args.width or 500, args.height or 375)
            source: Any = SyntheticCamera(
                scenario, camera, rig, fps=args.fps or 15.0, scene_time=robot.scene_time
            )
            settings.temperature_c = scenario.temperature_c
            if settings.duration_s is None:
                settings.duration_s = scenario.duration_s
            port: Any = robot.port
            synthetic = source

            def extra(rec: Any) -> dict[str, Any]:
                return {"scene_t_s": synthetic.scene_time_of(rec.frame_index)}

        else:
            from obstacle_fusion.sources import open_source

            port = resolve_port(args.port)
            source = open_source(
                args.camera,
                width=args.width,
                height=args.height,
                fps=args.fps,
                latency_s=args.camera_latency_ms / 1e3,
                realtime=True,
            )
        stack.callback(source.close)
        link = Link(port, baud=args.baud)
        jsonl = JsonLinesWriter(sys.stdout) if args.json else None
        recorder = None
        if args.record is not None:
            recorder = McapRecorder(
                args.record,
                metadata={
                    "run": {
                        "mode": settings.mode,
                        "method": args.method,
                        "temperature_c": str(settings.temperature_c),
                        "half_spacing_m": str(settings.half_spacing_m),
                        "stop_distance_m": str(args.stop_distance),
                        "rig": json.dumps(dataclasses.asdict(rig)),
                        "camera": json.dumps(_camera_dict(camera)),
                    }
                },
            )
            stack.callback(recorder.close)
        video = None
        if args.video is not None:
            video = AnnotatedVideoWriter(args.video, fps=args.fps or 15.0)
            stack.callback(video.close)
        view = None if args.quiet else ConsoleView(sys.stderr)
        if view is not None:
            stack.callback(view.close)
        app = App(
            settings,
            link,
            source,
            _LazyMeasurer(camera, rig, args.method),
            jsonl=jsonl,
            recorder=recorder,
            video=video,
            view=view,
            robot=robot,
            extra_fields=extra,
        )
        try:
            result = app.run()
        except KeyboardInterrupt:
            print("obstacle-fusion run: stopped; outputs closed", file=sys.stderr)
            return 130
        summary = result.stats
        f = summary["fusion"]
        print(
            f"obstacle-fusion run: {f['published']} records, {f['paired']} paired "
            f"({100 * f['paired_fraction']:.1f}%), {f['unpaired']} unpaired, "
            f"{f['detected']} measured, {f['alerts']} alerts; link: "
            f"{summary['link']['frames']} frames, {summary['link']['crc_errors']} CRC errors, "
            f"{summary['link']['seq_gaps']} lost, {summary['link']['reconnects']} reconnects",
            file=sys.stderr,
        )
        log.info("summary: %s", json.dumps(summary))
        return result.exit_code
    return 0


def _camera_dict(camera: Any) -> dict[str, Any] | None:
    if camera is None:
        return None
    return {
        "camera_matrix": [list(map(float, row)) for row in camera.camera_matrix],
        "dist_coeffs": [float(v) for v in camera.dist_coeffs],
        "width": camera.width,
        "height": camera.height,
    }
