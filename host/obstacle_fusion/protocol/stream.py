"""Streaming decoder: arbitrary byte chunks in, messages out, never an exception.

Frames end at 0x00. A frame that fails (COBS, CRC, id, length) is counted and dropped;
its bytes are then searched for an intact frame at its end, which recovers a good frame
that arrived right after line noise without a delimiter in between.
"""

from __future__ import annotations

import binascii
from dataclasses import asdict, dataclass

from cobs import cobs

from obstacle_fusion.protocol.codec import CRC_SEEDS, FrameError, decode_body
from obstacle_fusion.protocol.generated import MAX_FRAME, MESSAGES, Hello, Message

_crc = binascii.crc_hqx
_cobs_decode = cobs.decode
_CobsError = cobs.DecodeError
# Fixed-length messages decode on the fast path: (class, body length, struct unpacker).
_FAST = {
    msg_id: (cls, cls.MIN_LEN + 4, cls.STRUCT.unpack_from)
    for msg_id, cls in MESSAGES.items()
    if cls.TEXT_FIELD is None
}
_HELLO_ID = Hello.MSG_ID


@dataclass(slots=True)
class DecoderStats:
    """What the decoder has seen; every dropped byte is in one of these counters."""

    frames: int = 0  # good frames decoded
    bytes: int = 0  # bytes fed
    crc_errors: int = 0
    cobs_errors: int = 0
    unknown_ids: int = 0
    bad_lengths: int = 0
    truncated: int = 0  # frames shorter than header + CRC
    oversized: int = 0  # frames longer than the longest message
    seq_gaps: int = 0  # frames lost, from the device's sequence numbers
    resyncs: int = 0  # good frames recovered from behind line noise
    bytes_discarded: int = 0

    @property
    def bad_frames(self) -> int:
        return (
            self.crc_errors
            + self.cobs_errors
            + self.unknown_ids
            + self.bad_lengths
            + self.truncated
            + self.oversized
        )

    def as_dict(self) -> dict[str, int]:
        return asdict(self)


class StreamDecoder:
    """Feed it bytes as they arrive; it returns the messages completed by each chunk."""

    def __init__(self) -> None:
        self.stats = DecoderStats()
        self.last_seq: int | None = None
        self._tail = b""

    @property
    def pending_bytes(self) -> int:
        """Bytes of a frame whose delimiter has not arrived yet."""
        return len(self._tail)

    def feed(self, chunk: bytes) -> list[Message]:
        stats = self.stats
        stats.bytes += len(chunk)
        data = self._tail + chunk if self._tail else bytes(chunk)
        parts = data.split(b"\x00")
        tail = parts.pop()
        if len(tail) > 2 * MAX_FRAME:
            # Only the last MAX_FRAME bytes can still become a frame.
            stats.bytes_discarded += len(tail) - MAX_FRAME
            tail = tail[-MAX_FRAME:]
        self._tail = tail
        out: list[Message] = []
        append = out.append
        fast = _FAST
        seeds = CRC_SEEDS
        for part in parts:
            if not part:
                continue
            try:
                body = _cobs_decode(part)
            except _CobsError:
                body = None
            if body is not None:
                entry = fast.get(body[0]) if body else None
                if (
                    entry is not None
                    and len(body) == entry[1]
                    and _crc(body, seeds[body[0]]) == 0
                ):
                    msg = entry[0](*entry[2](body, 2))
                    self._count_seq(body[0], body[1])
                    stats.frames += 1
                    append(msg)
                    continue
            recovered = self._slow_path(part, body)
            if recovered is not None:
                append(recovered)
        return out

    def _count_seq(self, msg_id: int, seq: int) -> None:
        last = self.last_seq
        if last is not None and msg_id != _HELLO_ID:
            self.stats.seq_gaps += (seq - last - 1) & 0xFF
        self.last_seq = seq

    def _slow_path(self, part: bytes, body: bytes | None) -> Message | None:
        """Decode a frame the fast path refused, or count why it is bad."""
        stats = self.stats
        try:
            if body is None:
                raise FrameError("cobs_errors", "bad COBS encoding")
            msg = decode_body(bytes(body))
        except FrameError as exc:
            recovered = self._resync(part)
            if recovered is not None:
                return recovered
            setattr(stats, exc.kind, getattr(stats, exc.kind) + 1)
            stats.bytes_discarded += len(part) + 1
            return None
        self._count_seq(body[0], body[1])
        stats.frames += 1
        return msg

    def _resync(self, part: bytes) -> Message | None:
        """Find an intact frame at the end of a bad one (noise before its first byte)."""
        first = max(1, len(part) - (MAX_FRAME - 1))
        for start in range(first, len(part) - 3):
            try:
                body = _cobs_decode(part[start:])
                msg = decode_body(bytes(body))
            except (_CobsError, FrameError):
                continue
            self.stats.resyncs += 1
            self.stats.bytes_discarded += start
            self._count_seq(body[0], body[1])
            self.stats.frames += 1
            return msg
        return None
