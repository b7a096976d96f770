"""Fixtures for tests that run firmware in the emulator (tools/emulator).

`emulator_factory(**config)` starts an emulator (stopped after the test); `FirmwarePort`
talks to it through its pty with pyserial and the protocol codec, as the host does.
Builds the emulator (and the Uno firmware, if its Makefile exists) when they are missing.
"""

from __future__ import annotations

import subprocess
import time
from collections import deque
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
import serial
from obstacle_fusion.protocol import StreamDecoder, encode
from obstacle_fusion.protocol.generated import Message
from obstacle_fusion.sim.emulator import (
    REPO_ROOT,
    Emulator,
    EmulatorConfig,
    emulator_binary,
    firmware_elf,
)

TESTFW_DIR = REPO_ROOT / "tools" / "emulator" / "build" / "testfw"


def _make(args: list[str]) -> tuple[bool, str]:
    proc = subprocess.run(
        ["make", "-s", *args], cwd=REPO_ROOT, capture_output=True, text=True, timeout=300
    )
    return proc.returncode == 0, proc.stdout + proc.stderr


@pytest.fixture(scope="session")
def emulator_built() -> Path:
    """The emulator binary, built on first use; the tests fail (not skip) if it cannot be."""
    binary = emulator_binary()
    if not binary.is_file() or not (TESTFW_DIR / "echo_test.elf").is_file():
        ok, out = _make(["-C", "tools/emulator"])
        assert ok, f"building the emulator failed:\n{out}"
    return binary


@pytest.fixture(scope="session")
def uno_elf(emulator_built: Path) -> Path:
    """The real Uno firmware ELF (built if the firmware Makefile exists)."""
    elf = firmware_elf()
    if not elf.is_file() and (REPO_ROOT / "firmware" / "Makefile").is_file():
        ok, out = _make(["-C", "firmware", "BOARD=uno"])
        if not ok:
            pytest.fail(f"building the Uno firmware failed:\n{out}")
    if not elf.is_file():
        pytest.skip(f"the Uno firmware is not built yet ({elf}; firmware/Makefile missing)")
    return elf


@pytest.fixture
def emulator_factory(emulator_built: Path) -> Iterator[Callable[..., Emulator]]:
    """Start emulators with EmulatorConfig fields as keywords; all stop after the test."""
    started: list[Emulator] = []

    def make(**config: Any) -> Emulator:
        emu = Emulator(config=EmulatorConfig(**config), binary=emulator_built)
        started.append(emu)
        emu.start()
        return emu

    yield make
    for emu in started:
        emu.cleanup()


class FirmwarePort:
    """The host end of the emulated board: pyserial plus the stream decoder."""

    def __init__(self, path: str, baud: int = 115200) -> None:
        self.serial = serial.Serial(path, baud, timeout=0.02)
        self.decoder = StreamDecoder()
        self.raw = bytearray()
        self.pending: deque[Message] = deque()
        self.seq = 0

    def send(self, msg: Message) -> int:
        """Write one command frame; returns the seq it used."""
        seq = self.seq
        self.seq = (self.seq + 1) & 0xFF
        self.serial.write(encode(msg, seq))
        self.serial.flush()
        return seq

    def write_raw(self, data: bytes) -> None:
        self.serial.write(data)
        self.serial.flush()

    def _fill(self) -> None:
        data = self.serial.read(4096)
        if data:
            self.raw += data
            self.pending.extend(self.decoder.feed(data))

    def read_until(
        self, predicate: Callable[[Message], bool], timeout_s: float = 5.0
    ) -> tuple[Message | None, list[Message]]:
        """Consume messages up to and including the first that satisfies predicate."""
        seen: list[Message] = []
        deadline = time.monotonic() + timeout_s
        while True:
            while self.pending:
                msg = self.pending.popleft()
                seen.append(msg)
                if predicate(msg):
                    return msg, seen
            if time.monotonic() >= deadline:
                return None, seen
            self._fill()

    def collect(self, seconds: float) -> list[Message]:
        """Consume everything pending plus what arrives in the next `seconds`."""
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            self._fill()
        out = list(self.pending)
        self.pending.clear()
        return out

    def close(self) -> None:
        self.serial.close()


@pytest.fixture
def open_port() -> Iterator[Callable[[Emulator], FirmwarePort]]:
    """Open an emulator's pty as the host would; closed after the test."""
    ports: list[FirmwarePort] = []

    def opener(emu: Emulator) -> FirmwarePort:
        port = FirmwarePort(emu.pty_path)
        ports.append(port)
        return port

    yield opener
    for port in ports:
        port.close()


def firmware_for_tests(name: str) -> Path:
    """One of the emulator's own test firmwares (tools/emulator/testfw)."""
    return TESTFW_DIR / f"{name}.elf"
