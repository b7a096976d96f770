"""Streaming decoder: arbitrary byte chunks in, messages out, never an exception.

Frames end at 0x00. A frame that fails (COBS, CRC, id, length) is counted and dropped;
its bytes are then searched for an intact frame at its end, which recovers a good frame
that arrived right after line noise without a delimiter in between.

Every byte fed ends up in exactly one place: a good frame (its bytes and delimiter), the
pending tail (``pending_bytes``), or ``bytes_discarded``. A run longer than the longest
frame is ``oversized`` however it was chunked, and a 0x00 with no frame before it is a
``stray_zeros``.

The common case (an intact fixed-length frame) runs inline in ``feed``: one COBS decode,
one table look-up, one CRC, one struct unpack and the message's constructor per frame.
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
# The longest run of bytes that can be a frame: a frame without its 0x00 delimiter.
LONGEST_RUN = MAX_FRAME - 1
_FastEntry = tuple[type, int, object, int]
# Fixed-length messages decode on the fast path, indexed by message id:
# (class, body length, struct unpacker, CRC seed), None for the other ids.
_FAST: list[_FastEntry | None] = [None] * 256
for _msg_id, _cls in MESSAGES.items():
    if _cls.TEXT_FIELD is None:
        _FAST[_msg_id] = (_cls, _cls.MIN_LEN + 4, _cls.STRUCT.unpack_from, CRC_SEEDS[_msg_id])
_HELLO_ID = Hello.MSG_ID


@dataclass(slots=True)
class DecoderStats:
    """What the decoder has seen; every dropped byte is in ``bytes_discarded``, and every
    dropped frame in one of the frame counters."""

    frames: int = 0  # good frames decoded
    bytes: int = 0  # bytes fed
    crc_errors: int = 0
    cobs_errors: int = 0
    unknown_ids: int = 0
    bad_lengths: int = 0
    truncated: int = 0  # frames shorter than header + CRC
    oversized: int = 0  # runs longer than the longest frame, however they were chunked
    seq_gaps: int = 0  # frames lost, from the device's sequence numbers
    resyncs: int = 0  # good frames recovered from behind line noise
    stray_zeros: int = 0  # 0x00 bytes with no frame before them (runs of delimiters)
    bytes_discarded: int = 0  # every byte that is in no good frame and not pending

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
        # The pending tail lost its beginning (the run was longer than any frame).
        self._overflow = False

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
        out: list[Message] = []
        if parts and self._overflow:
            # The run that overflowed ends here: the first part is the end of it.
            self._overflow = False
            msg = self._bad_run(parts[0], len(parts[0]) - LONGEST_RUN, "oversized")
            if msg is not None:
                out.append(msg)
            del parts[0]
        if len(tail) > LONGEST_RUN:
            # Only the last LONGEST_RUN bytes can still become (the end of) a frame.
            stats.bytes_discarded += len(tail) - LONGEST_RUN
            tail = tail[-LONGEST_RUN:]
            self._overflow = True
        self._tail = tail
        append = out.append
        fast = _FAST
        crc = _crc
        cobs_decode = _cobs_decode
        last = self.last_seq
        gaps = 0
        good = 0
        zeros = 0
        for part in parts:
            if not part:
                zeros += 1
                continue
            body = None
            if len(part) <= LONGEST_RUN:
                try:
                    body = cobs_decode(part)
                except _CobsError:
                    pass
                else:
                    entry = fast[body[0]] if body else None
                    if entry is not None and len(body) == entry[1] and not crc(body, entry[3]):
                        append(entry[0](*entry[2](body, 2)))  # type: ignore[operator]
                        seq = body[1]
                        if last is not None and body[0] != _HELLO_ID:
                            gaps += (seq - last - 1) & 0xFF
                        last = seq
                        good += 1
                        continue
            self.last_seq = last
            stats.seq_gaps += gaps
            stats.frames += good
            gaps = good = 0
            if body is None and len(part) > LONGEST_RUN:
                msg = self._bad_run(part, len(part) - LONGEST_RUN, "oversized")
            else:
                msg = self._slow_path(part, body)
            last = self.last_seq
            if msg is not None:
                append(msg)
        self.last_seq = last
        stats.seq_gaps += gaps
        stats.frames += good
        if zeros:
            stats.stray_zeros += zeros
            stats.bytes_discarded += zeros
        return out

    def _count_seq(self, msg_id: int, seq: int) -> None:
        last = self.last_seq
        if last is not None and msg_id != _HELLO_ID:
            self.stats.seq_gaps += (seq - last - 1) & 0xFF
        self.last_seq = seq

    def _slow_path(self, part: bytes, body: bytes | None) -> Message | None:
        """Decode a frame the fast path refused, or count why it is bad."""
        try:
            if body is None:
                raise FrameError("cobs_errors", "bad COBS encoding")
            msg = decode_body(bytes(body))
        except FrameError as exc:
            return self._bad_run(part, 1, exc.kind)
        self._count_seq(body[0], body[1])
        self.stats.frames += 1
        return msg

    def _bad_run(self, part: bytes, first: int, kind: str) -> Message | None:
        """A run that is no frame (ended by its delimiter): recover an intact frame at its
        end (noise before the frame's first byte), else count it under ``kind``."""
        stats = self.stats
        recovered = self._resync(part, max(first, 0))
        if recovered is not None:
            return recovered
        setattr(stats, kind, getattr(stats, kind) + 1)
        stats.bytes_discarded += len(part) + 1
        return None

    def _resync(self, part: bytes, first: int) -> Message | None:
        """Find an intact frame starting at or after ``first`` that ends the run."""
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
