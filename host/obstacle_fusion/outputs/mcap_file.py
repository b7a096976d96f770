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
"""

from __future__ import annotations

import base64
import json
import logging
import time
from dataclasses import dataclass
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

    def write(self, msg: TopicMessage) -> None:
        """One message as the encoder made it (the App shares them with the live view)."""
        self._add(msg.topic, msg.data, msg.publish_time_ns, msg.log_time_ns)

    def _add(self, topic: str, data: bytes, publish_ns: int, log_ns: int) -> None:
        if self._closed:
            return
        self._seq[topic] += 1
        self._writer.add_message(
            channel_id=self._channels[topic],
            log_time=log_ns,
            publish_time=publish_ns,
            data=data,
            sequence=self._seq[topic],
        )
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
        self._writer.flush()
        self._file.flush()
        self._last_flush = time.monotonic()

    def close(self) -> None:
        if self._closed:
            return
        try:
            self._writer.finish()
        finally:
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


def decode_image(data: dict[str, Any]) -> np.ndarray | None:
    import cv2

    raw = np.frombuffer(base64.b64decode(data["data"]), np.uint8)
    image = cv2.imdecode(raw, cv2.IMREAD_COLOR)
    return None if image is None else np.asarray(image)


def read_recording(path: str | Path) -> Recording:
    """Every message of a recording in file order, and whether the file is whole.

    A file that does not start with the MCAP magic is refused with a UserError; a file
    cut short returns what precedes the cut, with ``complete=False``.
    """
    from mcap.exceptions import InvalidMagic, McapError
    from mcap.records import Channel as ChannelRecord
    from mcap.records import Footer, Message, Metadata
    from mcap.stream_reader import StreamReader

    p = Path(path)
    if not p.is_file():
        raise UserError(f"{p} does not exist or is not a file")
    with open(p, "rb") as fh:
        head = fh.read(8)
        if head[:5] != b"\x89MCAP":
            raise UserError(
                f"{p} is not an MCAP file (it does not start with the MCAP magic bytes); "
                "give a recording made with `obstacle-fusion run --record FILE.mcap`"
            )
        fh.seek(0)
        channels: dict[int, str] = {}
        messages: list[RecordedMessage] = []
        metadata: dict[str, dict[str, str]] = {}
        complete = False
        problem: str | None = None
        try:
            for record in StreamReader(fh, skip_magic=False).records:
                if isinstance(record, ChannelRecord):
                    channels[record.id] = record.topic
                elif isinstance(record, Message):
                    topic = channels.get(record.channel_id)
                    if topic is None:
                        continue
                    try:
                        data = json.loads(record.data)
                    except ValueError:
                        problem = f"undecodable message on {topic}"
                        continue
                    messages.append(
                        RecordedMessage(topic, record.log_time, record.publish_time, data)
                    )
                elif isinstance(record, Metadata):
                    metadata[record.name] = dict(record.metadata)
                elif isinstance(record, Footer):
                    complete = True
        except InvalidMagic as exc:
            raise UserError(f"{p} is not an MCAP file: {exc}") from exc
        except (McapError, EOFError, ValueError, KeyError, IndexError) as exc:
            complete = False
            problem = f"the file is cut short or damaged ({type(exc).__name__}: {exc})"
        except Exception as exc:  # a damaged record can fail in struct/zlib
            complete = False
            problem = f"the file is damaged ({type(exc).__name__}: {exc})"
    if not complete and problem is None:
        problem = "the file ends before its closing records (the recording was cut short)"
    return Recording(messages, metadata, complete, problem)
