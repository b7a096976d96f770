"""The run loop: link messages and camera frames in, obstacle records out.

Nothing here blocks on a device: the link has its reader thread and queue, the frame
source gets a grabber thread and a short queue (a slow consumer drops the oldest frame,
counted, rather than pairing stale ones). One loop drains both, keeps the clock model fed,
converts ranges, pairs frames, measures, and publishes to every output.

With no frame source (a robot with only the sonar) every range is published as a record on
its own (status "range", "clear" or "sonar_error"), and OpenCV is never loaded.
"""

from __future__ import annotations

import dataclasses
import logging
import queue
import sys
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from obstacle_fusion.fusion import (
    BeamChooser,
    Fusion,
    ObstacleRecord,
    PairingMode,
    RangePairer,
    TrackSettings,
)
from obstacle_fusion.link.connection import (
    Link,
    LinkError,
    PendingCommand,
    Received,
    describe_hello,
)
from obstacle_fusion.online import OnlineCalibration
from obstacle_fusion.outputs.console import ConsoleView, RateMeter, Status
from obstacle_fusion.outputs.foxglove_schemas import FoxgloveTopics, TopicMessage, encode_image
from obstacle_fusion.outputs.jsonl import JsonLinesWriter
from obstacle_fusion.protocol.generated import (
    Config,
    GetInfo,
    Hello,
    Log,
    Nack,
    Range,
    RangeStatus,
    SetConfig,
    TimeSyncReply,
)
from obstacle_fusion.sim.emulated_robot import EmulatedRobot
from obstacle_fusion.sonar import SonarConverter
from obstacle_fusion.sources.frames import Frame, FrameSource
from obstacle_fusion.timing.clock import ClockModel

if TYPE_CHECKING:  # imported where they are made: a sonar-only run never loads OpenCV
    from obstacle_fusion.outputs.mcap_file import McapRecorder
    from obstacle_fusion.outputs.video import AnnotatedVideoWriter

log = logging.getLogger(__name__)


@dataclass
class RunSettings:
    duration_s: float | None = None
    stop_distance_m: float | None = None
    exit_on_alert: int | None = None
    temperature_c: float = 20.0
    half_spacing_m: float = 0.013
    median_window: int = 1
    pair_tolerance_s: float = 0.05
    max_gap_s: float = 0.2
    max_wait_s: float = 0.25
    first_range_timeout_s: float = 5.0
    method: str | None = None
    mode: str = "robot"
    pairing: str = "predicted"  # or "interpolated" (waits for the echo after each frame)
    max_extrapolation_s: float = 0.2  # a prediction never reaches further past a reading
    sensors: int | None = None  # sonars to range (SET_CONFIG sensor_mask); None: as the board is

    def per_sensor_span(self) -> float:
        """The board ranges its sonars in turn, so each one's readings are N cycles apart:
        the gap limits (interpolation, extrapolation) scale with the number of sonars."""
        return float(max(self.sensors or 1, 1))


class FrameGrabber:
    """Reads a frame source on its own thread into a short queue."""

    def __init__(self, source: FrameSource, maxsize: int = 4) -> None:
        self.source = source
        self.queue: queue.Queue[Frame] = queue.Queue(maxsize=maxsize)
        self.dropped = 0
        self.finished = threading.Event()
        self.error: BaseException | None = None
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="frame-grabber", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def _run(self) -> None:
        try:
            while not self._stop.is_set():
                frame = self.source.read()
                if frame is None:
                    break
                while True:
                    try:
                        self.queue.put_nowait(frame)
                        break
                    except queue.Full:
                        try:
                            self.queue.get_nowait()
                            self.dropped += 1
                        except queue.Empty:
                            pass
        except BaseException as exc:  # reported by the loop, not lost in a thread
            self.error = exc
        finally:
            self.finished.set()

    def stop(self) -> None:
        self._stop.set()
        if self._thread.ident is not None:
            self._thread.join(timeout=3.0)


@dataclass
class RunResult:
    exit_code: int
    stats: dict[str, Any] = field(default_factory=dict)


class App:
    """Owns nothing it was given; close what you opened after run() returns."""

    def __init__(
        self,
        settings: RunSettings,
        link: Link,
        source: FrameSource | None,
        measurer: Any = None,
        *,
        jsonl: JsonLinesWriter | None = None,
        recorder: McapRecorder | None = None,
        video: AnnotatedVideoWriter | None = None,
        view: ConsoleView | None = None,
        robot: EmulatedRobot | None = None,
        extra_fields: Callable[[ObstacleRecord], dict[str, Any]] | None = None,
        live: Any = None,
        ros2: Any = None,
        topics: FoxgloveTopics | None = None,
        on_record: Callable[[ObstacleRecord], None] | None = None,
        on_connect: Callable[[], None] | None = None,
        beams: BeamChooser | None = None,
        online: OnlineCalibration | None = None,
    ) -> None:
        self.s = settings
        self.link = link
        self.source = source
        self.jsonl = jsonl
        self.recorder = recorder
        self.video = video
        self.view = view
        self.robot = robot
        self.extra_fields = extra_fields
        self.live = live  # a Foxglove WebSocket server (anything with write(TopicMessage))
        self.ros2 = ros2  # a Ros2BagWriter
        # One encoder for the recording and the live view: the same bytes go to both.
        self.topics = topics or (recorder.topics if recorder is not None else FoxgloveTopics())
        self._sinks = [s for s in (recorder, live) if s is not None]
        self.on_record = on_record  # called in the loop's thread for each published record
        self.on_connect = on_connect  # called once the link is up (each time it comes up)
        self._stop_requested = threading.Event()
        self.clock = ClockModel(baud=link.baud)
        self.converter = SonarConverter(
            temperature_c=settings.temperature_c,
            half_spacing_m=settings.half_spacing_m,
            median_window=settings.median_window,
        )
        span = settings.per_sensor_span()
        if hasattr(measurer, "rig_check"):
            from obstacle_fusion.vision.measure import STREAM_RIG_CHECK

            measurer.rig_check = STREAM_RIG_CHECK  # a stream's frames: see the constant
        self.fusion = Fusion(
            measurer=measurer,
            pairer=RangePairer(settings.pair_tolerance_s, settings.max_gap_s * span),
            stop_distance_m=settings.stop_distance_m,
            max_wait_s=settings.max_wait_s,
            method=settings.method,
            pairing=PairingMode(settings.pairing),
            track=TrackSettings(
                max_extrapolation_s=settings.max_extrapolation_s * span,
                max_gap_s=settings.max_gap_s * span,
            ),
            beams=beams,
        )
        self.config_sent_session = 0
        self.config_refused: str | None = None
        self.online = online
        if online is not None:
            self.fusion.observer = online.measured
        self.grabber = FrameGrabber(source) if source is not None else None
        self.session = 0
        self.timer_hz = 2_000_000
        self._unmapped: list[Received] = []
        self._images: dict[int, Any] = {}
        self.rates = {k: RateMeter() for k in ("frames", "ranges", "records")}
        self.status = Status(mode=settings.mode)
        self.latest: ObstacleRecord | None = None
        self.alerted = False
        self.ranges_mapped = 0
        self.ranges_unmapped_dropped = 0
        self._was_connected = False
        self._prepared = False
        self._commands: list[PendingCommand] = []
        self._carry: Frame | None = None
        self._drain_t = time.monotonic()
        self._log_t = 0.0
        self._online_logged = -1e9

    # ------------------------------------------------------------------ messages
    def _on_message(self, item: Received) -> list[ObstacleRecord]:
        msg = item.msg
        out: list[ObstacleRecord] = []
        if isinstance(msg, Hello):
            if item.session != self.session:
                out = self._map_ranges(item.t_host)  # the old session's, on the old clock
                self._unmapped.clear()
                self.session = item.session
                self.clock.reset()  # a new connection: the MCU may have rebooted
                self.converter.reset()
            self.timer_hz = msg.timer_hz
            self.converter.timer_hz = msg.timer_hz
            self._event("hello", {"session": item.session, "board": describe_hello(msg)})
            if self.s.sensors is not None and self.config_sent_session != item.session:
                self._send(GetInfo())  # its CONFIG answer says whether the mask is right
        elif isinstance(msg, Config):
            self._event("config", dataclasses.asdict(msg))
            self._check_config(msg, item.session)
        elif isinstance(msg, TimeSyncReply) and item.t_send is not None:
            self.clock.add_sync(item.t_send, item.t_host, msg.rx_us, msg.tx_us)
        elif isinstance(msg, Range):
            echo_us = msg.echo_ticks * 1_000_000 // max(self.timer_hz, 1)
            if msg.status != RangeStatus.TIMEOUT:  # a timeout's frame leaves at the timeout
                self.clock.add_oneway(item.t_host, (msg.trigger_us + echo_us) & 0xFFFFFFFF)
            self.rates["ranges"].tick(item.t_host)
            self._unmapped.append(item)
        elif isinstance(msg, Log):
            self._event("log", {"level": msg.level, "text": msg.text})
        return out

    def wanted_mask(self) -> int | None:
        n = self.s.sensors
        return None if n is None else (1 << n) - 1

    def _check_config(self, config: Config, session: int) -> None:
        """Ask for the sonars wanted (once per session: a NACK is reported, not retried)."""
        mask = self.wanted_mask()
        if mask is None or config.sensor_mask == mask or self.config_sent_session == session:
            return
        self.config_sent_session = session
        self._send(
            SetConfig(
                cycle_ms=config.cycle_ms,
                sensor_mask=mask,
                max_echo_us=config.max_echo_us,
                echo_timeout_us=config.echo_timeout_us,
                heartbeat_ms=config.heartbeat_ms,
            )
        )
        self._event("set_config", {"sensor_mask": mask, "session": session})

    def _send(self, msg: Any) -> None:
        try:
            pending = self.link.send(msg)
        except LinkError as exc:  # disconnected meanwhile: the next session asks again
            log.info("could not send %s: %s", msg.NAME, exc)
            self.config_sent_session = 0
            return
        if isinstance(msg, SetConfig):  # GET_INFO is answered by HELLO and CONFIG, not ACK
            self._commands.append(pending)

    def _check_commands(self) -> None:
        for pending in list(self._commands):
            reply = pending.reply
            if reply is None:
                if time.monotonic() - pending.t_send > 2.0:
                    self._commands.remove(pending)
                    log.warning("no answer to %s from the board", pending.msg.NAME)
                continue
            self._commands.remove(pending)
            if isinstance(reply, Nack):
                why = f"the board refused {pending.msg.NAME} (error {reply.error})"
                if isinstance(pending.msg, SetConfig):
                    self.config_refused = why
                log.error("%s", why)
                self._event("nack", {"command": pending.msg.NAME, "error": reply.error})

    def _map_ranges(self, now: float) -> list[ObstacleRecord]:
        """Convert the ranges waiting for the clock model (usually at once)."""
        out: list[ObstacleRecord] = []
        if not self._unmapped:
            return out
        if not self.clock.ready:
            stale = [r for r in self._unmapped if now - r.t_host > 2.0]
            if stale:
                self.ranges_unmapped_dropped += len(stale)
                self._unmapped = [r for r in self._unmapped if now - r.t_host <= 2.0]
            return out
        for item in self._unmapped:
            msg = item.msg
            assert isinstance(msg, Range)
            t_trig = self.clock.to_host(msg.trigger_us)
            est = self.clock.estimate()
            scale = est.slope if est is not None and est.source != "none" else 1.0
            reading = self.converter.convert(msg, t_trig, t_receipt=item.t_host, time_scale=scale)
            self.ranges_mapped += 1
            log_t = self._log_time(item.t_host)
            if self.online is not None:
                self.online.reading_in(reading)
            if self._sinks:
                self._emit(self.topics.reading(reading, self.timer_hz, item.session, log_t))
            if self.ros2 is not None:
                self.ros2.write_range(reading, log_t=log_t)
            if self.source is None:
                out.append(self.fusion.range_record(reading))
            else:
                out += self.fusion.add_reading(reading)
        self._unmapped.clear()
        return out

    def _emit(self, msgs: list[TopicMessage]) -> None:
        for sink in self._sinks:
            for m in msgs:
                sink.write(m)

    def _event(self, name: str, detail: dict[str, Any]) -> None:
        log.info("%s: %s", name, detail)
        if self._sinks:
            self._emit([self.topics.event(name, detail)])

    # ------------------------------------------------------------------ frames and records
    def _log_time(self, t: float) -> float:
        """The recording's log time for what is taken in now: its own instant (a range's
        receipt, a frame's drain), but never earlier than what was taken in before it, so
        the log order is the order the fusion saw (replay follows it)."""
        self._log_t = max(self._log_t, t)
        return self._log_t

    def _prepare_early(self) -> None:
        """A source that knows its frame size lets the measurer build its state before the
        first frame, so that frame does not wait for it."""
        size = getattr(self.source, "frame_size", None)
        if size is None:
            return
        width, height = int(size[0]), int(size[1])
        prepare = getattr(self.fusion.measurer, "prepare", None)
        if prepare is not None:
            prepare(np.zeros((height, width, 3), np.uint8))
            self._prepared = True
        elif hasattr(self.fusion.measurer, "prepare_size"):
            self.fusion.measurer.prepare_size(width, height)  # type: ignore[union-attr]

    def _on_frame(self, frame: Frame) -> list[ObstacleRecord]:
        if not self._prepared:
            # The measurer checks its calibration against the first frame's size: a camera it
            # cannot measure ends the run (UserError, exit 2) before anything is published.
            prepare = getattr(self.fusion.measurer, "prepare", None)
            if prepare is not None:
                prepare(frame.image)
            measurer = self.fusion.measurer
            camera = getattr(measurer, "camera_model", None) or getattr(measurer, "camera", None)
            if camera is not None:
                self.topics.set_camera(camera)
            self._prepared = True
        self.rates["frames"].tick()
        if self._sinks or self.ros2 is not None:
            # Logged at the instant the link was last drained, and never before what was
            # taken in ahead of it: replay, ordering by log time, gives this frame the same
            # readings the live fusion had.
            now = self._log_time(self._drain_t)
            h, w = frame.image.shape[:2]
            data = encode_image(frame.image, self.topics.image_format, self.topics.jpeg_quality)
            if data is None:
                log.warning("could not encode frame %d; not recorded", frame.index)
            else:
                if self._sinks:
                    self._emit(self.topics.encoded_frame(data, w, h, frame.t_host, now))
                if self.ros2 is not None:
                    self.ros2.write_image(data, self.topics.image_format, w, h, frame.t_host, now)
        if self.video is not None:
            self._images[frame.index] = frame.image
        if self.online is not None:
            frame = self.online.frame_in(frame)  # recorded raw, paired re-dated
        return self.fusion.add_frame(frame)

    def _publish(self, records: list[ObstacleRecord]) -> None:
        for rec in records:
            self.latest = rec
            self.rates["records"].tick()
            extra = self.extra_fields(rec) if self.extra_fields else None
            if self.jsonl is not None:
                self.jsonl.write(rec, extra)
            if self._sinks:
                self._emit(self.topics.record(rec))
            if self.ros2 is not None:
                self.ros2.write_record(rec)
            if self.on_record is not None:
                self.on_record(rec)
            if self.video is not None:
                image = self._images.pop(rec.frame_index, None)
                if image is not None:
                    self.video.write(image, rec)
            if rec.alert:
                self.alerted = True
        if self.video is not None and len(self._images) > 64:
            for k in sorted(self._images)[:-64]:
                del self._images[k]

    def _update_view(self, force: bool = False) -> None:
        if self.view is None:
            return
        st = self.status
        st.latest = self.latest
        st.link = self.link.counters.as_dict()
        st.fusion = self.fusion.stats.as_dict()
        est = self.clock.estimate()
        st.clock = (
            {"source": est.source, "drift_ppm": est.drift_ppm, "uncertainty_s": est.uncertainty_s}
            if est
            else {}
        )
        st.rates = {k: m.rate() for k, m in self.rates.items()}
        st.notes = [self.link.last_problem] if self.link.last_problem else []
        if self.online is not None:
            st.notes += [self.online.rig_text(), self.online.latency_text()]
        self.view.update(st, force=force)

    def _update_online(self, force: bool = False) -> None:
        if self.online is None:
            return
        before = (self.online.rig_estimate, self.online.latency_estimate)
        for text in self.online.update(force=force):
            self._event("online_warning", {"text": text})
        after = (self.online.rig_estimate, self.online.latency_estimate)
        if after != before and (force or time.monotonic() - self._online_logged >= 5.0):
            self._online_logged = time.monotonic()
            self._event("online_estimates", self.online.summary())

    def _watch_link(self) -> None:
        connected = self.link.connected
        if connected != self._was_connected:
            self._was_connected = connected
            self._event(
                "connected" if connected else "disconnected",
                {"port": self.link.counters.port, "counters": self.link.counters.as_dict()},
            )
            if connected and self.on_connect is not None:
                self.on_connect()
        if self.robot is not None and connected:
            self.robot.probe_t0()

    # ------------------------------------------------------------------ the loop
    def _wait_for_first_range(self, deadline: float) -> None:
        """Start the camera once ranges flow, so the first frames have a range to pair with.

        Sonar only (no camera) there is nothing to wait for: ranges are never paired, so
        waiting for one would only hold the run's start back by the whole time-out."""
        if self.grabber is None:
            return
        while time.monotonic() < deadline:
            if self.link.error is not None:
                raise self.link.error
            for item in self.link.drain():
                self._publish(self._on_message(item))
            self._publish(self._map_ranges(time.monotonic()))
            self._watch_link()
            if self.fusion.ready_for_frames() and (
                self.robot is None or self.robot.scene_time(time.monotonic()) is not None
            ):
                return
            time.sleep(0.01)
        log.warning(
            "no sonar range within %.1f s; starting the camera anyway", self.s.first_range_timeout_s
        )

    def stop(self) -> None:
        """End run() at its next turn (from another thread), as the duration would."""
        self._stop_requested.set()

    def run(self) -> RunResult:
        # The link and camera threads run Python too: with the default 5 ms GIL switch
        # interval a frame can wait that long for the loop to get the interpreter back.
        switch = sys.getswitchinterval()
        sys.setswitchinterval(min(switch, 0.0005))
        try:
            return self._run()
        finally:
            sys.setswitchinterval(switch)

    def _run(self) -> RunResult:
        start = time.monotonic()
        exit_code = 0
        self.link.start()
        grabber = self.grabber
        try:
            self._prepare_early()
            self._wait_for_first_range(start + self.s.first_range_timeout_s)
            if grabber is not None:
                grabber.start()
            run_start = time.monotonic()
            while not self._stop_requested.is_set():
                now = time.monotonic()
                if self.s.duration_s is not None and now - run_start >= self.s.duration_s:
                    break
                if self.link.error is not None:
                    raise self.link.error
                if self.robot is not None:
                    event = self.robot.check()
                    if event:
                        self._event("emulator_restart", {"detail": event})
                self._watch_link()
                records: list[ObstacleRecord] = []
                self._drain_t = time.monotonic()
                for item in self.link.drain():
                    records += self._on_message(item)
                records += self._map_ranges(now)
                got_frame = False
                while grabber is not None:
                    frame = self._carry
                    self._carry = None
                    if frame is None:
                        try:
                            frame = grabber.queue.get_nowait()
                        except queue.Empty:
                            break
                    got_frame = True
                    records += self._on_frame(frame)
                records += self.fusion.poll()
                self._publish(records)
                if self.alerted and self.s.exit_on_alert is not None:
                    exit_code = self.s.exit_on_alert
                    self._event("alert_exit", {"code": exit_code})
                    break
                if self.jsonl is not None and self.jsonl.broken:
                    log.info("the JSON reader went away (closed pipe); stopping")
                    break
                if grabber is not None and grabber.error is not None:
                    raise grabber.error
                if (
                    grabber is not None
                    and grabber.finished.is_set()
                    and grabber.queue.empty()
                    and self._carry is None
                ):
                    self._publish(self.fusion.flush())
                    log.info("frame source ended: %s", getattr(self.source, "end_reason", ""))
                    break
                self._update_online()
                self._update_view()
                self._check_commands()
                if not got_frame and not records:
                    # Idle: sleep until a frame comes (at once) or 2 ms pass (link, polls).
                    if grabber is None:
                        time.sleep(0.002)
                    else:
                        try:
                            self._carry = grabber.queue.get(timeout=0.002)
                        except queue.Empty:
                            pass
        finally:
            if grabber is not None:
                grabber.stop()
            try:
                for item in self.link.drain():
                    self._publish(self._on_message(item))
                self._publish(self._map_ranges(time.monotonic()))
                self._publish(self.fusion.flush())
                self._update_online(force=True)
                self._update_view(force=True)
            finally:
                self.link.close()
        return RunResult(exit_code, self.summary())

    def summary(self) -> dict[str, Any]:
        est = self.clock.estimate()
        return {
            "link": self.link.counters.as_dict(),
            "fusion": self.fusion.stats.as_dict(),
            "frames_dropped": self.grabber.dropped if self.grabber is not None else 0,
            "ranges_mapped": self.ranges_mapped,
            "ranges_dropped_before_clock": self.ranges_unmapped_dropped,
            "clock": None
            if est is None
            else {
                "source": est.source,
                "drift_ppm": est.drift_ppm,
                "uncertainty_s": est.uncertainty_s,
                "resets": self.clock.resets,
            },
            "emulator_restarts": self.robot.restarts if self.robot else 0,
            "online": None if self.online is None else self.online.summary(),
        }
