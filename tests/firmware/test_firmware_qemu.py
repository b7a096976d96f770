"""Smoke test of the blue pill image under QEMU's stm32vldiscovery machine.

QEMU models that board's USART1 and interrupt controller but not its timers, clocks or
GPIO, so time stands still and no echo is ever measured. What it does prove: the image
boots (vector table, reset handler, .data/.bss, the bounded clock start-up falling back to
the 8 MHz HSI when RCC never reports ready), announces itself with HELLO and CONFIG, and
answers commands over USART1 with correct frames. Skipped when qemu-system-arm is absent
(Debian: apt install qemu-system-arm).
"""

from __future__ import annotations

import os
import select
import shutil
import struct
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from obstacle_fusion.protocol import StreamDecoder, encode
from obstacle_fusion.protocol.generated import (
    Ack,
    Board,
    Config,
    Error,
    GetInfo,
    Hello,
    Message,
    Nack,
    SetConfig,
    TimeSync,
    TimeSyncReply,
)

ROOT = Path(__file__).resolve().parents[2]
QEMU = shutil.which("qemu-system-arm")

pytestmark = pytest.mark.skipif(QEMU is None, reason="qemu-system-arm is not installed")


class QemuBoard:
    """The blue pill image in QEMU, its USART1 on the process's stdin/stdout."""

    def __init__(self, elf: Path, extra: tuple[str, ...] = ()) -> None:
        assert QEMU is not None
        self.proc = subprocess.Popen(
            [
                QEMU,
                "-M",
                "stm32vldiscovery",
                "-kernel",
                str(elf),
                "-nographic",
                "-monitor",
                "none",
                "-serial",
                "stdio",
                *extra,
            ],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
        )
        self.decoder = StreamDecoder()

    def send(self, msg: Message, seq: int) -> None:
        assert self.proc.stdin is not None
        self.proc.stdin.write(encode(msg, seq))
        self.proc.stdin.flush()

    def read_until(self, count: int, timeout_s: float = 10.0) -> list[Message]:
        """Messages until `count` arrived or the timeout passed."""
        assert self.proc.stdout is not None
        out: list[Message] = []
        end = time.monotonic() + timeout_s
        while len(out) < count and time.monotonic() < end:
            ready, _, _ = select.select([self.proc.stdout], [], [], 0.05)
            if ready:
                chunk = os.read(self.proc.stdout.fileno(), 4096)
                if not chunk:
                    break
                out.extend(self.decoder.feed(chunk))
        return out

    def close(self) -> None:
        self.proc.terminate()
        try:
            self.proc.wait(5)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()


@pytest.fixture(scope="module")
def elf(tmp_path_factory: pytest.TempPathFactory) -> Path:
    build = tmp_path_factory.mktemp("qemu-fw")
    result = subprocess.run(
        ["make", "-C", str(ROOT / "firmware"), "BOARD=bluepill", f"BUILD_DIR={build}"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    return build / "bluepill" / "obstacle-fusion.elf"


@pytest.fixture
def board(elf: Path) -> Iterator[QemuBoard]:
    b = QemuBoard(elf)
    try:
        yield b
    finally:
        b.close()


def test_boots_and_says_hello(board: QemuBoard) -> None:
    msgs = board.read_until(2)
    assert [type(m) for m in msgs] == [Hello, Config]
    hello, config = msgs
    assert isinstance(hello, Hello) and isinstance(config, Config)
    assert hello.board == Board.BLUEPILL
    assert hello.timer_hz == 8_000_000
    assert hello.cpu_hz == 8_000_000  # QEMU has no RCC: the bounded waits fell back to HSI
    assert config.cycle_ms == 60 and config.echo_timeout_us == 40_000
    assert board.decoder.stats.crc_errors == 0


def test_answers_commands(board: QemuBoard) -> None:
    assert len(board.read_until(2)) == 2
    board.send(GetInfo(), 10)
    board.send(TimeSync(token=0xC0FFEE), 11)
    board.send(
        SetConfig(
            cycle_ms=5, sensor_mask=1, max_echo_us=100, echo_timeout_us=40_000, heartbeat_ms=0
        ),
        12,
    )
    board.send(
        SetConfig(
            cycle_ms=100, sensor_mask=1, max_echo_us=100, echo_timeout_us=40_000, heartbeat_ms=0
        ),
        13,
    )
    msgs = board.read_until(6)
    assert [type(m) for m in msgs] == [Hello, Config, TimeSyncReply, Nack, Ack, Config]
    reply, nack, ack, config = msgs[2], msgs[3], msgs[4], msgs[5]
    assert isinstance(reply, TimeSyncReply) and reply.token == 0xC0FFEE
    assert isinstance(nack, Nack) and nack.command_seq == 12 and nack.error == Error.BAD_CYCLE
    assert isinstance(ack, Ack) and ack.command_seq == 13
    assert isinstance(config, Config) and config.cycle_ms == 100 and config.max_echo_us == 100
    assert board.decoder.stats.seq_gaps == 0


# The ROM bootloader's vector table stand-in: in RAM, above the firmware's data and below
# its stack (which starts 8 KB up), aligned as VTOR requires.
ROM_TABLE = 0x2000_1000
VECTORS = 16 + 43


def boot_rom_table(image: bytes) -> bytes:
    """A vector table like the one the STM32's system memory (the ROM bootloader) shows at
    address 0 while BOOT0 is latched: initial SP and reset entry are the image's (the
    bootloader's GO command loads both from the image at 0x08000000), every other entry
    leads into the ROM's own code, here a `b .` loop."""
    sp, reset = struct.unpack_from("<II", image, 0)
    assert reset & 0xFFFF_0000 == 0x0800_0000  # the image runs from its flash address
    hang = ROM_TABLE + 0x100
    table = struct.pack(f"<{VECTORS}I", sp, reset, *([hang | 1] * (VECTORS - 2)))
    return table.ljust(0x100, b"\0") + b"\xfe\xe7"  # b .


def test_started_from_the_boot_alias_still_runs(elf: Path, tmp_path: Path) -> None:
    """Issue 13, defect 10 a. `stm32flash -g 0x0` starts the image at its flash address
    while address 0 (BOOT0 still latched) shows the ROM bootloader, and VTOR is still 0:
    without the firmware setting VTOR, its first interrupt vectors through the ROM's table
    and the chip hangs. QEMU's F100 maps flash at 0, so the test starts the CPU with its
    reset VTOR on a stand-in ROM table (armv7m init-nsvtor) holding the image's SP and
    reset entry, like the GO command. HELLO goes out by polling either way; a command is
    answered only if the USART interrupt reaches the firmware's own handler."""
    rom = tmp_path / "rom.bin"
    rom.write_bytes(boot_rom_table(elf.with_suffix(".bin").read_bytes()))
    board = QemuBoard(
        elf,
        (
            "-global",
            f"armv7m.init-nsvtor={ROM_TABLE:#x}",
            "-device",
            f"loader,file={rom},addr={ROM_TABLE:#x}",
        ),
    )
    try:
        assert [type(m) for m in board.read_until(2)] == [Hello, Config]
        board.send(TimeSync(token=0xB007), 1)
        board.send(GetInfo(), 2)
        msgs = board.read_until(3, timeout_s=5.0)
        assert [type(m) for m in msgs] == [TimeSyncReply, Hello, Config], msgs
        assert isinstance(msgs[0], TimeSyncReply) and msgs[0].token == 0xB007
    finally:
        board.close()
