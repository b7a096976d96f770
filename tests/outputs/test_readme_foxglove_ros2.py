"""README's "Use it with Foxglove" and "Use it with ROS 2" recipes, run as written.

The fenced ``sh`` block of each section is taken from README.md and run with bash in a
scratch folder that sees this checkout's ``.venv`` and ``tools/`` as the repository's root
does, so the README and the program cannot drift apart."""

from __future__ import annotations

import asyncio
import json
import os
import re
import socket
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import av
import numpy as np
import pytest
from mcap.reader import make_reader
from obstacle_fusion.outputs.foxglove_schemas import TOPIC_ANNOTATIONS, TOPIC_IMAGE, TOPIC_RANGE
from obstacle_fusion.outputs.ros2_bag import typestore
from obstacle_fusion.vision.camera import CameraModel
from rosbags.rosbag2 import Reader

from tests import emulator_fixtures
from tests.outputs.test_live_foxglove import _receive

uno_elf = emulator_fixtures.uno_elf
emulator_built = emulator_fixtures.emulator_built

REPO = Path(__file__).resolve().parents[2]


def readme_block(section: str) -> str:
    text = (REPO / "README.md").read_text(encoding="utf-8")
    start = text.index(f"\n## {section}\n")
    end = text.find("\n## ", start + 1)
    found = re.search(r"```sh\n(.*?)```", text[start : end if end > 0 else None], re.S)
    assert found, f"no ```sh block in README section {section!r}"
    return found.group(1)


def _scratch(tmp_path: Path) -> Path:
    venv = Path(sys.prefix)
    if not (venv / "bin" / "obstacle-fusion").exists():
        pytest.skip("the tests' interpreter is not a venv with obstacle-fusion installed")
    (tmp_path / ".venv").symlink_to(venv)
    (tmp_path / "tools").symlink_to(REPO / "tools")
    return tmp_path


def _bash(block: str, cwd: Path) -> subprocess.Popen[str]:
    return subprocess.Popen(
        ["bash", "-euo", "pipefail", "-c", block],
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
    )


def test_foxglove_recipe(uno_elf: Path, tmp_path: Path) -> None:
    block = readme_block("Use it with Foxglove")
    assert "--foxglove 8765" in block  # the port the prose tells Foxglove to open
    with socket.socket() as s:
        if s.connect_ex(("127.0.0.1", 8765)) == 0:
            pytest.skip("something already listens on 127.0.0.1:8765")
    cwd = _scratch(tmp_path)
    proc = _bash(block, cwd)
    got: dict[str, list[Any]] = {}
    try:
        deadline = time.monotonic() + 30.0
        while True:  # as a user would: connect once the run has started
            try:
                _, got = asyncio.run(_receive("ws://127.0.0.1:8765", 20.0))
                break
            except OSError:
                if time.monotonic() > deadline or proc.poll() is not None:
                    raise
                time.sleep(0.3)
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait(10)
    assert proc.returncode == 0, err
    assert all(len(got.get(t, [])) >= 2 for t in (TOPIC_IMAGE, TOPIC_ANNOTATIONS, TOPIC_RANGE))
    with open(cwd / "demo.mcap", "rb") as fh:
        summary = make_reader(fh).get_summary()
    assert summary is not None
    names = {s.name for s in summary.schemas.values()}
    assert {
        "foxglove.CompressedImage",
        "foxglove.ImageAnnotations",
        "foxglove.SceneUpdate",
        "foxglove.FrameTransform",
        "foxglove.Log",
    } <= names
    assert summary.statistics is not None
    assert summary.statistics.message_start_time > 1_600_000_000 * 10**9  # Unix time
    with av.open(str(cwd / "demo.mp4")) as container:
        assert container.streams.video[0].codec_context.name == "h264"
    assert (REPO / "tools/foxglove/layout.json").is_file()  # what the prose says to import


def test_ros2_recipe(uno_elf: Path, tmp_path: Path) -> None:
    cwd = _scratch(tmp_path)
    proc = _bash(readme_block("Use it with ROS 2"), cwd)
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 0, err
    store = typestore()
    for bag in ("demo_bag", "replay_bag"):
        with Reader(cwd / bag) as reader:
            types = {c.topic: c.msgtype for c in reader.connections}
            counts = {c.topic: c.msgcount for c in reader.connections}
            assert types["/sonar/range"] == "sensor_msgs/msg/Range"
            assert types["/obstacle/detections"] == "vision_msgs/msg/Detection3DArray"
            assert counts["/camera/image/compressed"] == counts["/obstacle/detections"] > 20
            conn = next(c for c in reader.connections if c.topic == "/obstacle/detections")
            found = [
                store.deserialize_cdr(raw, conn.msgtype)
                for _, _, raw in reader.messages(connections=[conn])
            ]
            assert sum(len(a.detections) for a in found) > 0.8 * len(found)
    replayed = [json.loads(line) for line in (cwd / "replay.jsonl").read_text().splitlines()]
    assert len(replayed) == counts["/obstacle/detections"]
    from ruamel.yaml import YAML

    info = YAML(typ="safe").load((cwd / "camera_info.yaml").read_text())
    cam = CameraModel.load(cwd / "camera.yaml")
    k = np.array(info["camera_matrix"]["data"]).reshape(3, 3)
    assert k == pytest.approx(cam.camera_matrix)
    assert (info["image_width"], info["image_height"]) == (640, 480)
