"""MCAP recording that Foxglove opens as it is, and reading it back for replay.

Frames go on /camera/image as foxglove.CompressedImage (JSON encoding, image bytes in
base64 as Foxglove's JSON-schema convention says); sonar readings on /sonar/range and
obstacle records on /obstacle as JSON-schema messages; link events (handshakes,
disconnects, counters) on /link/event. publish_time is the acquisition instant on the
host's monotonic clock (frame capture, echo reflection), log_time the moment the host
received it; both in nanoseconds. The offset to Unix time is in the file's metadata.

Chunks are closed at least every ``flush_interval_s`` and the file flushed, so a crash
loses at most that much: everything before it stays readable (replay reads such a file
and says it was cut short). A reconnect is not a crash: the same file keeps going.

A write that fails (disk full, a removed USB stick) stops the recording, never the run:
``McapRecorder.failed`` says why, it is logged once, the file is closed as far as it got
(``obstacle-fusion recover`` makes it an indexed file again), and later writes are dropped.
"""

from __future__ import annotations

import base64
import errno
import json
import logging
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any

import cv2
import numpy as np

from obstacle_fusion import __version__
from obstacle_fusion.errors import UserError
from obstacle_fusion.fusion import ObstacleRecord
from obstacle_fusion.sonar import SonarReading
from obstacle_fusion.sources.frames import Frame

log = logging.getLogger(__name__)

TOPIC_IMAGE = "/camera/image"
TOPIC_RANGE = "/sonar/range"
TOPIC_OBSTACLE = "/obstacle"
TOPIC_EVENT = "/link/event"

_TIME = {
    "type": "object",
    "title": "time",
    "properties": {
        "sec": {"type": "integer", "minimum": 0},
        "nsec": {"type": "integer", "minimum": 0, "maximum": 999999999},
    },
}
_NUM = {"type": ["number", "null"]}

COMPRESSED_IMAGE_SCHEMA = {
    "title": "foxglove.CompressedImage",
    "description": "A compressed image",
    "type": "object",
    "properties": {
        "timestamp": {**_TIME, "description": "Timestamp of image"},
        "frame_id": {"type": "string", "description": "Frame of reference for the image"},
        "data": {
            "type": "string",
            "contentEncoding": "base64",
            "description": "Compressed image data",
        },
        "format": {"type": "string", "description": "Image format"},
    },
}

RANGE_SCHEMA = {
    "title": "obstacle_fusion.SonarRange",
    "description": "One HC-SR04 measurement: raw MCU values and the host's conversion",
    "type": "object",
    "properties": {
        "timestamp": _TIME,
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

OBSTACLE_SCHEMA = {
    "title": "obstacle_fusion.Obstacle",
    "description": "The obstacle in front at one frame's capture instant",
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
    },
}

EVENT_SCHEMA = {
    "title": "obstacle_fusion.LinkEvent",
    "description": "Link lifecycle and health: handshake, disconnect, counters, clock",
    "type": "object",
    "properties": {
        "timestamp": _TIME,
        "event": {"type": "string"},
        "detail": {"type": "object"},
    },
}


def _stamp(t: float) -> dict[str, int]:
    ns = max(int(round(t * 1e9)), 0)
    return {"sec": ns // 1_000_000_000, "nsec": ns % 1_000_000_000}


def _ns(t: float | None) -> int:
    return max(int(round((t or 0.0) * 1e9)), 0)


def _clean(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_clean(v) for v in value]
    return value


def _dumps(obj: dict[str, Any]) -> bytes:
    return json.dumps(_clean(obj), separators=(",", ":"), allow_nan=False).encode()


def reading_to_dict(r: SonarReading, timer_hz: int, session: int) -> dict[str, Any]:
    return {
        "timestamp": _stamp(r.t_host or 0.0),
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


class McapRecorder:
    """Write a run to an MCAP file; close() (or the context manager) finishes it."""

    def __init__(
        self,
        path: str | Path,
        *,
        image_format: str = "jpeg",
        jpeg_quality: int = 85,
        flush_interval_s: float = 1.0,
        chunk_size: int = 1 << 20,
        metadata: dict[str, dict[str, str]] | None = None,
        overwrite: bool = False,
    ) -> None:
        from mcap.writer import CompressionType, Writer

        if image_format not in ("jpeg", "png"):
            raise UserError(f"image format must be jpeg or png, got {image_format!r}")
        self.path = Path(path)
        self.failed: str | None = None  # why the recording stopped early, if it did
        self.dropped = 0  # messages not written after a failure
        try:  # "x": an earlier recording is never truncated unless asked
            self._file: IO[bytes] = open(self.path, "wb" if overwrite else "xb")  # noqa: SIM115
        except FileExistsError:
            raise UserError(
                f"the recording {self.path} already exists; give another name, or --overwrite "
                "to replace it"
            ) from None
        except OSError as exc:
            raise UserError(f"cannot write the recording {self.path}: {exc.strerror}") from exc
        self.image_format = image_format
        self._ext = ".jpg" if image_format == "jpeg" else ".png"
        self._params = (
            [int(cv2.IMWRITE_JPEG_QUALITY), jpeg_quality] if image_format == "jpeg" else []
        )
        self.flush_interval_s = flush_interval_s
        self._writer = Writer(self._file, chunk_size=chunk_size, compression=CompressionType.NONE)
        self._writer.start(profile="", library=f"obstacle-fusion {__version__}")
        self._channels: dict[str, int] = {}
        for topic, schema in (
            (TOPIC_IMAGE, COMPRESSED_IMAGE_SCHEMA),
            (TOPIC_RANGE, RANGE_SCHEMA),
            (TOPIC_OBSTACLE, OBSTACLE_SCHEMA),
            (TOPIC_EVENT, EVENT_SCHEMA),
        ):
            sid = self._writer.register_schema(
                name=str(schema["title"]), encoding="jsonschema", data=json.dumps(schema).encode()
            )
            self._channels[topic] = self._writer.register_channel(
                topic=topic, message_encoding="json", schema_id=sid
            )
        self._seq: dict[str, int] = dict.fromkeys(self._channels, 0)
        self.counts: dict[str, int] = dict.fromkeys(self._channels, 0)
        meta = {
            "obstacle_fusion": {
                "version": __version__,
                "time_base": "host monotonic clock, nanoseconds",
                "monotonic_to_unix_offset_s": f"{time.time() - time.monotonic():.6f}",
            }
        }
        meta.update(metadata or {})
        for name, data in meta.items():
            self._writer.add_metadata(name, {k: str(v) for k, v in data.items()})
        self._last_flush = time.monotonic()
        self._closed = False

    def _fail(self, exc: OSError) -> None:
        """The file cannot take more: say so once, close it as far as it got, go on."""
        reason = exc.strerror or str(exc)
        if exc.errno is not None and exc.errno in errno.errorcode:
            reason = f"{reason} ({errno.errorcode[exc.errno]})"
        self.failed = (
            f"the recording {self.path} stopped: {reason}; it holds what was written before "
            f"(`obstacle-fusion recover {self.path} FIXED.mcap` makes it an indexed file)"
        )
        log.error("%s; sensing goes on without it", self.failed)
        self._closed = True
        try:
            self._file.close()
        except OSError:
            pass  # the buffered tail could not be written either; what is on disk stays

    def _add(self, topic: str, payload: dict[str, Any], publish_t: float, log_t: float) -> None:
        if self._closed:
            if self.failed is not None:
                self.dropped += 1
            return
        self._seq[topic] += 1
        try:
            self._writer.add_message(
                channel_id=self._channels[topic],
                log_time=_ns(log_t),
                publish_time=_ns(publish_t),
                data=_dumps(payload),
                sequence=self._seq[topic],
            )
        except OSError as exc:
            self.dropped += 1
            self._fail(exc)
            return
        self.counts[topic] += 1
        now = time.monotonic()
        if now - self._last_flush >= self.flush_interval_s:
            self.flush()

    def write_frame(self, frame: Frame, log_t: float | None = None) -> None:
        ok, buf = cv2.imencode(self._ext, frame.image, self._params)
        if not ok:
            log.warning("could not encode frame %d; not recorded", frame.index)
            return
        payload = {
            "timestamp": _stamp(frame.t_host),
            "frame_id": frame.source,
            "data": base64.b64encode(buf.tobytes()).decode("ascii"),
            "format": self.image_format,
        }
        self._add(TOPIC_IMAGE, payload, frame.t_host, log_t if log_t is not None else frame.t_host)

    def write_range(
        self, reading: SonarReading, timer_hz: int, session: int, log_t: float | None = None
    ) -> None:
        payload = reading_to_dict(reading, timer_hz, session)
        publish = reading.t_host if reading.t_host is not None else (log_t or 0.0)
        self._add(TOPIC_RANGE, payload, publish, log_t if log_t is not None else publish)

    def write_obstacle(self, record: ObstacleRecord, log_t: float | None = None) -> None:
        payload = record.to_dict()
        payload["timestamp"] = _stamp(record.t_host)
        log_time = log_t if log_t is not None else (record.t_published or record.t_host)
        self._add(TOPIC_OBSTACLE, payload, record.t_host, log_time)

    def write_event(self, event: str, detail: dict[str, Any], t: float | None = None) -> None:
        now = time.monotonic() if t is None else t
        self._add(
            TOPIC_EVENT, {"timestamp": _stamp(now), "event": event, "detail": detail}, now, now
        )

    def flush(self) -> None:
        """Close the open chunk and push everything to the file (readable up to here)."""
        if self._closed:
            return
        try:
            self._writer.flush()
            self._file.flush()
        except OSError as exc:
            self._fail(exc)
            return
        self._last_flush = time.monotonic()

    def close(self) -> None:
        if self._closed:
            return
        try:
            self._writer.finish()
        except OSError as exc:
            self._fail(exc)
            return
        finally:
            if self.failed is None:
                self._closed = True
                self._file.close()

    def __enter__(self) -> McapRecorder:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


# ---------------------------------------------------------------------- reading back


@dataclass(frozen=True, slots=True)
class RecordedMessage:
    topic: str
    log_time_ns: int
    publish_time_ns: int
    data: dict[str, Any]


@dataclass
class Recording:
    messages: list[RecordedMessage]
    metadata: dict[str, dict[str, str]]
    complete: bool  # False: the file ends mid-way (crash, copy cut short)
    problem: str | None = None
    damage: str = ""  # what was damaged in the middle and lost, '' when nothing was
    skipped: dict[str, int] = field(default_factory=dict)  # per topic: not JSON, not a dict


def decode_image(data: dict[str, Any]) -> np.ndarray | None:
    """The image of a /camera/image message, or None (no data, not base64, not an image)."""
    payload = data.get("data")
    if not isinstance(payload, str):
        return None
    try:
        raw = np.frombuffer(base64.b64decode(payload, validate=True), np.uint8)
    except ValueError:
        return None
    if raw.size == 0:
        return None
    image = cv2.imdecode(raw, cv2.IMREAD_COLOR)
    return None if image is None else np.asarray(image)


def read_recording(path: str | Path) -> Recording:
    """Every intact message of a recording in file order, and whether the file is whole.

    A file that does not start with the MCAP magic is refused with a UserError; a file
    cut short returns what precedes the cut, with ``complete=False``; damage in the middle
    is skipped (every intact message after it is kept) and described in ``damage``.
    """
    from obstacle_fusion.outputs.mcap_salvage import describe, scan

    p = Path(path)
    try:
        if not p.is_file():
            raise UserError(f"{p} does not exist or is not a file")
        salvage = scan(p)
    except PermissionError:
        raise UserError(f"cannot read {p}: permission denied") from None
    except OSError as exc:
        raise UserError(f"cannot read {p}: {exc.strerror or exc}") from None
    except ValueError:
        raise UserError(
            f"{p} is not an MCAP file (it does not start with the MCAP magic bytes); "
            "give a recording made with `obstacle-fusion run --record FILE.mcap`"
        ) from None
    messages: list[RecordedMessage] = []
    skipped: dict[str, int] = {}
    for m in salvage.messages:
        channel = salvage.channels.get(m.channel_id)
        topic = channel.topic if channel is not None else f"(channel {m.channel_id})"
        try:
            if channel is None or channel.message_encoding != "json":
                raise ValueError(topic)
            data = json.loads(m.data)
            if not isinstance(data, dict):
                raise ValueError(topic)
        except ValueError:
            skipped[topic] = skipped.get(topic, 0) + 1
            continue
        messages.append(RecordedMessage(topic, m.log_time, m.publish_time, data))
    metadata = {md.name: dict(md.metadata) for md in salvage.metadata}
    problem = None
    if not salvage.complete:
        problem = "the file ends before its closing records (the recording was cut short)"
    return Recording(messages, metadata, salvage.complete, problem, describe(salvage), skipped)
