"""`obstacle-fusion run --port PORT` with no camera: the sonar alone, live.

The real Uno firmware in the emulator stands in for the board; every reading becomes one
range record on every output (JSON lines, MCAP, console), with no vision and no OpenCV.
"""

from __future__ import annotations

import json
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path

from obstacle_fusion.outputs.mcap_file import TOPIC_OBSTACLE, TOPIC_RANGE, read_recording
from obstacle_fusion.sim.emulator import Emulator

from tests import emulator_fixtures

uno_elf = emulator_fixtures.uno_elf
emulator_built = emulator_fixtures.emulator_built
emulator_factory = emulator_fixtures.emulator_factory


def test_sonar_only_run_publishes_range_records(
    uno_elf: Path, emulator_factory: Callable[..., Emulator], tmp_path: Path
) -> None:
    emu = emulator_factory(elf=uno_elf, distance_m=1.5)
    mcap = tmp_path / "sonar.mcap"
    proc = subprocess.Popen(
        [sys.executable, "-m", "obstacle_fusion", "run", "--port", emu.pty_path, "--duration",
         "4", "--json", "--record", str(mcap), "--stop-distance", "0.6"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    assert proc.stdout is not None and proc.stderr is not None
    errors: list[str] = []
    reader = threading.Thread(target=lambda: errors.extend(proc.stderr), daemon=True)  # type: ignore[arg-type]
    reader.start()
    # 1.5 m, then nothing in range, then 0.5 m (an alert), as the records come in
    lines: list[str] = []
    for line in proc.stdout:
        lines.append(line)
        if len(lines) == 20:
            emu.control.set_distance(None)
        elif len(lines) == 30:
            emu.control.set_distance(0.5)
    proc.wait(60)
    reader.join(10)
    out, err = "".join(lines), "".join(errors)
    assert proc.returncode == 0, err
    assert "sonar only" in err and "Traceback" not in err
    records = [json.loads(line) for line in out.splitlines()]
    assert len(records) >= 40  # ~16 readings a second for 4 s, after the handshake
    assert {r["source"] for r in records} == {"sonar"}
    assert {r["frame_index"] for r in records} == {-1}
    assert all(r["height_m"] is None and r["width_m"] is None for r in records)
    ranges = [r for r in records if r["status"] == "range"]
    near = [r for r in ranges if r["distance_m"] < 1.0]
    far = [r for r in ranges if r["distance_m"] >= 1.0]
    clear = [r for r in records if r["status"] == "clear"]
    assert len(far) >= 15 and len(near) >= 5 and len(clear) >= 5
    assert all(abs(r["distance_m"] - 1.5) < 0.015 for r in far)  # within 1 %
    assert all(abs(r["distance_m"] - 0.5) < 0.005 for r in near)
    assert all(r["alert"] for r in near) and not any(r["alert"] for r in far + clear)
    assert all(r["distance_m"] is None and r["sonar_status"] == "no_echo" for r in clear)
    times = [r["t_host"] for r in records]
    assert times == sorted(times)
    assert f"{len(records)} range records" in err
    rec = read_recording(mcap)
    assert rec.complete, rec.problem
    obstacles = [m for m in rec.messages if m.topic == TOPIC_OBSTACLE]
    assert len(obstacles) == len(records)
    assert len([m for m in rec.messages if m.topic == TOPIC_RANGE]) >= len(records)
    assert rec.metadata["run"]["mode"] == "sonar-only"


def test_sonar_only_needs_no_opencv(
    uno_elf: Path, emulator_factory: Callable[..., Emulator]
) -> None:
    """A robot with only the sonar never pays for OpenCV (the console view included)."""
    emu = emulator_factory(elf=uno_elf, distance_m=0.9)
    probe = (
        "import io, sys\n"
        "from obstacle_fusion.cli import main\n"
        f"code = main(['run', '--port', {emu.pty_path!r}, '--duration', '1.5'])\n"
        "sys.exit(3 if 'cv2' in sys.modules else code)\n"
    )
    t0 = time.monotonic()
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert "range d=0.900 m" in done.stderr  # the console view's last line
    # no camera to wait for: the run starts with the first range, not after a time-out
    assert "starting the camera anyway" not in done.stderr
    assert time.monotonic() - t0 < 30


def test_video_without_a_camera_is_refused(tmp_path: Path) -> None:
    done = subprocess.run(
        [sys.executable, "-m", "obstacle_fusion", "run", "--port", "/dev/null", "--video",
         str(tmp_path / "v.mp4")],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert done.returncode == 2
    assert "--video needs --camera" in done.stderr and "Traceback" not in done.stderr
