"""Build hook: the firmware images and the emulator's C sources become package data.

`pip install .` (and `pip wheel .`) run setuptools' build_py; this subclass then builds the
firmware with `make -C firmware BOARD=uno|bluepill` into a scratch folder and copies the
images into obstacle_fusion/_data/firmware/<board>/ of the wheel (the Uno's .hex and the .elf
the emulator runs, the blue pill's .bin), and copies tools/emulator/src/ into
obstacle_fusion/_data/emulator/src/ (the emulator is compiled on first use, see
host/obstacle_fusion/bundled.py). A board whose compiler is missing is left out with a
message saying what to install; nothing built is ever written into the source tree.
Editable installs skip all this: a clone finds the same files in its own build tree.

The stream decoder's C accelerator, obstacle_fusion.protocol._cdecode, is built as an
optional extension (and so is the fused vision method's,
obstacle_fusion.vision.fused._cmiddle), into the wheel, and by editable installs in place
(the only build outputs in the source tree: the two extensions' *.so files, ignored by
git). If one does not compile, setuptools says so, the install goes on, and that part runs
pure Python.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_py import build_py

ROOT = Path(__file__).resolve().parent
BOARDS = {
    # board: (compiler, files to ship, Debian packages)
    "uno": ("avr-gcc", ("obstacle-fusion.hex", "obstacle-fusion.elf"),
            "gcc-avr avr-libc binutils-avr"),
    "bluepill": ("arm-none-eabi-gcc", ("obstacle-fusion.bin",),
                 "gcc-arm-none-eabi libnewlib-arm-none-eabi"),
}  # fmt: skip


def _say(text: str) -> None:
    print(f"obstacle-fusion build: {text}", file=sys.stderr, flush=True)


class BuildPyWithFirmware(build_py):
    def run(self) -> None:
        super().run()
        if getattr(self, "editable_mode", False):
            return
        data = Path(self.build_lib) / "obstacle_fusion" / "_data"
        self._ship_firmware(data / "firmware")
        self._ship_emulator_sources(data / "emulator" / "src")

    def _ship_firmware(self, dest: Path) -> None:
        firmware = ROOT / "firmware"
        if not (firmware / "Makefile").is_file():
            _say(f"no firmware sources in {firmware}: the package ships no firmware images")
            return
        make = shutil.which("make")
        with tempfile.TemporaryDirectory(prefix="of-fw-") as scratch:
            for board, (compiler, files, packages) in BOARDS.items():
                if make is None or shutil.which(compiler) is None:
                    missing = "make" if make is None else compiler
                    _say(
                        f"{missing} not found: the package ships no {board} firmware image, so "
                        f"`flash --board {board}` needs --image"
                        + (
                            " and the emulated robot needs OF_FIRMWARE_ELF"
                            if board == "uno"
                            else ""
                        )
                        + f" (apt install {packages} make, then reinstall)"
                    )
                    continue
                done = subprocess.run(
                    [make, "-s", "-C", str(firmware), f"BOARD={board}", f"BUILD_DIR={scratch}"],
                    capture_output=True, text=True,
                )  # fmt: skip
                if done.returncode != 0:
                    raise SystemExit(
                        f"obstacle-fusion build: building the {board} firmware failed:\n"
                        f"{done.stdout}{done.stderr}"
                    )
                (dest / board).mkdir(parents=True, exist_ok=True)
                for name in files:
                    shutil.copy2(Path(scratch) / board / name, dest / board / name)
                _say(f"{board} firmware built: {', '.join(files)}")

    def _ship_emulator_sources(self, dest: Path) -> None:
        src = ROOT / "tools" / "emulator" / "src"
        if not src.is_dir():
            _say(f"no emulator sources in {src}: the package cannot build the emulator")
            return
        dest.mkdir(parents=True, exist_ok=True)
        for path in sorted([*src.glob("*.c"), *src.glob("*.h")]):
            shutil.copy2(path, dest / path.name)


# C99 and warning-clean; optional: a failed compile leaves the pure-Python decoder.
CDECODE = Extension(
    "obstacle_fusion.protocol._cdecode",
    sources=["host/obstacle_fusion/protocol/_cdecode.c"],
    extra_compile_args=["-std=c99", "-O2", "-Wall", "-Wextra", "-Werror"],
    optional=True,
)

# Likewise: without it, the fused vision method takes its medians in numpy.
CMIDDLE = Extension(
    "obstacle_fusion.vision.fused._cmiddle",
    sources=["host/obstacle_fusion/vision/fused/_cmiddle.c"],
    # -O3: its byte minima and maxima over rows of lanes vectorise
    extra_compile_args=["-std=c99", "-O3", "-Wall", "-Wextra", "-Werror"],
    libraries=["m"],  # row_norms' square roots
    optional=True,
)

setup(cmdclass={"build_py": BuildPyWithFirmware}, ext_modules=[CDECODE, CMIDDLE])
