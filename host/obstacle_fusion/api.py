"""Use it from robot code: an obstacle sensor object, as robot builders' libraries give.

    from obstacle_fusion import ObstacleSensor

    with ObstacleSensor() as sensor:              # no hardware: the emulated robot
        sensor.wait_for_closer_than(1.5, timeout=30)
        print(sensor.distance, sensor.latest.height_m)

As gpiozero's DistanceSensor: ``distance`` (metres, capped at ``max_distance``),
``when_closer_than(metres, callback)`` (gpiozero's ``when_in_range`` with the threshold as an
argument) and ``wait_for_closer_than(metres, timeout)``; as Telemetrix, a callback per
reading (``on_record``); ``latest`` is the newest obstacle record (distance, height,
width, status, times) and iterating gives every record from then on.
:class:`AsyncObstacleSensor` is the asyncio twin (``async with``, ``async for``, ``await
wait_for_closer_than``), as telemetrix-aio.

Where the data comes from is the CLI's ``run``: ``port`` and ``camera`` for a robot (either
one: a camera alone finds the board by USB VID:PID, a port alone is the sonar-only mode with
range records and no vision), neither for the emulated robot (the real firmware under
simavr and a synthetic camera filming the same scene). ``obstacle-fusion run`` is a thin
user of :meth:`ObstacleSensor.run`, the same loop in the caller's thread.

Callbacks run in the sensor's thread (as gpiozero's do): keep them short.
"""

from __future__ import annotations

import asyncio
import dataclasses
import inspect
import logging
import queue
import threading
import time
from collections.abc import AsyncIterator, Awaitable, Callable, Iterator
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path
from types import TracebackType
from typing import TYPE_CHECKING, Any, TextIO

from obstacle_fusion.errors import UserError
from obstacle_fusion.fusion import ObstacleRecord, ObstacleStatus

if TYPE_CHECKING:
    from obstacle_fusion.app import App, RunResult
    from obstacle_fusion.online import OnlineCalibration
    from obstacle_fusion.sim.emulated_robot import EmulatedRobot
    from obstacle_fusion.sim.scenario import Scenario
    from obstacle_fusion.vision.camera import CameraModel
    from obstacle_fusion.vision.rig import Rig

log = logging.getLogger(__name__)

DEFAULT_MAX_DISTANCE_M = 4.0  # the HC-SR04's rated range
_END = object()  # the end-of-stream mark in a subscriber's queue


class SensorError(UserError):
    """The sensor stopped (the board went away for good, a camera failed, ...)."""


def _rig_moved(old: Any, new: Any) -> bool:
    """Rebuild the measurer's maps only when the online rig moved by more than the fit's
    own noise (5 mm, 0.2 degree): every frame's refit differs in the last digits."""
    return (
        abs(old.camera_height_m - new.camera_height_m) > 0.005
        or abs(old.camera_pitch_deg - new.camera_pitch_deg) > 0.2
    )


class LazyMeasurer:
    """Builds the vision measurer on the first frame, when the frame size is known."""

    def __init__(self, camera: Any, rig: Any, method: str, calib: Path | None = None) -> None:
        self.camera = camera
        self.rig = rig
        self.method = method
        self.calib = calib
        self._impl: Any = None
        self.camera_model: Any = None  # the camera measured with, once the frame size is known
        # with no rig: the run's online rig fit (height and pitch from confident detections
        # over many frames), once it exists; each frame finds its floor contact until then
        self.rig_provider: Callable[[], Any] | None = None
        self._online: Any = None  # (rig, Measurer) built from the provider's latest rig

    def prepare(self, image: Any) -> None:
        """Check the calibration against the frame size; a UserError ends the run (exit 2)
        before a single record claims "nothing there" for a camera it cannot measure."""
        if self._impl is not None:
            return
        from obstacle_fusion.vision.camera import CameraModel, CameraModelError
        from obstacle_fusion.vision.measure import STREAM_RIG_CHECK, Measurer

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
        self._impl.rig_check = STREAM_RIG_CHECK  # built for a stream's frames
        self._impl.prepare_size(w, h)
        self.camera_model = camera

    def camera_at(self, width: int, height: int) -> Any:
        """The measuring camera at this frame size (None before the first frame)."""
        return None if self.camera_model is None else self.camera_model.scaled_to(width, height)

    def measure(self, image: Any, range_m: float) -> Any:
        if self._impl is None:
            self.prepare(image)
        if self.rig is None and self.rig_provider is not None:
            online_rig = self.rig_provider()
            if online_rig is not None:
                if self._online is None or _rig_moved(self._online[0], online_rig):
                    from obstacle_fusion.vision.measure import STREAM_RIG_CHECK, Measurer

                    online = Measurer(
                        self.camera_model, online_rig, self.method, rig_source="estimated"
                    )
                    online.rig_check = STREAM_RIG_CHECK  # a stream's frames
                    self._online = (online_rig, online)
                return self._online[1].measure(image, range_m)
        return self._impl.measure(image, range_m)


@dataclass
class _Watch:
    """One when_closer_than: fires on the record that crosses below `metres`."""

    metres: float
    callback: Callable[[ObstacleRecord], Any]
    closer: bool = False


@dataclass
class _Waiter:
    """One wait_for_closer_than: the first record below `metres`, whoever reads it when."""

    metres: float
    found: ObstacleRecord | None = None


def _record_online(recorder: Any, online: OnlineCalibration) -> None:
    """What the run learnt (online rig, camera latency), as the recording's last metadata."""
    import json

    recorder.add_metadata("online", {k: json.dumps(v) for k, v in online.summary().items()})


def _check_span(name: str, value: float | None, lo: float, hi: float) -> None:
    if value is not None and not lo <= value <= hi:
        raise UserError(f"{name} must be within {lo:g}..{hi:g}, got {value}")


def camera_dict(camera: Any) -> dict[str, Any] | None:
    """A camera model as the MCAP metadata holds it."""
    if camera is None:
        return None
    return {
        "camera_matrix": [list(map(float, row)) for row in camera.camera_matrix],
        "dist_coeffs": [float(v) for v in camera.dist_coeffs],
        "width": camera.width,
        "height": camera.height,
    }


class ObstacleSensor:
    """The obstacle ahead, live: a context manager (``with``) or ``run()`` in the foreground.

    ``port``: the board's serial port; ``camera``: a camera index, ``/dev/videoN``, a video
    file or an image folder; neither: the emulated robot (``scenario`` picks its scene).
    ``calib``/``rig``: files (or CameraModel/Rig objects) as the CLI's ``--calib``/``--rig``.
    ``record``/``video``/``foxglove``/``ros2_bag``/``json_stream``/``console``: the CLI's
    outputs, optional here too (``foxglove``: ``"[HOST:]PORT"`` of a live Foxglove WebSocket
    server; ``ros2_bag``: a ROS 2 bag folder to write).
    """

    def __init__(
        self,
        port: str | None = None,
        camera: str | int | None = None,
        calib: str | Path | CameraModel | None = None,
        rig: str | Path | Rig | None = None,
        *,
        max_distance: float = DEFAULT_MAX_DISTANCE_M,
        baud: int = 115200,
        method: str = "fused",
        stop_distance: float | None = None,
        exit_on_alert: int | None = None,
        temperature: float | None = None,
        median: int = 1,
        half_spacing_mm: float = 13.0,
        pair_tolerance_ms: float = 50.0,
        max_wait_ms: float = 250.0,
        width: int | None = None,
        height: int | None = None,
        fps: float | None = None,
        camera_latency_ms: float | None = None,
        scenario: str | Path | Scenario | None = None,
        emulated_latency_ms: float = 0.0,
        clock_ppm: float = 0.0,
        duration: float | None = None,
        record: str | Path | None = None,
        video: str | Path | None = None,
        foxglove: str | None = None,
        ros2_bag: str | Path | None = None,
        overwrite: bool = False,
        json_stream: TextIO | None = None,
        console: TextIO | None = None,
        queue_size: int = 256,
        connect_timeout: float = 20.0,
        pairing: str = "predicted",
        max_extrapolation_ms: float = 200.0,
        sensors: int | None = None,
    ) -> None:
        if max_distance <= 0:
            raise UserError(f"max_distance must be > 0 m, got {max_distance}")
        _check_span("max_wait_ms", max_wait_ms, 0.0, 5000.0)
        _check_span("max_extrapolation_ms", max_extrapolation_ms, 10.0, 1000.0)
        if pairing not in ("predicted", "interpolated"):
            raise UserError(f"pairing must be 'predicted' or 'interpolated', got {pairing!r}")
        if sensors is not None and not 1 <= sensors <= 4:
            raise UserError(f"sensors must be within 1..4, got {sensors}")
        _check_span("half_spacing_mm", half_spacing_mm, 0.0, 50.0)
        _check_span("pair_tolerance_ms", pair_tolerance_ms, 0.0, 1000.0)
        _check_span("camera_latency_ms", camera_latency_ms, 0.0, 2000.0)
        _check_span("emulated_latency_ms", emulated_latency_ms, 0.0, 2000.0)
        if emulated_latency_ms and (port or camera is not None):
            raise UserError(
                "emulated_latency_ms is for the emulated robot; leave out port and camera"
            )
        _check_span("temperature", temperature, -50.0, 80.0)
        if exit_on_alert is not None and stop_distance is None:
            raise UserError("exit_on_alert needs stop_distance (the alert's threshold)")
        if scenario is not None and (port or camera is not None):
            raise UserError("a scenario is for the emulated robot; leave out port and camera")
        if median < 1:
            raise UserError(f"median must be >= 1 readings, got {median}")
        if video is not None and port and camera is None:
            raise UserError("a video needs a camera: sonar-only runs have no frames")
        self.port = port
        self.camera = camera
        self.calib = calib
        self.rig = rig
        self._max_distance = float(max_distance)
        self.baud = baud
        self.method = method
        self.stop_distance = stop_distance
        self.exit_on_alert = exit_on_alert
        self.temperature = temperature
        self.median = median
        self.half_spacing_mm = half_spacing_mm
        self.pair_tolerance_ms = pair_tolerance_ms
        self.max_wait_ms = max_wait_ms
        self.pairing = pairing
        self.max_extrapolation_ms = max_extrapolation_ms
        self.sensors = sensors
        self.width, self.height, self.fps = width, height, fps
        #: None: estimated during the run and used for pairing once confident (online.py)
        self.camera_latency_ms = camera_latency_ms
        self.emulated_latency_ms = emulated_latency_ms
        self.online: OnlineCalibration | None = None  # the online rig and latency, once built
        self.scenario_spec = scenario
        self.clock_ppm = clock_ppm
        self.duration = duration
        self.record = Path(record) if record is not None else None
        self.video = Path(video) if video is not None else None
        self.ros2_bag = Path(ros2_bag) if ros2_bag is not None else None
        self.overwrite = overwrite
        self.json_stream = json_stream
        self.console = console
        self.queue_size = queue_size
        self.connect_timeout = connect_timeout

        self.mode = "emulator" if not port and camera is None else (
            "sonar-only" if camera is None else "robot"
        )  # fmt: skip
        self.scenario: Scenario | None = None  # the emulated robot's, once started
        self.robot: EmulatedRobot | None = None
        self.app: App | None = None
        self.result: RunResult | None = None
        self.view: Any = None  # the console view, when `console` is given
        self.dropped = 0  # records a slow iterator missed (its queue was full)
        self.live: Any = None  # the live Foxglove server, while open
        self.foxglove_address: Any = None
        self._check_outputs(foxglove)

        self._lock = threading.Lock()
        self._changed = threading.Condition(self._lock)
        self._latest: ObstacleRecord | None = None
        self._subscribers: list[queue.Queue[Any]] = []
        self._async_subscribers: list[tuple[asyncio.AbstractEventLoop, asyncio.Queue[Any]]] = []
        self._watches: list[_Watch] = []
        self._waiters: list[_Waiter] = []
        self._callbacks: list[Callable[[ObstacleRecord], Any]] = []
        self._stack: ExitStack | None = None
        self._thread: threading.Thread | None = None
        self._connected = threading.Event()
        self._finished = threading.Event()
        self._error: BaseException | None = None

    def _check_outputs(self, foxglove: str | None) -> None:
        """What the outputs need, before anything starts: a free --foxglove port, the
        optional packages (foxglove-sdk, rosbags, PyAV), a video path the writer can make."""
        if foxglove is not None:
            from obstacle_fusion.outputs.live_foxglove import Address, check_free, require_sdk

            self.foxglove_address = Address.parse(foxglove)
            require_sdk()
            check_free(self.foxglove_address)  # a taken port ends the run before it starts
        if self.ros2_bag is not None:
            from obstacle_fusion.outputs.ros2_bag import require_rosbags

            require_rosbags()
        if self.video is not None:
            from obstacle_fusion.outputs.video import check_video_path

            check_video_path(self.video)

    # ------------------------------------------------------------------ reading it
    @property
    def latest(self) -> ObstacleRecord | None:
        """The newest obstacle record (None before the first)."""
        self._raise_if_failed()
        return self._latest

    @property
    def max_distance(self) -> float:
        """The farthest distance reported; farther, or nothing heard, reads as this."""
        return self._max_distance

    @max_distance.setter
    def max_distance(self, metres: float) -> None:
        if metres <= 0:
            raise ValueError(f"max_distance must be > 0 m, got {metres}")
        self._max_distance = float(metres)

    @property
    def distance(self) -> float | None:
        """The newest distance in metres, at most max_distance (max_distance when the sonar
        hears nothing in range); None while unknown (no record yet, or the newest one has
        no valid range: a sonar error or a frame with no reading near it)."""
        return self._distance_of(self.latest)

    def _distance_of(self, rec: ObstacleRecord | None) -> float | None:
        if rec is None:
            return None
        if rec.distance_m is not None:
            return min(rec.distance_m, self._max_distance)
        if rec.status == ObstacleStatus.CLEAR:
            return self._max_distance
        return None

    @property
    def connected(self) -> bool:
        return self._connected.is_set() and not self._finished.is_set()

    @property
    def running(self) -> bool:
        return self._thread is not None and not self._finished.is_set()

    def __iter__(self) -> Iterator[ObstacleRecord]:
        """Every record from now on, blocking; ends when the sensor stops."""
        q = self._subscribe()
        try:
            while True:
                item = q.get()
                if item is _END:
                    self._raise_if_failed()
                    return
                yield item
        finally:
            self._unsubscribe(q)

    def on_record(self, callback: Callable[[ObstacleRecord], Any]) -> Callable[[], None]:
        """Call ``callback(record)`` for every record (Telemetrix's callback per reading).
        Returns a function that removes it."""
        with self._lock:
            self._callbacks.append(callback)

        def remove() -> None:
            with self._lock:
                if callback in self._callbacks:
                    self._callbacks.remove(callback)

        return remove

    def when_closer_than(
        self, metres: float, callback: Callable[[ObstacleRecord], Any]
    ) -> Callable[[], None]:
        """Call ``callback(record)`` each time the distance drops below ``metres`` (from
        farther, clear or unknown). Returns a function that removes the callback."""
        if metres <= 0:
            raise ValueError(f"metres must be > 0, got {metres}")
        with self._lock:
            latest = self._distance_of(self._latest)
            watch = _Watch(metres, callback, closer=latest is not None and latest < metres)
            self._watches.append(watch)

        def remove() -> None:
            with self._lock:
                if watch in self._watches:
                    self._watches.remove(watch)

        return remove

    def wait_for_closer_than(
        self, metres: float, timeout: float | None = None
    ) -> ObstacleRecord | None:
        """The first record (the newest, if it already is) closer than ``metres``; None when
        ``timeout`` seconds pass or the sensor stops first. No record is missed, however
        fast they come: each one is checked as it is published."""
        deadline = None if timeout is None else time.monotonic() + timeout
        with self._changed:
            rec = self._latest
            d = self._distance_of(rec)
            if rec is not None and d is not None and d < metres:
                return rec
            waiter = _Waiter(metres)
            self._waiters.append(waiter)
            try:
                while waiter.found is None and self._error is None:
                    if self._finished.is_set():
                        return None
                    left = None if deadline is None else deadline - time.monotonic()
                    if left is not None and left <= 0:
                        return None
                    self._changed.wait(0.5 if left is None else min(left, 0.5))
            finally:
                self._waiters.remove(waiter)
            if waiter.found is not None:
                return waiter.found
        self._raise_if_failed()
        return None

    # ------------------------------------------------------------------ life cycle
    def open(self) -> ObstacleSensor:
        """Start in the background; return once the board answers (or raise why not)."""
        if self._thread is not None:
            raise UserError("this sensor is already open")
        stack = ExitStack()
        try:
            app = self._build(stack)
        except BaseException:
            stack.close()
            raise
        self._stack = stack
        self._thread = threading.Thread(
            target=self._run_thread, args=(app,), name="obstacle-sensor", daemon=True
        )
        self._thread.start()
        deadline = time.monotonic() + self.connect_timeout
        while not self._connected.wait(0.05):
            if self._finished.is_set() or time.monotonic() > deadline:
                error = self._error
                self.close()
                if error is not None:
                    raise error
                where = self.port or (
                    "the emulated robot"
                    if self.mode == "emulator"
                    else "the board found by USB VID:PID"
                )
                raise SensorError(
                    f"the board did not answer within {self.connect_timeout:g} s ({where})"
                )
        return self

    def close(self) -> None:
        """Stop and close everything it opened (outputs are finished, nothing is lost)."""
        if self.app is not None:
            self.app.stop()
        if self._thread is not None:
            self._thread.join(15.0)
        if self._stack is not None:
            self._stack.close()
            self._stack = None
        self._finish()

    def run(self, on_ready: Callable[[ObstacleSensor], None] | None = None) -> RunResult:
        """The whole run in this thread (what `obstacle-fusion run` does): until the
        duration, the end of the frame source, an alert exit or Ctrl-C. ``on_ready`` is
        called once everything is open, before the loop."""
        with ExitStack() as stack:
            app = self._build(stack)
            if on_ready is not None:
                on_ready(self)
            try:
                self.result = app.run()
            finally:
                self._finish()
            return self.result

    def __enter__(self) -> ObstacleSensor:
        return self.open()

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    # ------------------------------------------------------------------ inside
    def _run_thread(self, app: App) -> None:
        try:
            self.result = app.run()
        except BaseException as exc:  # reported to the caller, not lost in a thread
            self._error = exc
            log.debug("sensor stopped: %r", exc)
        finally:
            self._finish()

    def _finish(self) -> None:
        with self._changed:
            if self._finished.is_set():
                return
            self._finished.set()
            self._changed.notify_all()
            subscribers = list(self._subscribers)
            async_subscribers = list(self._async_subscribers)
        for q in subscribers:
            self._put(q, _END)
        for loop, aq in async_subscribers:
            self._put_async(loop, aq, _END)

    def _raise_if_failed(self) -> None:
        if self._error is not None:
            error = self._error
            if isinstance(error, UserError):
                raise error
            raise SensorError(f"the sensor stopped: {error!r}") from error

    def _subscribe(self) -> queue.Queue[Any]:
        q: queue.Queue[Any] = queue.Queue(maxsize=self.queue_size)
        with self._lock:
            self._subscribers.append(q)
            if self._finished.is_set():
                q.put_nowait(_END)
        return q

    def _unsubscribe(self, q: queue.Queue[Any]) -> None:
        with self._lock:
            if q in self._subscribers:
                self._subscribers.remove(q)

    def _subscribe_async(self, loop: asyncio.AbstractEventLoop) -> asyncio.Queue[Any]:
        aq: asyncio.Queue[Any] = asyncio.Queue(maxsize=self.queue_size)
        with self._lock:
            self._async_subscribers.append((loop, aq))
            if self._finished.is_set():
                aq.put_nowait(_END)
        return aq

    def _unsubscribe_async(self, aq: asyncio.Queue[Any]) -> None:
        with self._lock:
            self._async_subscribers = [(lp, q) for lp, q in self._async_subscribers if q is not aq]

    def _put(self, q: queue.Queue[Any], item: Any) -> None:
        while True:
            try:
                q.put_nowait(item)
                return
            except queue.Full:
                try:
                    q.get_nowait()  # a slow reader loses the oldest record, counted
                    self.dropped += 1
                except queue.Empty:
                    pass

    def _put_async(
        self, loop: asyncio.AbstractEventLoop, aq: asyncio.Queue[Any], item: Any
    ) -> None:
        def put() -> None:
            while True:
                try:
                    aq.put_nowait(item)
                    return
                except asyncio.QueueFull:
                    aq.get_nowait()
                    self.dropped += 1

        try:
            loop.call_soon_threadsafe(put)
        except RuntimeError:  # that event loop is closed: nobody is listening
            pass

    def _deliver(self, rec: ObstacleRecord) -> None:
        """Each published record, in the loop's thread."""
        fire: list[_Watch] = []
        with self._changed:
            self._latest = rec
            d = self._distance_of(rec)
            for w in self._watches:
                closer = d is not None and d < w.metres
                if closer and not w.closer:
                    fire.append(w)
                w.closer = closer
            for waiter in self._waiters:
                if waiter.found is None and d is not None and d < waiter.metres:
                    waiter.found = rec
            subscribers = list(self._subscribers)
            async_subscribers = list(self._async_subscribers)
            callbacks = list(self._callbacks)
            self._changed.notify_all()
        for q in subscribers:
            self._put(q, rec)
        for loop, aq in async_subscribers:
            self._put_async(loop, aq, rec)
        for callback in callbacks:
            try:
                callback(rec)
            except Exception:  # a robot's callback must not stop the sensor
                log.exception("on_record callback failed")
        for w in fire:
            try:
                w.callback(rec)
            except Exception:  # a robot's callback must not stop the sensor
                log.exception("when_closer_than(%g) callback failed", w.metres)

    def _build(self, stack: ExitStack) -> App:
        """Open the robot (or the emulated one), the frame source, the link and the outputs;
        everything opened is closed by `stack`."""
        from obstacle_fusion.app import App, RunSettings
        from obstacle_fusion.link.connection import Link, resolve_port
        from obstacle_fusion.vision.rig import Rig

        rig = self.rig if isinstance(self.rig, Rig) else (Rig.load(self.rig) if self.rig else Rig())
        calib_path: Path | None = None
        camera_model: Any = None
        if isinstance(self.calib, str | Path):
            from obstacle_fusion.vision.camera import CameraModel

            calib_path = Path(self.calib)
            camera_model = CameraModel.load(calib_path)
        elif self.calib is not None:
            camera_model = self.calib
        settings = RunSettings(
            duration_s=self.duration,
            stop_distance_m=self.stop_distance,
            exit_on_alert=self.exit_on_alert,
            temperature_c=20.0 if self.temperature is None else self.temperature,
            median_window=self.median,
            half_spacing_m=self.half_spacing_mm / 1e3,
            pair_tolerance_s=self.pair_tolerance_ms / 1e3,
            max_wait_s=self.max_wait_ms / 1e3,
            method=self.method,
            mode="emulator" if self.mode == "emulator" else "robot",
            pairing=self.pairing,
            max_extrapolation_s=self.max_extrapolation_ms / 1e3,
            sensors=self.sensors if self.sensors is not None else rig.sensor_count_wanted(),
        )
        robot = None
        extra = None
        source: Any = None
        port: Any
        if self.mode == "emulator":
            from obstacle_fusion.sim.emulated_robot import EmulatedRobot
            from obstacle_fusion.sim.scenario import Scenario, demo_scenario, load_scenario
            from obstacle_fusion.sim.synthetic_camera import SyntheticCamera, synthetic_camera_model

            spec = self.scenario_spec
            scenario = (
                spec if isinstance(spec, Scenario) else load_scenario(spec) if spec else None
            ) or demo_scenario()
            if self.temperature is not None and self.temperature != scenario.temperature_c:
                scenario = dataclasses.replace(scenario, temperature_c=self.temperature)
            self.scenario = scenario
            log.info("the emulated robot: scene %r, %g s", scenario.name, scenario.duration_s)
            if settings.sensors is None and scenario.sensor_count > 1:
                settings.sensors = scenario.sensor_count
            robot = EmulatedRobot(
                scenario, clock_ppm=self.clock_ppm, sensors=settings.sensors or 1
            ).start()
            stack.callback(robot.stop)
            self.robot = robot
            if camera_model is None:
                camera_model = synthetic_camera_model(self.width or 500, self.height or 375)
            synthetic = SyntheticCamera(
                scenario,
                camera_model,
                rig,
                fps=self.fps or 15.0,
                scene_time=robot.scene_time,
                latency_s=self.emulated_latency_ms / 1e3,
            )
            source = synthetic
            settings.temperature_c = scenario.temperature_c
            if settings.duration_s is None:
                settings.duration_s = scenario.duration_s
            port = robot.port

            def extra(rec: ObstacleRecord) -> dict[str, Any]:
                return {"scene_t_s": synthetic.scene_time_of(rec.frame_index)}

        else:
            port = resolve_port(self.port)
            if self.camera is not None:
                from obstacle_fusion.sources.opencv_sources import open_source

                source = open_source(
                    self.camera,
                    width=self.width,
                    height=self.height,
                    fps=self.fps,
                    latency_s=(self.camera_latency_ms or 0.0) / 1e3,
                    realtime=True,
                )
        if source is not None:
            stack.callback(source.close)
        link = Link(port, baud=self.baud)
        from obstacle_fusion.outputs.foxglove_schemas import FoxgloveTopics

        topics = FoxgloveTopics(rig=rig, camera=camera_model)  # one encoder: record and live
        jsonl = None
        if self.json_stream is not None:
            from obstacle_fusion.outputs.jsonl import JsonLinesWriter

            jsonl = JsonLinesWriter(self.json_stream)
        recorder = None
        if self.record is not None:
            import json

            from obstacle_fusion.outputs.mcap_file import McapRecorder

            recorder = _start_recorder(
                McapRecorder,
                self.record,
                overwrite=self.overwrite,
                topics=topics,
                metadata={
                    "run": {
                        "mode": settings.mode if self.mode != "sonar-only" else "sonar-only",
                        "method": self.method,
                        "temperature_c": str(settings.temperature_c),
                        "half_spacing_m": str(settings.half_spacing_m),
                        "stop_distance_m": str(self.stop_distance),
                        "rig": json.dumps(dataclasses.asdict(rig)),
                        "rig_source": "file" if self.rig is not None else "default",
                        "camera_latency_ms": str(self.camera_latency_ms),
                        "camera": json.dumps(camera_dict(camera_model)),
                        "pairing": settings.pairing,
                        "max_extrapolation_s": str(settings.max_extrapolation_s),
                        "sensors": str(settings.sensors or 1),
                    }
                },
            )
            stack.callback(recorder.close)
        video = None
        if self.video is not None:
            if source is None:
                raise UserError("a video needs a camera: sonar-only runs have no frames")
            from obstacle_fusion.outputs.video import AnnotatedVideoWriter

            video = AnnotatedVideoWriter(self.video, fps=self.fps or 15.0, overwrite=self.overwrite)
            stack.callback(video.close)
        live = None
        if self.foxglove_address is not None:
            from obstacle_fusion.outputs.live_foxglove import FoxgloveLiveServer

            live = FoxgloveLiveServer(self.foxglove_address)
            stack.callback(live.close)
            log.info("Foxglove live on %s", live.url)
        ros2 = None
        if self.ros2_bag is not None:
            from obstacle_fusion.outputs.ros2_bag import Ros2BagWriter

            ros2 = Ros2BagWriter(self.ros2_bag, topics=topics, overwrite=self.overwrite)
            stack.callback(ros2.close)
        view = None
        if self.console is not None:
            from obstacle_fusion.outputs.console import ConsoleView

            view = ConsoleView(self.console)
            stack.callback(view.close)
        # a real camera with no rig: the floor contact is found in each frame, never a
        # guessed camera height; the emulated robot films with a known rig
        measure_rig = rig if (self.mode == "emulator" or self.rig is not None) else None
        measurer = (
            LazyMeasurer(camera_model, measure_rig, self.method, calib_path)
            if source is not None
            else None
        )
        online = None
        if measurer is not None:
            from obstacle_fusion.online import OnlineCalibration

            given = None if self.camera_latency_ms is None else self.camera_latency_ms / 1e3
            online = OnlineCalibration(
                rig,
                rig_source="file"
                if self.rig is not None
                else ("default" if self.mode == "emulator" else "none"),
                latency_given_s=given,
                # the synthetic camera stamps frames as read; a real source subtracts it itself
                stamp_shift_s=(given or 0.0) if self.mode == "emulator" else 0.0,
                camera_of=measurer.camera_at,
            )
            if measure_rig is None:  # no rig file: measure with the online fit once it exists
                measurer.rig_provider = online.estimated_rig
            if recorder is not None:  # runs before the recorder closes (LIFO)
                stack.callback(_record_online, recorder, online)
        self.online = online
        app = App(
            settings,
            link,
            source,
            measurer,
            jsonl=jsonl,
            recorder=recorder,
            video=video,
            view=view,
            robot=robot,
            extra_fields=extra,
            live=live,
            ros2=ros2,
            topics=topics,
            on_record=self._deliver,
            on_connect=self._connected.set,
            online=online,
            beams=_beams(rig, measurer),
        )
        self.app = app
        self.view = view
        self.live = live
        return app


def _beams(rig: Any, measurer: LazyMeasurer | None) -> Any:
    """Several sonars on the rig, and a camera: which beam covers the image's box."""
    if measurer is None or len(rig.sonar_mounts()) < 2:
        return None
    from obstacle_fusion.vision.rig import BeamSelector

    return BeamSelector(rig, lambda: measurer.camera_model)


class AsyncObstacleSensor:
    """The asyncio twin: ``async with AsyncObstacleSensor() as s: async for rec in s: ...``.

    Takes the same arguments as :class:`ObstacleSensor`; the sensor's loop runs in its own
    thread and hands records to the event loop, which never blocks on the board."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self.sensor = ObstacleSensor(*args, **kwargs)
        self._loop: asyncio.AbstractEventLoop | None = None

    @property
    def latest(self) -> ObstacleRecord | None:
        return self.sensor.latest

    @property
    def distance(self) -> float | None:
        return self.sensor.distance

    @property
    def max_distance(self) -> float:
        return self.sensor.max_distance

    @max_distance.setter
    def max_distance(self, metres: float) -> None:
        self.sensor.max_distance = metres

    async def open(self) -> AsyncObstacleSensor:
        self._loop = asyncio.get_running_loop()
        await self._loop.run_in_executor(None, self.sensor.open)
        return self

    async def close(self) -> None:
        await asyncio.get_running_loop().run_in_executor(None, self.sensor.close)

    async def __aenter__(self) -> AsyncObstacleSensor:
        return await self.open()

    async def __aexit__(self, *exc: object) -> None:
        await self.close()

    async def _records(self) -> AsyncIterator[ObstacleRecord]:
        aq = self.sensor._subscribe_async(asyncio.get_running_loop())
        try:
            while True:
                item = await aq.get()
                if item is _END:
                    self.sensor._raise_if_failed()
                    return
                yield item
        finally:
            self.sensor._unsubscribe_async(aq)

    def __aiter__(self) -> AsyncIterator[ObstacleRecord]:
        return self._records()

    def _on_loop(
        self, callback: Callable[[ObstacleRecord], Awaitable[Any] | Any]
    ) -> Callable[[ObstacleRecord], None]:
        """A callback that runs on this event loop (a coroutine function is scheduled)."""
        loop = self._loop or asyncio.get_running_loop()

        def fire(rec: ObstacleRecord) -> None:
            if inspect.iscoroutinefunction(callback):
                asyncio.run_coroutine_threadsafe(callback(rec), loop)
            else:
                loop.call_soon_threadsafe(callback, rec)

        return fire

    def on_record(
        self, callback: Callable[[ObstacleRecord], Awaitable[Any] | Any]
    ) -> Callable[[], None]:
        """As ObstacleSensor's (every record), run on this event loop."""
        return self.sensor.on_record(self._on_loop(callback))

    def when_closer_than(
        self,
        metres: float,
        callback: Callable[[ObstacleRecord], Awaitable[Any] | Any],
    ) -> Callable[[], None]:
        """As ObstacleSensor's; a coroutine function runs on this event loop."""
        return self.sensor.when_closer_than(metres, self._on_loop(callback))

    async def wait_for_closer_than(
        self, metres: float, timeout: float | None = None
    ) -> ObstacleRecord | None:
        """As ObstacleSensor's, without blocking the event loop."""
        rec = self.sensor._latest
        d = self.sensor._distance_of(rec)
        if rec is not None and d is not None and d < metres:
            return rec
        loop = asyncio.get_running_loop()
        found: asyncio.Future[ObstacleRecord] = loop.create_future()

        def done(r: ObstacleRecord) -> None:
            if not found.done():
                found.set_result(r)

        remove = self.sensor.when_closer_than(metres, lambda r: loop.call_soon_threadsafe(done, r))
        deadline = None if timeout is None else loop.time() + timeout
        try:
            while True:
                left = None if deadline is None else deadline - loop.time()
                if left is not None and left <= 0:
                    return None
                try:
                    return await asyncio.wait_for(
                        asyncio.shield(found), 0.2 if left is None else min(left, 0.2)
                    )
                except TimeoutError:
                    if not self.sensor.running:
                        self.sensor._raise_if_failed()
                        return None
        finally:
            remove()


def _start_recorder(cls: Any, path: Any, **kwargs: Any) -> Any:
    """The recorder, or a UserError when the file cannot even be started (disk full)."""
    try:
        return cls(path, **kwargs)
    except OSError as exc:
        raise UserError(f"cannot start the recording {path}: {exc.strerror or exc}") from None
