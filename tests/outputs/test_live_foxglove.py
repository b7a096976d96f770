"""The live Foxglove WebSocket server, seen from a WebSocket client on the loopback: the
advertised channels and schemas, and images, annotations and ranges received after a
subscribe; first from the server alone, then from `obstacle-fusion run --foxglove`."""

from __future__ import annotations

import asyncio
import json
import re
import socket
import struct
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import websockets
from obstacle_fusion.errors import UserError
from obstacle_fusion.fusion import ObstacleRecord
from obstacle_fusion.outputs.foxglove_schemas import (
    TOPIC_ANNOTATIONS,
    TOPIC_IMAGE,
    TOPIC_RANGE,
    FoxgloveTopics,
    foxglove_schema,
)
from obstacle_fusion.outputs.live_foxglove import Address, FoxgloveLiveServer
from obstacle_fusion.protocol.generated import Range
from obstacle_fusion.sonar import SonarConverter

from tests import emulator_fixtures

uno_elf = emulator_fixtures.uno_elf
emulator_built = emulator_fixtures.emulator_built

SUBPROTOCOL = "foxglove.sdk.v1"  # what foxglove-sdk's server speaks (Foxglove app: the same)
WANTED = (TOPIC_IMAGE, TOPIC_ANNOTATIONS, TOPIC_RANGE)


def test_address_parsing() -> None:
    assert Address.parse("8765") == Address("127.0.0.1", 8765)  # loopback unless asked
    assert Address.parse("0.0.0.0:9000") == Address("0.0.0.0", 9000)
    assert Address.parse("[::1]:8765") == Address("::1", 8765)
    for bad in ("http", "127.0.0.1:", "70000", ":8765", "[::1]8765"):
        with pytest.raises(UserError, match="--foxglove"):
            Address.parse(bad)


def test_a_taken_port_is_a_clear_error() -> None:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen()
        port = s.getsockname()[1]
        with pytest.raises(UserError, match="in use"):
            FoxgloveLiveServer(Address("127.0.0.1", port))
        from obstacle_fusion.cli import main

        t0 = time.monotonic()
        assert main(["run", "--foxglove", str(port), "--duration", "1"]) == 2
        assert time.monotonic() - t0 < 5.0  # refused before the emulated robot starts


async def _receive(url: str, timeout_s: float) -> tuple[dict[str, Any], dict[str, list[Any]]]:
    """Advertised channels by topic, and the first messages received on WANTED topics."""
    got: dict[str, list[Any]] = {}
    async with websockets.connect(url, subprotocols=[SUBPROTOCOL]) as ws:  # type: ignore[list-item]
        assert ws.subprotocol == SUBPROTOCOL
        channels: dict[str, Any] = {}
        deadline = time.monotonic() + timeout_s
        while not all(t in channels for t in WANTED):
            msg = await asyncio.wait_for(ws.recv(), deadline - time.monotonic())
            if isinstance(msg, str):
                d = json.loads(msg)
                if d["op"] == "advertise":
                    channels.update({c["topic"]: c for c in d["channels"]})
        subs = {i: channels[t] for i, t in enumerate(WANTED, start=1)}
        await ws.send(
            json.dumps(
                {
                    "op": "subscribe",
                    "subscriptions": [{"id": i, "channelId": c["id"]} for i, c in subs.items()],
                }
            )
        )
        while time.monotonic() < deadline and not all(len(got.get(t, [])) >= 2 for t in WANTED):
            msg = await asyncio.wait_for(ws.recv(), deadline - time.monotonic())
            if isinstance(msg, bytes) and msg[0] == 1:  # MessageData
                sub_id, log_time = struct.unpack_from("<IQ", msg, 1)
                topic = subs[sub_id]["topic"]
                got.setdefault(topic, []).append((log_time, json.loads(msg[13:])))
    return channels, got


def _record(i: int) -> ObstacleRecord:
    return ObstacleRecord(
        t_host=100.0 + i * 0.1,
        distance_m=1.5,
        height_m=0.4,
        width_m=0.5,
        confidence=0.9,
        status="ok",
        alert=False,
        frame_index=i,
        source="t",
        pairing="nearest",
        pair_dt_s=0.0,
        sonar_status="ok",
        measurements=(i,),
        trigger_us=(i,),
        box_px=(10.0, 20.0, 30.0, 40.0),
        t_published=100.05 + i * 0.1,
    )


def test_a_client_subscribes_and_receives_images_annotations_and_ranges() -> None:
    unix = 1_750_000_000_000_000_000
    topics = FoxgloveTopics(unix_offset_ns=unix)
    conv = SonarConverter()
    stop = threading.Event()
    with FoxgloveLiveServer(Address("127.0.0.1", 0)) as server:
        assert server.url.startswith("ws://127.0.0.1:") and server.port > 0

        def pump() -> None:
            i = 0
            while not stop.is_set() and i < 400:  # bounded: 20 s at most
                t = 100.0 + i * 0.1
                for m in topics.frame(np.full((48, 64, 3), i % 255, np.uint8), t, t + 0.01):
                    server.write(m)
                reading = conv.convert(Range(i, 0, 0, 11662, 0), t - 0.01)
                for m in topics.reading(reading, 2_000_000, 1, t):
                    server.write(m)
                for m in topics.record(_record(i)):
                    server.write(m)
                i += 1
                time.sleep(0.05)

        thread = threading.Thread(target=pump, daemon=True)
        thread.start()
        try:
            channels, got = asyncio.run(_receive(server.url, 15.0))
        finally:
            stop.set()
            thread.join(5)
    assert channels[TOPIC_IMAGE]["schemaName"] == "foxglove.CompressedImage"
    assert channels[TOPIC_ANNOTATIONS]["schemaName"] == "foxglove.ImageAnnotations"
    assert json.loads(channels[TOPIC_ANNOTATIONS]["schema"]) == foxglove_schema(
        "foxglove.ImageAnnotations"
    )
    assert channels[TOPIC_RANGE]["encoding"] == "json"
    log_time, image = got[TOPIC_IMAGE][0]
    assert image["format"] == "jpeg" and image["frame_id"] == "camera"
    stamp = image["timestamp"]["sec"] * 10**9 + image["timestamp"]["nsec"]
    assert log_time == stamp + 10_000_000  # log time: 10 ms after the capture, Unix ns
    _, ann = got[TOPIC_ANNOTATIONS][0]
    assert ann["points"][0]["points"][0] == {"x": 10.0, "y": 20.0}
    assert [t["text"] for t in ann["texts"]][1] == "L 1.500 m"
    _, rng = got[TOPIC_RANGE][0]
    assert rng["distance_m"] == pytest.approx(1.0, abs=0.01) and rng["echo_ticks"] == 11662


def test_run_serves_the_emulated_robot_live(uno_elf: Path) -> None:
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "obstacle_fusion",
            "run",
            "--duration",
            "8",
            "--quiet",
            "--foxglove",
            "127.0.0.1:0",
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert proc.stderr is not None
    url = None
    lines: list[str] = []
    try:
        for line in proc.stderr:
            lines.append(line)
            found = re.search(r"Foxglove live on (ws://127\.0\.0\.1:\d+)", line)
            if found:
                url = found.group(1)
                break
        assert url is not None, "".join(lines)
        channels, got = asyncio.run(_receive(url, 20.0))
        rest = proc.stderr.read()
        assert proc.wait(30) == 0, rest
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait(10)
    assert {t: len(got.get(t, [])) >= 2 for t in WANTED} == dict.fromkeys(WANTED, True)
    _, image = got[TOPIC_IMAGE][0]
    assert image["timestamp"]["sec"] > 1_600_000_000  # Unix time, not seconds since boot
    boxes = [a for _, a in got[TOPIC_ANNOTATIONS] if a["points"]]
    assert boxes, "no annotation with the obstacle's box"  # the demo box is in view
    assert any(t["text"].startswith("L ") for t in boxes[0]["texts"])
    _, rng = got[TOPIC_RANGE][-1]
    assert rng["status"] == "ok" and 0.5 < rng["distance_m"] < 3.5


def test_without_the_sdk_run_names_the_extra(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    from obstacle_fusion.cli import main

    monkeypatch.setitem(sys.modules, "foxglove", None)
    assert main(["run", "--foxglove", "8765", "--duration", "1"]) == 2
    assert "obstacle-fusion[foxglove]" in capsys.readouterr().err
    assert main(["run", "--foxglove", "no-port-here"]) == 2  # checked before anything starts
    assert "HOST:PORT" in capsys.readouterr().err
