"""Both firmware images build with -Wall -Wextra -Werror and fit their flash/RAM budgets.

Builds into a temporary BUILD_DIR (never over firmware/build, which the emulator uses),
then checks `make size` against the limits: Uno flash <= 6 KB and RAM <= 768 B, blue pill
flash <= 8 KB; and that the images are what a loader expects.
"""

from __future__ import annotations

import re
import shutil
import struct
import subprocess
from pathlib import Path

import pytest

#: one xdist worker builds the module fixture once (run_tests.sh: --dist loadgroup)
pytestmark = [pytest.mark.cpu_only, pytest.mark.xdist_group("firmware_build")]

ROOT = Path(__file__).resolve().parents[2]
FIRMWARE = ROOT / "firmware"
LIMITS = {"uno": (6144, 768), "bluepill": (8192, 20480)}
COMPILERS = {"uno": "avr-gcc", "bluepill": "arm-none-eabi-gcc"}


def make(board: str, build_dir: Path, *targets: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        ["make", "-C", str(FIRMWARE), f"BOARD={board}", f"BUILD_DIR={build_dir}", *targets],
        capture_output=True,
        text=True,
        timeout=300,
    )


@pytest.fixture(scope="module", params=["uno", "bluepill"])
def built(
    request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory
) -> tuple[str, Path, str]:
    board: str = request.param
    if shutil.which(COMPILERS[board]) is None or shutil.which("make") is None:
        pytest.fail(f"{COMPILERS[board]} or make missing: run `make setup`")
    build_dir = tmp_path_factory.mktemp(f"fw-{board}")
    result = make(board, build_dir)
    assert result.returncode == 0, result.stdout + result.stderr
    return board, build_dir / board, result.stdout


def test_built_with_warnings_as_errors(built: tuple[str, Path, str]) -> None:
    board, _, log = built
    compiles = [line for line in log.splitlines() if " -c " in line]
    assert len(compiles) >= 6
    for line in compiles:
        for flag in ("-std=c99", "-Wall", "-Wextra", "-Werror"):
            assert flag in line.split(), f"{flag} missing in: {line}"
    assert "warning:" not in log


def test_size_within_limits(built: tuple[str, Path, str]) -> None:
    board, build, _ = built
    result = make(board, build.parent, "size")
    assert result.returncode == 0, result.stdout + result.stderr
    m = re.search(
        r"flash (\d+) bytes \(limit (\d+)\), ram (\d+) bytes \(limit (\d+)\)", result.stdout
    )
    assert m, result.stdout
    flash, flash_limit, ram, ram_limit = map(int, m.groups())
    assert (flash_limit, ram_limit) == LIMITS[board]
    assert 1000 < flash <= flash_limit
    assert 0 < ram <= ram_limit


def test_images(built: tuple[str, Path, str]) -> None:
    board, build, _ = built
    elf = build / "obstacle-fusion.elf"
    assert elf.read_bytes()[:4] == b"\x7fELF"
    if board == "uno":
        hexfile = build / "obstacle-fusion.hex"
        lines = hexfile.read_text().split()
        assert lines[-1] == ":00000001FF"
        # Only flash records: no extended address (the .mmcu tag lives at 0x910000).
        assert not any(line[7:9] in ("02", "04") for line in lines)
        # The simavr tag names the part and the clock (when libsimavr-dev is installed).
        if Path("/usr/include/simavr/avr/avr_mcu_section.h").exists():
            tag = build / "mmcu.bin"
            subprocess.run(
                ["avr-objcopy", "-O", "binary", "-j", ".mmcu", str(elf), str(tag)], check=True
            )
            data = tag.read_bytes()
            assert b"atmega328p" in data
            assert struct.pack("<I", 16_000_000) in data
    else:
        image = (build / "obstacle-fusion.bin").read_bytes()
        sp, reset = struct.unpack("<II", image[:8])
        assert sp == 0x20000000 + 8 * 1024  # 8 KB up: also boots on QEMU's 8 KB STM32F100
        assert reset & 1 and 0x08000000 <= reset < 0x08000000 + len(image)
        tim2, usart1 = (
            struct.unpack_from("<I", image, (16 + 28) * 4)[0],
            struct.unpack_from("<I", image, (16 + 37) * 4)[0],
        )
        default = struct.unpack_from("<I", image, 2 * 4)[0]
        assert tim2 != default and usart1 != default and tim2 != usart1


def test_bad_board_is_refused(tmp_path: Path) -> None:
    result = make("mega", tmp_path)
    assert result.returncode != 0
    assert "BOARD must be uno or bluepill" in result.stdout + result.stderr
