"""`obstacle-fusion flash --board uno|bluepill [--port PORT]`: flash the firmware to a board.

For users who never open a Makefile. The image comes from, in order: `--image FILE`; a build
of the firmware's sources (`make -C firmware BOARD=...`) in a clone of the repository or with
`--firmware-dir`; else the image shipped inside the package (a `pip install`: no compiler
needed). Checks that the flashing tool is installed (and names the Debian package when not),
finds the board's port as the host does, then runs the flasher: avrdude through the Uno's
bootloader (STK500v1), st-flash/openocd through an ST-Link, or stm32flash through the blue
pill's serial bootloader.
"""

from __future__ import annotations

import argparse
import logging
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

from obstacle_fusion import bundled
from obstacle_fusion.errors import UserError
from obstacle_fusion.link.ports import check_port, find_board_port

log = logging.getLogger(__name__)


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
        help="flash the firmware to a board (building it first in a clone of the repository)",
        description="Flash the firmware to a board: the Uno through its bootloader with "
        "avrdude, the blue pill with an ST-Link (st-flash or openocd) or through its serial "
        "bootloader with stm32flash when --port is given. In a clone of the repository (or "
        "with --firmware-dir) the firmware is built first; installed with pip, the image "
        "shipped in the package is flashed and no compiler is needed.",
    )
    parser.add_argument(
        "--board", required=True, type=str.lower, choices=sorted(BOARDS), help="target board"
    )
    parser.add_argument("--port", help="serial port (default: the one board found by USB VID:PID)")
    parser.add_argument(
        "--firmware-dir",
        type=Path,
        help="firmware sources to build (default: the clone's firmware/, if any)",
    )
    parser.add_argument("--build-dir", type=Path, help="where to build (default: firmware/build)")
    parser.add_argument(
        "--image",
        type=Path,
        help="flash this image (.hex for the Uno, .bin for the blue pill) instead of building",
    )
    parser.set_defaults(func=run)


def check_flasher(board: str) -> None:
    tools = BOARDS[board]
    if not any(shutil.which(f) for f in tools.flashers):
        raise UserError(f"no flashing tool for the {board} found: install {tools.flasher_hint}")


def check_compiler(board: str) -> str:
    """The make program, after checking the board's compiler is present."""
    tools = BOARDS[board]
    make = shutil.which("make")
    if make is None:
        raise UserError("make not found: install it (apt install make), or pass --image FILE")
    if shutil.which(tools.compiler) is None:
        raise UserError(
            f"{tools.compiler} not found: building the {board} firmware needs it; install "
            f"{tools.compiler_package} (apt install {tools.compiler_package}), or pass "
            "--image FILE to flash a ready image"
        )
    return make


def build_command(make: str, firmware_dir: Path, board: str, build_dir: Path | None) -> list[str]:
    cmd = [make, "-C", str(firmware_dir), f"BOARD={board}"]
    if build_dir is not None:
        cmd.append(f"BUILD_DIR={build_dir.resolve()}")
    return cmd


def flash_command(board: str, image: Path, port: str | None) -> list[str]:
    """The flasher's command line (as firmware/Makefile's `flash` target has it)."""
    if board == "uno":
        assert port is not None
        return ["avrdude", "-p", "atmega328p", "-c", "arduino", "-P", port, "-b", "115200",
                "-D", "-U", f"flash:w:{image}:i"]  # fmt: skip
    if port is not None and shutil.which("stm32flash"):
        return ["stm32flash", "-w", str(image), "-v", "-g", "0x0", port]
    if shutil.which("st-flash"):
        return ["st-flash", "--reset", "write", str(image), "0x08000000"]
    return ["openocd", "-f", "interface/stlink.cfg", "-f", "target/stm32f1x.cfg", "-c",
            f"program {image} 0x08000000 verify reset exit"]  # fmt: skip


def resolve_image(board: str, args: argparse.Namespace) -> Path:
    """The image to flash, built first when there are sources to build."""
    if args.image is not None:
        if not args.image.is_file():
            raise UserError(f"--image {args.image} does not exist")
        return Path(args.image)
    firmware_dir: Path | None = args.firmware_dir or bundled.firmware_sources()
    if firmware_dir is None:
        image = bundled.firmware_image(board)
        if image is None:
            raise UserError(
                f"this install ships no {board} firmware image (it was built without "
                f"{BOARDS[board].compiler}); pass --image FILE or --firmware-dir DIR (a clone's "
                "firmware/ folder)"
            )
        log.info("flashing the image shipped in the package: %s", image)
        return image
    if not (firmware_dir / "Makefile").is_file():
        raise UserError(
            f"firmware sources not found in {firmware_dir}: run from a clone of the "
            "repository or pass --firmware-dir"
        )
    make = check_compiler(board)
    cmd = build_command(make, firmware_dir, board, args.build_dir)
    log.info("running %s", " ".join(cmd))
    result = subprocess.run(cmd)
    if result.returncode != 0:
        raise UserError(
            f"building the {board} firmware failed (make exited with {result.returncode}); "
            "see the messages above",
            exit_code=1,
        )
    build_dir = args.build_dir.resolve() if args.build_dir is not None else firmware_dir / "build"
    return build_dir / board / bundled.IMAGE_NAMES[board]


def run(args: argparse.Namespace) -> int:
    board: str = args.board
    if args.firmware_dir is not None and not (args.firmware_dir / "Makefile").is_file():
        raise UserError(
            f"firmware sources not found in {args.firmware_dir}: run from a clone of the "
            "repository or pass --firmware-dir"
        )
    if args.build_dir is not None and args.build_dir.exists() and not args.build_dir.is_dir():
        raise UserError(f"--build-dir {args.build_dir} is a file; give a folder to build in")
    if args.image is None and (args.firmware_dir or bundled.firmware_sources()) is not None:
        check_compiler(board)  # before looking for a port: the first thing missing is named
    check_flasher(board)
    port = None if args.port is None else check_port(args.port)
    if port is None and BOARDS[board].needs_port:
        port = find_board_port()
    if port is not None and not BOARDS[board].needs_port and shutil.which("stm32flash") is None:
        log.warning(
            "--port %s is used only by stm32flash (serial bootloader), which is not installed: "
            "flashing through the ST-Link instead",
            port,
        )
    image = resolve_image(board, args)
    cmd = flash_command(board, image, port)
    log.info("running %s", " ".join(cmd))
    result = subprocess.run(cmd)
    if result.returncode != 0:
        raise UserError(
            f"flashing the {board} failed ({cmd[0]} exited with {result.returncode}); see the "
            "messages above",
            exit_code=1,
        )
    return 0
