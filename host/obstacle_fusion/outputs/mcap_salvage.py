"""Read every intact message of an MCAP file, however it was damaged, and say what was lost.

The mcap library's readers stop at the first bad byte (a stream reader) or need the summary
at the end (an indexed reader), so a recording cut by a power cut or a SIGKILL, or with a
few bytes damaged in the middle, loses everything after the damage or everything at all.
This scanner walks the records itself: a record that does not parse, or a chunk whose CRC
does not match, is a damaged region; the scan then looks, byte by byte, for the next record
that parses whole (a chunk with a matching CRC, or a message on a known channel whose JSON
decodes), so every intact message after the damage is recovered. Messages lost are counted
from the per-channel sequence numbers the recorder writes (and the file's statistics record,
when the summary survived).

``write_indexed`` writes what was read as a new, fully indexed MCAP file (chunk indexes,
statistics, summary), which any MCAP reader opens: ``obstacle-fusion recover``.
"""

from __future__ import annotations

import io
import json
import re
import zlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from mcap.data_stream import ReadDataStream
from mcap.opcode import Opcode
from mcap.records import (
    Channel,
    Chunk,
    Footer,
    Message,
    Metadata,
    Schema,
    Statistics,
)

MAGIC = b"\x89MCAP0\r\n"
_HEAD = 9  # opcode (1) + length (8)
# Records a reader needs; the index records (rebuilt by any writer) are only checked.
_KNOWN = {int(op) for op in Opcode}
_MIN_MESSAGE = 2 + 4 + 8 + 8  # channel id, sequence, log time, publish time
_OPCODE = re.compile(b"[" + b"".join(re.escape(bytes([op])) for op in sorted(_KNOWN)) + b"]")


@dataclass
class SalvagedMessage:
    channel_id: int
    sequence: int
    log_time: int
    publish_time: int
    data: bytes


@dataclass
class Salvage:
    """What a scan of an MCAP file found."""

    schemas: dict[int, Schema] = field(default_factory=dict)
    channels: dict[int, Channel] = field(default_factory=dict)
    messages: list[SalvagedMessage] = field(default_factory=list)
    metadata: list[Metadata] = field(default_factory=list)
    statistics: Statistics | None = None
    complete: bool = False  # the footer and the closing magic were read
    cut_short: bool = False  # the file ends inside a record (or before the footer)
    damaged_regions: int = 0  # stretches of bytes that were no record
    skipped_bytes: int = 0  # bytes in those stretches
    damaged_chunks: int = 0  # chunks with a wrong CRC (their intact messages are kept)

    def lost_per_topic(self) -> dict[str, int]:
        """Messages missing, per topic: the gaps in each channel's sequence numbers, or the
        file's statistics when they say more (messages lost at a channel's end)."""
        seqs: dict[int, list[int]] = {}
        for m in self.messages:
            seqs.setdefault(m.channel_id, []).append(m.sequence)
        lost: dict[str, int] = {}
        for cid, channel in self.channels.items():
            got = sorted(set(seqs.get(cid, [])))
            gaps = 0
            if got and got[0] > 0:  # the recorder numbers from 1; 0 = not numbered
                gaps = (got[-1] - got[0] + 1) - len(got) + (got[0] - 1)
            if self.statistics is not None:
                counted = self.statistics.channel_message_counts.get(cid)
                if counted is not None:
                    gaps = max(gaps, counted - len(seqs.get(cid, [])))
            if gaps > 0:
                lost[channel.topic] = lost.get(channel.topic, 0) + gaps
        return lost

    @property
    def damaged(self) -> bool:
        return bool(self.damaged_regions or self.damaged_chunks)


class _Bad(Exception):
    """This offset holds no record that parses whole."""


def _stream(data: bytes) -> ReadDataStream:
    return ReadDataStream(io.BytesIO(data))


def _record(data: bytes | memoryview, pos: int, end: int) -> tuple[int, int, bytes]:
    """(opcode, end offset, body) of the record at pos, or _Bad."""
    if pos + _HEAD > end:
        raise _Bad
    opcode = data[pos]
    length = int.from_bytes(data[pos + 1 : pos + _HEAD], "little")
    stop = pos + _HEAD + length
    if opcode not in _KNOWN or stop > end:
        raise _Bad
    return opcode, stop, bytes(data[pos + _HEAD : stop])


class _Scanner:
    def __init__(self, data: bytes) -> None:
        self.data = data
        self.out = Salvage()
        self.unfinished = 0  # chunks read in place because they overran the end

    # ---------------------------------------------------------------- one record
    def _message(self, body: bytes, strict: bool) -> SalvagedMessage:
        if len(body) < _MIN_MESSAGE:
            raise _Bad
        msg = Message.read(_stream(body), len(body))
        channel = self.out.channels.get(msg.channel_id)
        if strict:
            # Found by searching: accept it only if it is plainly a message of this file.
            if channel is None:
                raise _Bad
            if channel.message_encoding == "json":
                try:
                    json.loads(msg.data)
                except ValueError:
                    raise _Bad from None
        return SalvagedMessage(
            msg.channel_id, msg.sequence, msg.log_time, msg.publish_time, bytes(msg.data)
        )

    def _take(self, opcode: int, body: bytes, strict: bool, in_chunk: bool) -> None:
        """Parse one record's body and keep what a reader needs; _Bad if it does not parse."""
        out = self.out
        try:
            if opcode == Opcode.MESSAGE:
                out.messages.append(self._message(body, strict))
            elif opcode == Opcode.SCHEMA:
                s = Schema.read(_stream(body))
                out.schemas.setdefault(s.id, s)
            elif opcode == Opcode.CHANNEL:
                c = Channel.read(_stream(body))
                if strict and c.schema_id and c.schema_id not in out.schemas:
                    raise _Bad
                out.channels.setdefault(c.id, c)
            elif in_chunk:
                if strict:
                    raise _Bad  # only messages, schemas and channels live in chunks
            elif opcode == Opcode.CHUNK:
                self._chunk(body)
            elif opcode == Opcode.METADATA:
                out.metadata.append(Metadata.read(_stream(body)))
            elif opcode == Opcode.STATISTICS:
                out.statistics = Statistics.read(_stream(body))
            elif opcode == Opcode.FOOTER:
                Footer.read(_stream(body))
            elif strict and opcode not in (Opcode.MESSAGE_INDEX, Opcode.CHUNK_INDEX):
                raise _Bad  # the others are not worth a false match
        except _Bad:
            raise
        except Exception as exc:  # struct, unicode, EndOfFile...: not a record
            raise _Bad from exc

    def _chunk(self, body: bytes) -> None:
        chunk = Chunk.read(_stream(body))
        if chunk.compression == "":
            records = chunk.data
        else:
            from mcap.stream_reader import get_chunk_data_stream

            stream, n = get_chunk_data_stream(chunk)
            records = stream.read(n)
        if chunk.uncompressed_crc and zlib.crc32(records) != chunk.uncompressed_crc:
            self.out.damaged_chunks += 1
            self._walk(records, 0, len(records), in_chunk=True, suspect=True)
        else:
            self._walk(records, 0, len(records), in_chunk=True, suspect=False)

    # ---------------------------------------------------------------- a run of records
    def _walk(self, data: bytes, pos: int, end: int, in_chunk: bool, suspect: bool) -> int:
        """Records from pos to end; damage is skipped to the next record that parses.
        Returns where the walk stopped (end, or the footer's end)."""
        out = self.out
        while pos < end:
            try:
                opcode, stop, body = _record(data, pos, end)
                self._take(opcode, body, strict=suspect, in_chunk=in_chunk)
            except _Bad:
                if not in_chunk:
                    inner = self._unfinished_chunk(data, pos, end)
                    if inner is not None:
                        # A chunk that runs past the end of the file: the recording was cut
                        # while writing it. Its records are framed as the file's are: read on.
                        self.unfinished += 1
                        pos = inner
                        continue
                    if pos + _HEAD > end or (
                        data[pos] in _KNOWN
                        and pos + _HEAD + int.from_bytes(data[pos + 1 : pos + _HEAD], "little")
                        > end
                        and self._resync(data, pos + 1, end, in_chunk, keep=False) == end
                    ):
                        out.cut_short = True  # the last record runs past the end: a cut
                        return end
                nxt = self._resync(data, pos + 1, end, in_chunk, keep=True)
                out.damaged_regions += 1
                out.skipped_bytes += nxt - pos
                pos = nxt
                continue
            pos = stop
            if opcode == Opcode.FOOTER and not in_chunk:
                return pos
        return pos

    def _unfinished_chunk(self, data: bytes, pos: int, end: int) -> int | None:
        """Where the records of an uncompressed chunk that overruns the end start, or None."""
        if data[pos] != Opcode.CHUNK or pos + _HEAD + 40 > end:
            return None
        length = int.from_bytes(data[pos + 1 : pos + _HEAD], "little")
        if pos + _HEAD + length <= end:
            return None
        at = pos + _HEAD + 8 + 8 + 8 + 4
        if int.from_bytes(data[at : at + 4], "little") != 0:
            return None  # compressed: its records are not readable in place
        return at + 4 + 8

    def _resync(self, data: bytes, pos: int, end: int, in_chunk: bool, keep: bool) -> int:
        """The next offset after damage where a record parses whole and plainly belongs to
        this file (kept when `keep`), or end."""
        saved = (len(self.out.messages), dict(self.out.channels), dict(self.out.schemas))
        find = _OPCODE.search
        while pos < end:
            hit = find(data, pos, end)
            if hit is None:
                break
            pos = hit.start()
            try:
                op, stop, body = _record(data, pos, end)
                if op == Opcode.CHUNK and not in_chunk:
                    chunk = Chunk.read(_stream(body))
                    if (
                        chunk.compression == ""
                        and chunk.uncompressed_crc
                        and (zlib.crc32(chunk.data) != chunk.uncompressed_crc)
                    ):
                        raise _Bad
                self._take(op, body, strict=True, in_chunk=in_chunk)
            except Exception:  # noqa: S112 - a false start in the middle of data
                pos += 1
                continue
            if not keep:
                del self.out.messages[saved[0] :]
                self.out.channels, self.out.schemas = saved[1], saved[2]
            return stop
        return end


def scan(path: str | Path) -> Salvage:
    """Every intact message of the MCAP file at path; OSError if it cannot be read."""
    data = Path(path).read_bytes()
    scanner = _Scanner(data)
    out = scanner.out
    if not data.startswith(MAGIC):
        raise ValueError("not an MCAP file (it does not start with the MCAP magic bytes)")
    pos = scanner._walk(data, len(MAGIC), len(data), in_chunk=False, suspect=False)
    if scanner.unfinished and pos < len(data):
        # A chunk overran the end, yet the file goes on: its length was damaged, not cut.
        out.damaged_regions += scanner.unfinished
        out.damaged_chunks += scanner.unfinished
    elif scanner.unfinished:
        out.cut_short = True
    if not out.cut_short:
        tail = data[pos:]
        if tail == MAGIC:
            out.complete = True
        elif pos >= len(data) or MAGIC.startswith(tail):
            out.cut_short = True
        else:
            out.damaged_regions += 1
            out.skipped_bytes += len(tail)
    return out


def write_indexed(salvage: Salvage, path: str | Path, *, overwrite: bool = False) -> int:
    """Write the salvaged schemas, channels, messages (in log-time order) and metadata as a
    new indexed MCAP file; returns the number of messages written."""
    from mcap.writer import CompressionType, Writer

    mode = "wb" if overwrite else "xb"
    with open(path, mode) as fh:
        writer = Writer(fh, compression=CompressionType.NONE)
        writer.start(profile="", library="obstacle-fusion recover")
        schema_ids: dict[int, int] = {}
        for sid, schema in salvage.schemas.items():
            schema_ids[sid] = writer.register_schema(schema.name, schema.encoding, schema.data)
        channel_ids: dict[int, int] = {}
        for cid, ch in salvage.channels.items():
            channel_ids[cid] = writer.register_channel(
                ch.topic, ch.message_encoding, schema_ids.get(ch.schema_id, 0), ch.metadata
            )
        n = 0
        for m in sorted(salvage.messages, key=lambda m: m.log_time):
            target = channel_ids.get(m.channel_id)
            if target is None:
                continue  # its channel record was lost with the damage
            writer.add_message(target, m.log_time, m.data, m.publish_time, m.sequence)
            n += 1
        for meta in salvage.metadata:
            writer.add_metadata(meta.name, dict(meta.metadata))
        writer.finish()
    return n


def describe(salvage: Salvage) -> str:
    """One sentence on what was damaged and lost, or '' for an intact file."""
    parts: list[str] = []
    if salvage.damaged_regions:
        parts.append(
            f"{salvage.damaged_regions} damaged region(s), {salvage.skipped_bytes} bytes skipped"
        )
    if salvage.damaged_chunks:
        parts.append(f"{salvage.damaged_chunks} chunk(s) failed their CRC")
    lost = salvage.lost_per_topic()
    if lost:
        parts.append(
            "messages lost: " + ", ".join(f"{n} on {topic}" for topic, n in sorted(lost.items()))
        )
    return "; ".join(parts)


def message_dict(data: bytes) -> Any:
    return json.loads(data)
