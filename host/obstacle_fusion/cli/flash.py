"""`obstacle-fusion flash --board uno|bluepill [--port PORT]`: build the firmware and flash it.

For users who never open a Makefile: checks that the compiler and the flashing tool are
installed (and says which package to install when not), finds the board's port as the
host does, then runs `make -C firmware BOARD=... flash PORT=...`.
"""

from __future__ import annotations

import argparse
import logging
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

from obstacle_fusion.errors import UserError
from obstacle_fusion.link.ports import check_port, find_board_port

log = logging.getLogger(__name__)

FIRMWARE_DIR = Path(__file__).resolve().parents[3] / "firmware"


@dataclass(frozen=True, slots=True)
class BoardTools:
    """What one board needs on the PATH to build and flash."""

    compiler: str
    compiler_package: str
    flashers: tuple[str, ...]  # any one of them will do
    flasher_hint: str
    needs_port: bool


BOARDS: dict[str, BoardTools] = {
    "uno": BoardTools(
        compiler="avr-gcc",
        compiler_package="gcc-avr avr-libc binutils-avr",
        flashers=("avrdude",),
        flasher_hint="avrdude (apt install avrdude)",
        needs_port=True,
    ),
    "bluepill": BoardTools(
        compiler="arm-none-eabi-gcc",
        compiler_package="gcc-arm-none-eabi libnewlib-arm-none-eabi",
        flashers=("st-flash", "openocd", "stm32flash"),
        flasher_hint="st-flash (apt install stlink-tools), openocd, or stm32flash for the "
        "serial bootloader",
        needs_port=False,  # an ST-Link needs no serial port
    ),
}


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    parser = subparsers.add_parser(
        "flash",
        help="build the firmware and flash it to a board",
        description="Build the firmware for a board and flash it: the Uno through its "
        "bootloader with avrdude, the blue pill with an ST-Link (st-flash or openocd) or "
        "through its serial bootloader with stm32flash when --port is given.",
    )
    parser.add_argument(
        "--board", required=True, type=str.lower, choices=sorted(BOARDS), help="target board"
    )
    parser.add_argument("--port", help="serial port (default: the one board found by USB VID:PID)")
    parser.add_argument(
        "--firmware-dir", type=Path, default=FIRMWARE_DIR, help="firmware sources (Makefile)"
    )
    parser.add_argument("--build-dir", type=Path, help="where to build (default: firmware/build)")
    parser.set_defaults(func=run)


def check_tools(board: str) -> str:
    """The make program, after checking the board's compiler and a flasher are present."""
    tools = BOARDS[board]
    make = shutil.which("make")
    if make is None:
        raise UserError("make not found: install it (apt install make)")
    if shutil.which(tools.compiler) is None:
        raise UserError(
            f"{tools.compiler} not found: the {board} firmware needs it; install "
            f"{tools.compiler_package} (apt install {tools.compiler_package})"
        )
    if not any(shutil.which(f) for f in tools.flashers):
        raise UserError(f"no flashing tool for the {board} found: install {tools.flasher_hint}")
    return make


def make_command(
    make: str, firmware_dir: Path, board: str, port: str | None, build_dir: Path | None
) -> list[str]:
    cmd = [make, "-C", str(firmware_dir), f"BOARD={board}"]
    if build_dir is not None:
        cmd.append(f"BUILD_DIR={build_dir.resolve()}")
    cmd.append("flash")
    if port:
        cmd.append(f"PORT={port}")
    return cmd


def run(args: argparse.Namespace) -> int:
    board: str = args.board
    firmware_dir: Path = args.firmware_dir
    if not (firmware_dir / "Makefile").is_file():
        raise UserError(
            f"firmware sources not found in {firmware_dir}: run from a clone of the "
            "repository or pass --firmware-dir"
        )
    if args.build_dir is not None and args.build_dir.exists() and not args.build_dir.is_dir():
        raise UserError(f"--build-dir {args.build_dir} is a file; give a folder to build in")
    make = check_tools(board)
    port = None if args.port is None else check_port(args.port)
    if port is None and BOARDS[board].needs_port:
        port = find_board_port()
    if port is not None and not BOARDS[board].needs_port and shutil.which("stm32flash") is None:
        log.warning(
            "--port %s is used only by stm32flash (serial bootloader), which is not installed: "
            "flashing through the ST-Link instead",
            port,
        )
    cmd = make_command(make, firmware_dir, board, port, args.build_dir)
    log.info("running %s", " ".join(cmd))
    result = subprocess.run(cmd)
    if result.returncode != 0:
        raise UserError(
            f"building or flashing the {board} firmware failed (make exited with "
            f"{result.returncode}); see the messages above",
            exit_code=1,
        )
    return 0
