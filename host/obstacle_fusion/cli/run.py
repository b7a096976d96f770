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
        "synthetic camera filming the same scene.",
    )
    hw = p.add_argument_group("hardware (omit both for the emulated robot)")
    hw.add_argument("--port", help="the board's serial port (default with --camera: auto-find)")
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
        default=0.0,
        help="exposure-to-read delay to subtract (0..2000)",
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
        "--max-wait-ms",
        type=float,
        default=250.0,
        help="longest a frame waits for the range after it (0: nearest range at once, lower "
        "latency, fewer frames paired)",
    )
    out = p.add_argument_group("outputs")
    out.add_argument(
        "--duration", type=_args.positive_float, help="seconds to run (demo: the scene's)"
    )
    out.add_argument("--json", action="store_true", help="JSON lines on standard output")
    out.add_argument("--record", type=Path, metavar="FILE.mcap", help="MCAP recording")
    out.add_argument("--video", type=Path, metavar="OUT.mp4", help="annotated video")
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
        "--overwrite", action="store_true", help="replace an existing --record or --video file"
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

    def __init__(self, camera: Any, rig: Any, method: str, calib: Path | None = None) -> None:
        self.camera = camera
        self.rig = rig
        self.method = method
        self.calib = calib
        self._impl: Any = None

    def prepare(self, image: Any) -> None:
        """Check the calibration against the frame size; a UserError ends the run (exit 2)
        before a single record claims "nothing there" for a camera it cannot measure."""
        if self._impl is not None:
            return
        from obstacle_fusion.vision.camera import CameraModel, CameraModelError
        from obstacle_fusion.vision.measure import Measurer

        h, w = image.shape[:2]
        if self.camera is None:
            try:
                camera = CameraModel.paper(w, h)
            except CameraModelError:
                raise UserError(
                    f"no --calib given, and the frames are {w}x{h}: the default camera is the "
                    "paper's 4:3 one, which cannot measure frames of another aspect; calibrate "
                    "this camera (obstacle-fusion calibrate) and pass --calib FILE"
                ) from None
            log.warning(
                "no --calib: measuring with the paper's lens at %dx%d; heights and widths will "
                "be only as right as that guess (run obstacle-fusion calibrate)",
                w,
                h,
            )
        else:
            try:
                camera = self.camera.scaled_to(w, h)
            except CameraModelError as exc:
                raise UserError(
                    f"--calib {self.calib}: it does not fit the camera's {w}x{h} frames: {exc}"
                ) from None
        self._impl = Measurer(camera, self.rig, self.method)

    def measure(self, image: Any, range_m: float) -> Any:
        if self._impl is None:
            self.prepare(image)
        return self._impl.measure(image, range_m)


class _Terminated(KeyboardInterrupt):
    """SIGTERM: stop as for Ctrl-C, but exit 143 (128 + 15) as a service manager expects."""


def _sigterm(signum: int, frame: FrameType | None) -> None:
    raise _Terminated


def run(args: argparse.Namespace) -> int:
    from obstacle_fusion.app import RunSettings
    from obstacle_fusion.vision.camera import CameraModel
    from obstacle_fusion.vision.rig import Rig

    if args.port and not args.camera:
        raise UserError(
            "--port needs --camera too (a camera index, /dev/videoN, a video file or an image "
            "folder); with neither, the emulated robot runs"
        )
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
    if args.camera and (args.width or args.height) and Path(args.camera).exists():
        if not str(args.camera).startswith("/dev/"):  # a folder or a video file
            log.warning(
                "--width/--height only ask a camera for a size; %s plays at its own size",
                args.camera,
            )
    _args.refuse_overwrite(args.record, "--record", args.overwrite)
    _args.refuse_overwrite(args.video, "--video", args.overwrite)
    rig = Rig.load(args.rig) if args.rig else Rig()
    camera = CameraModel.load(args.calib) if args.calib else None
    demo = not args.port and not args.camera
    settings = RunSettings(
        duration_s=args.duration,
        stop_distance_m=args.stop_distance,
        exit_on_alert=args.exit_on_alert,
        temperature_c=20.0 if args.temperature is None else args.temperature,
        median_window=args.median,
        half_spacing_m=args.half_spacing_mm / 1e3,
        pair_tolerance_s=args.pair_tolerance_ms / 1e3,
        max_wait_s=args.max_wait_ms / 1e3,
        method=args.method,
        mode="emulator" if demo else "robot",
    )
    if signal.getsignal(signal.SIGTERM) is signal.SIG_DFL:
        signal.signal(signal.SIGTERM, _sigterm)
    try:
        return _run(args, settings, rig, camera, demo)
    except KeyboardInterrupt as exc:
        print("obstacle-fusion run: stopped; outputs closed", file=sys.stderr)
        return 143 if isinstance(exc, _Terminated) else 130


def _run(args: argparse.Namespace, settings: Any, rig: Any, camera: Any, demo: bool) -> int:
    from obstacle_fusion.app import App
    from obstacle_fusion.link.connection import Link, resolve_port
    from obstacle_fusion.outputs.console import ConsoleView
    from obstacle_fusion.outputs.jsonl import JsonLinesWriter
    from obstacle_fusion.outputs.mcap_file import McapRecorder
    from obstacle_fusion.outputs.video import AnnotatedVideoWriter

    with ExitStack() as stack:
        robot = None
        extra = None
        if demo:
            from obstacle_fusion.sim.emulated_robot import EmulatedRobot
            from obstacle_fusion.sim.scenario import demo_scenario, load_scenario
            from obstacle_fusion.sim.synthetic_camera import SyntheticCamera, synthetic_camera_model

            scenario = load_scenario(args.scenario) if args.scenario else demo_scenario()
            if args.temperature is not None and args.temperature != scenario.temperature_c:
                print(
                    f"obstacle-fusion run: --temperature {args.temperature:g} C replaces the "
                    f"scenario's {scenario.temperature_c:g} C, for the emulated air and the "
                    "host's conversion alike",
                    file=sys.stderr,
                )
                scenario = dataclasses.replace(scenario, temperature_c=args.temperature)
            print(
                "obstacle-fusion run: no --port or --camera given: running the emulated robot "
                "(the real Uno firmware under simavr, a virtual HC-SR04 and a synthetic camera "
                f"playing the '{scenario.name}' scene, {scenario.duration_s:g} s, "
                f"{scenario.temperature_c:g} C)",
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
            from obstacle_fusion.sources.opencv_sources import open_source

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
            recorder = _start_recorder(
                McapRecorder,
                args.record,
                overwrite=args.overwrite,
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
            video = AnnotatedVideoWriter(args.video, fps=args.fps or 15.0, overwrite=args.overwrite)
            stack.callback(video.close)
        view = None if args.quiet else ConsoleView(sys.stderr)
        if view is not None:
            stack.callback(view.close)
        app = App(
            settings,
            link,
            source,
            _LazyMeasurer(camera, rig, args.method, args.calib),
            jsonl=jsonl,
            recorder=recorder,
            video=video,
            view=view,
            robot=robot,
            extra_fields=extra,
        )
        result = app.run()
        if view is not None:
            view.close()  # the table's last line ends before the summary starts
        summary = result.stats
        f = summary["fusion"]
        print(
            f"obstacle-fusion run: {f['published']} records, {f['paired']} paired "
            f"({100 * f['paired_fraction']:.1f}%), {f['unpaired']} unpaired, "
            f"{f['detected']} measured, {f['vision_errors']} vision errors, {f['alerts']} "
            f"alerts; link: {summary['link']['frames']} frames, "
            f"{summary['link']['crc_errors']} CRC errors, {summary['link']['seq_gaps']} lost, "
            f"{summary['link']['reconnects']} reconnects",
            file=sys.stderr,
        )
        log.info("summary: %s", json.dumps(summary))
        if recorder is not None and recorder.failed is not None:
            print(
                f"obstacle-fusion run: recording failed: {recorder.failed}; "
                f"{recorder.dropped} messages not recorded (exit {EXIT_RECORDING_FAILED})",
                file=sys.stderr,
            )
            if result.exit_code == 0:
                return EXIT_RECORDING_FAILED
        return result.exit_code
    return 0


EXIT_RECORDING_FAILED = 4  # the run went on to its end, but --record stopped early


def _start_recorder(cls: Any, path: Path, **kwargs: Any) -> Any:
    """The recorder, or a UserError when the file cannot even be started (disk full)."""
    try:
        return cls(path, **kwargs)
    except OSError as exc:
        raise UserError(f"cannot start the recording {path}: {exc.strerror or exc}") from None


def _camera_dict(camera: Any) -> dict[str, Any] | None:
    if camera is None:
        return None
    return {
        "camera_matrix": [list(map(float, row)) for row in camera.camera_matrix],
        "dist_coeffs": [float(v) for v in camera.dist_coeffs],
        "width": camera.width,
        "height": camera.height,
    }
