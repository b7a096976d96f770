"""`obstacle-fusion flash`: tool checks, port choice, and a real build driven through make."""

from __future__ import annotations

import os
import shutil
import stat
from pathlib import Path

import pytest
from obstacle_fusion.cli import flash as flash_cli
from obstacle_fusion.cli import main

pytestmark = pytest.mark.cpu_only

HAVE_AVR = shutil.which("avr-gcc") is not None and shutil.which("make") is not None


def fake_tool(bindir: Path, name: str, log: Path) -> None:
    """A stand-in flasher that records its arguments."""
    path = bindir / name
    path.write_text(f'#!/bin/sh\necho "{name} $*" >> "{log}"\n')
    path.chmod(path.stat().st_mode | stat.S_IXUSR)


def which_without(*missing: str):  # type: ignore[no-untyped-def]
    real = shutil.which

    def which(name: str, *args: object, **kwargs: object) -> str | None:
        return None if name in missing else real(name)

    return which


def test_missing_avrdude_is_named(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setattr(flash_cli.shutil, "which", which_without("avrdude"))
    assert main(["flash", "--board", "uno", "--port", "/dev/null"]) == 2
    err = capsys.readouterr().err
    assert "avrdude" in err and "apt install avrdude" in err
    assert "Traceback" not in err


def test_missing_stlink_tools_are_named(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setattr(
        flash_cli.shutil, "which", which_without("st-flash", "openocd", "stm32flash")
    )
    assert main(["flash", "--board", "bluepill"]) == 2
    err = capsys.readouterr().err
    assert "st-flash" in err and "stlink-tools" in err


def test_missing_compiler_is_named(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setattr(flash_cli.shutil, "which", which_without("arm-none-eabi-gcc"))
    assert main(["flash", "--board", "bluepill"]) == 2
    assert "arm-none-eabi-gcc not found" in capsys.readouterr().err


def test_bad_firmware_dir(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["flash", "--board", "uno", "--firmware-dir", str(tmp_path)]) == 2
    assert "firmware sources not found" in capsys.readouterr().err


def test_unknown_board_is_refused(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        main(["flash", "--board", "mega"])
    assert "invalid choice" in capsys.readouterr().err


def test_no_port_found_is_a_user_error(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bindir = tmp_path / "bin"
    bindir.mkdir()
    fake_tool(bindir, "avrdude", tmp_path / "calls.log")
    monkeypatch.setenv("PATH", f"{bindir}{os.pathsep}{os.environ['PATH']}")
    monkeypatch.setattr("obstacle_fusion.link.ports._system_ports", lambda: [])
    if shutil.which("avr-gcc") is None:
        pytest.skip("avr-gcc not installed")
    assert main(["flash", "--board", "uno"]) == 2
    assert "no board found" in capsys.readouterr().err
    assert not (tmp_path / "calls.log").exists()


@pytest.mark.skipif(not HAVE_AVR, reason="avr-gcc and make are needed to build the Uno image")
def test_uno_build_and_flash_through_make(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    bindir = tmp_path / "bin"
    bindir.mkdir()
    calls = tmp_path / "calls.log"
    fake_tool(bindir, "avrdude", calls)
    monkeypatch.setenv("PATH", f"{bindir}{os.pathsep}{os.environ['PATH']}")
    build = tmp_path / "build"
    controller, device = os.openpty()  # a real character device stands in for the board
    tty = os.ttyname(device)
    try:
        assert main(["flash", "--board", "uno", "--port", tty, "--build-dir", str(build)]) == 0
    finally:
        os.close(controller)
        os.close(device)
    hexfile = build / "uno" / "obstacle-fusion.hex"
    assert hexfile.is_file() and hexfile.read_text().startswith(":")
    line = calls.read_text().strip()
    assert line.startswith("avrdude ")
    assert "-p atmega328p" in line and "-c arduino" in line and f"-P {tty}" in line
    assert f"flash:w:{hexfile}:i" in line


@pytest.mark.skipif(not HAVE_AVR, reason="avr-gcc and make are needed to build the Uno image")
def test_uno_port_found_by_vid_pid(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from tests.link.test_ports import FakePort

    bindir = tmp_path / "bin"
    bindir.mkdir()
    calls = tmp_path / "calls.log"
    fake_tool(bindir, "avrdude", calls)
    monkeypatch.setenv("PATH", f"{bindir}{os.pathsep}{os.environ['PATH']}")
    monkeypatch.setattr(
        "obstacle_fusion.link.ports._system_ports",
        lambda: [FakePort("/dev/ttyS0", None, None), FakePort("/dev/ttyACM3", 0x2341, 0x0043)],
    )
    assert main(["flash", "--board", "uno", "--build-dir", str(tmp_path / "build")]) == 0
    assert "-P /dev/ttyACM3" in calls.read_text()


@pytest.mark.parametrize(
    ("make_port", "expected"),
    [
        (lambda d: str(d / "ttyNOPE"), "does not exist"),
        (lambda d: str(d), "is a folder, not a serial port"),
        (lambda d: str(d / "notes.txt"), "is a file, not a serial port"),
    ],
)
def test_a_port_that_cannot_be_a_board_is_refused_before_flashing(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    make_port,  # type: ignore[no-untyped-def]
    expected: str,
) -> None:
    bindir = tmp_path / "bin"
    bindir.mkdir()
    calls = tmp_path / "calls.log"
    fake_tool(bindir, "avrdude", calls)
    monkeypatch.setenv("PATH", f"{bindir}{os.pathsep}{os.environ['PATH']}")
    monkeypatch.setattr(flash_cli.shutil, "which", lambda name, *a, **k: f"/usr/bin/{name}")
    (tmp_path / "notes.txt").write_text("not a port")
    assert main(["flash", "--board", "uno", "--port", make_port(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert expected in err and "Traceback" not in err
    assert not calls.exists()  # nothing was run


def test_board_name_is_case_insensitive_and_build_dir_must_be_a_folder(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    afile = tmp_path / "build.txt"
    afile.write_text("")
    assert main(["flash", "--board", "UNO", "--build-dir", str(afile)]) == 2
    assert "is a file; give a folder" in capsys.readouterr().err


def test_bluepill_port_without_stm32flash_is_not_ignored_silently(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    caplog: pytest.LogCaptureFixture,
) -> None:
    monkeypatch.setattr(
        flash_cli.shutil,
        "which",
        lambda name, *a, **k: None if name in ("stm32flash", "openocd") else f"/usr/bin/{name}",
    )
    ran: list[list[str]] = []
    monkeypatch.setattr(flash_cli.subprocess, "run", lambda cmd: ran.append(cmd) or subprocess_ok())
    controller, device = os.openpty()
    try:
        with caplog.at_level("WARNING"):
            assert main(["flash", "--board", "bluepill", "--port", os.ttyname(device)]) == 0
    finally:
        os.close(controller)
        os.close(device)
    assert "stm32flash" in caplog.text and "ST-Link" in caplog.text
    assert ran[0][:2] == ["/usr/bin/make", "-C"] and ran[0][-1] == "BOARD=bluepill"  # the build
    assert ran[1][:3] == ["st-flash", "--reset", "write"]  # then the ST-Link, not the port
    assert ran[1][3].endswith("bluepill/obstacle-fusion.bin") and len(ran) == 2


def subprocess_ok():  # type: ignore[no-untyped-def]
    import subprocess

    return subprocess.CompletedProcess([], 0)


def test_installed_without_sources_the_shipped_image_is_flashed_without_a_compiler(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """As after `pip install .`: no firmware sources, no avr-gcc, no make; avrdude alone."""
    from obstacle_fusion import bundled

    shipped = tmp_path / "site" / "obstacle_fusion" / "_data" / "firmware" / "uno"
    shipped.mkdir(parents=True)
    (shipped / "obstacle-fusion.hex").write_text(":00000001FF\n")
    monkeypatch.setattr(bundled, "checkout_root", lambda: None)
    monkeypatch.setattr(bundled, "DATA_DIR", tmp_path / "site" / "obstacle_fusion" / "_data")
    bindir = tmp_path / "bin"
    bindir.mkdir()
    calls = tmp_path / "calls.log"
    fake_tool(bindir, "avrdude", calls)
    monkeypatch.setenv("PATH", str(bindir))  # no make, no avr-gcc
    controller, device = os.openpty()
    try:
        assert main(["flash", "--board", "uno", "--port", os.ttyname(device)]) == 0
    finally:
        os.close(controller)
        os.close(device)
    line = calls.read_text().strip()
    assert f"flash:w:{shipped / 'obstacle-fusion.hex'}:i" in line and "-c arduino" in line


def test_installed_without_an_image_for_the_board_says_so(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    from obstacle_fusion import bundled

    monkeypatch.setattr(bundled, "checkout_root", lambda: None)
    monkeypatch.setattr(bundled, "DATA_DIR", tmp_path / "nothing")
    monkeypatch.setattr(flash_cli.shutil, "which", lambda name, *a, **k: f"/usr/bin/{name}")
    assert main(["flash", "--board", "bluepill"]) == 2
    err = capsys.readouterr().err
    assert "ships no bluepill firmware image" in err and "--image" in err


def test_an_image_given_is_flashed_as_is(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    ran: list[list[str]] = []
    monkeypatch.setattr(flash_cli.shutil, "which", lambda name, *a, **k: f"/usr/bin/{name}")
    monkeypatch.setattr(flash_cli.subprocess, "run", lambda cmd: ran.append(cmd) or subprocess_ok())
    image = tmp_path / "mine.bin"
    image.write_bytes(b"\x00" * 16)
    assert main(["flash", "--board", "bluepill", "--image", str(image)]) == 0
    assert ran == [["st-flash", "--reset", "write", str(image), "0x08000000"]]  # no build
    assert main(["flash", "--board", "bluepill", "--image", str(tmp_path / "no.bin")]) == 2
    assert "does not exist" in capsys.readouterr().err
