"""Start and stop the firmware emulator (of-emulator) from Python.

The emulator runs the real firmware ELF under simavr with a virtual HC-SR04 and exposes
USART0 on a pseudo-terminal that the host opens like a board. This module gives that
process a context manager: the pty path, a control handle that moves the obstacle (or sets
temperature, noise, dropouts, UART faults) while it runs, and the truth log, one record per
measurement of what the virtual sensor really sent.
"""

from __future__ import annotations

import logging
import math
import os
import shutil
import signal
import socket
import subprocess
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from types import TracebackType

from obstacle_fusion import bundled
from obstacle_fusion.errors import UserError

log = logging.getLogger(__name__)

REPO_ROOT = bundled.REPO_ROOT  # the clone, in an editable install (tests, benchmarks)
TIMER_HZ = 2_000_000  # Uno Timer1 with prescaler 8: the unit of the truth log's echo_ticks


class EmulatorError(UserError):
    """The emulator cannot start or stopped unexpectedly."""


def emulator_binary() -> Path:
    """The emulator program: $OF_EMULATOR, the clone's `make setup` build, or (installed
    from a wheel) the per-user build of the shipped sources, made on first use."""
    return bundled.default_emulator_binary()


def firmware_elf() -> Path:
    """The Uno firmware ELF: $OF_FIRMWARE_ELF, the clone's build, or the package's copy."""
    return bundled.default_firmware_elf()


def check_built(elf: Path | None = None, binary: Path | None = None) -> tuple[Path, Path]:
    """Both files the emulator needs (building the emulator on first use when installed
    from a wheel), or a UserError that says how to get them."""
    binary = bundled.ensure_emulator(binary or emulator_binary())
    elf = elf or firmware_elf()
    in_clone = bundled.checkout_root() is not None
    if not binary.is_file() or not os.access(binary, os.X_OK):
        how = (
            "run `make setup` (or `make -C tools/emulator`)"
            if in_clone
            else "set OF_EMULATOR to an emulator program, or reinstall the package"
        )
        raise EmulatorError(f"the emulator is not built ({binary} is missing); {how}")
    if not elf.is_file():
        how = (
            "run `make setup` (or `make -C firmware BOARD=uno`)"
            if in_clone
            else "this install was built without avr-gcc (install gcc-avr avr-libc "
            "binutils-avr and reinstall), or set OF_FIRMWARE_ELF to a firmware ELF"
        )
        raise EmulatorError(f"the firmware ELF is not built ({elf} is missing); {how}")
    return elf, binary


@dataclass(frozen=True)
class EmulatorConfig:
    """Everything the emulator command line takes; None leaves the emulator's default."""

    elf: Path | None = None
    distance_m: float | None = 1.0  # None: no obstacle (the sensor's ~38 ms pulse)
    scene: Path | None = None  # keyframe file; overrides distance_m
    sensor_scenes: tuple[tuple[int, Path], ...] = ()  # (sensor id, its own keyframe file)
    temperature_c: float = 20.0
    fast: bool = False
    clock_ppm: float = 0.0
    duration_s: float | None = None  # simulated seconds
    noise_mm: float = 0.0
    dropout: float = 0.0
    spike: float = 0.0
    burst_us: float | None = None
    no_echo_us: float | None = None
    max_range_m: float | None = None
    sensors: int = 1  # 1..4, TRIG on D9.. D12, ECHO lines OR-ed onto one pin (firmware README)
    trig_pin: str | None = None  # sensor 0's TRIG: "D9", "PB1"
    echo_pin: str | None = None
    uart_drop: float = 0.0
    uart_corrupt: float = 0.0
    uart_insert: float = 0.0
    fault_dir: str = "tx"  # tx (MCU to host), rx or both
    wait_client: bool = True  # hold the MCU in reset until the pty is opened
    client_grace_ms: float | None = None
    reset_on_open: bool = False
    optiboot: bool = False  # start as Optiboot does: MCUSR cleared, the reset cause in r2
    exit_with_parent: bool = True  # no orphans when the starting process dies
    seed: int = 1
    quirk_fixes: bool = True
    # The Uno's bootloader (Intel HEX, e.g. Optiboot): every reset starts there, as with the
    # BOOTRST fuse; with application=False the flash holds nothing else (a board to flash).
    bootloader: Path | None = None
    application: bool = True
    verbose: int = 0
    extra_args: tuple[str, ...] = ()

    def arguments(
        self,
        elf: Path | None,
        truth: Path | None = None,
        pty_file: Path | None = None,
        control: Path | None = None,
    ) -> list[str]:
        """The emulator's command-line arguments (without the program)."""
        args: list[str] = []

        def opt(name: str, value: object | None) -> None:
            if value is not None:
                args.extend([name, str(value)])

        if self.scene is not None:
            opt("--scene", self.scene)
        else:
            opt("--distance", "none" if self.distance_m is None else repr(self.distance_m))
        opt("--temperature", self.temperature_c)
        if self.fast:
            args.append("--fast")
        if self.clock_ppm:
            opt("--clock-ppm", self.clock_ppm)
        opt("--duration", self.duration_s)
        opt("--noise-mm", self.noise_mm or None)
        opt("--dropout", self.dropout or None)
        opt("--spike", self.spike or None)
        opt("--burst-us", self.burst_us)
        opt("--no-echo-us", self.no_echo_us)
        opt("--max-range", self.max_range_m)
        if self.sensors != 1:
            opt("--sensors", self.sensors)
        for sensor_id, path in self.sensor_scenes:
            opt("--sensor-scene", f"{sensor_id}:{path}")
        opt("--trig", self.trig_pin)
        opt("--echo", self.echo_pin)
        opt("--uart-drop", self.uart_drop or None)
        opt("--uart-corrupt", self.uart_corrupt or None)
        opt("--uart-insert", self.uart_insert or None)
        opt("--fault-dir", self.fault_dir)
        if self.wait_client:
            args.append("--wait-client")
        opt("--client-grace-ms", self.client_grace_ms)
        if self.reset_on_open:
            args.append("--reset-on-open")
        if self.optiboot:
            args.append("--optiboot")
        if self.exit_with_parent:
            args.append("--exit-with-parent")
        opt("--seed", self.seed)
        if not self.quirk_fixes:
            args.append("--no-quirk-fixes")
        args.extend(["-v"] * self.verbose)
        opt("--truth", truth)
        opt("--pty-file", pty_file)
        opt("--control", control)
        opt("--bootloader", self.bootloader)
        args.extend(self.extra_args)
        if elf is not None:
            args.append(str(elf))
        return args


@dataclass(frozen=True, slots=True)
class TruthRecord:
    """One measurement as the virtual sensor made it (the firmware should report this)."""

    index: int  # 0 for the first trigger accepted after power-up
    trigger_s: float  # simulated MCU time of the TRIG rising edge
    echo_s: float  # ECHO high time in true seconds
    echo_ticks: float  # ECHO high time in MCU timer ticks (2 MHz on the Uno)
    distance_m: float | None  # the scene's distance; None: no obstacle
    echo_distance_m: float | None  # the distance that made the echo (noise, spikes)
    temperature_c: float
    kind: str  # echo, none, beyond, dropout, spike
    trigger_cycle: int
    rise_cycle: int
    echo_cycles: int
    sensor_id: int = 0  # which sensor was triggered

    @property
    def has_echo(self) -> bool:
        return self.echo_distance_m is not None


def _opt_float(text: str) -> float | None:
    value = float(text)
    return None if math.isnan(value) else value


def parse_truth_line(line: str) -> TruthRecord | None:
    """A record from one truth-log line; None for comments and blank lines."""
    line = line.strip()
    if not line or line.startswith("#"):
        return None
    f = line.split()
    if len(f) not in (11, 12):
        raise ValueError(f"truth log line has {len(f)} fields, expected 12: {line!r}")
    return TruthRecord(
        index=int(f[0]),
        trigger_s=float(f[1]),
        echo_s=float(f[2]),
        echo_ticks=float(f[3]),
        distance_m=_opt_float(f[4]),
        echo_distance_m=_opt_float(f[5]),
        temperature_c=float(f[6]),
        kind=f[7],
        trigger_cycle=int(f[8]),
        rise_cycle=int(f[9]),
        echo_cycles=int(f[10]),
        sensor_id=int(f[11]) if len(f) > 11 else 0,
    )


class TruthLog:
    """Reads the truth log as the emulator appends to it; only complete lines count."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self._records: list[TruthRecord] = []
        self._offset = 0
        self._partial = ""

    def read(self) -> list[TruthRecord]:
        """All records so far (the list grows as the emulator runs)."""
        try:
            with open(self.path, encoding="ascii") as fh:
                fh.seek(self._offset)
                chunk = fh.read()
                self._offset = fh.tell()
        except FileNotFoundError:
            return list(self._records)
        text = self._partial + chunk
        lines = text.split("\n")
        self._partial = lines.pop()
        for line in lines:
            rec = parse_truth_line(line)
            if rec is not None:
                self._records.append(rec)
        return list(self._records)

    def __iter__(self) -> Iterator[TruthRecord]:
        return iter(self.read())

    def __len__(self) -> int:
        return len(self.read())


class EmulatorControl:
    """The live control channel: one text command, one reply (README in tools/emulator)."""

    def __init__(self, path: Path, timeout_s: float = 5.0) -> None:
        self.path = path
        self.timeout_s = timeout_s
        self._sock: socket.socket | None = None
        self._buf = b""
        self._lock = threading.Lock()

    def _connect(self) -> socket.socket:
        if self._sock is None:
            sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
            sock.settimeout(self.timeout_s)
            sock.connect(str(self.path))
            self._sock = sock
        return self._sock

    def command(self, line: str) -> str:
        """Send one command; return the text after `ok`, raise EmulatorError on `error`."""
        if "\n" in line:
            raise ValueError("one command per call")
        with self._lock:
            sock = self._connect()
            sock.sendall(line.encode("ascii") + b"\n")
            while b"\n" not in self._buf:
                data = sock.recv(4096)
                if not data:
                    self.close()
                    raise EmulatorError(f"the emulator closed the control channel ({line!r})")
                self._buf += data
            reply, _, self._buf = self._buf.partition(b"\n")
        text = reply.decode("ascii", "replace")
        if text == "ok" or text.startswith("ok "):
            return text[3:]
        raise EmulatorError(f"emulator refused {line!r}: {text.removeprefix('error ')}")

    def set_distance(self, distance_m: float | None, sensor: int | None = None) -> None:
        """A constant distance from now on (None: no obstacle) for one sensor or all;
        replaces its scene."""
        text = "none" if distance_m is None else repr(distance_m)
        self.command(f"distance {text}" + ("" if sensor is None else f" {sensor}"))

    def set_temperature(self, celsius: float) -> None:
        self.command(f"temperature {celsius!r}")

    def set_noise(self, sigma_mm: float) -> None:
        self.command(f"noise {sigma_mm!r}")

    def set_dropout(self, probability: float) -> None:
        self.command(f"dropout {probability!r}")

    def set_spike(self, probability: float) -> None:
        self.command(f"spike {probability!r}")

    def set_uart_fault(self, kind: str, probability: float) -> None:
        """kind: drop, corrupt or insert; applies in the configured fault direction."""
        self.command(f"uart {kind} {probability!r}")

    def load_scene(self, path: Path, sensor: int | None = None) -> None:
        """Keyframes from a file; their time 0 is the moment the command is applied."""
        self.command(f"scene {path}" + ("" if sensor is None else f" {sensor}"))

    def reset(self, watchdog: bool = False) -> None:
        """Reset the MCU, like pressing the board's reset button; watchdog=True: as if
        its watchdog had fired (MCUSR.WDRF set, or r2 under --optiboot)."""
        self.command("reset watchdog" if watchdog else "reset")

    def hang(self, interrupts_off: bool = False, seconds: float | None = None) -> None:
        """Make the firmware's main program stop where it is, as an endless loop would
        (interrupt handlers still run; interrupts_off: as after `cli`), until the MCU
        resets (its own watchdog's work, or `reset`), or for `seconds` of simulated time
        (then it goes on, interrupts on again)."""
        words = ["hang"] + (["cli"] if interrupts_off else [])
        if seconds is not None:
            words.append(repr(float(seconds)))
        self.command(" ".join(words))

    def resume(self) -> None:
        """End a hang: the main program goes on."""
        self.command("hang off")

    def poke(self, address: int, data: bytes) -> None:
        """Write the MCU's SRAM at a data address (at most 16 bytes): what an earlier run
        left there, or power-on noise."""
        self.command(f"poke {address:#x} " + " ".join(f"{b:#x}" for b in data))

    def sim_time(self) -> float:
        """Simulated seconds since power-up."""
        return float(self.command("time").split()[0])

    def stats(self) -> dict[str, float]:
        out: dict[str, float] = {}
        for item in self.command("stats").split():
            key, _, value = item.partition("=")
            out[key] = float(value)
        return out

    def close(self) -> None:
        if self._sock is not None:
            self._sock.close()
            self._sock = None
            self._buf = b""


@dataclass
class Emulator:
    """One emulator process. Use as a context manager; `pty_path` is ready on entry."""

    config: EmulatorConfig = field(default_factory=EmulatorConfig)
    binary: Path | None = None
    start_timeout_s: float = 10.0
    pty_path: str = ""
    workdir: Path | None = None
    _proc: subprocess.Popen[bytes] | None = None
    _control: EmulatorControl | None = None
    _truth: TruthLog | None = None
    _own_workdir: bool = False

    def start(self) -> Emulator:
        if self.config.bootloader is not None and not self.config.application:
            binary = bundled.ensure_emulator(self.binary or emulator_binary())
            elf: Path | None = None
            if not self.config.bootloader.is_file():
                raise EmulatorError(f"no such bootloader: {self.config.bootloader}")
        else:
            elf, binary = check_built(self.config.elf, self.binary)
        if self.workdir is None:
            # Short path: a UNIX socket path must fit in 108 bytes.
            self.workdir = Path(tempfile.mkdtemp(prefix="ofemu-"))
            self._own_workdir = True
        self.workdir.mkdir(parents=True, exist_ok=True)
        wd = self.workdir
        args = [
            str(binary),
            *self.config.arguments(elf, wd / "truth.log", wd / "pty", wd / "control.sock"),
        ]
        log.debug("starting %s", " ".join(args))
        stderr = open(self.workdir / "stderr.log", "wb")  # noqa: SIM115 - the child owns it
        try:
            self._proc = subprocess.Popen(
                args, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=stderr
            )
        finally:
            stderr.close()
        self.pty_path = self._read_pty_path()
        self._control = EmulatorControl(self.workdir / "control.sock")
        self._truth = TruthLog(self.workdir / "truth.log")
        log.info("emulator running on %s (pid %d)", self.pty_path, self._proc.pid)
        return self

    def _read_pty_path(self) -> str:
        assert self._proc is not None and self._proc.stdout is not None
        result: list[bytes] = []
        reader = threading.Thread(
            target=lambda: result.append(self._proc.stdout.readline()),  # type: ignore[union-attr]
            daemon=True,
        )
        reader.start()
        reader.join(self.start_timeout_s)
        line = result[0].decode().strip() if result else ""
        if not line:
            self.stop()
            raise EmulatorError(
                f"the emulator did not start: {self.stderr_text().strip() or 'no output'}"
            )
        return line

    @property
    def control(self) -> EmulatorControl:
        if self._control is None:
            raise EmulatorError("the emulator is not running")
        return self._control

    @property
    def truth(self) -> TruthLog:
        if self._truth is None:
            raise EmulatorError("the emulator is not running")
        return self._truth

    @property
    def pid(self) -> int | None:
        return self._proc.pid if self._proc else None

    def running(self) -> bool:
        return self._proc is not None and self._proc.poll() is None

    def returncode(self) -> int | None:
        return self._proc.poll() if self._proc else None

    def stderr_text(self) -> str:
        if self.workdir is None:
            return ""
        try:
            return (self.workdir / "stderr.log").read_text(errors="replace")
        except FileNotFoundError:
            return ""

    def wait(self, timeout_s: float | None = None) -> int:
        """Wait for the process to end by itself (duration reached, quit)."""
        assert self._proc is not None
        return self._proc.wait(timeout_s)

    def stop(self, timeout_s: float = 5.0) -> int | None:
        """End the process (SIGTERM, then SIGKILL) and keep its files until cleanup."""
        if self._control is not None:
            self._control.close()
        proc = self._proc
        if proc is None:
            return None
        if proc.poll() is None:
            proc.send_signal(signal.SIGTERM)
            try:
                proc.wait(timeout_s)
            except subprocess.TimeoutExpired:
                log.warning("emulator %d ignored SIGTERM; killing it", proc.pid)
                proc.kill()
                proc.wait()
        if proc.stdout is not None:
            proc.stdout.close()
        return proc.returncode

    def cleanup(self) -> None:
        self.stop()
        if self._own_workdir and self.workdir is not None:
            shutil.rmtree(self.workdir, ignore_errors=True)

    def __enter__(self) -> Emulator:
        return self.start()

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.cleanup()


def run_emulator(config: EmulatorConfig | None = None, **overrides: object) -> Emulator:
    """An Emulator for `with`: ``with run_emulator(fast=True) as emu: ...``."""
    base = config or EmulatorConfig()
    if overrides:
        fields = {**base.__dict__, **overrides}
        base = EmulatorConfig(**fields)  # type: ignore[arg-type]
    return Emulator(config=base)


def wait_for(predicate: Callable[[], object], timeout_s: float, poll_s: float = 0.01) -> bool:
    """Poll until predicate() is true or the time is up (wall clock)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(poll_s)
    return bool(predicate())
