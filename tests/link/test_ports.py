"""Board port detection by USB VID:PID (obstacle_fusion.link.ports)."""

from __future__ import annotations

from dataclasses import dataclass

import pytest
from obstacle_fusion.errors import UserError
from obstacle_fusion.link.ports import find_board_port, known_device, list_board_ports

pytestmark = pytest.mark.cpu_only


@dataclass
class FakePort:
    device: str
    vid: int | None
    pid: int | None
    description: str = "n/a"


BLUETOOTH = FakePort("/dev/ttyS0", None, None, "built-in serial")
MOUSE_LIKE = FakePort("/dev/ttyUSB7", 0x046D, 0xC52B, "some other USB serial")


@pytest.mark.parametrize(
    ("vid", "pid"),
    [
        (0x2341, 0x0043),
        (0x2341, 0x0001),
        (0x2A03, 0x0043),
        (0x1A86, 0x7523),
        (0x0403, 0x6001),
        (0x10C4, 0xEA60),
        (0x0483, 0x374B),
    ],
)
def test_known_boards_are_found(vid: int, pid: int) -> None:
    ports = [BLUETOOTH, FakePort("/dev/ttyACM0", vid, pid, "a board"), MOUSE_LIKE]
    assert find_board_port(ports) == "/dev/ttyACM0"


def test_unknown_devices_are_ignored() -> None:
    assert known_device(0x046D, 0xC52B) is None
    assert known_device(None, None) is None
    assert known_device(0x1A86, 0x0001) is None  # the CH340 vendor, another product
    assert list_board_ports([BLUETOOTH, MOUSE_LIKE]) == []


def test_no_board_is_a_clear_error() -> None:
    with pytest.raises(UserError) as err:
        find_board_port([BLUETOOTH, MOUSE_LIKE])
    text = str(err.value)
    assert "no board found" in text
    assert "--port" in text
    assert "1a86:7523" in text  # names what it looked for


def test_several_boards_are_ambiguous() -> None:
    ports = [FakePort("/dev/ttyUSB1", 0x1A86, 0x7523), FakePort("/dev/ttyACM0", 0x2341, 0x43)]
    with pytest.raises(UserError) as err:
        find_board_port(ports)
    text = str(err.value)
    assert "/dev/ttyACM0" in text and "/dev/ttyUSB1" in text
    assert "--port" in text
    found = list_board_ports(ports)
    assert [b.device for b in found] == ["/dev/ttyACM0", "/dev/ttyUSB1"]
    assert found[0].kind == "Arduino"


def test_system_ports_are_listed_without_error() -> None:
    # Whatever this machine has: the scan itself must work and return only known ids.
    for port in list_board_ports():
        assert known_device(port.vid, port.pid) is not None
