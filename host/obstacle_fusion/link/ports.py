"""Find the board's serial port by USB VID:PID, so users need not know /dev/ttyACM0 or COM3.

Both the serial link (when no --port is given) and `obstacle-fusion flash` use this: a
port is a candidate when its USB vendor/product id belongs to an Arduino, a USB-serial
bridge commonly wired to a blue pill (CH340, FTDI, CP210x) or an ST-Link's virtual COM
port. Exactly one candidate is needed; none or several is a UserError that says what to do.
"""

from __future__ import annotations

import logging
import os
import stat
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

from obstacle_fusion.errors import UserError

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class KnownDevice:
    """A USB serial device a board shows up as; pid None matches any product."""

    vid: int
    pid: int | None
    name: str


KNOWN_DEVICES: tuple[KnownDevice, ...] = (
    KnownDevice(0x2341, None, "Arduino"),
    KnownDevice(0x2A03, None, "Arduino (arduino.org)"),
    KnownDevice(0x1A86, 0x7523, "CH340 USB-serial"),
    KnownDevice(0x1A86, 0x5523, "CH341 USB-serial"),
    KnownDevice(0x0403, 0x6001, "FTDI FT232R USB-serial"),
    KnownDevice(0x0403, 0x6015, "FTDI FT231X USB-serial"),
    KnownDevice(0x10C4, 0xEA60, "CP210x USB-serial"),
    KnownDevice(0x0483, 0x374B, "ST-Link/V2-1 virtual COM port"),
    KnownDevice(0x0483, 0x3752, "ST-Link/V2-1 virtual COM port"),
    KnownDevice(0x0483, 0x374E, "ST-Link/V3 virtual COM port"),
    KnownDevice(0x0483, 0x5740, "STM32 USB virtual COM port"),
)


class PortInfo(Protocol):
    """What we read from pyserial's ListPortInfo (a protocol, so tests can pass fakes)."""

    device: str
    vid: int | None
    pid: int | None
    description: str


@dataclass(frozen=True, slots=True)
class BoardPort:
    """A serial port that looks like one of our boards."""

    device: str
    vid: int
    pid: int
    kind: str  # KnownDevice.name
    description: str

    def __str__(self) -> str:
        return f"{self.device} ({self.kind}, {self.vid:04x}:{self.pid:04x})"


def known_device(vid: int | None, pid: int | None) -> KnownDevice | None:
    """The known device with this VID:PID, if any."""
    if vid is None or pid is None:
        return None
    for dev in KNOWN_DEVICES:
        if dev.vid == vid and (dev.pid is None or dev.pid == pid):
            return dev
    return None


def _system_ports() -> list[PortInfo]:
    from serial.tools import list_ports

    return list(list_ports.comports())


def list_board_ports(ports: Iterable[PortInfo] | None = None) -> list[BoardPort]:
    """Every port with a known VID:PID, sorted by device name (ports: default the system's)."""
    found = []
    for p in _system_ports() if ports is None else ports:
        dev = known_device(p.vid, p.pid)
        if dev is None:
            log.debug("ignoring %s (%s): not a known board", p.device, p.description)
            continue
        assert p.vid is not None and p.pid is not None
        found.append(BoardPort(p.device, p.vid, p.pid, dev.name, p.description))
    return sorted(found, key=lambda b: b.device)


def _known_list() -> str:
    return ", ".join(
        f"{d.name} {d.vid:04x}:{'*' if d.pid is None else f'{d.pid:04x}'}" for d in KNOWN_DEVICES
    )


def find_board_port(ports: Iterable[PortInfo] | None = None) -> str:
    """The one board's port; UserError when there is none or more than one."""
    found = list_board_ports(ports)
    if not found:
        raise UserError(
            "no board found: no USB serial port with a known VID:PID ("
            + _known_list()
            + "). Plug the board in (a charge-only cable shows no port), check that "
            "you may open serial ports (Linux: the dialout group), or pass --port."
        )
    if len(found) > 1:
        raise UserError(
            "several possible boards found: "
            + "; ".join(str(b) for b in found)
            + ". Pass --port to choose one."
        )
    log.info("using board port %s", found[0])
    return found[0].device


def check_port(device: str) -> str:
    """A port the user named, refused early when it cannot be a serial port.

    Tools such as avrdude otherwise fail later with a message about something else. Only
    POSIX device paths are checked: COM3 and pyserial URLs (socket://...) pass as given.
    """
    if os.name != "posix" or "://" in device:
        return device
    path = Path(device)
    if not path.exists():
        raise UserError(
            f"serial port {device} does not exist; plug the board in and check the name "
            "(ls /dev/ttyACM* /dev/ttyUSB*), or leave out --port to find the board by USB VID:PID"
        )
    if not stat.S_ISCHR(path.stat().st_mode):
        kind = "a folder" if path.is_dir() else "a file"
        raise UserError(
            f"{device} is {kind}, not a serial port; give the board's device, e.g. "
            "/dev/ttyACM0, or leave out --port to find the board by USB VID:PID"
        )
    return device
