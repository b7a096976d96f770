"""A ROS 2 bag (rosbag2, MCAP storage, CDR) of a run, written with the ``rosbags`` package.

Topics (standard ROS 2 messages; stamps in Unix-epoch time, as ROS keeps them):

=============================  =================================  ============================
topic                          type                               frame_id
=============================  =================================  ============================
/sonar/range                   sensor_msgs/msg/Range              sonar_N
/camera/image/compressed       sensor_msgs/msg/CompressedImage    camera (optical)
/camera/camera_info            sensor_msgs/msg/CameraInfo         camera
/obstacle/detections           vision_msgs/msg/Detection3DArray   robot
/tf_static                     tf2_msgs/msg/TFMessage             robot -> camera, sonar_N
=============================  =================================  ============================

Range follows REP 117: ``radiation_type`` ULTRASOUND, ``field_of_view`` the rig's beam
width, ``min_range`` 0.02 m and ``max_range`` 4 m (the HC-SR04's span; the firmware's
max_echo_us is 4 m); ``range`` is +inf for no echo / out of range, -inf for too close,
NaN for a timeout. CameraInfo: K and D (plumb_bob) from the calibration, R identity,
P = [K | 0]. Detection3DArray is vision_msgs 4 (ROS 2 Humble) exactly; its definition is
stored in the bag, so any ROS 2 reader decodes it: one Detection3D per measured obstacle
(class_id "obstacle", score = confidence, bbox centre in the robot frame, size = depth
x width x height with the unmeasured depth 0.05 m), an empty array when nothing was
measured. Frames as in :mod:`obstacle_fusion.outputs.foxglove_schemas` (robot: REP 103,
origin on the floor below the lens).
"""

from __future__ import annotations

import logging
import math
import shutil
from pathlib import Path
from typing import Any

import numpy as np

from obstacle_fusion.errors import UserError
from obstacle_fusion.fusion import ObstacleRecord
from obstacle_fusion.outputs.foxglove_schemas import (
    CUBE_DEPTH_M,
    FRAME_CAMERA,
    FRAME_ROBOT,
    FoxgloveTopics,
    camera_pose,
    sonar_pose,
)
from obstacle_fusion.sonar import SonarReading, SonarStatus
from obstacle_fusion.vision.rig import Rig

log = logging.getLogger(__name__)

TOPIC_RANGE = "/sonar/range"
TOPIC_IMAGE = "/camera/image/compressed"
TOPIC_CAMERA_INFO = "/camera/camera_info"
TOPIC_DETECTIONS = "/obstacle/detections"
TOPIC_TF_STATIC = "/tf_static"

MIN_RANGE_M = 0.02
MAX_RANGE_M = 4.0

#: vision_msgs 4.x (ROS 2 Humble) message definitions, as the package defines them.
VISION_MSGS = {
    "vision_msgs/msg/ObjectHypothesis": "string class_id\nfloat64 score\n",
    "vision_msgs/msg/ObjectHypothesisWithPose": (
        "vision_msgs/ObjectHypothesis hypothesis\ngeometry_msgs/PoseWithCovariance pose\n"
    ),
    "vision_msgs/msg/BoundingBox3D": "geometry_msgs/Pose center\ngeometry_msgs/Vector3 size\n",
    "vision_msgs/msg/Detection3D": (
        "std_msgs/Header header\nvision_msgs/ObjectHypothesisWithPose[] results\n"
        "vision_msgs/BoundingBox3D bbox\nstring id\n"
    ),
    "vision_msgs/msg/Detection3DArray": (
        "std_msgs/Header header\nvision_msgs/Detection3D[] detections\n"
    ),
}


def require_rosbags() -> Any:
    try:
        import rosbags.rosbag2
        import rosbags.typesys
    except ImportError:
        raise UserError(
            "--ros2-bag needs the rosbags package: pip install 'obstacle-fusion[ros]' "
            "(make setup installs it)"
        ) from None
    return rosbags


def typestore() -> Any:
    """ROS 2 Humble's message types plus vision_msgs."""
    require_rosbags()
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    types: dict[str, Any] = {}
    for name, text in VISION_MSGS.items():
        types.update(get_types_from_msg(text, name))
    store.register(types)
    return store


def _latched_qos() -> Any:
    """/tf_static's QoS (reliable, transient local), so `ros2 bag play` latches it."""
    from rosbags.interfaces import (
        Qos,
        QosDurability,
        QosHistory,
        QosLiveliness,
        QosReliability,
        QosTime,
    )

    never = QosTime(sec=0, nsec=0)
    return Qos(
        history=QosHistory.KEEP_LAST,
        depth=1,
        reliability=QosReliability.RELIABLE,
        durability=QosDurability.TRANSIENT_LOCAL,
        deadline=never,
        lifespan=never,
        liveliness=QosLiveliness.AUTOMATIC,
        liveliness_lease_duration=never,
        avoid_ros_namespace_conventions=False,
    )


def range_value(reading: SonarReading) -> float:
    """REP 117: the distance, +inf for nothing in range, -inf for too close, NaN otherwise."""
    if reading.status == SonarStatus.OK and reading.distance_m is not None:
        return float(reading.distance_m)
    if reading.status in (SonarStatus.NO_ECHO, SonarStatus.OUT_OF_RANGE):
        return math.inf
    if reading.status == SonarStatus.TOO_CLOSE:
        return -math.inf
    return math.nan


class Ros2BagWriter:
    """Write ranges, images, camera info and detections; close() finishes the bag."""

    def __init__(
        self,
        path: str | Path,
        *,
        rig: Rig | None = None,
        camera: Any = None,
        topics: FoxgloveTopics | None = None,
        overwrite: bool = False,
    ) -> None:
        rosbags = require_rosbags()
        from rosbags.rosbag2 import StoragePlugin, Writer

        self.path = Path(path)
        if self.path.exists():
            if not overwrite:
                raise UserError(
                    f"the ROS 2 bag {self.path} already exists; give another name, or "
                    "--overwrite to replace it"
                )
            if not (self.path.is_dir() and (self.path / "metadata.yaml").is_file()):
                raise UserError(
                    f"--ros2-bag {self.path} exists and is not a ROS 2 bag; not replacing it"
                )
            shutil.rmtree(self.path)
        if not self.path.parent.exists():
            raise UserError(f"--ros2-bag {self.path}: folder {self.path.parent} does not exist")
        self.topics = topics or FoxgloveTopics(rig=rig, camera=camera)
        if rig is not None:
            self.topics.rig = rig
        if camera is not None:
            self.topics.set_camera(camera)
        self.store = typestore()
        self._types = self.store.types
        self._writer = Writer(self.path, version=9, storage_plugin=StoragePlugin.MCAP)
        try:
            self._writer.open()
        except rosbags.rosbag2.WriterError as exc:
            raise UserError(f"cannot write the ROS 2 bag {self.path}: {exc}") from None
        self._conns = {
            topic: self._writer.add_connection(
                topic, msgtype, typestore=self.store, offered_qos_profiles=qos
            )
            for topic, msgtype, qos in (
                (TOPIC_RANGE, "sensor_msgs/msg/Range", ()),
                (TOPIC_IMAGE, "sensor_msgs/msg/CompressedImage", ()),
                (TOPIC_CAMERA_INFO, "sensor_msgs/msg/CameraInfo", ()),
                (TOPIC_DETECTIONS, "vision_msgs/msg/Detection3DArray", ()),
                (TOPIC_TF_STATIC, "tf2_msgs/msg/TFMessage", (_latched_qos(),)),
            )
        }
        self.counts: dict[str, int] = dict.fromkeys(self._conns, 0)
        self._sensors: set[int] = set()
        self._closed = False

    # -------------------------------------------------------------- helpers
    def _header(self, ns: int, frame_id: str) -> Any:
        t = self._types
        return t["std_msgs/msg/Header"](
            stamp=t["builtin_interfaces/msg/Time"](
                sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000
            ),
            frame_id=frame_id,
        )

    def _write(self, topic: str, msg: Any, log_ns: int) -> None:
        if self._closed:
            return
        data = self.store.serialize_cdr(msg, msg.__msgtype__)
        self._writer.write(self._conns[topic], log_ns, bytes(data))
        self.counts[topic] += 1

    def _pose(self, xyz: list[float], rot: dict[str, float]) -> Any:
        t = self._types
        return t["geometry_msgs/msg/Pose"](
            position=t["geometry_msgs/msg/Point"](x=xyz[0], y=xyz[1], z=xyz[2]),
            orientation=t["geometry_msgs/msg/Quaternion"](**rot),
        )

    def _tf_static(self, log_ns: int) -> None:
        t = self._types
        poses = [(FRAME_CAMERA, camera_pose(self.topics.rig))]
        poses += [(f"sonar_{i}", sonar_pose(self.topics.rig)) for i in sorted(self._sensors)]
        transforms = [
            t["geometry_msgs/msg/TransformStamped"](
                header=self._header(log_ns, FRAME_ROBOT),
                child_frame_id=child,
                transform=t["geometry_msgs/msg/Transform"](
                    translation=t["geometry_msgs/msg/Vector3"](x=xyz[0], y=xyz[1], z=xyz[2]),
                    rotation=t["geometry_msgs/msg/Quaternion"](**rot),
                ),
            )
            for child, (xyz, rot) in poses
        ]
        self._write(TOPIC_TF_STATIC, t["tf2_msgs/msg/TFMessage"](transforms=transforms), log_ns)

    # -------------------------------------------------------------- messages
    def write_range(self, reading: SonarReading, log_t: float | None = None) -> None:
        if reading.t_host is None:
            return  # never mapped to host time: no stamp to give it
        if reading.sensor_id not in self._sensors:
            self._sensors.add(reading.sensor_id)
            self._tf_static(self.topics.ns(log_t if log_t is not None else reading.t_host))
        pub = self.topics.ns(reading.t_host)
        msg = self._types["sensor_msgs/msg/Range"](
            header=self._header(pub, f"sonar_{reading.sensor_id}"),
            radiation_type=0,  # ULTRASOUND
            field_of_view=math.radians(self.topics.rig.beam_width_deg),
            min_range=MIN_RANGE_M,
            max_range=MAX_RANGE_M,
            range=range_value(reading),
        )
        self._write(TOPIC_RANGE, msg, self.topics.ns(log_t) if log_t is not None else pub)

    def write_image(
        self, data: bytes, fmt: str, width: int, height: int, t_host: float, log_t: float
    ) -> None:
        """A compressed frame (JPEG/PNG bytes) and, when the camera is known, its CameraInfo."""
        pub, lg = self.topics.ns(t_host), self.topics.ns(log_t)
        self.topics.frame_size = (width, height)
        t = self._types
        msg = t["sensor_msgs/msg/CompressedImage"](
            header=self._header(pub, FRAME_CAMERA),
            format=fmt,
            data=np.frombuffer(data, np.uint8),
        )
        self._write(TOPIC_IMAGE, msg, lg)
        cam = self.topics.camera_at(width, height)
        if cam is not None:
            self._write(TOPIC_CAMERA_INFO, self.camera_info(cam, pub), lg)

    def camera_info(self, cam: Any, pub: int) -> Any:
        k = np.asarray(cam.camera_matrix, float).ravel()
        d = np.asarray(cam.dist_coeffs, float).ravel()
        p = np.zeros((3, 4))
        p[:, :3] = k.reshape(3, 3)
        t = self._types
        return t["sensor_msgs/msg/CameraInfo"](
            header=self._header(pub, FRAME_CAMERA),
            height=int(cam.height),
            width=int(cam.width),
            distortion_model="plumb_bob" if d.size <= 5 else "rational_polynomial",
            d=d,
            k=k,
            r=np.eye(3).ravel(),
            p=p.ravel(),
            binning_x=0,
            binning_y=0,
            roi=t["sensor_msgs/msg/RegionOfInterest"](
                x_offset=0, y_offset=0, height=0, width=0, do_rectify=False
            ),
        )

    def write_record(self, rec: ObstacleRecord, log_t: float | None = None) -> None:
        t = self._types
        pub = self.topics.ns(rec.t_host)
        lg = self.topics.ns(log_t if log_t is not None else (rec.t_published or rec.t_host))
        detections = []
        centre = self.topics.obstacle_pose(rec)
        if centre is not None and rec.width_m is not None and rec.height_m is not None:
            pose = self._pose(centre, {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0})
            detections.append(
                t["vision_msgs/msg/Detection3D"](
                    header=self._header(pub, FRAME_ROBOT),
                    results=[
                        t["vision_msgs/msg/ObjectHypothesisWithPose"](
                            hypothesis=t["vision_msgs/msg/ObjectHypothesis"](
                                class_id="obstacle", score=float(rec.confidence)
                            ),
                            pose=t["geometry_msgs/msg/PoseWithCovariance"](
                                pose=pose, covariance=np.zeros(36)
                            ),
                        )
                    ],
                    bbox=t["vision_msgs/msg/BoundingBox3D"](
                        center=pose,
                        size=t["geometry_msgs/msg/Vector3"](
                            x=CUBE_DEPTH_M, y=float(rec.width_m), z=float(rec.height_m)
                        ),
                    ),
                    id=str(rec.frame_index),
                )
            )
        msg = t["vision_msgs/msg/Detection3DArray"](
            header=self._header(pub, FRAME_ROBOT), detections=detections
        )
        self._write(TOPIC_DETECTIONS, msg, lg)

    def close(self) -> None:
        if self._closed:
            return
        self._closed = True
        self._writer.close()

    def __enter__(self) -> Ros2BagWriter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def camera_info_yaml(camera: Any, camera_name: str = "camera") -> str:
    """ROS camera_info YAML (camera_calibration_parsers' format) for a CameraModel.

    K and D (plumb_bob for up to 5 coefficients) from the calibration, R identity and
    P = [K | 0]: the rectified image keeps the calibrated intrinsics."""
    k = [float(v) for v in np.asarray(camera.camera_matrix, float).ravel()]
    d = [float(v) for v in np.asarray(camera.dist_coeffs, float).ravel()]
    p = [k[0], k[1], k[2], 0.0, k[3], k[4], k[5], 0.0, k[6], k[7], k[8], 0.0]

    def matrix(rows: int, cols: int, data: list[float]) -> str:
        values = ", ".join(repr(v) for v in data)
        return f"\n  rows: {rows}\n  cols: {cols}\n  data: [{values}]"

    return (
        f"image_width: {int(camera.width)}\n"
        f"image_height: {int(camera.height)}\n"
        f"camera_name: {camera_name}\n"
        f"camera_matrix:{matrix(3, 3, k)}\n"
        f"distortion_model: {'plumb_bob' if len(d) <= 5 else 'rational_polynomial'}\n"
        f"distortion_coefficients:{matrix(1, len(d), d)}\n"
        f"rectification_matrix:{matrix(3, 3, [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0])}\n"
        f"projection_matrix:{matrix(3, 4, p)}\n"
    )
