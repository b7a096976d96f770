"""The ROS 2 bag read back with rosbags: types, REP 117 ranges, CameraInfo from the
calibration, the obstacle as vision_msgs/Detection3DArray; replay --ros2-bag; and
calibrate --ros-yaml parsed back against the OpenCV camera file."""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import pytest
from obstacle_fusion.cli import main
from obstacle_fusion.errors import UserError
from obstacle_fusion.fusion import ObstacleRecord
from obstacle_fusion.outputs.foxglove_schemas import FoxgloveTopics
from obstacle_fusion.outputs.mcap_file import McapRecorder
from obstacle_fusion.outputs.ros2_bag import Ros2BagWriter, camera_info_yaml, typestore
from obstacle_fusion.protocol.generated import Range
from obstacle_fusion.sonar import SonarConverter
from obstacle_fusion.sources.frames import Frame
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.rig import Rig
from rosbags.rosbag2 import Reader

pytestmark = pytest.mark.cpu_only

UNIX = 1_750_000_000_000_000_000
CHESSBOARDS = Path(__file__).resolve().parents[3] / "shared/data/opencv-chessboard"


def _read(path: Path) -> dict[str, list[tuple[str, int, Any]]]:
    store = typestore()
    out: dict[str, list[tuple[str, int, Any]]] = {}
    with Reader(path) as reader:
        assert reader.connections[0].ext.serialization_format == "cdr"
        for conn, t, raw in reader.messages():
            out.setdefault(conn.topic, []).append(
                (conn.msgtype, t, store.deserialize_cdr(raw, conn.msgtype))
            )
    return out


def _record(**kw: Any) -> ObstacleRecord:
    base: dict[str, Any] = {
        "t_host": 10.0,
        "distance_m": 1.5,
        "height_m": 0.4,
        "width_m": 0.5,
        "confidence": 0.8,
        "status": "ok",
        "alert": False,
        "frame_index": 3,
        "source": "test",
        "pairing": "interpolated",
        "pair_dt_s": 0.01,
        "sonar_status": "ok",
        "measurements": (1, 2),
        "trigger_us": (1, 2),
        "box_px": None,
        "t_published": 10.05,
    }
    base.update(kw)
    return ObstacleRecord(**base)


def test_bag_holds_standard_messages_with_the_right_values(tmp_path: Path) -> None:
    rig = Rig(beam_width_deg=20.0, sonar_below_m=0.05, camera_height_m=0.2)
    cam = CameraModel.paper(500, 375)
    topics = FoxgloveTopics(rig=rig, camera=cam, unix_offset_ns=UNIX)
    conv = SonarConverter()
    bag = tmp_path / "bag"
    with Ros2BagWriter(bag, topics=topics) as w:
        # ok (1.0 m), no echo, too close (echo shorter than the transducers' spacing), timeout
        for i, (ticks, status) in enumerate(((11662, 0), (0, 1), (10, 0), (0, 2))):
            w.write_range(conv.convert(Range(i, 0, 0, ticks, status), 9.9 + 0.05 * i), 10.0)
        ok, jpeg = cv2.imencode(".jpg", np.zeros((375, 500, 3), np.uint8))
        w.write_image(jpeg.tobytes(), "jpeg", 500, 375, 10.0, 10.02)
        w.write_record(_record())
        w.write_record(_record(status="not_detected", height_m=None, width_m=None))
    assert (bag / "metadata.yaml").is_file() and list(bag.glob("*.mcap"))
    msgs = _read(bag)
    types = {t: v[0][0] for t, v in msgs.items()}
    assert types == {
        "/sonar/range": "sensor_msgs/msg/Range",
        "/camera/image/compressed": "sensor_msgs/msg/CompressedImage",
        "/camera/camera_info": "sensor_msgs/msg/CameraInfo",
        "/obstacle/detections": "vision_msgs/msg/Detection3DArray",
        "/tf_static": "tf2_msgs/msg/TFMessage",
    }
    ranges = [m for _, _, m in msgs["/sonar/range"]]
    r0 = ranges[0]
    assert r0.radiation_type == 0 and r0.radiation_type == r0.ULTRASOUND
    assert r0.field_of_view == pytest.approx(math.radians(20.0))
    assert r0.min_range == pytest.approx(0.02) and r0.max_range == pytest.approx(4.0)
    assert r0.range == pytest.approx(1.0, abs=0.01)
    assert r0.header.frame_id == "sonar_0"
    stamp_ns = r0.header.stamp.sec * 10**9 + r0.header.stamp.nanosec
    reading = conv.convert(Range(0, 0, 0, 11662, 0), 9.9)
    assert stamp_ns == pytest.approx(UNIX + reading.t_host * 1e9, abs=2)  # reflection, Unix
    assert math.isinf(ranges[1].range) and ranges[1].range > 0  # REP 117: nothing in range
    assert math.isinf(ranges[2].range) and ranges[2].range < 0  # too close
    assert math.isnan(ranges[3].range)  # timeout: invalid
    ((_, t_img, img),) = msgs["/camera/image/compressed"]
    assert img.format == "jpeg" and bytes(img.data[:2]) == b"\xff\xd8"
    assert t_img == UNIX + 10_020_000_000  # bag time: when the host had it
    assert img.header.stamp.sec == 1_750_000_010 and img.header.frame_id == "camera"
    ((_, _, info),) = msgs["/camera/camera_info"]
    assert (info.width, info.height, info.distortion_model) == (500, 375, "plumb_bob")
    assert info.k.reshape(3, 3) == pytest.approx(cam.camera_matrix)
    assert info.p.reshape(3, 4)[:, :3] == pytest.approx(cam.camera_matrix)
    assert info.d == pytest.approx(np.ravel(cam.dist_coeffs))
    found, empty = (m for _, _, m in msgs["/obstacle/detections"])
    (det,) = found.detections
    assert det.results[0].hypothesis.class_id == "obstacle"
    assert det.results[0].hypothesis.score == pytest.approx(0.8)
    assert (det.bbox.size.x, det.bbox.size.y, det.bbox.size.z) == pytest.approx((0.05, 0.5, 0.4))
    c = det.bbox.center.position
    assert (c.x, c.y, c.z) == pytest.approx((1.525, 0.0, 0.2))  # range + half depth, on floor
    assert found.header.frame_id == "robot" and det.id == "3"
    assert empty.detections == []  # nothing measured on that frame
    ((_, _, tf),) = msgs["/tf_static"]
    by_child = {t.child_frame_id: t.transform for t in tf.transforms}
    assert set(by_child) == {"camera", "sonar_0"}
    s = by_child["sonar_0"].translation
    assert (s.x, s.y, s.z) == pytest.approx((0.0, 0.0, 0.15))
    with Reader(bag) as reader:
        tf_conn = next(c for c in reader.connections if c.topic == "/tf_static")
        assert tf_conn.ext.offered_qos_profiles[0].durability.name == "TRANSIENT_LOCAL"


def test_an_existing_bag_is_kept_unless_overwrite(tmp_path: Path) -> None:
    bag = tmp_path / "bag"
    Ros2BagWriter(bag).close()
    with pytest.raises(UserError, match="already exists"):
        Ros2BagWriter(bag)
    Ros2BagWriter(bag, overwrite=True).close()
    notes = tmp_path / "notes"
    notes.mkdir()
    with pytest.raises(UserError, match="not a ROS 2 bag"):
        Ros2BagWriter(notes, overwrite=True)
    assert notes.is_dir()


def test_replay_writes_a_bag_of_the_recording(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    rec_path = tmp_path / "run.mcap"
    conv = SonarConverter()
    with McapRecorder(rec_path, topics=FoxgloveTopics(unix_offset_ns=UNIX)) as rec:
        for i in range(3):
            img = np.full((375, 500, 3), 90, np.uint8)
            rec.write_frame(Frame(img, 10.0 + 0.1 * i, i, "t"), log_t=10.02 + 0.1 * i)
            for j in range(2):
                t = 9.98 + 0.1 * i + 0.05 * j
                rec.write_range(conv.convert(Range(2 * i + j, 0, 0, 11662, 0), t), 2_000_000, 1, t)
    bag = tmp_path / "out"
    assert main(["replay", str(rec_path), "--ros2-bag", str(bag)]) == 0
    err = capsys.readouterr().err
    assert f"wrote the ROS 2 bag {bag}" in err
    msgs = _read(bag)
    assert len(msgs["/sonar/range"]) == 6 and len(msgs["/camera/image/compressed"]) == 3
    assert len(msgs["/obstacle/detections"]) == 3  # one per replayed frame
    assert len(msgs["/camera/camera_info"]) == 3  # the synthetic camera the replay measured with
    stamps = [
        m.header.stamp.sec + m.header.stamp.nanosec / 1e9
        for _, _, m in msgs["/camera/image/compressed"]
    ]
    assert stamps == pytest.approx([1_750_000_010.0, 1_750_000_010.1, 1_750_000_010.2])
    # a second replay into the same folder is refused, and the first bag kept
    assert main(["replay", str(rec_path), "--ros2-bag", str(bag)]) == 2
    assert "--ros2-bag" in capsys.readouterr().err
    assert len(_read(bag)["/sonar/range"]) == 6


def test_camera_info_yaml_matches_the_calibration(tmp_path: Path) -> None:
    from ruamel.yaml import YAML

    cam = CameraModel(
        np.array([[520.5, 0.0, 251.2], [0.0, 521.0, 186.9], [0.0, 0.0, 1.0]]),
        np.array([-0.21, 0.05, 0.001, -0.002, 0.01]),
        500,
        375,
    )
    data = YAML(typ="safe").load(camera_info_yaml(cam, "front"))
    assert data["image_width"] == 500 and data["image_height"] == 375
    assert data["camera_name"] == "front" and data["distortion_model"] == "plumb_bob"
    assert data["camera_matrix"]["rows"] == 3 and data["camera_matrix"]["cols"] == 3
    assert data["camera_matrix"]["data"] == [520.5, 0.0, 251.2, 0.0, 521.0, 186.9, 0.0, 0.0, 1.0]
    assert data["distortion_coefficients"]["cols"] == 5
    assert data["distortion_coefficients"]["data"] == [-0.21, 0.05, 0.001, -0.002, 0.01]
    assert data["rectification_matrix"]["data"] == [1.0, 0, 0, 0, 1.0, 0, 0, 0, 1.0]
    assert data["projection_matrix"]["cols"] == 4
    assert data["projection_matrix"]["data"][:4] == [520.5, 0.0, 251.2, 0.0]


@pytest.mark.skipif(not CHESSBOARDS.is_dir(), reason="needs ../shared/data/opencv-chessboard")
def test_calibrate_writes_ros_yaml_that_matches_its_camera_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from ruamel.yaml import YAML

    photos = sorted(str(p) for p in CHESSBOARDS.glob("*.jpg"))
    out, ros = tmp_path / "camera.yaml", tmp_path / "camera_info.yaml"
    code = main(["calibrate", *photos, "-o", str(out), "--ros-yaml", str(ros), "--no-progress"])
    assert code == 0
    cam = CameraModel.load(out)
    data = YAML(typ="safe").load(ros.read_text())
    assert (data["image_width"], data["image_height"]) == (640, 480)
    k = np.array(data["camera_matrix"]["data"]).reshape(3, 3)
    assert k == pytest.approx(cam.camera_matrix, rel=1e-12)
    assert data["distortion_coefficients"]["data"] == pytest.approx(np.ravel(cam.dist_coeffs))
    assert k[0, 0] == pytest.approx(534.1, abs=1.0)  # the README's figure for these photos
    assert main(["calibrate", *photos, "-o", str(out), "--ros-yaml", str(out)]) == 2
    assert "same file" in capsys.readouterr().err


def test_without_rosbags_the_cli_names_the_extra(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setitem(sys.modules, "rosbags.rosbag2", None)
    rec = tmp_path / "r.mcap"
    McapRecorder(rec).close()
    assert main(["replay", str(rec), "--ros2-bag", str(tmp_path / "b")]) == 2
    assert "obstacle-fusion[ros]" in capsys.readouterr().err
    assert main(["run", "--ros2-bag", str(tmp_path / "b"), "--duration", "1"]) == 2
    assert "obstacle-fusion[ros]" in capsys.readouterr().err
    assert not (tmp_path / "b").exists()
