"""The serial link to a board: a reader thread, a queue, the handshake, commands, time sync.

The fusion loop never touches the port: one thread reads it, stamps every chunk with the
host's monotonic clock at the moment read() returned, decodes, and puts messages on a queue.
The same thread sends TIME_SYNC requests on a schedule (stamping them just before write) and
re-opens the port after an unplug or an emulator restart; the counters survive reconnects.
"""

from __future__ import annotations

import logging
import queue
import threading
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import serial

from obstacle_fusion.errors import UserError
from obstacle_fusion.protocol import StreamDecoder, encode
from obstacle_fusion.protocol.generated import (
    PROTOCOL_VERSION,
    SCHEMA_FINGERPRINT,
    Ack,
    Board,
    Config,
    GetInfo,
    Heartbeat,
    Hello,
    Log,
    LogLevel,
    Message,
    Nack,
    TimeSync,
    TimeSyncReply,
)
from obstacle_fusion.protocol.generated import Error as NackError

log = logging.getLogger(__name__)

_LOG_LEVELS: dict[int, int] = {
    int(LogLevel.DEBUG): logging.DEBUG,
    int(LogLevel.INFO): logging.INFO,
    int(LogLevel.WARNING): logging.WARNING,
}

PortProvider = Callable[[], str | None]
SerialFactory = Callable[[str, int], Any]


class LinkError(UserError):
    """The board cannot be used: no port, no answer, or a protocol mismatch."""


@dataclass(frozen=True, slots=True)
class Received:
    """A message with the host monotonic time its last byte was read and its session."""

    msg: Message
    t_host: float
    session: int
    t_send: float | None = None  # TIME_SYNC_REPLY only: when the matching request was written


@dataclass(slots=True)
class LinkCounters:
    """Link health; every field accumulates across reconnects."""

    frames: int = 0
    bytes: int = 0
    crc_errors: int = 0
    bad_frames: int = 0  # all undecodable frames, CRC ones included
    seq_gaps: int = 0
    resyncs: int = 0
    reconnects: int = 0
    board_restarts: int = 0  # HELLOs nobody asked for: the MCU rebooted on the same port
    queue_drops: int = 0  # messages lost because the consumer fell behind
    time_syncs_sent: int = 0
    time_syncs_answered: int = 0
    device_frames_sent: int = 0  # from HEARTBEAT
    device_rx_errors: int = 0
    device_tx_overruns: int = 0
    connected: bool = False
    session: int = 0
    port: str | None = None

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass
class PendingCommand:
    """A command sent and the ACK or NACK that answers it, matched by the frame's seq."""

    msg: Message
    seq: int
    t_send: float
    done: threading.Event = field(default_factory=threading.Event)
    reply: Ack | Nack | None = None

    def wait(self, timeout: float) -> Ack | Nack:
        if not self.done.wait(timeout) or self.reply is None:
            raise LinkError(
                f"no ACK/NACK for {self.msg.NAME} (seq {self.seq}) within {timeout:g} s; "
                "the board may be busy, resetting or not running obstacle-fusion firmware"
            )
        return self.reply


def _default_serial(port: str, baud: int) -> Any:
    return serial.serial_for_url(port, baudrate=baud, timeout=0.02, write_timeout=1.0)


def describe_hello(h: Hello) -> str:
    try:
        board = Board(h.board).name.lower()
    except ValueError:
        board = f"board#{h.board}"
    return (
        f"{board} firmware {h.fw_major}.{h.fw_minor}.{h.fw_patch}, protocol v{h.protocol_version}"
        f" schema {h.schema_fingerprint:#010x}, cpu {h.cpu_hz} Hz, timer {h.timer_hz} Hz,"
        f" {h.sensor_count} sensor(s)"
    )


def check_hello(h: Hello, port: str) -> None:
    """Refuse a board speaking another protocol, naming both sides and the fix."""
    if h.protocol_version != PROTOCOL_VERSION or h.schema_fingerprint != SCHEMA_FINGERPRINT:
        raise LinkError(
            f"{port}: the board speaks protocol v{h.protocol_version} (schema "
            f"{h.schema_fingerprint:#010x}) but this host speaks v{PROTOCOL_VERSION} (schema "
            f"{SCHEMA_FINGERPRINT:#010x}). Flash firmware built from this checkout "
            "(make -C firmware BOARD=uno flash) or install the host that matches the firmware."
        )
    if h.timer_hz <= 0:
        raise LinkError(
            f"{port}: the board announced timer_hz={h.timer_hz}; its firmware is broken"
        )


class Link:
    """A board on a serial port (or a pty), read on its own thread.

    ``port`` is a fixed path or a callable that returns the current one (auto-detection,
    or an emulator whose pty changes on restart). Messages come out of :meth:`get` in order.
    """

    def __init__(
        self,
        port: str | PortProvider,
        baud: int = 115200,
        *,
        reconnect: bool = True,
        handshake_timeout_s: float = 3.0,
        get_info_after_s: float = 0.3,
        sync_interval_s: float = 0.2,
        fast_sync_interval_s: float = 0.05,
        fast_sync_for_s: float = 2.0,
        retry_interval_s: float = 0.25,
        queue_size: int = 20000,
        serial_factory: SerialFactory = _default_serial,
    ) -> None:
        self._port_provider: PortProvider = port if callable(port) else (lambda: port)
        self._fixed_port = None if callable(port) else port
        self.baud = baud
        self.reconnect = reconnect
        self.handshake_timeout_s = handshake_timeout_s
        self.get_info_after_s = get_info_after_s
        self.sync_interval_s = sync_interval_s
        self.fast_sync_interval_s = fast_sync_interval_s
        self.fast_sync_for_s = fast_sync_for_s
        self.retry_interval_s = retry_interval_s
        self._serial_factory = serial_factory
        self.queue: queue.Queue[Received] = queue.Queue(maxsize=queue_size)
        self.counters = LinkCounters()
        self.hello: Hello | None = None
        self.config: Config | None = None
        self.error: LinkError | None = None  # fatal: the thread stopped because of it
        self.last_problem: str | None = None  # latest non-fatal trouble (for the live view)
        self._ser: Any = None
        self._decoder = StreamDecoder()
        self._base_stats: dict[str, int] = {}
        self._write_lock = threading.Lock()
        self._seq = 0
        self._token = 0
        self._pending: dict[int, PendingCommand] = {}
        self._sync_sent: dict[int, float] = {}
        self._stop = threading.Event()
        self._ready = threading.Event()
        self._thread: threading.Thread | None = None
        self._handshake_started = 0.0
        self._handshake_done = False
        self._last_get_info = 0.0
        self._held: list[tuple[Message, float]] = []
        self._next_sync = 0.0
        self._session_start = 0.0

    # ------------------------------------------------------------------ lifecycle
    def start(self, timeout_s: float | None = None) -> Hello:
        """Open, handshake, and keep reading in the background; raise LinkError on failure."""
        self._thread = threading.Thread(target=self._run, name="obstacle-fusion-link", daemon=True)
        self._thread.start()
        wait = self.handshake_timeout_s + 2.0 if timeout_s is None else timeout_s
        deadline = time.monotonic() + wait
        while not self._ready.wait(0.05):
            if self.error is not None:
                self.close()
                raise self.error
            if time.monotonic() > deadline:
                problem = self.last_problem or "no HELLO"
                self.close()
                raise LinkError(
                    f"the board did not complete the handshake within {wait:g} s ({problem}); "
                    f"{self.counters.bytes} bytes and {self.counters.bad_frames} bad frames seen. "
                    "Check the port, the baud rate (115200) and that the obstacle-fusion "
                    "firmware is flashed."
                )
        assert self.hello is not None
        return self.hello

    def close(self) -> None:
        self._stop.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=2.0)
        self._close_port()

    def __enter__(self) -> Link:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    @property
    def connected(self) -> bool:
        return self.counters.connected and self._handshake_done

    def get(self, timeout: float | None = None) -> Received | None:
        try:
            return self.queue.get(timeout=timeout) if timeout else self.queue.get_nowait()
        except queue.Empty:
            return None

    def drain(self, limit: int = 100000) -> list[Received]:
        out: list[Received] = []
        while len(out) < limit:
            try:
                out.append(self.queue.get_nowait())
            except queue.Empty:
                break
        return out

    # ------------------------------------------------------------------ commands
    def send(self, msg: Message) -> PendingCommand:
        """Write a command now; the returned handle's wait() gives its ACK or NACK."""
        ser = self._ser
        if ser is None:
            raise LinkError("the board is not connected; the command was not sent")
        with self._write_lock:
            seq = self._seq
            self._seq = (self._seq + 1) & 0xFF
            pending = PendingCommand(msg, seq, time.monotonic())
            if isinstance(msg, GetInfo):  # its HELLO answer is asked for, not a restart
                self._last_get_info = pending.t_send
            self._pending[seq] = pending
            try:
                ser.write(encode(msg, seq))
            except (serial.SerialException, OSError) as exc:
                self._pending.pop(seq, None)
                raise LinkError(f"writing {msg.NAME} failed: {exc}") from exc
        return pending

    def command(self, msg: Message, timeout_s: float = 1.0) -> Ack:
        """Send and wait; a NACK becomes a LinkError naming the reason."""
        reply = self.send(msg).wait(timeout_s)
        if isinstance(reply, Nack):
            try:
                why = NackError(reply.error).name.lower()
            except ValueError:
                why = f"error {reply.error}"
            raise LinkError(f"the board refused {msg.NAME}: {why}; nothing was applied")
        return reply

    # ------------------------------------------------------------------ thread
    def _run(self) -> None:
        try:
            while not self._stop.is_set():
                if self._ser is None:
                    if not self._open():
                        if not self.reconnect and self.counters.session > 0:
                            return
                        self._stop.wait(self.retry_interval_s)
                    continue
                self._step()
        except LinkError as exc:
            self.error = exc
            log.debug("link stopped: %s", exc)
        except Exception as exc:  # never die silently: the app shows it
            self.error = LinkError(f"link thread failed: {exc!r}")
            log.exception("link thread failed")
        finally:
            self._close_port()

    def _open(self) -> bool:
        port = None
        try:
            port = self._port_provider()
            if not port:
                self.last_problem = "no port found"
                return False
            ser = self._serial_factory(port, self.baud)
        except (serial.SerialException, OSError, ValueError) as exc:
            self.last_problem = f"cannot open {port}: {exc}"
            log.debug(self.last_problem)
            if self.counters.session == 0 and self._fixed_port and not Path(port or "").exists():
                if "://" not in str(port):  # a device path that is not there: say so now
                    raise LinkError(
                        f"serial port {port} does not exist; check the cable and the name "
                        "(ls /dev/ttyACM* /dev/ttyUSB*), or leave --port out to auto-find"
                    ) from exc
            return False
        if self.counters.session > 0:
            self.counters.reconnects += 1
            log.warning("reconnected to %s", port)
        self._ser = ser
        self.counters.port = port
        self.counters.connected = True
        self._fold_decoder_stats()
        self._decoder = StreamDecoder()
        self._handshake_done = False
        self._handshake_started = time.monotonic()
        self._last_get_info = 0.0
        self._held.clear()
        self._sync_sent.clear()
        return True

    def _close_port(self) -> None:
        ser, self._ser = self._ser, None
        self.counters.connected = False
        if ser is not None:
            try:
                ser.close()
            except (serial.SerialException, OSError):
                pass
        for pending in list(self._pending.values()):
            pending.done.set()  # waiters see no reply and raise
        self._pending.clear()

    def _disconnected(self, why: str) -> None:
        self.last_problem = f"{self.counters.port}: {why}"
        log.warning("link lost: %s", self.last_problem)
        self._close_port()
        if not self.reconnect:
            self.error = LinkError(f"the board disconnected: {why}")
            self._stop.set()

    def _step(self) -> None:
        ser = self._ser
        try:
            waiting = ser.in_waiting
            data = ser.read(waiting if waiting > 0 else 1)
        except (serial.SerialException, OSError, TypeError) as exc:
            self._disconnected(str(exc))
            return
        now = time.monotonic()
        if data:
            self._handle(self._decoder.feed(data), now)
            self._update_stats()
        if not self._handshake_done:
            self._handshake_tick(now)
        elif now >= self._next_sync:
            self._send_sync(now)

    def _handshake_tick(self, now: float) -> None:
        elapsed = now - self._handshake_started
        if elapsed >= self.get_info_after_s and now - self._last_get_info >= 0.5:
            self._last_get_info = now
            self._write(GetInfo())
        if elapsed > self.handshake_timeout_s:
            bad = self._decoder.stats.bad_frames
            hint = (
                f"; {bad} frames failed their check, as when the firmware was built from "
                "another protocol schema"
                if bad
                else ""
            )
            self.last_problem = f"no HELLO from {self.counters.port} in {elapsed:.1f} s{hint}"
            if self.counters.session == 0 and bad:
                raise LinkError(self.last_problem + ". Flash firmware built from this checkout.")

    def _write(self, msg: Message) -> float | None:
        ser = self._ser
        if ser is None:
            return None
        with self._write_lock:
            seq = self._seq
            self._seq = (self._seq + 1) & 0xFF
            frame = encode(msg, seq)
            try:
                t = time.monotonic()
                ser.write(frame)
            except (serial.SerialException, OSError) as exc:
                self._disconnected(f"write failed: {exc}")
                return None
        return t

    def _send_sync(self, now: float) -> None:
        self._token = (self._token + 1) & 0xFFFFFFFF
        token = self._token
        t = self._write(TimeSync(token=token))
        if t is None:
            return
        self._sync_sent[token] = t
        if len(self._sync_sent) > 64:
            self._sync_sent.pop(next(iter(self._sync_sent)))
        self.counters.time_syncs_sent += 1
        fast = now - self._session_start < self.fast_sync_for_s
        self._next_sync = now + (self.fast_sync_interval_s if fast else self.sync_interval_s)

    def _handle(self, msgs: list[Message], now: float) -> None:
        for msg in msgs:
            if isinstance(msg, Hello):
                check_hello(msg, str(self.counters.port))
                first = not self._handshake_done
                self.hello = msg
                if first:
                    self._handshake_done = True
                    self.counters.session += 1
                    self._session_start = now
                    self._next_sync = now
                    self.last_problem = None
                    log.info("%s: %s", self.counters.port, describe_hello(msg))
                    self._put(Received(msg, now, self.counters.session))
                    for held, t in self._held:
                        self._put(Received(held, t, self.counters.session))
                    self._held.clear()
                    self._ready.set()
                    continue
                if now - self._last_get_info > 1.0:
                    # Unasked: the board restarted (reset button, watchdog, brown-out). Its
                    # clock restarted too, so this is a new session for the clock model.
                    self.counters.session += 1
                    self.counters.board_restarts += 1
                    self._session_start = now
                    self._next_sync = now
                    self._sync_sent.clear()
                    log.warning("%s: the board restarted (unasked HELLO)", self.counters.port)
            if not self._handshake_done:
                if len(self._held) < 1000:
                    self._held.append((msg, now))
                continue
            t_send = None
            if isinstance(msg, Config):
                self.config = msg
            elif isinstance(msg, Heartbeat):
                self.counters.device_frames_sent = msg.frames_sent
                self.counters.device_rx_errors = msg.rx_errors
                self.counters.device_tx_overruns = msg.tx_overruns
            elif isinstance(msg, (Ack, Nack)):
                pending = self._pending.get(msg.command_seq)
                if pending is not None and pending.msg.MSG_ID == msg.command_id:
                    del self._pending[msg.command_seq]
                    pending.reply = msg
                    pending.done.set()
                else:
                    log.debug("unmatched %s for seq %d", msg.NAME, msg.command_seq)
            elif isinstance(msg, TimeSyncReply):
                t_send = self._sync_sent.pop(msg.token, None)
                if t_send is None:
                    continue  # an answer to a request from before a reconnect
                self.counters.time_syncs_answered += 1
            elif isinstance(msg, Log):
                level = _LOG_LEVELS.get(msg.level, logging.ERROR)
                log.log(level, "board: %s", msg.text)
            self._put(Received(msg, now, self.counters.session, t_send))

    def _put(self, item: Received) -> None:
        try:
            self.queue.put_nowait(item)
        except queue.Full:
            self.counters.queue_drops += 1

    def _fold_decoder_stats(self) -> None:
        for key, value in self._decoder.stats.as_dict().items():
            self._base_stats[key] = self._base_stats.get(key, 0) + value

    def _update_stats(self) -> None:
        s = self._decoder.stats
        b = self._base_stats
        c = self.counters
        c.frames = b.get("frames", 0) + s.frames
        c.bytes = b.get("bytes", 0) + s.bytes
        c.crc_errors = b.get("crc_errors", 0) + s.crc_errors
        c.seq_gaps = b.get("seq_gaps", 0) + s.seq_gaps
        c.resyncs = b.get("resyncs", 0) + s.resyncs
        c.bad_frames = sum(
            b.get(k, 0) + getattr(s, k)
            for k in (
                "crc_errors",
                "cobs_errors",
                "unknown_ids",
                "bad_lengths",
                "truncated",
                "oversized",
            )
        )


def resolve_port(port: str | None) -> str | PortProvider:
    """--port as given, or a provider that finds the board by USB VID/PID on every
    (re)connect, so a board that comes back on another device name is found again."""
    if port:
        return port
    try:
        from obstacle_fusion.link.ports import find_board_port  # the firmware side's VID/PID table
    except ImportError as exc:
        raise LinkError(
            "no --port given and board auto-detection (obstacle_fusion.link.ports) is not "
            "available; pass --port /dev/ttyACM0 (or COM3)"
        ) from exc
    first = find_board_port()  # raises a UserError naming what was looked for

    def provider() -> str | None:
        try:
            return str(find_board_port())
        except UserError as exc:
            log.debug("board not found yet: %s", exc)
            return None

    log.info("board found on %s", first)
    return provider
