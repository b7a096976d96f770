"""The run as Foxglove topics: standard Foxglove schemas where one exists, on Unix time.

One encoder, :class:`FoxgloveTopics`, turns frames, sonar readings, obstacle records and
link events into :class:`TopicMessage` values (topic, JSON bytes, publish and log time in
Unix-epoch nanoseconds). The MCAP recorder and the live WebSocket server write the very
same messages, so a recording and a live view show the same thing.

Topics (frame ids in brackets):

==========================  ===========================  ======================================
topic                       schema                       what
==========================  ===========================  ======================================
/camera/image               foxglove.CompressedImage     the frame, JPEG [camera]
/camera/calibration         foxglove.CameraCalibration   intrinsics, with every frame [camera]
/camera/annotations         foxglove.ImageAnnotations    the face's box, its edges, L/H/W text
/scene                      foxglove.SceneUpdate         the obstacle as a cube [robot]
/tf                         foxglove.FrameTransform      robot -> camera, robot -> sonar_N
/sonar/range                obstacle_fusion.SonarRange   JSON schema: raw and converted values
/obstacle                   obstacle_fusion.Obstacle     JSON schema: the fused record
/link/event                 foxglove.Log                 link events (handshake, disconnect...)
==========================  ===========================  ======================================

Frames: ``robot`` follows ROS REP 103 (x forward, y left, z up) with its origin on the
floor below the camera's lens; ``camera`` is the optical frame (x right, y down, z
forward, pitched down by the rig's pitch); ``sonar_N`` sits where the rig puts the sonar,
x along the beam (as a ROS Range). The rig describes one sonar: every sensor id gets that
mounting. The cube's depth is not measured: it is drawn 5 cm deep behind the measured face.

The schema texts for the foxglove.* names are the published ones (foxglove_jsonschema/,
vendored unchanged from @foxglove/schemas; see its LICENSE).
"""

from __future__ import annotations

import base64
import json
import math
import time
from dataclasses import dataclass
from functools import cache
from importlib import resources
from typing import Any

import numpy as np
import numpy.typing as npt

from obstacle_fusion.fusion import ObstacleRecord
from obstacle_fusion.sonar import SonarReading
from obstacle_fusion.vision.rig import Rig

TOPIC_IMAGE = "/camera/image"
TOPIC_CALIBRATION = "/camera/calibration"
TOPIC_ANNOTATIONS = "/camera/annotations"
TOPIC_SCENE = "/scene"
TOPIC_TF = "/tf"
TOPIC_RANGE = "/sonar/range"
TOPIC_OBSTACLE = "/obstacle"
TOPIC_EVENT = "/link/event"

FRAME_ROBOT = "robot"
FRAME_CAMERA = "camera"
CUBE_DEPTH_M = 0.05  # the obstacle's depth is not measured; the cube is this deep
TRANSFORM_PERIOD_S = 1.0  # transforms and calibration are repeated (late joiners see them)

#: Metadata key under "obstacle_fusion" that marks Unix-epoch message times.
TIME_BASE_UNIX = "unix epoch nanoseconds (host monotonic + unix_offset_ns)"

_TIME = {
    "type": "object",
    "title": "time",
    "properties": {
        "sec": {"type": "integer", "minimum": 0},
        "nsec": {"type": "integer", "minimum": 0, "maximum": 999999999},
    },
}
_NUM = {"type": ["number", "null"]}

RANGE_SCHEMA: dict[str, Any] = {
    "title": "obstacle_fusion.SonarRange",
    "description": "One HC-SR04 measurement: raw MCU values and the host's conversion; "
    "t_* are host-monotonic seconds, timestamp is Unix time",
    "type": "object",
    "properties": {
        "timestamp": _TIME,
        "frame_id": {"type": "string"},
        "t_host": _NUM,
        "t_trigger_host": _NUM,
        "t_receipt": _NUM,
        "trigger_us": {"type": "integer"},
        "measurement": {"type": "integer"},
        "sensor_id": {"type": "integer"},
        "echo_ticks": {"type": "integer"},
        "timer_hz": {"type": "integer"},
        "echo_s": {"type": "number"},
        "status": {"type": "string"},
        "distance_m": _NUM,
        "raw_distance_m": _NUM,
        "slant_m": _NUM,
        "time_scale": {"type": "number"},
        "session": {"type": "integer"},
    },
}

OBSTACLE_SCHEMA: dict[str, Any] = {
    "title": "obstacle_fusion.Obstacle",
    "description": "The obstacle in front at one frame's capture instant; t_host is "
    "host-monotonic seconds, timestamp is Unix time",
    "type": "object",
    "properties": {
        "timestamp": _TIME,
        "t_host": {"type": "number"},
        "distance_m": _NUM,
        "height_m": _NUM,
        "width_m": _NUM,
        "confidence": {"type": "number"},
        "status": {"type": "string"},
        "alert": {"type": "boolean"},
        "frame_index": {"type": "integer"},
        "pairing": {"type": "string"},
        "pair_dt_s": _NUM,
        "sonar_status": {"type": ["string", "null"]},
        "latency_s": _NUM,
        "source": {"type": "string"},
        "measurements": {"type": "array", "items": {"type": "integer"}},
        "trigger_us": {"type": "array", "items": {"type": "integer"}},
        "box_px": {"type": ["array", "null"], "items": {"type": "number"}},
        "depth_m": _NUM,
        "method": {"type": ["string", "null"]},
        "vision_ms": _NUM,
        "t_published": _NUM,
        "reason": {"type": ["string", "null"]},
    },
}


@cache
def foxglove_schema(name: str) -> dict[str, Any]:
    """The published JSON schema of a Foxglove message, e.g. ``"foxglove.SceneUpdate"``."""
    text = (
        resources.files("obstacle_fusion.outputs")
        .joinpath("foxglove_jsonschema", f"{name}.json")
        .read_text(encoding="utf-8")
    )
    schema: dict[str, Any] = json.loads(text)
    return schema


#: topic -> (schema name, schema)
def topic_schemas() -> dict[str, tuple[str, dict[str, Any]]]:
    fox = {
        TOPIC_IMAGE: "foxglove.CompressedImage",
        TOPIC_CALIBRATION: "foxglove.CameraCalibration",
        TOPIC_ANNOTATIONS: "foxglove.ImageAnnotations",
        TOPIC_SCENE: "foxglove.SceneUpdate",
        TOPIC_TF: "foxglove.FrameTransform",
        TOPIC_EVENT: "foxglove.Log",
    }
    out: dict[str, tuple[str, dict[str, Any]]] = {
        t: (n, foxglove_schema(n)) for t, n in fox.items()
    }
    out[TOPIC_RANGE] = (RANGE_SCHEMA["title"], RANGE_SCHEMA)
    out[TOPIC_OBSTACLE] = (OBSTACLE_SCHEMA["title"], OBSTACLE_SCHEMA)
    return out


@dataclass(frozen=True, slots=True)
class TopicMessage:
    topic: str
    data: bytes  # JSON
    publish_time_ns: int  # acquisition instant (frame capture, echo reflection), Unix ns
    log_time_ns: int  # when the host had it, Unix ns


# ---------------------------------------------------------------------- small helpers


def stamp(ns: int) -> dict[str, int]:
    ns = max(int(ns), 0)
    return {"sec": ns // 1_000_000_000, "nsec": ns % 1_000_000_000}


def _clean(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_clean(v) for v in value]
    return value


def dumps(obj: dict[str, Any]) -> bytes:
    return json.dumps(_clean(obj), separators=(",", ":"), allow_nan=False).encode()


def _color(r: float, g: float, b: float, a: float = 1.0) -> dict[str, float]:
    return {"r": r, "g": g, "b": b, "a": a}


def _point(x: float, y: float) -> dict[str, float]:
    return {"x": float(x), "y": float(y)}


def quaternion(rot: npt.NDArray[np.float64]) -> dict[str, float]:
    """The unit quaternion (x, y, z, w) of a proper rotation matrix."""
    m = np.asarray(rot, float)
    tr = m[0, 0] + m[1, 1] + m[2, 2]
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        w, x = 0.25 * s, (m[2, 1] - m[1, 2]) / s
        y, z = (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = math.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2]) * 2
        w, x = (m[2, 1] - m[1, 2]) / s, 0.25 * s
        y, z = (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s
    elif m[1, 1] > m[2, 2]:
        s = math.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2]) * 2
        w, x = (m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s
        y, z = 0.25 * s, (m[1, 2] + m[2, 1]) / s
    else:
        s = math.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1]) * 2
        w, x = (m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s
        y, z = (m[1, 2] + m[2, 1]) / s, 0.25 * s
    if w < 0:
        w, x, y, z = -w, -x, -y, -z
    return {"x": float(x), "y": float(y), "z": float(z), "w": float(w)}


#: rig axes (x right, y down, z forward) -> robot axes (x forward, y left, z up)
RIG_TO_ROBOT = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])


def rig_point_to_robot(rig: Rig, p_rig: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """A point in the rig frame (origin at the lens) in the robot frame (origin on the floor)."""
    return np.asarray(RIG_TO_ROBOT @ np.asarray(p_rig, float) + [0.0, 0.0, rig.camera_height_m])


def camera_pose(rig: Rig) -> tuple[list[float], dict[str, float]]:
    """robot -> camera optical frame: translation (m) and rotation."""
    rot = RIG_TO_ROBOT @ rig.camera_to_robot
    return [0.0, 0.0, rig.camera_height_m], quaternion(rot)


def sonar_pose(rig: Rig) -> tuple[list[float], dict[str, float]]:
    """robot -> sonar frame (x along the beam, level): translation (m) and rotation."""
    p = rig_point_to_robot(rig, [rig.sonar_right_m, rig.sonar_below_m, rig.sonar_ahead_m])
    return [float(v) for v in p], {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}


def unix_offset_ns_now() -> int:
    """Unix time minus host-monotonic time, in ns: the mapping kept in the metadata."""
    return int(round((time.time() - time.monotonic()) * 1e9))


def recording_unix_offset_ns(metadata: dict[str, dict[str, str]]) -> int:
    """What to subtract from a recording's message times to get host-monotonic ns.

    Recordings made before the Unix time base stored monotonic times (offset 0)."""
    meta = metadata.get("obstacle_fusion", {})
    if meta.get("time_base") != TIME_BASE_UNIX:
        return 0
    try:
        return int(meta["unix_offset_ns"])
    except (KeyError, ValueError):
        return 0


def recording_monotonic_to_unix_ns(metadata: dict[str, dict[str, str]]) -> int:
    """Host-monotonic -> Unix offset of a recording, old or new (0 when not recorded)."""
    meta = metadata.get("obstacle_fusion", {})
    try:
        if "unix_offset_ns" in meta:
            return int(meta["unix_offset_ns"])
        return int(round(float(meta.get("monotonic_to_unix_offset_s", "0")) * 1e9))
    except ValueError:
        return 0


_EVENT_LEVELS = {
    "disconnected": 3,
    "emulator_restart": 3,
    "alert_exit": 3,
    "record_error": 4,
}


def event_of_log(data: dict[str, Any]) -> tuple[str, dict[str, Any]]:
    """(event, detail) of a /link/event message: a foxglove.Log, or the older JSON form."""
    if "event" in data:
        return str(data["event"]), dict(data.get("detail") or {})
    text = str(data.get("message", ""))
    name, _, rest = text.partition(" ")
    try:
        detail = json.loads(rest) if rest else {}
    except ValueError:
        detail = {"text": rest}
    return name, detail if isinstance(detail, dict) else {"value": detail}


def encode_image(image: npt.NDArray[np.uint8], fmt: str, jpeg_quality: int = 85) -> bytes | None:
    """JPEG or PNG bytes of a BGR frame, or None if OpenCV cannot encode it."""
    import cv2

    ext = ".jpg" if fmt == "jpeg" else ".png"
    params = [int(cv2.IMWRITE_JPEG_QUALITY), jpeg_quality] if ext == ".jpg" else []
    ok, buf = cv2.imencode(ext, image, params)
    return buf.tobytes() if ok else None


# ---------------------------------------------------------------------- the encoder


class FoxgloveTopics:
    """Frames, readings, records and events -> TopicMessages on Unix time.

    ``camera`` (a CameraModel) gives the calibration topic and the cube's lateral place;
    without it (a real camera before its first frame) both wait for :meth:`set_camera`.
    """

    def __init__(
        self,
        rig: Rig | None = None,
        camera: Any = None,
        *,
        unix_offset_ns: int | None = None,
        image_format: str = "jpeg",
        jpeg_quality: int = 85,
    ) -> None:
        if image_format not in ("jpeg", "png"):
            from obstacle_fusion.errors import UserError

            raise UserError(f"image format must be jpeg or png, got {image_format!r}")
        self.rig = rig or Rig()
        self.camera = camera
        self.unix_offset_ns = unix_offset_ns_now() if unix_offset_ns is None else unix_offset_ns
        self.image_format = image_format
        self.jpeg_quality = jpeg_quality
        self._last_static_ns: int | None = None
        self._sensors: set[int] = {0}
        self.frame_size: tuple[int, int] | None = None  # the latest frame's

    # -------------------------------------------------------------- time
    def ns(self, t_monotonic: float | None) -> int:
        """Host-monotonic seconds -> Unix-epoch ns."""
        return max(int(round((t_monotonic or 0.0) * 1e9)) + self.unix_offset_ns, 0)

    def metadata(self) -> dict[str, str]:
        return {
            "time_base": TIME_BASE_UNIX,
            "unix_offset_ns": str(self.unix_offset_ns),
            "monotonic_to_unix_offset_s": f"{self.unix_offset_ns / 1e9:.6f}",
            "frames": "robot: x forward, y left, z up, origin on the floor below the lens; "
            "camera: optical (x right, y down, z forward); sonar_N: x along the beam",
        }

    def set_camera(self, camera: Any) -> None:
        self.camera = camera

    def camera_at(self, width: int, height: int) -> Any:
        if self.camera is None:
            return None
        try:
            return self.camera.scaled_to(width, height)
        except Exception:
            return None

    # -------------------------------------------------------------- frames
    def frame(
        self, image: npt.NDArray[np.uint8], t_host: float, log_t: float
    ) -> list[TopicMessage]:
        """The image (and the calibration and transforms now and then); [] if unencodable."""
        data = encode_image(image, self.image_format, self.jpeg_quality)
        if data is None:
            return []
        return self.encoded_frame(data, image.shape[1], image.shape[0], t_host, log_t)

    def encoded_frame(
        self, data: bytes, width: int, height: int, t_host: float, log_t: float
    ) -> list[TopicMessage]:
        self.frame_size = (width, height)
        pub, lg = self.ns(t_host), self.ns(log_t)
        payload = {
            "timestamp": stamp(pub),
            "frame_id": FRAME_CAMERA,
            "data": base64.b64encode(data).decode("ascii"),
            "format": self.image_format,
        }
        out = [TopicMessage(TOPIC_IMAGE, dumps(payload), pub, lg)]
        cal = self.calibration(width, height, pub, lg)
        if cal is not None:
            out.append(cal)
        return out + self.transforms(lg, stamp_ns=pub)

    def calibration(self, width: int, height: int, pub: int, lg: int) -> TopicMessage | None:
        cam = self.camera_at(width, height)
        if cam is None:
            return None
        k = [float(v) for v in np.asarray(cam.camera_matrix, float).ravel()]
        d = [float(v) for v in np.asarray(cam.dist_coeffs, float).ravel()]
        p = [k[0], k[1], k[2], 0.0, k[3], k[4], k[5], 0.0, k[6], k[7], k[8], 0.0]
        payload = {
            "timestamp": stamp(pub),
            "frame_id": FRAME_CAMERA,
            "width": int(width),
            "height": int(height),
            "distortion_model": "plumb_bob" if len(d) <= 5 else "rational_polynomial",
            "D": d,
            "K": k,
            "R": [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
            "P": p,
        }
        return TopicMessage(TOPIC_CALIBRATION, dumps(payload), pub, lg)

    def transforms(
        self, lg: int, force: bool = False, stamp_ns: int | None = None
    ) -> list[TopicMessage]:
        """robot -> camera and robot -> sonar_N, at most once per TRANSFORM_PERIOD_S.

        Stamped ``stamp_ns`` (default: the log time): with a frame, its capture instant, so
        the first image already has its transform at its own time."""
        if (
            not force
            and self._last_static_ns is not None
            and lg - self._last_static_ns < TRANSFORM_PERIOD_S * 1e9
        ):
            return []
        self._last_static_ns = lg
        poses = [(FRAME_CAMERA, camera_pose(self.rig))]
        poses += [(f"sonar_{i}", sonar_pose(self.rig)) for i in sorted(self._sensors)]
        out = []
        for child, (xyz, rot) in poses:
            payload = {
                "timestamp": stamp(lg if stamp_ns is None else stamp_ns),
                "parent_frame_id": FRAME_ROBOT,
                "child_frame_id": child,
                "translation": {"x": xyz[0], "y": xyz[1], "z": xyz[2]},
                "rotation": rot,
            }
            out.append(TopicMessage(TOPIC_TF, dumps(payload), stamp_ns or lg, lg))
        return out

    # -------------------------------------------------------------- sonar
    def reading(
        self, r: SonarReading, timer_hz: int, session: int, log_t: float | None = None
    ) -> list[TopicMessage]:
        new_sensor = r.sensor_id not in self._sensors
        self._sensors.add(r.sensor_id)
        t_pub = r.t_host if r.t_host is not None else (log_t or 0.0)
        pub = self.ns(t_pub)
        lg = self.ns(log_t if log_t is not None else t_pub)
        payload = {
            "timestamp": stamp(pub),
            "frame_id": f"sonar_{r.sensor_id}",
            "t_host": r.t_host,
            "t_trigger_host": r.t_trigger_host,
            "t_receipt": r.t_receipt,
            "trigger_us": r.trigger_us,
            "measurement": r.measurement,
            "sensor_id": r.sensor_id,
            "echo_ticks": r.echo_ticks,
            "timer_hz": timer_hz,
            "echo_s": r.echo_s,
            "status": str(r.status),
            "distance_m": r.distance_m,
            "raw_distance_m": r.raw_distance_m,
            "slant_m": r.slant_m,
            "time_scale": r.time_scale,
            "session": session,
        }
        out = [TopicMessage(TOPIC_RANGE, dumps(payload), pub, lg)]
        if new_sensor:
            out += self.transforms(lg, force=True, stamp_ns=pub)
        return out

    # -------------------------------------------------------------- records
    def record(self, rec: ObstacleRecord, log_t: float | None = None) -> list[TopicMessage]:
        """The obstacle record, its image annotations and its 3D scene update."""
        pub = self.ns(rec.t_host)
        lg = self.ns(log_t if log_t is not None else (rec.t_published or rec.t_host))
        payload = rec.to_dict()
        payload["timestamp"] = stamp(pub)
        return [
            TopicMessage(TOPIC_OBSTACLE, dumps(payload), pub, lg),
            TopicMessage(TOPIC_ANNOTATIONS, dumps(self.annotations(rec, pub)), pub, lg),
            TopicMessage(TOPIC_SCENE, dumps(self.scene(rec, pub)), pub, lg),
        ]

    @staticmethod
    def status_color(rec: ObstacleRecord) -> dict[str, float]:
        if rec.alert:
            return _color(1.0, 0.1, 0.1)
        if rec.status == "ok":
            return _color(0.1, 0.85, 0.1)
        return _color(1.0, 0.75, 0.0)

    @staticmethod
    def text_lines(rec: ObstacleRecord) -> list[str]:
        lines = [f"{rec.status}{'  STOP' if rec.alert else ''}"]
        if rec.distance_m is not None:
            lines.append(f"L {rec.distance_m:.3f} m")
        if rec.height_m is not None and rec.width_m is not None:
            lines.append(f"H {rec.height_m:.3f} m  W {rec.width_m:.3f} m")
        return lines

    def annotations(self, rec: ObstacleRecord, pub: int) -> dict[str, Any]:
        ts = stamp(pub)
        color = self.status_color(rec)
        clear = _color(0.0, 0.0, 0.0, 0.0)
        points: list[dict[str, Any]] = []
        if rec.box_px is not None:
            x0, y0, x1, y1 = rec.box_px
            points.append(
                {
                    "timestamp": ts,
                    "type": 2,  # LINE_LOOP
                    "points": [_point(x0, y0), _point(x1, y0), _point(x1, y1), _point(x0, y1)],
                    "outline_color": color,
                    "outline_colors": [],
                    "fill_color": clear,
                    "thickness": 2.0,
                }
            )
        if rec.edges_px:
            pts = []
            for ax, ay, bx, by in rec.edges_px:
                pts += [_point(ax, ay), _point(bx, by)]
            points.append(
                {
                    "timestamp": ts,
                    "type": 4,  # LINE_LIST
                    "points": pts,
                    "outline_color": _color(1.0, 1.0, 0.0),
                    "outline_colors": [],
                    "fill_color": clear,
                    "thickness": 1.0,
                }
            )
        texts = [
            {
                "timestamp": ts,
                "position": _point(8.0, 22.0 * (i + 1)),  # bottom-left of the text, stacked
                "text": line,
                "font_size": 16.0,
                "text_color": color,
                "background_color": _color(0.0, 0.0, 0.0, 0.6),
            }
            for i, line in enumerate(self.text_lines(rec))
        ]
        return {"timestamp": ts, "circles": [], "points": points, "texts": texts}

    def obstacle_pose(self, rec: ObstacleRecord) -> list[float] | None:
        """Centre of the cube in the robot frame, or None when nothing was measured."""
        if rec.status != "ok" or rec.distance_m is None or rec.height_m is None:
            return None
        depth = self.rig.face_depth(rec.distance_m)  # rig z of the face
        lateral = self.rig.sonar_right_m  # rig x: the beam's axis unless the box says better
        if rec.box_px is not None and self.frame_size is not None:
            cam = self.camera_at(*self.frame_size)
            if cam is not None:  # the ray through the box's centre, undistorted and levelled
                u = 0.5 * (rec.box_px[0] + rec.box_px[2])
                v = 0.5 * (rec.box_px[1] + rec.box_px[3])
                ray = self.rig.camera_to_robot @ cam.unproject([[u, v]])[0]
                lateral = float(ray[0] / ray[2]) * depth
        centre = rig_point_to_robot(self.rig, [lateral, 0.0, depth + CUBE_DEPTH_M / 2])
        centre[2] = rec.height_m / 2.0  # it stands on the floor
        return [float(v) for v in centre]

    def scene(self, rec: ObstacleRecord, pub: int) -> dict[str, Any]:
        ts = stamp(pub)
        centre = self.obstacle_pose(rec)
        if centre is None or rec.width_m is None or rec.height_m is None:
            return {
                "deletions": [{"timestamp": ts, "type": 0, "id": "obstacle"}],
                "entities": [],
            }
        identity = {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}
        color = self.status_color(rec)
        color["a"] = 0.6
        entity = {
            "timestamp": ts,
            "frame_id": FRAME_ROBOT,
            "id": "obstacle",
            "lifetime": {"sec": 0, "nsec": 0},
            "frame_locked": False,
            "metadata": [
                {"key": "distance_m", "value": f"{rec.distance_m:.3f}"},
                {"key": "height_m", "value": f"{rec.height_m:.3f}"},
                {"key": "width_m", "value": f"{rec.width_m:.3f}"},
            ],
            "arrows": [],
            "cubes": [
                {
                    "pose": {
                        "position": {"x": centre[0], "y": centre[1], "z": centre[2]},
                        "orientation": identity,
                    },
                    "size": {"x": CUBE_DEPTH_M, "y": rec.width_m, "z": rec.height_m},
                    "color": color,
                }
            ],
            "spheres": [],
            "cylinders": [],
            "lines": [],
            "triangles": [],
            "texts": [
                {
                    "pose": {
                        "position": {
                            "x": centre[0],
                            "y": centre[1],
                            "z": rec.height_m + 0.1,
                        },
                        "orientation": identity,
                    },
                    "billboard": True,
                    "font_size": 14.0,
                    "scale_invariant": True,
                    "color": _color(1.0, 1.0, 1.0),
                    "text": "  ".join(self.text_lines(rec)[1:]),
                }
            ],
            "models": [],
        }
        return {"deletions": [], "entities": [entity]}

    # -------------------------------------------------------------- events
    def event(self, name: str, detail: dict[str, Any], t: float | None = None) -> TopicMessage:
        now = time.monotonic() if t is None else t
        ns = self.ns(now)
        level = _EVENT_LEVELS.get(name, 2)
        if name == "log":  # the firmware's own log lines keep their level (0 debug .. 3 error)
            level = {0: 1, 1: 2, 2: 3, 3: 4}.get(int(detail.get("level", 1)), 2)
        payload = {
            "timestamp": stamp(ns),
            "level": level,
            "message": f"{name} {json.dumps(_clean(detail), separators=(',', ':'))}",
            "name": "obstacle_fusion.link",
            "file": "",
            "line": 0,
        }
        return TopicMessage(TOPIC_EVENT, dumps(payload), ns, ns)
