"""`obstacle-fusion flash --board uno --port PTY` through the Uno's real bootloader.

The emulator boots Optiboot (built from the source Debian's arduino-core-avr ships) with an
erased application flash; opening its pty resets the MCU into the bootloader as a real Uno's
DTR line does. The real avrdude writes and verifies the firmware over STK500v1; Optiboot
then starts it through a watchdog reset, and the host's handshake succeeds.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import time

import pytest
from obstacle_fusion import bundled
from obstacle_fusion.link.connection import Link, LinkError
from obstacle_fusion.protocol.generated import Hello, Log, Range
from obstacle_fusion.sim.emulator import Emulator, EmulatorConfig

ROOT = bundled.REPO_ROOT


@pytest.fixture(scope="module")
def optiboot() -> object:
    if shutil.which("avrdude") is None or not (bundled.OPTIBOOT_SOURCE / "optiboot.c").is_file():
        pytest.skip("avrdude and arduino-core-avr are needed (tools/setup.sh installs them)")
    done = subprocess.run(
        ["make", "-s", "-C", str(ROOT / "tools" / "emulator"), "optiboot"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    hexfile = bundled.optiboot_hex()
    assert hexfile is not None
    return hexfile


def test_optiboot_fits_its_512_bytes(optiboot: object) -> None:
    """Debian's own prebuilt hex runs past 0x8000; the one the emulator boots must not."""
    data = 0
    top = 0
    for line in open(str(optiboot)).read().split():  # noqa: SIM115
        if line[7:9] == "00":
            n, addr = int(line[1:3], 16), int(line[3:7], 16)
            data += n
            top = max(top, addr + n)
    assert top <= 0x8000 and data <= 512


def _handshake(port: str, timeout_s: float) -> tuple[Hello, list[Range], list[Log]]:
    link = Link(port, reconnect=False, handshake_timeout_s=timeout_s)
    try:
        hello = link.start(timeout_s=timeout_s)
        ranges: list[Range] = []
        logs: list[Log] = []
        deadline = time.monotonic() + 5.0
        while len(ranges) < 3 and time.monotonic() < deadline:
            got = [it.msg for it in link.drain()]
            ranges += [m for m in got if isinstance(m, Range)]
            logs += [m for m in got if isinstance(m, Log)]
            time.sleep(0.05)
        return hello, ranges, logs
    finally:
        link.close()


def test_avrdude_flashes_the_emulated_uno_through_optiboot(optiboot: object) -> None:
    config = EmulatorConfig(
        bootloader=optiboot,  # type: ignore[arg-type]
        application=False,
        distance_m=1.2,
        wait_client=False,
        reset_on_open=True,
    )
    with Emulator(config) as emu:
        # An erased Uno: Optiboot alone, nothing speaks the obstacle-fusion protocol.
        with pytest.raises(LinkError, match="handshake"):
            _handshake(emu.pty_path, 1.5)
        assert emu.running()
        done = subprocess.run(
            [sys.executable, "-m", "obstacle_fusion", "flash", "--board", "uno", "--port",
             emu.pty_path],
            capture_output=True, text=True, timeout=120,
        )  # fmt: skip
        assert done.returncode == 0, done.stderr
        size = (ROOT / "firmware" / "build" / "uno" / "obstacle-fusion.hex").read_text()
        n_bytes = sum(int(line[1:3], 16) for line in size.split() if line[7:9] == "00")
        assert f"{n_bytes} bytes of flash written" in done.stderr
        assert f"{n_bytes} bytes of flash verified" in done.stderr
        hello, ranges, logs = _handshake(emu.pty_path, 5.0)
        assert emu.running()
    assert hello.timer_hz == 2_000_000  # the Uno firmware's Timer1 at 2 MHz
    assert len(ranges) >= 3
    # Optiboot starts the firmware through its own watchdog reset (after the flashing, and
    # after the port's open): that is no hang of the firmware's, so no "watchdog reset".
    assert logs == []
    # 1.2 m at 20 C: 2 * 1.2 / 343.2 m/s = 6.99 ms = ~13986 ticks of 0.5 us
    echo_s = [r.echo_ticks / 2e6 for r in ranges]
    assert all(abs(e * 343.2 / 2 - 1.2) < 0.02 for e in echo_s), echo_s
