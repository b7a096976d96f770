"""Streaming decoder: arbitrary byte chunks in, messages out, never an exception.

Frames end at 0x00. A frame that fails (COBS, CRC, id, length) is counted and dropped;
its bytes are then searched for an intact frame at its end, which recovers a good frame
that arrived right after line noise without a delimiter in between.

Every byte fed ends up in exactly one place: a good frame (its bytes and delimiter), the
pending tail (``pending_bytes``), or ``bytes_discarded``. A run longer than the longest
frame is ``oversized`` however it was chunked, and a 0x00 with no frame before it is a
``stray_zeros``.

Fast paths decode the common cases with the results and counters of the general path:
they accept only frames it would accept, and hand everything else to it.

* A chunk whose frames are all one fixed-length message (a run of RANGE) is decoded whole:
  every delimiter's place checked by one strided slice, the frames' COBS by one ``map``,
  each frame's own CRC by one ``map``, the ids and sequence numbers by strided slices, and
  the messages built by ``Struct.iter_unpack``: no Python-level step per frame.
* Otherwise an intact fixed-length frame runs inline: one COBS decode, one table look-up,
  one struct unpack (which checks the length), one CRC and the message's constructor. A
  short chunk (fewer than RUN_MIN_FRAMES frames, nothing overflowed, a seq to count from)
  takes a lean copy of that loop straight in ``feed``; the rest goes to ``_feed_parts``.
* A chunk of PAUSE_GC_FRAMES frames or more is decoded with the automatic garbage
  collection paused: its messages live until it returns them, so a collection could free
  none of them. Every message is built in full (no field decoded later on access).

The optional C accelerator (``_cdecode.c``, built with the package; see setup.py) does the
fast path's work for a whole chunk in C: it finds the delimiters, COBS-decodes each run,
checks its CRC and length, makes the message of every intact fixed-length frame (the
class's ``tp_new`` and its slot descriptors: what the dataclass ``__init__`` does, without a
Python call) and counts their sequence gaps, pausing the collection as above. Every other
run comes back as bytes in its place, and goes through the same frame-by-frame step as in
Python (``_one``), after which the frames that follow it count their gap from its seq; a
chunk after an overflowed run takes the Python path. Both paths give the same messages and
counters for any bytes and any chunking. Without the module (it did not compile), or with
OBSTACLE_FUSION_PURE_PYTHON=1, the pure-Python paths run.
"""

from __future__ import annotations

import binascii
import dataclasses
import gc
import logging
import os
import struct
import types
from collections.abc import Callable
from dataclasses import asdict, dataclass
from itertools import repeat, starmap
from typing import Any

from cobs import cobs

from obstacle_fusion.protocol.codec import CRC_SEEDS, FrameError, decode_body
from obstacle_fusion.protocol.generated import MAX_FRAME, MESSAGES, Hello, Message

log = logging.getLogger(__name__)
_crc = binascii.crc_hqx
_cobs_decode = cobs.decode
_CobsError = cobs.DecodeError
# The longest run of bytes that can be a frame: a frame without its 0x00 delimiter.
LONGEST_RUN = MAX_FRAME - 1
# The shortest run that can be a frame: id, seq and CRC behind one COBS code byte.
_SHORTEST_RUN = 5
_HELLO_ID = Hello.MSG_ID
_FastEntry = tuple[Callable[..., Message], Callable[[bytes], tuple[Any, ...]], int]
# Fixed-length messages but HELLO (whose seq starts a new count) decode on the fast path,
# indexed by message id: (class, unpacker of a whole body that skips its id, seq and CRC
# and raises struct.error for any other length, CRC seed); None otherwise.
_FAST: list[_FastEntry | None] = [None] * 256
_RunEntry = tuple[Callable[..., Message], int, int, struct.Struct]
# The same messages decoded a chunk at a time: (class, body length, CRC seed, a Struct over
# a whole body that skips its id, seq and CRC).
_RUN: list[_RunEntry | None] = [None] * 256
for _msg_id, _cls in MESSAGES.items():
    if _cls.TEXT_FIELD is None and _msg_id != _HELLO_ID:
        _row = struct.Struct("<xx" + _cls.STRUCT.format.lstrip("<") + "xx")
        _FAST[_msg_id] = (_cls, _row.unpack, CRC_SEEDS[_msg_id])
        _RUN[_msg_id] = (_cls, _row.size, CRC_SEEDS[_msg_id], _row)
# Setting this variable (to anything but "" or "0") makes pure Python the default path.
PURE_PYTHON_ENV = "OBSTACLE_FUSION_PURE_PYTHON"
_Scan = Callable[[bytes, int | None], tuple[Any, ...]]


def _accelerated_entries() -> list[tuple[int, type, bytes, tuple[Any, ...], int]]:
    """The C accelerator's table: (msg id, class, struct codes, slot descriptors, CRC seed)
    for the messages of the fast path whose dataclass ``__init__`` only sets its fields (so
    a message made by ``tp_new`` and the slots equals the one ``__init__`` makes)."""
    entries = []
    for msg_id, entry in enumerate(_RUN):
        if entry is None:
            continue
        cls = MESSAGES[msg_id]
        codes = cls.STRUCT.format.lstrip("<")
        fields = dataclasses.fields(cls)
        slots = tuple(getattr(cls, f.name) for f in fields)
        if (
            hasattr(cls, "__post_init__")
            or len(fields) != len(codes)
            or not all(f.init for f in fields)
            or not all(isinstance(slot, types.MemberDescriptorType) for slot in slots)
            or set(codes) - set("BHIbhi")
        ):
            log.debug("stream decoder: %s is left to Python by the C accelerator", cls.__name__)
            continue
        entries.append((msg_id, cls, codes.encode("ascii"), slots, entry[2]))
    return entries


def _load_accelerator() -> _Scan | None:
    """The C accelerator's scan, configured with this module's table; None without it."""
    try:
        import obstacle_fusion.protocol._cdecode as _cdecode
    except ImportError as exc:
        log.debug("stream decoder: no C accelerator (%s); pure Python", exc)
        return None
    _cdecode.configure(_accelerated_entries(), LONGEST_RUN, PAUSE_GC_FRAMES)
    scan: _Scan = _cdecode.scan
    return scan


# A chunk with at least this many frames tries the whole-chunk path first.
RUN_MIN_FRAMES = 8
# A chunk with at least this many frames is decoded with the automatic garbage collection
# paused (it is restored before feed returns, and left alone if it was off).
PAUSE_GC_FRAMES = 8
# seq -> seq + 1 (mod 256): a run of sequence numbers has no gap when shifting all but its
# last by one gives all but its first.
_NEXT_SEQ = bytes((i + 1) & 0xFF for i in range(256))
# The accelerator, whether it is the default or not (tests run both side by side).
ACCELERATOR = _load_accelerator()
_DEFAULT_SCAN = ACCELERATOR if os.environ.get(PURE_PYTHON_ENV, "") in ("", "0") else None
if ACCELERATOR is not None and _DEFAULT_SCAN is None:
    log.debug("stream decoder: %s is set; pure Python", PURE_PYTHON_ENV)


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

    def __init__(self, accelerated: bool | None = None) -> None:
        """``accelerated``: None takes the C accelerator when it is there and not turned off
        by OBSTACLE_FUSION_PURE_PYTHON; False the pure-Python path; True the accelerator
        (RuntimeError if it was not built)."""
        self.stats = DecoderStats()
        self.last_seq: int | None = None
        self._tail = b""
        # The pending tail lost its beginning (the run was longer than any frame).
        self._overflow = False
        self._scan: _Scan | None
        if accelerated is None:
            self._scan = _DEFAULT_SCAN
        elif not accelerated:
            self._scan = None
        elif ACCELERATOR is None:
            raise RuntimeError("the stream decoder's C accelerator is not built")
        else:
            self._scan = ACCELERATOR

    @property
    def accelerated(self) -> bool:
        """Whether this decoder runs the C accelerator."""
        return self._scan is not None

    @property
    def pending_bytes(self) -> int:
        """Bytes of a frame whose delimiter has not arrived yet."""
        return len(self._tail)

    def feed(self, chunk: bytes) -> list[Message]:
        if self._scan is not None and not self._overflow:
            return self._feed_scan(chunk)
        stats = self.stats
        stats.bytes += len(chunk)
        data = self._tail + chunk if self._tail else bytes(chunk)
        parts = data.split(b"\x00")
        tail = parts.pop()
        last = self.last_seq
        if (
            len(parts) >= RUN_MIN_FRAMES
            or len(tail) > LONGEST_RUN
            or self._overflow
            or last is None
        ):
            if len(parts) < PAUSE_GC_FRAMES or not gc.isenabled():
                return self._feed_parts(data, parts, tail)
            # The messages of a chunk are all alive until it returns them: an automatic
            # collection while they are built could only walk them and move them to an
            # older generation (a fifth of the time of a 64 KiB chunk of RANGE). gc's
            # switch is process-wide: nothing else in the package turns it.
            gc.disable()
            try:
                return self._feed_parts(data, parts, tail)
            finally:
                gc.enable()
        # The common case of a short chunk: no run to try, nothing overflowed, a seq to
        # count from. Each frame is tried as an intact fixed-length frame (as in the
        # general path's loop); anything else goes to its frame-by-frame step (_one).
        self._tail = tail
        out: list[Message] = []
        append = out.append
        fast = _FAST
        gaps = 0
        others = 0  # messages that came from _one (it counts its own frames)
        zeros = 0
        for part in parts:
            try:
                body = _cobs_decode(part)
                cls, unpack, seed = fast[body[0]]  # type: ignore[misc]
                if not _crc(body, seed):
                    append(cls(*unpack(body)))  # a body of another length: struct.error
                    seq = body[1]
                    gaps += (seq - last - 1) & 0xFF  # type: ignore[operator]
                    last = seq
                    continue
            except (_CobsError, IndexError, TypeError, struct.error):
                # No COBS; an empty part (a 0x00 run); no fast entry; a wrong length.
                pass
            if not part:
                zeros += 1
                continue
            self.last_seq = last
            msg = self._one(part)
            last = self.last_seq
            if msg is not None:
                append(msg)
                others += 1
        self.last_seq = last
        if gaps:
            stats.seq_gaps += gaps
        stats.frames += len(out) - others
        if zeros:
            stats.stray_zeros += zeros
            stats.bytes_discarded += zeros
        return out

    def _feed_scan(self, chunk: bytes) -> list[Message]:
        """``feed`` through the C accelerator (nothing overflowed before this chunk)."""
        stats = self.stats
        stats.bytes += len(chunk)
        out, tail, last, good, gaps, zeros, others = self._scan(  # type: ignore[misc]
            self._tail + chunk if self._tail else bytes(chunk), self.last_seq
        )
        if len(tail) > LONGEST_RUN:
            # Only the last LONGEST_RUN bytes can still become (the end of) a frame.
            stats.bytes_discarded += len(tail) - LONGEST_RUN
            tail = tail[-LONGEST_RUN:]
            self._overflow = True
        self._tail = tail
        stats.frames += good
        if zeros:
            stats.stray_zeros += zeros
            stats.bytes_discarded += zeros
        if others is not None:
            # Runs that are no intact fixed-length frame, in their places in out: each goes
            # through the frame-by-frame step, then the frames after it count from its seq.
            for index, first, final, inner, count in others:
                self.last_seq = last
                out[index] = self._one(out[index])
                last = self.last_seq
                if count:
                    if last is not None:
                        gaps += (first - last - 1) & 0xFF
                    gaps += inner
                    last = final
            out = [msg for msg in out if msg is not None]
        self.last_seq = last
        if gaps:
            stats.seq_gaps += gaps
        return out  # type: ignore[no-any-return]

    def _feed_parts(self, data: bytes, parts: list[bytes], tail: bytes) -> list[Message]:
        """The general path: ``data`` split at its delimiters into ``parts`` and ``tail``."""
        stats = self.stats
        end = len(data) - len(tail)  # just after the last delimiter
        if len(tail) > LONGEST_RUN:
            # Only the last LONGEST_RUN bytes can still become (the end of) a frame.
            stats.bytes_discarded += len(tail) - LONGEST_RUN
            tail = tail[-LONGEST_RUN:]
            overflow = True
        else:
            overflow = False
        self._tail = tail
        if not parts:
            self._overflow |= overflow
            return []
        out: list[Message] = []
        start = 0  # where parts[0] begins in data
        if self._overflow:
            # The run that overflowed ends here: the first part is the end of it.
            first = parts.pop(0)
            start = len(first) + 1
            msg = self._bad_run(first, len(first) - LONGEST_RUN, "oversized")
            if msg is not None:
                out.append(msg)
        self._overflow = overflow
        if len(parts) >= RUN_MIN_FRAMES:
            run = self._decode_run(parts, data, start, end)
            if run is not None:
                if out:  # a frame recovered from the end of an overflowed run
                    out += run
                    return out
                return run
        append = out.append
        fast = _FAST
        crc = _crc
        cobs_decode = _cobs_decode
        last = self.last_seq
        gaps = 0
        good = 0
        zeros = 0
        for part in parts:
            if part:
                # A run too long for any frame decodes to a body too long for any entry.
                try:
                    body = cobs_decode(part)
                    cls, unpack, seed = fast[body[0]]  # type: ignore[misc]
                    if not crc(body, seed):
                        append(cls(*unpack(body)))
                        seq = body[1]
                        if last is not None:
                            gaps += (seq - last - 1) & 0xFF
                        last = seq
                        good += 1
                        continue
                except (_CobsError, IndexError, TypeError, struct.error):
                    pass
            else:
                zeros += 1
                continue
            self.last_seq = last
            msg = self._one(part)
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

    def _one(self, part: bytes) -> Message | None:
        """A run (not empty, ended by its delimiter) that is no intact fixed-length frame:
        decoded by the general decoder, or counted, or a frame recovered from its end."""
        if len(part) > LONGEST_RUN:
            return self._bad_run(part, len(part) - LONGEST_RUN, "oversized")
        decoded: bytes | None
        try:
            decoded = _cobs_decode(part)
        except _CobsError:
            decoded = None
        return self._slow_path(part, decoded)

    def _decode_run(
        self, parts: list[bytes], data: bytes, start: int, end: int
    ) -> list[Message] | None:
        """``parts`` (``data[start:end]`` split at its delimiters) decoded at once when they
        are all intact frames of one fixed-length message other than HELLO; else None, with
        nothing counted (the frame-by-frame path then decodes them)."""
        n = len(parts)
        width = len(parts[0])
        # Every part is ``width`` bytes long when the n delimiters fall every width + 1 bytes.
        if (
            not _SHORTEST_RUN <= width <= LONGEST_RUN
            or end - start != n * (width + 1)
            or data[start + width : end : width + 1].count(0) != n
        ):
            return None
        try:
            bodies = list(map(_cobs_decode, parts))
        except _CobsError:
            return None
        blob = b"".join(bodies)
        size = width - 1  # what COBS decodes a run this short to
        msg_id = blob[0]
        entry = _RUN[msg_id]
        if entry is None or entry[1] != size or len(blob) != n * size:
            return None
        cls, _, seed, row = entry
        if blob[::size].count(msg_id) != n or any(map(_crc, bodies, repeat(seed))):
            return None
        seqs = blob[1::size]
        last = self.last_seq
        gaps = 0 if last is None else (seqs[0] - last - 1) & 0xFF
        if seqs[:-1].translate(_NEXT_SEQ) != seqs[1:]:
            gaps += sum((b - a - 1) & 0xFF for a, b in zip(seqs[:-1], seqs[1:], strict=True))
        out: list[Message] = list(starmap(cls, row.iter_unpack(blob)))
        self.stats.seq_gaps += gaps
        self.stats.frames += n
        self.last_seq = seqs[-1]
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
