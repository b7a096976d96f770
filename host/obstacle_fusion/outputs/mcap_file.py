"""MCAP recording that Foxglove opens as it is, and reading it back for replay.

The topics and their schemas are those of :mod:`obstacle_fusion.outputs.foxglove_schemas`
(standard Foxglove schemas where one exists: the image, its annotations, the 3D scene, the
transforms, the link log; JSON-schema messages for the sonar range and the obstacle
record), JSON-encoded. publish_time is the acquisition instant (frame capture, echo
reflection), log_time the moment the host had it; both in Unix-epoch nanoseconds, mapped
from the host's monotonic clock with the offset kept in the file's metadata
(``obstacle_fusion``: ``time_base``, ``unix_offset_ns``). Recordings made before that
stored monotonic times; :func:`recording_unix_offset_ns` tells them apart.

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
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any

import numpy as np

from obstacle_fusion import __version__
from obstacle_fusion.errors import UserError
from obstacle_fusion.fusion import ObstacleRecord
from obstacle_fusion.outputs.foxglove_schemas import (
    OBSTACLE_SCHEMA,
    RANGE_SCHEMA,
    TOPIC_ANNOTATIONS,
    TOPIC_CALIBRATION,
    TOPIC_EVENT,
    TOPIC_IMAGE,
    TOPIC_OBSTACLE,
    TOPIC_RANGE,
    TOPIC_SCENE,
    TOPIC_TF,
    FoxgloveTopics,
    TopicMessage,
    event_of_log,
    recording_unix_offset_ns,
    topic_schemas,
)
from obstacle_fusion.sonar import SonarReading
from obstacle_fusion.sources.frames import Frame

log = logging.getLogger(__name__)

__all__ = [
    "OBSTACLE_SCHEMA",
    "RANGE_SCHEMA",
    "TOPIC_ANNOTATIONS",
    "TOPIC_CALIBRATION",
    "TOPIC_EVENT",
    "TOPIC_IMAGE",
    "TOPIC_OBSTACLE",
    "TOPIC_RANGE",
    "TOPIC_SCENE",
    "TOPIC_TF",
    "McapRecorder",
    "RecordedMessage",
    "Recording",
    "decode_image",
    "event_of_log",
    "read_recording",
    "recording_unix_offset_ns",
]


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
        topics: FoxgloveTopics | None = None,
    ) -> None:
        from mcap.writer import CompressionType, Writer

        self.topics = topics or FoxgloveTopics(image_format=image_format, jpeg_quality=jpeg_quality)
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
        self.image_format = self.topics.image_format
        self.flush_interval_s = flush_interval_s
        self._writer = Writer(self._file, chunk_size=chunk_size, compression=CompressionType.NONE)
        self._writer.start(profile="", library=f"obstacle-fusion {__version__}")
        self._channels: dict[str, int] = {}
        for topic, (name, schema) in topic_schemas().items():
            sid = self._writer.register_schema(
                name=name, encoding="jsonschema", data=json.dumps(schema).encode()
            )
            self._channels[topic] = self._writer.register_channel(
                topic=topic, message_encoding="json", schema_id=sid
            )
        self._seq: dict[str, int] = dict.fromkeys(self._channels, 0)
        self.counts: dict[str, int] = dict.fromkeys(self._channels, 0)
        meta = {
            "obstacle_fusion": {
                "version": __version__,
                **self.topics.metadata(),
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

    def write(self, msg: TopicMessage) -> None:
        """One message as the encoder made it (the App shares them with the live view)."""
        self._add(msg.topic, msg.data, msg.publish_time_ns, msg.log_time_ns)

    def _add(self, topic: str, data: bytes, publish_ns: int, log_ns: int) -> None:
        if self._closed:
            if self.failed is not None:
                self.dropped += 1
            return
        self._seq[topic] += 1
        try:
            self._writer.add_message(
                channel_id=self._channels[topic],
                log_time=log_ns,
                publish_time=publish_ns,
                data=data,
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
        log_time = log_t if log_t is not None else frame.t_host
        msgs = self.topics.frame(frame.image, frame.t_host, log_time)
        if not msgs:
            log.warning("could not encode frame %d; not recorded", frame.index)
        for m in msgs:
            self.write(m)

    def write_range(
        self, reading: SonarReading, timer_hz: int, session: int, log_t: float | None = None
    ) -> None:
        for m in self.topics.reading(reading, timer_hz, session, log_t):
            self.write(m)

    def write_obstacle(self, record: ObstacleRecord, log_t: float | None = None) -> None:
        for m in self.topics.record(record, log_t):
            self.write(m)

    def write_event(self, event: str, detail: dict[str, Any], t: float | None = None) -> None:
        self.write(self.topics.event(event, detail, t))

    def add_metadata(self, name: str, data: dict[str, str]) -> None:
        """One more metadata record (e.g. what the run learnt, written at its end)."""
        if not self._closed:
            self._writer.add_metadata(name, {k: str(v) for k, v in data.items()})

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
    import cv2

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
