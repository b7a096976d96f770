"""A fake board behind a pseudo-terminal: enough firmware behaviour to test the host's link.

It is not the emulator (that runs the real firmware); it lets link tests run in a second
with exact control over faults: a wrong schema, silence, garbage, lost frames, an unplug.
"""

from __future__ import annotations

import os
import select
import threading
import time
import tty

from obstacle_fusion.protocol import StreamDecoder, encode
from obstacle_fusion.protocol.generated import (
    PROTOCOL_VERSION,
    SCHEMA_FINGERPRINT,
    Ack,
    Config,
    GetInfo,
    Heartbeat,
    Hello,
    Nack,
    Range,
    SetConfig,
    Start,
    Stop,
    TimeSync,
    TimeSyncReply,
)


class FakeBoard:
    def __init__(
        self,
        fingerprint: int = SCHEMA_FINGERPRINT,
        silent: bool = False,
        cycle_s: float = 0.02,
        ppm: float = 0.0,
        skip_seq_every: int = 0,
    ) -> None:
        self.fingerprint = fingerprint
        self.silent = silent
        self.cycle_s = cycle_s
        self.ppm = ppm
        self.skip_seq_every = skip_seq_every
        self.running = True
        self.seq = 0
        self.measurement = 0
        self.frames_sent = 0
        self.master = -1
        self.slave = -1
        self.path = ""
        self.generation = 0
        self._stop = threading.Event()
        self._lock = threading.Lock()
        self._thread: threading.Thread | None = None
        self.received: list[object] = []
        self._t0 = time.monotonic()
        self.plug()

    # -------------------------------------------------------------- plumbing
    def plug(self) -> None:
        master, slave = os.openpty()
        tty.setraw(slave)
        self.master, self.slave = master, slave
        self.path = os.ttyname(slave)
        self.generation += 1
        self.decoder = StreamDecoder()
        self._t0 = time.monotonic()  # a replugged Uno resets: its clock restarts
        self.measurement = 0

    def reboot(self) -> None:
        """A reset on the same port: the clock restarts and HELLO comes unasked."""
        self._t0 = time.monotonic()
        self.measurement = 0
        self.send(self.hello())
        self.send(self.config())

    def unplug(self) -> None:
        with self._lock:
            os.close(self.master)
            os.close(self.slave)
            self.master = self.slave = -1

    def port(self) -> str | None:
        return self.path if self.master >= 0 else None

    def start(self) -> FakeBoard:
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()
        return self

    def close(self) -> None:
        self._stop.set()
        if self._thread:
            self._thread.join(2)
        if self.master >= 0:
            self.unplug()

    def __enter__(self) -> FakeBoard:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close()

    def mcu_us(self) -> int:
        return int((time.monotonic() - self._t0) * 1e6 * (1 + self.ppm * 1e-6)) & 0xFFFFFFFF

    def send(self, msg: object, raw: bytes | None = None) -> None:
        with self._lock:
            if self.master < 0 or self.silent:
                return
            if self.skip_seq_every and self.seq % self.skip_seq_every == 0:
                self.seq = (self.seq + 1) & 0xFF  # a frame "lost" on the wire
            data = raw if raw is not None else encode(msg, self.seq)  # type: ignore[arg-type]
            self.seq = (self.seq + 1) & 0xFF
            self.frames_sent += 1
            try:
                os.write(self.master, data)
            except OSError:
                pass

    def garbage(self, data: bytes) -> None:
        with self._lock:
            if self.master >= 0:
                os.write(self.master, data)

    def hello(self) -> Hello:
        return Hello(PROTOCOL_VERSION, self.fingerprint, 0, 1, 0, 1, 16_000_000, 2_000_000, 1)

    def config(self) -> Config:
        return Config(60, 1, 23324, 40000, 1000, int(self.running))

    # -------------------------------------------------------------- behaviour
    def _run(self) -> None:
        next_range = time.monotonic()
        next_hb = time.monotonic() + 0.3
        gen = 0
        while not self._stop.is_set():
            if self.master < 0:
                time.sleep(0.01)
                continue
            if gen != self.generation:
                gen = self.generation
                self.send(self.hello())
                self.send(self.config())
            try:
                ready, _, _ = select.select([self.master], [], [], 0.003)
                data = os.read(self.master, 4096) if ready else b""
            except (OSError, ValueError):
                continue
            for i in range(len(data)):  # byte by byte, so decoder.last_seq is each frame's
                for msg in self.decoder.feed(data[i : i + 1]):
                    self.received.append(msg)
                    self._answer(msg)
            now = time.monotonic()
            if self.running and now >= next_range:
                next_range = now + self.cycle_s
                self.measurement += 1
                self.send(Range(self.measurement, 0, self.mcu_us(), 11662, 0))
            if now >= next_hb:
                next_hb = now + 0.3
                self.send(Heartbeat(int((now - self._t0) * 1000), self.frames_sent, 0, 3, 1))

    def _answer(self, msg: object) -> None:
        seq = self.decoder.last_seq or 0
        if isinstance(msg, GetInfo):
            self.send(self.hello())
            self.send(self.config())
        elif isinstance(msg, (Start, Stop)):
            self.running = isinstance(msg, Start)
            self.send(Ack(msg.MSG_ID, seq))
        elif isinstance(msg, SetConfig):
            if not 29 <= msg.cycle_ms <= 10000 or msg.cycle_ms * 1000 <= msg.echo_timeout_us:
                self.send(Nack(msg.MSG_ID, seq, 3))
            else:
                self.send(Ack(msg.MSG_ID, seq))
                self.send(self.config())
        elif isinstance(msg, TimeSync):
            rx = self.mcu_us()
            self.send(TimeSyncReply(msg.token, rx, self.mcu_us()))
