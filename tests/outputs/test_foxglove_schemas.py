"""The recording's topics against the published Foxglove JSON schemas, its Unix times, the
geometry of the transforms and of the obstacle's cube, and replay of old and new files."""

from __future__ import annotations

import copy
import json
import math
from pathlib import Path
from typing import Any

import cv2
import jsonschema
import numpy as np
import pytest
from mcap.reader import make_reader
from obstacle_fusion.cli import main
from obstacle_fusion.fusion import ObstacleRecord
from obstacle_fusion.outputs.foxglove_schemas import (
    TOPIC_ANNOTATIONS,
    TOPIC_CALIBRATION,
    TOPIC_EVENT,
    TOPIC_IMAGE,
    TOPIC_OBSTACLE,
    TOPIC_RANGE,
    TOPIC_SCENE,
    TOPIC_TF,
    FoxgloveTopics,
    camera_pose,
    event_of_log,
    foxglove_schema,
    quaternion,
    sonar_pose,
)
from obstacle_fusion.outputs.mcap_file import McapRecorder
from obstacle_fusion.protocol.generated import Range
from obstacle_fusion.sonar import SonarConverter
from obstacle_fusion.sources.frames import Frame
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.rig import Rig

pytestmark = pytest.mark.cpu_only

UNIX = 1_750_000_000_000_000_000
VENDORED = Path(__file__).resolve().parents[2] / "host/obstacle_fusion/outputs/foxglove_jsonschema"


def _strict(schema: Any) -> Any:
    """The published schema with no unknown field allowed anywhere: a misspelt field fails."""
    out = copy.deepcopy(schema)

    def walk(node: Any) -> None:
        if isinstance(node, dict):
            if node.get("type") == "object" and "properties" in node:
                node["additionalProperties"] = False
            for v in node.values():
                walk(v)
        elif isinstance(node, list):
            for v in node:
                walk(v)

    walk(out)
    return out


def _record(**kw: Any) -> ObstacleRecord:
    base: dict[str, Any] = {
        "t_host": 12.5,
        "distance_m": 2.0,
        "height_m": 0.4,
        "width_m": 0.5,
        "confidence": 0.9,
        "status": "ok",
        "alert": False,
        "frame_index": 7,
        "source": "test",
        "pairing": "interpolated",
        "pair_dt_s": 0.01,
        "sonar_status": "ok",
        "measurements": (4, 5),
        "trigger_us": (100, 200),
        "box_px": (200.0, 150.0, 300.0, 250.0),
        "t_published": 12.55,
        "edges_px": ((200.0, 250.0, 300.0, 250.0), (200.0, 150.0, 200.0, 250.0)),
    }
    base.update(kw)
    return ObstacleRecord(**base)


def _write_run(path: Path, topics: FoxgloveTopics, metadata: Any = None) -> None:
    """A short run: frames of a box, ranges around them, records of each kind, events."""
    conv = SonarConverter()
    with McapRecorder(path, topics=topics, metadata=metadata) as rec:
        rec.write_event("hello", {"session": 1, "board": "uno"}, t=9.9)
        for i in range(4):
            img = np.full((375, 500, 3), 90, np.uint8)
            cv2.rectangle(img, (200, 150), (300, 250), (40, 120, 220), -1)
            rec.write_frame(Frame(img, 10.0 + 0.1 * i, i, "test"), log_t=10.02 + 0.1 * i)
            for j in range(2):
                t = 9.98 + 0.1 * i + 0.05 * j
                reading = conv.convert(Range(2 * i + j, 0, 1000 * i, 11662, 0), t)
                rec.write_range(reading, 2_000_000, 1, log_t=t + 0.02)
        rec.write_obstacle(_record())
        rec.write_obstacle(_record(status="not_detected", height_m=None, width_m=None))
        rec.write_obstacle(_record(distance_m=0.3, alert=True, box_px=None, edges_px=()))
        rec.write_event("disconnected", {"port": "/dev/pts/9"}, t=10.5)
        rec.write_event("log", {"level": 3, "text": "echo stuck"}, t=10.6)


def _messages(path: Path) -> list[tuple[Any, Any, Any]]:
    with open(path, "rb") as fh:
        reader = make_reader(fh)
        return [(s, c, m) for s, c, m in reader.iter_messages()]


def test_every_message_validates_against_the_published_schema(tmp_path: Path) -> None:
    path = tmp_path / "run.mcap"
    cam = CameraModel.paper(500, 375)
    _write_run(path, FoxgloveTopics(rig=Rig(), camera=cam, unix_offset_ns=UNIX))
    msgs = _messages(path)
    by_topic: dict[str, int] = {}
    for schema, channel, message in msgs:
        by_topic[channel.topic] = by_topic.get(channel.topic, 0) + 1
        assert schema.encoding == "jsonschema" and channel.message_encoding == "json"
        data = json.loads(message.data)
        if schema.name.startswith("foxglove."):
            # the schema stored in the file is the published one, unchanged
            published = json.loads((VENDORED / f"{schema.name}.json").read_text())
            assert json.loads(schema.data) == published
            jsonschema.validate(data, _strict(published))
        else:
            jsonschema.validate(data, _strict(json.loads(schema.data)))
    expected = {
        TOPIC_IMAGE: ("foxglove.CompressedImage", 4),
        TOPIC_CALIBRATION: ("foxglove.CameraCalibration", 4),
        TOPIC_ANNOTATIONS: ("foxglove.ImageAnnotations", 3),
        TOPIC_SCENE: ("foxglove.SceneUpdate", 3),
        TOPIC_TF: ("foxglove.FrameTransform", 2),  # camera and sonar_0, once (within 1 s)
        TOPIC_EVENT: ("foxglove.Log", 3),
        TOPIC_RANGE: ("obstacle_fusion.SonarRange", 8),
        TOPIC_OBSTACLE: ("obstacle_fusion.Obstacle", 3),
    }
    names = {c.topic: s.name for s, c, _ in msgs}
    assert {t: (names[t], by_topic[t]) for t in expected} == expected


def test_a_misspelt_field_fails_the_strict_check() -> None:
    """The validation above has teeth: one wrong field name is caught."""
    topics = FoxgloveTopics(unix_offset_ns=UNIX)
    ann = topics.annotations(_record(), UNIX)
    schema = _strict(foxglove_schema("foxglove.ImageAnnotations"))
    jsonschema.validate(ann, schema)
    ann["texts"][0]["fontsize"] = ann["texts"][0].pop("font_size")
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(ann, schema)


def test_times_are_unix_nanoseconds_with_the_mapping_in_the_metadata(tmp_path: Path) -> None:
    path = tmp_path / "run.mcap"
    _write_run(path, FoxgloveTopics(unix_offset_ns=UNIX))
    msgs = _messages(path)
    image = next(m for _, c, m in msgs if c.topic == TOPIC_IMAGE)
    assert image.publish_time == UNIX + 10_000_000_000  # capture instant
    assert image.log_time == UNIX + 10_020_000_000  # when the host had it
    assert json.loads(image.data)["timestamp"] == {"sec": 1_750_000_010, "nsec": 0}
    rng = next(m for _, c, m in msgs if c.topic == TOPIC_RANGE)
    d = json.loads(rng.data)
    assert rng.publish_time == UNIX + round(d["t_host"] * 1e9)  # the echo's reflection
    ann = next(m for _, c, m in msgs if c.topic == TOPIC_ANNOTATIONS)
    assert ann.publish_time == UNIX + 12_500_000_000  # its frame's instant: synced to the image
    assert ann.log_time == UNIX + 12_550_000_000
    with open(path, "rb") as fh:
        meta = {m.name: m.metadata for m in make_reader(fh).iter_metadata()}
    assert int(meta["obstacle_fusion"]["unix_offset_ns"]) == UNIX
    assert meta["obstacle_fusion"]["time_base"].startswith("unix epoch")


@pytest.mark.realtime  # two clocks read 50 ms apart at most
def test_default_offset_maps_monotonic_time_to_now() -> None:
    import time

    topics = FoxgloveTopics()
    assert abs(topics.ns(time.monotonic()) - time.time_ns()) < 50_000_000


def test_annotations_draw_the_box_the_edges_and_the_numbers() -> None:
    topics = FoxgloveTopics(unix_offset_ns=UNIX)
    ann = topics.annotations(_record(), UNIX + 5)
    loop, edges = ann["points"]
    assert loop["type"] == 2  # LINE_LOOP around the face
    assert [(p["x"], p["y"]) for p in loop["points"]] == [
        (200.0, 150.0),
        (300.0, 150.0),
        (300.0, 250.0),
        (200.0, 250.0),
    ]
    assert edges["type"] == 4 and len(edges["points"]) == 4  # LINE_LIST: two edges
    assert edges["points"][1] == {"x": 300.0, "y": 250.0}
    texts = [t["text"] for t in ann["texts"]]
    assert texts == ["ok", "L 2.000 m", "H 0.400 m  W 0.500 m"]
    assert all(t["timestamp"] == {"sec": 1_750_000_000, "nsec": 5} for t in ann["texts"])
    alert = topics.annotations(_record(alert=True, box_px=None, edges_px=()), UNIX)
    assert alert["points"] == [] and alert["texts"][0]["text"] == "ok  STOP"
    assert (
        alert["texts"][0]["text_color"]["r"] == 1.0 and alert["texts"][0]["text_color"]["g"] < 0.2
    )


def test_quaternion_of_known_rotations() -> None:
    assert quaternion(np.eye(3)) == {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}
    a = math.radians(30)
    rz = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
    q = quaternion(rz)
    assert q["z"] == pytest.approx(math.sin(a / 2)) and q["w"] == pytest.approx(math.cos(a / 2))
    flip = np.diag([1.0, -1.0, -1.0])  # 180 degrees about x: the trace is negative
    assert quaternion(flip) == pytest.approx({"x": 1.0, "y": 0.0, "z": 0.0, "w": 0.0})


def _rotate(q: dict[str, float], v: list[float]) -> np.ndarray:
    x, y, z, w = q["x"], q["y"], q["z"], q["w"]
    r = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )
    return np.asarray(r @ np.asarray(v, float))


def test_transforms_place_the_camera_and_the_sonar_from_the_rig() -> None:
    rig = Rig(
        camera_height_m=0.3,
        camera_pitch_deg=10.0,
        sonar_right_m=0.02,
        sonar_below_m=0.05,
        sonar_ahead_m=0.01,
    )
    xyz, q = camera_pose(rig)
    assert xyz == [0.0, 0.0, 0.3]
    # the optical axis (camera z) looks forward (robot x) and 10 degrees down
    fwd = _rotate(q, [0, 0, 1])
    p = math.radians(10)
    assert fwd == pytest.approx([math.cos(p), 0.0, -math.sin(p)], abs=1e-12)
    assert _rotate(q, [1, 0, 0]) == pytest.approx([0.0, -1.0, 0.0], abs=1e-12)  # x right
    sxyz, sq = sonar_pose(rig)
    assert sxyz == pytest.approx([0.01, -0.02, 0.25])  # ahead, right (= -y), 5 cm below
    assert sq == {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}
    topics = FoxgloveTopics(rig=rig, unix_offset_ns=UNIX)
    tfs = [json.loads(m.data) for m in topics.transforms(UNIX)]
    assert [(t["parent_frame_id"], t["child_frame_id"]) for t in tfs] == [
        ("robot", "camera"),
        ("robot", "sonar_0"),
    ]
    assert topics.transforms(UNIX + 900_000_000) == []  # repeated once a second, not more
    assert len(topics.transforms(UNIX + 1_000_000_000)) == 2


def test_the_cube_stands_on_the_floor_at_the_measured_range() -> None:
    rig = Rig(sonar_ahead_m=0.02)
    cam = CameraModel.paper(500, 375)
    topics = FoxgloveTopics(rig=rig, camera=cam, unix_offset_ns=UNIX)
    topics.frame_size = (500, 375)

    def box_at(x_right: float) -> tuple[float, float, float, float]:
        """A 100 px box centred where the camera sees a point x_right metres right, 2.02 deep."""
        u, v = cam.project([[x_right, 0.0, 2.02]])[0]
        return (u - 50.0, v - 50.0, u + 50.0, v + 50.0)

    scene = topics.scene(_record(box_px=box_at(0.0)), UNIX)
    (entity,) = scene["entities"]
    cube = entity["cubes"][0]
    assert entity["frame_id"] == "robot" and entity["id"] == "obstacle"
    pos = cube["pose"]["position"]
    assert pos["x"] == pytest.approx(2.0 + 0.02 + 0.025)  # range + sonar ahead + half depth
    assert pos["y"] == pytest.approx(0.0, abs=1e-6)
    assert pos["z"] == pytest.approx(0.2)  # half its height: on the floor
    assert cube["size"] == {"x": 0.05, "y": 0.5, "z": 0.4}
    right = topics.scene(_record(box_px=box_at(0.5)), UNIX)  # 0.5 m right: robot y = -0.5
    assert right["entities"][0]["cubes"][0]["pose"]["position"]["y"] == pytest.approx(
        -0.5, abs=1e-6
    )
    # a camera pitched down 10 degrees: the ray is levelled before it meets the face's depth
    pitched = FoxgloveTopics(rig=Rig(camera_pitch_deg=10.0, sonar_ahead_m=0.02), camera=cam)
    pitched.frame_size = (500, 375)
    p_cam = pitched.rig.camera_to_robot.T @ np.array([0.5, 0.1, 2.02])
    u, v = cam.project([p_cam])[0]
    lean = pitched.scene(_record(box_px=(u - 40, v - 40, u + 40, v + 40)), UNIX)
    assert lean["entities"][0]["cubes"][0]["pose"]["position"]["y"] == pytest.approx(-0.5, abs=1e-6)
    gone = topics.scene(_record(status="not_detected", height_m=None, width_m=None), UNIX)
    assert gone["entities"] == [] and gone["deletions"][0]["id"] == "obstacle"


def test_link_events_are_foxglove_logs_with_levels() -> None:
    topics = FoxgloveTopics(unix_offset_ns=UNIX)
    warn = json.loads(topics.event("disconnected", {"port": "/dev/ttyACM0"}, t=1.0).data)
    assert warn["level"] == 3 and warn["name"] == "obstacle_fusion.link"
    assert event_of_log(warn) == ("disconnected", {"port": "/dev/ttyACM0"})
    info = json.loads(topics.event("hello", {"session": 2}, t=1.0).data)
    assert info["level"] == 2
    err = json.loads(topics.event("log", {"level": 3, "text": "x"}, t=1.0).data)
    assert err["level"] == 4  # the firmware's error -> foxglove ERROR
    assert event_of_log({"event": "hello", "detail": {"a": 1}}) == ("hello", {"a": 1})  # old form


def _replay(path: Path, capsys: pytest.CaptureFixture[str]) -> list[dict[str, Any]]:
    assert main(["replay", str(path)]) == 0
    records = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    for r in records:
        del r["vision_ms"]  # a timing
    return records


def test_replay_reads_old_monotonic_and_new_unix_recordings_alike(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    new = tmp_path / "new.mcap"
    _write_run(new, FoxgloveTopics(unix_offset_ns=UNIX))
    old = tmp_path / "old.mcap"  # as recorded before: monotonic times, no Unix time base
    _write_run(
        old,
        FoxgloveTopics(unix_offset_ns=0),
        metadata={
            "obstacle_fusion": {
                "version": "0.1.0",
                "time_base": "host monotonic clock, nanoseconds",
                "monotonic_to_unix_offset_s": "1750000000.0",
            }
        },
    )
    a, b = _replay(new, capsys), _replay(old, capsys)
    assert len(a) == 4
    assert a == b
    assert [r["t_host"] for r in a] == pytest.approx([10.0, 10.1, 10.2, 10.3])
    assert all(r["pairing"] == "interpolated" for r in a)  # frames met their ranges


def test_schemas_ship_with_the_package() -> None:
    for name in ("CompressedImage", "ImageAnnotations", "SceneUpdate", "FrameTransform", "Log"):
        schema = foxglove_schema(f"foxglove.{name}")
        assert schema["title"] == f"foxglove.{name}"
    assert "MIT License" in (VENDORED / "LICENSE").read_text()
