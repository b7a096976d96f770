"""`pip install .` without the Makefile: the wheel, installed in a fresh venv outside the
clone, runs the emulated robot and flashes the image it ships, with no compiler for the
firmware (the emulator itself is compiled on first use into the user's cache).

The clone's files are copied to a scratch folder first (as a fresh clone would have them);
the wheel is built there with --no-build-isolation and installed with --no-deps, its
dependencies coming from this venv through a .pth file: nothing is downloaded.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
NEEDED = ("avr-gcc", "arm-none-eabi-gcc", "make", "git")


def _clone_files(dest: Path) -> None:
    """The files a clone holds (tracked, plus new ones not ignored): no build outputs."""
    listed = subprocess.run(
        ["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
        cwd=ROOT, capture_output=True, check=True,
    ).stdout.decode()  # fmt: skip
    for rel in filter(None, listed.split("\0")):
        src = ROOT / rel
        if src.is_file():
            (dest / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / rel)


@pytest.fixture(scope="module")
def installed(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    missing = [t for t in NEEDED if shutil.which(t) is None]
    if missing:
        pytest.skip(f"building the wheel needs {', '.join(missing)} (make setup installs them)")
    base = tmp_path_factory.mktemp("wheel")
    src, dist, venv = base / "src", base / "dist", base / "venv"
    _clone_files(src)
    assert not (src / "firmware" / "build").exists()
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "--no-build-isolation",
         "--no-index", "-w", str(dist), str(src)],
        check=True, capture_output=True, timeout=240,
    )  # fmt: skip
    wheels = list(dist.glob("obstacle_fusion-*.whl"))
    assert len(wheels) == 1
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    py = venv / "bin" / "python"
    subprocess.run(
        [sys.executable, "-m", "pip", "--python", str(py), "install", "-q", "--no-deps",
         "--no-index", str(wheels[0])],
        check=True, capture_output=True, timeout=120,
    )  # fmt: skip
    site = Path(
        subprocess.run(
            [str(py), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
            check=True,
            capture_output=True,
            text=True,
        ).stdout.strip()
    )
    # The dependencies (numpy, OpenCV, ...) from this venv; its editable obstacle_fusion is
    # not activated (.pth files in an added path are not read), as the import check shows.
    (site / "zz_main_venv.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    work = base / "elsewhere"
    work.mkdir()
    return {"base": base, "venv": venv, "site": site, "work": work, "wheel": wheels[0]}


def _env(installed: dict[str, Path], path: str | None = None) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith("OF_")}
    env["XDG_CACHE_HOME"] = str(installed["base"] / "cache")
    env.pop("PYTHONPATH", None)
    if path is not None:
        env["PATH"] = path
    return env


def test_the_wheel_ships_the_images_and_the_emulator_sources(installed: dict[str, Path]) -> None:
    import zipfile

    names = set(zipfile.ZipFile(installed["wheel"]).namelist())
    for name in (
        "obstacle_fusion/_data/firmware/uno/obstacle-fusion.hex",
        "obstacle_fusion/_data/firmware/uno/obstacle-fusion.elf",
        "obstacle_fusion/_data/firmware/bluepill/obstacle-fusion.bin",
        "obstacle_fusion/_data/emulator/src/main.c",
        "obstacle_fusion/_data/emulator/src/bootloader.c",
    ):
        assert name in names, name
    assert any(n.endswith("licenses/LICENSE") for n in names)
    # the stream decoder's C accelerator, compiled for this Python, and its types
    assert any(
        n.startswith("obstacle_fusion/protocol/_cdecode.cpython-") and n.endswith(".so")
        for n in names
    ), sorted(n for n in names if "_cdecode" in n)
    assert "obstacle_fusion/protocol/_cdecode.pyi" in names
    assert not any(n.endswith(".c") and "protocol" in n for n in names)
    # and the fused vision method's
    assert any(
        n.startswith("obstacle_fusion/vision/fused/_cmiddle.cpython-") and n.endswith(".so")
        for n in names
    ), sorted(n for n in names if "_cmiddle" in n)
    assert "obstacle_fusion/vision/fused/_cmiddle.pyi" in names
    assert not any(n.endswith(".c") and "vision" in n for n in names)
    meta = next(n for n in names if n.endswith("METADATA"))
    text = zipfile.ZipFile(installed["wheel"]).read(meta).decode()
    assert "License-Expression: MIT" in text and "Project-URL: Repository" in text
    assert "Classifier: Topic :: Software Development :: Embedded Systems" in text


def test_installed_package_runs_the_emulated_robot_outside_the_clone(
    installed: dict[str, Path],
) -> None:
    venv, work = installed["venv"], installed["work"]
    where = subprocess.run(
        [str(venv / "bin" / "python"), "-c", "import obstacle_fusion; print(obstacle_fusion.__file__)"],
        cwd=work, env=_env(installed), capture_output=True, text=True, check=True,
    ).stdout.strip()  # fmt: skip
    assert Path(where).is_relative_to(installed["site"]), where
    accelerated = subprocess.run(
        [str(venv / "bin" / "python"), "-c",
         "from obstacle_fusion.protocol import StreamDecoder; print(StreamDecoder().accelerated)"],
        cwd=work, env=_env(installed), capture_output=True, text=True, check=True,
    ).stdout.strip()  # fmt: skip
    assert accelerated == "True"
    done = subprocess.run(
        [str(venv / "bin" / "obstacle-fusion"), "run", "--duration", "5", "--json"],
        cwd=work, env=_env(installed), capture_output=True, text=True, timeout=90,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    records = [json.loads(line) for line in done.stdout.splitlines()]
    measured = [r for r in records if r["status"] == "ok"]
    assert len(records) >= 45  # 15 fps for 5 s, less the start
    assert len(measured) >= 0.9 * len(records)
    # the demo's first box, 2.5 m -> 0.8 m: heights near its 0.40 m
    assert all(0.8 <= r["distance_m"] <= 2.6 for r in measured)
    assert all(abs(r["height_m"] - 0.40) < 0.02 for r in measured)
    built = list((installed["base"] / "cache" / "obstacle-fusion").glob("emulator-*/of-emulator"))
    assert len(built) == 1, "the emulator was built on first use in the user's cache"


def test_installed_flash_needs_no_compiler(installed: dict[str, Path], tmp_path: Path) -> None:
    venv, work = installed["venv"], installed["work"]
    help_ = subprocess.run(
        [str(venv / "bin" / "obstacle-fusion"), "flash", "--help"],
        cwd=work, env=_env(installed), capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert help_.returncode == 0 and "--image" in help_.stdout
    # PATH with only a stand-in avrdude: no make, no avr-gcc
    bindir = tmp_path / "bin"
    bindir.mkdir()
    calls = tmp_path / "calls.log"
    (bindir / "avrdude").write_text(f'#!/bin/sh\necho "$*" >> "{calls}"\n')
    (bindir / "avrdude").chmod(0o755)
    controller, device = os.openpty()
    try:
        done = subprocess.run(
            [str(venv / "bin" / "obstacle-fusion"), "flash", "--board", "uno", "--port",
             os.ttyname(device)],
            cwd=work, env=_env(installed, path=str(bindir)), capture_output=True, text=True,
            timeout=60,
        )  # fmt: skip
    finally:
        os.close(controller)
        os.close(device)
    assert done.returncode == 0, done.stderr
    args = calls.read_text().split()
    image = Path(args[args.index("-U") + 1].removeprefix("flash:w:").removesuffix(":i"))
    assert image.is_relative_to(installed["site"])
    assert (
        image.read_text()
        == (ROOT / "firmware" / "build" / "uno" / "obstacle-fusion.hex").read_text()
    )


@pytest.mark.cpu_only  # its own wheel, no run: on the xdist workers (tests/conftest.py)
def test_a_c_accelerator_that_does_not_compile_leaves_the_pure_decoder(tmp_path: Path) -> None:
    """An install on a machine where the decoder's C accelerator fails to compile (here: an
    #error in its source) succeeds; the package then decodes in pure Python, says so in a
    debug log line, and refuses accelerated=True."""
    src, dist, venv = tmp_path / "src", tmp_path / "dist", tmp_path / "venv"
    _clone_files(src)
    c_source = src / "host" / "obstacle_fusion" / "protocol" / "_cdecode.c"
    c_source.write_text(
        "#error this machine cannot compile the accelerator\n" + c_source.read_text()
    )
    done = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation",
         "--no-index", "-w", str(dist), str(src)],
        capture_output=True, text=True, timeout=240,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    wheels = list(dist.glob("obstacle_fusion-*.whl"))
    assert len(wheels) == 1
    import zipfile

    assert not [
        n for n in zipfile.ZipFile(wheels[0]).namelist() if "_cdecode" in n and n.endswith(".so")
    ]
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    py = venv / "bin" / "python"
    subprocess.run(
        [sys.executable, "-m", "pip", "--python", str(py), "install", "-q", "--no-deps",
         "--no-index", str(wheels[0])],
        check=True, capture_output=True, timeout=120,
    )  # fmt: skip
    site = subprocess.run(
        [str(py), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
        check=True, capture_output=True, text=True,
    ).stdout.strip()  # fmt: skip
    (Path(site) / "zz_main_venv.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    code = (
        "import logging; logging.basicConfig(level=logging.DEBUG, format='%(message)s')\n"
        "from obstacle_fusion.protocol import StreamDecoder, encode\n"
        "from obstacle_fusion.protocol.generated import Range\n"
        "m = Range(measurement=1, sensor_id=0, trigger_us=2, echo_ticks=3, status=0)\n"
        "d = StreamDecoder()\n"
        "assert d.feed(encode(m, 1) * 30) == [m] * 30 and d.stats.frames == 30\n"
        "print('accelerated', d.accelerated)\n"
        "try:\n    StreamDecoder(accelerated=True)\nexcept RuntimeError as exc:\n"
        "    print('refused', exc)\n"
    )
    ran = subprocess.run([str(py), "-c", code], cwd=tmp_path, capture_output=True, text=True,
                         timeout=60, env={k: v for k, v in os.environ.items()
                                          if k != "PYTHONPATH"})  # fmt: skip
    assert ran.returncode == 0, ran.stderr
    assert "accelerated False" in ran.stdout and "refused" in ran.stdout
    assert "stream decoder: no C accelerator" in ran.stderr
