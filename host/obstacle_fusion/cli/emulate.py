"""`obstacle-fusion emulate`: the real firmware under simavr, on a pty a host can open."""

from __future__ import annotations

import argparse
import math
import signal
import subprocess
import sys
import time
from pathlib import Path

from obstacle_fusion import bundled
from obstacle_fusion.errors import UserError
from obstacle_fusion.sim.emulator import EmulatorConfig, check_built, emulator_binary


def _distance(text: str) -> float | None:
    if text.lower() == "none":
        return None
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not metres or none") from None
    if not value >= 0.0:
        raise argparse.ArgumentTypeError(f"distance must be >= 0, got {text}")
    return value


def _probability(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not 0.0 <= value <= 1.0:
        raise argparse.ArgumentTypeError(f"a probability is 0..1, got {text}")
    return value


def _sensor_count(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a whole number") from None
    if not 1 <= value <= 4:
        raise argparse.ArgumentTypeError(f"the emulator has 1 to 4 sensors, got {value}")
    return value


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = subparsers.add_parser(
        "emulate",
        help="run the Uno firmware in the emulator, on a pty the host opens like a board",
        description="Run the real firmware ELF under simavr with a virtual HC-SR04; print "
        "the pseudo-terminal's path and run until Ctrl-C or --duration. Open the printed "
        "path with `obstacle-fusion run --port PATH` or any serial program.",
    )
    p.add_argument(
        "--elf", type=Path, help="firmware ELF (default: the `make setup` build or the package's)"
    )
    p.add_argument(
        "--bootloader",
        type=Path,
        nargs="?",
        const=Path("optiboot"),
        metavar="HEX",
        help="boot the Uno's bootloader first, as a real Uno does (default HEX: Optiboot as "
        "`make setup` builds it); with no --elf the flash is empty, ready for "
        "`obstacle-fusion flash --board uno --port PTY`",
    )
    world = p.add_argument_group("world")
    world.add_argument(
        "--distance", type=_distance, default=1.0, help="obstacle distance in m, or none"
    )
    world.add_argument("--scene", type=Path, help="keyframe file `<time_s> <distance_m|none>`")
    world.add_argument("--temperature", type=float, default=20.0, help="air, celsius")
    world.add_argument("--noise-mm", type=float, default=0.0, help="distance noise sigma")
    world.add_argument("--dropout", type=_probability, default=0.0, help="P(no echo)")
    world.add_argument("--spike", type=_probability, default=0.0, help="P(random echo)")
    world.add_argument(
        "--sensors",
        type=_sensor_count,
        default=1,
        help="HC-SR04s 1..4: TRIG on D9, D10..., ECHOs OR-ed onto D8 (firmware README)",
    )
    timing = p.add_argument_group("time")
    timing.add_argument("--fast", action="store_true", help="as fast as possible")
    timing.add_argument(
        "--clock-ppm", type=float, default=0.0, help="MCU crystal error, ppm (+ is fast)"
    )
    timing.add_argument("--duration", type=float, help="stop after this many seconds")
    uart = p.add_argument_group("serial faults")
    uart.add_argument("--uart-drop", type=_probability, default=0.0)
    uart.add_argument("--uart-corrupt", type=_probability, default=0.0)
    uart.add_argument("--uart-insert", type=_probability, default=0.0)
    uart.add_argument("--fault-dir", choices=("tx", "rx", "both"), default="tx")
    files = p.add_argument_group("files")
    files.add_argument("--truth", type=Path, help="write the truth log here")
    files.add_argument("--pty-file", type=Path, help="also write the pty path here")
    files.add_argument("--control", type=Path, help="UNIX socket for live commands")
    p.add_argument(
        "--wait-client",
        action="store_true",
        help="hold the MCU in reset until a program opens the pty (see HELLO from power-up)",
    )
    p.add_argument("--seed", type=int, default=1, help="random seed (noise, faults)")
    p.set_defaults(func=run)


def _check_given_file(path: Path | None, what: str, hint: str = "") -> None:
    """A path the user typed: say plainly when it is missing or a folder."""
    if path is None:
        return
    if path.is_dir():
        raise UserError(f"{what} {path} is a folder; give the file itself")
    if not path.exists():
        raise UserError(f"no such {what}: {path}{hint}")
    if not path.is_file():
        raise UserError(f"{what} {path} is not a regular file; give the file itself")


def run(args: argparse.Namespace) -> int:
    _check_given_file(
        args.elf, "firmware ELF", " (`make setup` builds firmware/build/uno/obstacle-fusion.elf)"
    )
    _check_given_file(args.scene, "scene file")
    boot: Path | None = args.bootloader
    if boot == Path("optiboot") and not boot.exists():
        boot = bundled.optiboot_hex()
        if boot is None:
            raise UserError(
                "no Optiboot build found: install arduino-core-avr (its source) and run "
                "`make -C tools/emulator optiboot`, or give --bootloader HEX"
            )
    _check_given_file(boot, "bootloader")
    if boot is not None and args.elf is None:
        elf: Path | None = None
        binary = bundled.ensure_emulator(emulator_binary())
    else:
        elf, binary = check_built(args.elf, emulator_binary())
    if args.duration is not None and not (0 < args.duration < math.inf):
        raise UserError(f"--duration must be a number of seconds > 0, got {args.duration}")
    config = EmulatorConfig(
        elf=elf,
        distance_m=args.distance,
        scene=args.scene,
        temperature_c=args.temperature,
        fast=args.fast,
        clock_ppm=args.clock_ppm,
        noise_mm=args.noise_mm,
        dropout=args.dropout,
        spike=args.spike,
        sensors=args.sensors,
        uart_drop=args.uart_drop,
        uart_corrupt=args.uart_corrupt,
        uart_insert=args.uart_insert,
        fault_dir=args.fault_dir,
        wait_client=args.wait_client,
        seed=args.seed,
        verbose=args.verbose,
        bootloader=boot,
        application=elf is not None,
        reset_on_open=boot is not None,  # DTR: opening the port resets into the bootloader
    )
    cmd = [str(binary), *config.arguments(elf, args.truth, args.pty_file, args.control)]
    # The emulator prints the pty path on our stdout itself; we only bound its life.
    sys.stdout.flush()
    proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL)
    deadline = None if args.duration is None else time.monotonic() + args.duration
    try:
        while proc.poll() is None:
            if deadline is not None and time.monotonic() >= deadline:
                proc.send_signal(signal.SIGTERM)
                break
            time.sleep(0.05)
    except KeyboardInterrupt:
        proc.send_signal(signal.SIGTERM)
    finally:
        try:
            proc.wait(5.0)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
    code = proc.returncode
    if code == 2:
        raise UserError("the emulator refused its arguments (see its message above)")
    # SIGTERM from us is a normal end.
    return 0 if code in (0, -signal.SIGTERM) else code
