"""The Python API for robot code: ObstacleSensor and AsyncObstacleSensor.

On the real Uno firmware in the emulator (its pty as the port, sonar only: fast, no vision)
and on the emulated robot (no port, no camera: the demo scene with the synthetic camera).
"""

from __future__ import annotations

import asyncio
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path

import pytest
from obstacle_fusion import AsyncObstacleSensor, ObstacleSensor
from obstacle_fusion.errors import UserError
from obstacle_fusion.fusion import ObstacleRecord
from obstacle_fusion.sim.emulator import Emulator
from obstacle_fusion.sim.scenario import demo_scenario

from tests import emulator_fixtures

uno_elf = emulator_fixtures.uno_elf
emulator_built = emulator_fixtures.emulator_built
emulator_factory = emulator_fixtures.emulator_factory


def _until(predicate: Callable[[], object], timeout_s: float = 10.0) -> None:
    deadline = time.monotonic() + timeout_s
    while not predicate():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.02)


def test_sensor_on_a_board_port(uno_elf: Path, emulator_factory: Callable[..., Emulator]) -> None:
    emu = emulator_factory(elf=uno_elf, distance_m=2.0)
    fired: list[ObstacleRecord] = []
    with ObstacleSensor(port=emu.pty_path, max_distance=3.0) as sensor:
        assert sensor.connected and sensor.mode == "sonar-only"
        _until(lambda: sensor.latest is not None)
        assert sensor.distance == pytest.approx(2.0, abs=0.02)
        remove = sensor.when_closer_than(1.0, fired.append)
        # the iterator gives every record from now on, in order, each one new
        it = iter(sensor)
        first = [next(it) for _ in range(5)]
        assert [r.t_host for r in first] == sorted(r.t_host for r in first)
        assert len({r.measurements for r in first}) == 5
        assert all(r.distance_m == pytest.approx(2.0, abs=0.02) for r in first)
        assert not fired and sensor.wait_for_closer_than(1.0, timeout=0.3) is None
        emu.control.set_distance(0.7)
        rec = sensor.wait_for_closer_than(1.0, timeout=5)
        assert rec is not None and rec.distance_m == pytest.approx(0.7, abs=0.01)
        _until(lambda: len(fired) == 1)
        assert fired[0].distance_m == pytest.approx(0.7, abs=0.01)
        time.sleep(0.3)
        assert len(fired) == 1  # once per crossing, not once per reading
        # out of range: the distance reads as max_distance; farther than it, capped
        emu.control.set_distance(None)
        _until(lambda: sensor.latest is not None and sensor.latest.status == "clear")
        assert sensor.distance == 3.0
        emu.control.set_distance(0.6)
        _until(lambda: len(fired) == 2)  # the next crossing fires again
        remove()
        emu.control.set_distance(3.5)
        _until(lambda: sensor.latest is not None and sensor.latest.distance_m is not None
               and sensor.latest.distance_m > 3.2)  # fmt: skip
        assert sensor.distance == 3.0
        sensor.max_distance = 4.0
        assert sensor.distance == pytest.approx(3.5, abs=0.03)
        emu.control.set_distance(0.5)
        assert sensor.wait_for_closer_than(0.8, timeout=5) is not None
        time.sleep(0.2)
        assert len(fired) == 2  # removed callbacks stay quiet
    assert not sensor.running
    assert list(sensor) == []  # a closed sensor's iterator ends at once


def test_a_failing_callback_does_not_stop_the_sensor(
    uno_elf: Path, emulator_factory: Callable[..., Emulator]
) -> None:
    emu = emulator_factory(elf=uno_elf, distance_m=2.0)

    def boom(rec: ObstacleRecord) -> None:
        raise RuntimeError("robot code bug")

    with ObstacleSensor(port=emu.pty_path) as sensor:
        sensor.when_closer_than(1.0, boom)
        emu.control.set_distance(0.5)
        assert sensor.wait_for_closer_than(1.0, timeout=5) is not None
        emu.control.set_distance(1.5)
        rec = sensor.wait_for_closer_than(1.6, timeout=0.1)  # the newest is already closer?
        _until(lambda: sensor.distance is not None and sensor.distance > 1.2)
        assert sensor.running and rec is not None


def test_a_port_that_never_answers_is_a_clear_error(tmp_path: Path) -> None:
    import os

    controller, device = os.openpty()  # a serial device with nothing behind it
    try:
        sensor = ObstacleSensor(port=os.ttyname(device), connect_timeout=1.0)
        t0 = time.monotonic()
        with pytest.raises(UserError, match="handshake|did not answer"):
            sensor.open()
        assert time.monotonic() - t0 < 10
        assert not sensor.running
    finally:
        os.close(controller)
        os.close(device)


def test_options_are_checked_up_front() -> None:
    with pytest.raises(UserError, match="max_distance"):
        ObstacleSensor(max_distance=0)
    with pytest.raises(UserError, match="exit_on_alert needs stop_distance"):
        ObstacleSensor(exit_on_alert=3)
    with pytest.raises(UserError, match="scenario is for the emulated robot"):
        ObstacleSensor(port="/dev/ttyACM0", scenario=demo_scenario())
    with pytest.raises(UserError, match="max_wait_ms must be within 0..5000"):
        ObstacleSensor(max_wait_ms=5001)


def test_async_sensor(uno_elf: Path, emulator_factory: Callable[..., Emulator]) -> None:
    emu = emulator_factory(elf=uno_elf, distance_m=1.8)

    async def main() -> tuple[list[ObstacleRecord], ObstacleRecord | None, list[float]]:
        seen: list[float] = []
        got: list[ObstacleRecord] = []
        async with AsyncObstacleSensor(port=emu.pty_path) as sensor:

            async def on_close(rec: ObstacleRecord) -> None:  # a coroutine callback
                seen.append(rec.distance_m or 0.0)

            sensor.when_closer_than(1.0, on_close)
            async for rec in sensor:
                got.append(rec)
                if len(got) == 4:
                    break
            assert await sensor.wait_for_closer_than(1.0, timeout=0.2) is None
            threading.Timer(0.2, lambda: emu.control.set_distance(0.8)).start()
            near = await sensor.wait_for_closer_than(1.0, timeout=5)
            for _ in range(50):
                if seen:
                    break
                await asyncio.sleep(0.02)
            assert sensor.distance == pytest.approx(0.8, abs=0.01)
        return got, near, seen

    got, near, seen = asyncio.run(main())
    assert len(got) == 4 and all(r.distance_m == pytest.approx(1.8, abs=0.02) for r in got)
    assert near is not None and near.distance_m == pytest.approx(0.8, abs=0.01)
    assert seen and seen[0] == pytest.approx(0.8, abs=0.01)


def test_sensor_on_the_emulated_robot_measures_the_box(uno_elf: Path) -> None:
    """No port, no camera: the demo's first box, 0.40 m high and 0.50 m wide, approaching."""
    with ObstacleSensor(fps=10) as sensor:
        assert sensor.mode == "emulator" and sensor.robot is not None
        rec = sensor.wait_for_closer_than(2.3, timeout=30)
        assert rec is not None and rec.status == "ok"
        assert 2.0 < rec.distance_m < 2.3  # type: ignore[operator]
        assert rec.height_m == pytest.approx(0.40, rel=0.03)
        assert rec.width_m == pytest.approx(0.50, rel=0.03)
        frames = [next(iter(sensor)).frame_index for _ in range(3)]
        assert frames == sorted(frames) and min(frames) > rec.frame_index
    assert sensor.robot is not None and sensor.robot.emulator is None  # stopped with it


def test_readme_example_runs_as_written(uno_elf: Path, tmp_path: Path) -> None:
    """The README's "Use it from Python" recipe, run exactly as printed there."""
    import re
    import subprocess

    readme = (Path(__file__).resolve().parents[1] / "README.md").read_text()
    section = readme.split("## Use it from Python", 1)[1].split("\n## ", 1)[0]
    code = re.search(r"```python\n(.*?)```", section, re.S)
    assert code is not None
    lines = code.group(1).strip().splitlines()
    assert len(lines) <= 10
    done = subprocess.run(
        [sys.executable, "-c", code.group(1)], cwd=tmp_path, capture_output=True, text=True,
        timeout=90,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    out = done.stdout.splitlines()
    m = re.fullmatch(r"obstacle (\d\.\d\d) m ahead, (\d\.\d\d) m high, (\d\.\d\d) m wide", out[0])
    assert m is not None, out
    assert 1.85 <= float(m[1]) <= 2.0 and m[2] == "0.40" and m[3] == "0.50"
    m2 = re.fullmatch(r"closer than 1\.8 m: (\d\.\d\d) m", out[1])
    assert m2 is not None and 1.7 <= float(m2[1]) <= 1.8, out  # 1.7996 prints 1.80
    m3 = re.fullmatch(r"stopped at (\d\.\d\d) m", out[-1])
    assert m3 is not None and 1.6 <= float(m3[1]) <= 1.7, out


def _record(distance: float | None, status: str = "range", index: int = 0) -> ObstacleRecord:
    return ObstacleRecord(
        t_host=float(index), distance_m=distance, height_m=None, width_m=None, confidence=1.0,
        status=status, alert=False, frame_index=-1, source="sonar", pairing="none",
        pair_dt_s=None, sonar_status="ok", measurements=(index,), trigger_us=(index,),
    )  # fmt: skip


def test_a_waiter_sees_a_closer_record_however_briefly_it_is_the_newest() -> None:
    """Records published faster than a waiting thread wakes: none is missed."""
    sensor = ObstacleSensor(port="/dev/null")  # never opened: records fed as the loop does
    got: list[ObstacleRecord | None] = []
    waiter = threading.Thread(target=lambda: got.append(sensor.wait_for_closer_than(1.0, 5)))
    waiter.start()
    _until(lambda: sensor._waiters)
    sensor._deliver(_record(2.0, index=1))
    sensor._deliver(_record(0.9, index=2))  # closer, and at once replaced
    sensor._deliver(_record(2.0, index=3))
    waiter.join(5)
    assert got and got[0] is not None and got[0].measurements == (2,)
    assert sensor.distance == 2.0 and not sensor._waiters


def test_distance_reads_as_gpiozero_does() -> None:
    sensor = ObstacleSensor(port="/dev/null", max_distance=2.5)
    assert sensor.distance is None and sensor.latest is None
    every: list[int] = []
    remove = sensor.on_record(lambda r: every.append(r.measurements[0]))
    sensor.on_record(lambda r: 1 / 0)  # a failing callback: logged, the others still run
    sensor._deliver(_record(1.234))
    assert sensor.distance == 1.234
    sensor._deliver(_record(3.1))
    assert sensor.distance == 2.5  # capped at max_distance
    sensor._deliver(_record(None, status="clear"))
    assert sensor.distance == 2.5  # nothing in range reads as max_distance
    sensor._deliver(_record(None, status="sonar_error"))
    assert sensor.distance is None  # unknown is not "far"
    sensor._deliver(_record(None, status="unpaired", index=7))
    assert sensor.distance is None
    assert every == [0, 0, 0, 0, 7]
    remove()
    sensor._deliver(_record(1.0, index=8))
    assert every == [0, 0, 0, 0, 7]
    with pytest.raises(ValueError):
        sensor.max_distance = 0


async def _live_ranges(url: str, wanted: int, timeout_s: float) -> list[dict[str, object]]:
    """The first `wanted` /sonar/range messages a Foxglove WebSocket client receives."""
    import json
    import struct

    import websockets

    got: list[dict[str, object]] = []
    deadline = time.monotonic() + timeout_s
    async with websockets.connect(url, subprotocols=["foxglove.sdk.v1"]) as ws:  # type: ignore[list-item]
        channel = None
        while channel is None:
            msg = await asyncio.wait_for(ws.recv(), deadline - time.monotonic())
            if isinstance(msg, str) and json.loads(msg)["op"] == "advertise":
                for c in json.loads(msg)["channels"]:
                    if c["topic"] == "/sonar/range":
                        channel = c["id"]
        subscribe = {"op": "subscribe", "subscriptions": [{"id": 1, "channelId": channel}]}
        await ws.send(json.dumps(subscribe))
        while len(got) < wanted:
            msg = await asyncio.wait_for(ws.recv(), deadline - time.monotonic())
            if isinstance(msg, bytes) and msg[0] == 1 and struct.unpack_from("<I", msg, 1)[0] == 1:
                got.append(json.loads(msg[13:]))
    return got


def test_sonar_only_ranges_reach_the_recording_the_live_view_and_the_ros2_bag(
    uno_elf: Path, emulator_factory: Callable[..., Emulator], tmp_path: Path
) -> None:
    """With no camera every reading still goes to every sink: MCAP, Foxglove live, ROS 2."""
    from obstacle_fusion.outputs.mcap_file import TOPIC_OBSTACLE, TOPIC_RANGE, read_recording
    from obstacle_fusion.outputs.ros2_bag import typestore
    from rosbags.rosbag2 import Reader

    emu = emulator_factory(elf=uno_elf, distance_m=1.2)
    mcap, bag = tmp_path / "sonar.mcap", tmp_path / "bag"
    with ObstacleSensor(
        port=emu.pty_path, record=mcap, ros2_bag=bag, foxglove="127.0.0.1:0"
    ) as sensor:
        assert sensor.live is not None and sensor.mode == "sonar-only"
        live = asyncio.run(_live_ranges(sensor.live.url, 5, 15.0))
        _until(lambda: sensor.app is not None and sensor.app.fusion.stats.published >= 10)
    published = sensor.app.fusion.stats.published  # type: ignore[union-attr]
    assert len(live) == 5
    assert all(m["distance_m"] == pytest.approx(1.2, abs=0.015) for m in live)
    rec = read_recording(mcap)
    assert rec.complete, rec.problem
    assert len([m for m in rec.messages if m.topic == TOPIC_OBSTACLE]) == published
    assert len([m for m in rec.messages if m.topic == TOPIC_RANGE]) >= published
    store = typestore()
    ranges, detections = [], 0
    with Reader(bag) as reader:
        for conn, _, raw in reader.messages():
            if conn.topic == "/sonar/range":
                assert conn.msgtype == "sensor_msgs/msg/Range"
                ranges.append(store.deserialize_cdr(raw, conn.msgtype))
            elif conn.topic == "/obstacle/detections":
                msg = store.deserialize_cdr(raw, conn.msgtype)
                assert msg.detections == []  # a range record has no box to detect
                detections += 1
            assert not conn.topic.startswith("/camera")  # no camera: no image, no camera_info
    assert len(ranges) >= published and detections == published
    assert all(r.range == pytest.approx(1.2, abs=0.015) for r in ranges)
    assert {r.radiation_type for r in ranges} == {0}  # ULTRASOUND
