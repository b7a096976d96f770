"""The decoder's fast paths against its plain path, on random mixed and damaged streams.

Fast paths: the lean loop ``feed`` runs for a short chunk, the inline fixed-length frame
(table look-up, whole-body struct, CRC), the whole-chunk run of one message, and the
garbage collection paused for a long chunk; and the C accelerator (``_cdecode``), which
scans a whole chunk and builds its intact fixed-length frames' messages. The plain path has
them all off: every frame goes through ``decode_body``. Whatever the bytes and the
chunking, all must give the same messages, the same counters, the same last seq and the
same pending bytes.
"""

from __future__ import annotations

import binascii
import dataclasses
import gc
import os
import struct
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import pytest
from cobs import cobs
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from obstacle_fusion.protocol import StreamDecoder, encode, stream
from obstacle_fusion.protocol.generated import MESSAGES, Heartbeat, Hello, Message, Range

pytestmark = pytest.mark.cpu_only

_INT_RANGES = {
    "B": (0, 0xFF),
    "H": (0, 0xFFFF),
    "I": (0, 0xFFFFFFFF),
    "b": (-0x80, 0x7F),
    "h": (-0x8000, 0x7FFF),
    "i": (-0x80000000, 0x7FFFFFFF),
}


def _message_strategy(cls: type[Message]) -> st.SearchStrategy[Message]:
    values = [st.integers(*_INT_RANGES[code]) for code in cls.STRUCT.format.lstrip("<")]
    if cls.TEXT_FIELD is not None:
        values.append(
            st.text(
                st.characters(min_codepoint=32, max_codepoint=126),
                max_size=cls.MAX_LEN - cls.MIN_LEN,
            )
        )
    return st.tuples(*values).map(lambda v: cls(*v))


# Every message the spec knows (both directions: the decoder takes any known id).
any_message = st.one_of(*[_message_strategy(cls) for cls in MESSAGES.values()])

# What can happen to a frame on the wire: 0 none, 1 a byte flipped (maybe into 0x00),
# 2 a byte lost, 3 a 0x00 inserted, 4 a byte turned into 0xFF, 5 cut short, 6 lost whole.
damage = st.tuples(st.sampled_from([0, 0, 0, 0, 1, 2, 3, 4, 5, 6]), st.integers(0, 60))

item = st.one_of(
    # one frame, its seq advanced by 1 (or by more: frames lost before it; 0: seq repeated)
    st.tuples(st.just("frame"), any_message, st.sampled_from([1, 1, 1, 2, 7, 0, 130]), damage),
    # a run of one fixed-length message (the whole-chunk path), a few frames damaged
    st.tuples(
        st.just("run"),
        st.sampled_from(["range", "heartbeat"]),
        st.integers(1, 40),
        st.lists(st.tuples(st.integers(0, 39), damage), max_size=3),
    ),
    # line noise: random bytes (0x00 included), a run of 0x00, a run longer than any frame
    st.tuples(st.just("noise"), st.binary(max_size=30)),
    st.tuples(st.just("zeros"), st.integers(1, 5)),
    st.tuples(st.just("long"), st.integers(54, 300), st.integers(1, 255)),
)


def _damaged(frame: bytes, how: int, at: int) -> bytes:
    if how == 0 or len(frame) < 2:  # undamaged, or already lost or cut to its delimiter
        return frame
    if how == 6:
        return b""
    out = bytearray(frame)
    pos = at % (len(out) - 1)  # never the delimiter itself
    if how == 1:
        out[pos] ^= 0x5A
    elif how == 2:
        del out[pos]
    elif how == 3:
        out.insert(pos, 0)
    elif how == 4:
        out[pos] = 0xFF
    else:
        del out[pos:-1]
    return bytes(out)


def build_stream(items: list[Any], first_seq: int) -> bytes:
    out = bytearray()
    seq = first_seq
    for entry in items:
        kind = entry[0]
        if kind == "frame":
            _, msg, step, (how, at) = entry
            seq = 0 if isinstance(msg, Hello) else (seq + step) & 0xFF
            out += _damaged(encode(msg, seq), how, at)
        elif kind == "run":
            _, which, count, hurts = entry
            frames = []
            for i in range(count):
                seq = (seq + 1) & 0xFF
                if which == "range":
                    msg: Message = Range(
                        measurement=i,
                        sensor_id=i % 4,
                        trigger_us=60_000 * i,
                        echo_ticks=4000 + 7 * i,
                        status=i % 4,
                    )
                else:
                    msg = Heartbeat(
                        uptime_ms=1000 * i,
                        frames_sent=3 * i,
                        rx_errors=0,
                        tx_overruns=i % 2,
                        state=1,
                    )
                frames.append(encode(msg, seq))
            for index, (how, at) in hurts:
                frames[index % count] = _damaged(frames[index % count], how, at)
            out += b"".join(frames)
        elif kind == "noise":
            out += entry[1]
        elif kind == "zeros":
            out += bytes(entry[1])
        else:
            out += bytes([entry[2]]) * entry[1]
    return bytes(out)


@contextmanager
def plain_path() -> Iterator[None]:
    """Every fast path off: no fixed-length table, no whole-chunk run, no GC pause."""
    saved = stream._FAST, stream.RUN_MIN_FRAMES, stream.PAUSE_GC_FRAMES
    stream._FAST = [None] * 256
    stream.RUN_MIN_FRAMES = stream.PAUSE_GC_FRAMES = 10**9
    try:
        yield
    finally:
        stream._FAST, stream.RUN_MIN_FRAMES, stream.PAUSE_GC_FRAMES = saved


def pieces_of(data: bytes, size: int) -> list[bytes]:
    return [data[i : i + size] for i in range(0, len(data), size)]


def _cdecode() -> Any:
    """The C accelerator module; the tests fail (never skip) when it was not built."""
    assert stream.ACCELERATOR is not None, "the C accelerator is not built (make setup)"
    from obstacle_fusion.protocol import _cdecode

    return _cdecode


def decode(
    pieces: list[bytes], last_seq: int | None, accelerated: bool = False
) -> tuple[list[Message], dict[str, int], int | None, int]:
    decoder = StreamDecoder(accelerated=accelerated)
    decoder.last_seq = last_seq
    out: list[Message] = []
    for piece in pieces:
        out += decoder.feed(piece)
    return out, decoder.stats.as_dict(), decoder.last_seq, decoder.pending_bytes


def cut(data: bytes, cuts: list[int]) -> list[bytes]:
    points = sorted({c % (len(data) + 1) for c in cuts})
    return [data[a:b] for a, b in zip([0, *points], [*points, len(data)], strict=True)]


@settings(suppress_health_check=[HealthCheck.too_slow], max_examples=120, deadline=None)
@given(
    st.lists(item, min_size=1, max_size=30),
    st.integers(0, 255),
    st.sampled_from([None, 0, 254]),
    st.lists(st.integers(0, 5000), max_size=6),
)
def test_fast_paths_decode_exactly_as_the_plain_path(
    items: list[Any], first_seq: int, last_seq: int | None, cuts: list[int]
) -> None:
    data = build_stream(items, first_seq)
    with plain_path():
        expected = decode(pieces_of(data, 1), last_seq)
        assert decode([data], last_seq) == expected  # the plain path ignores chunking too
    assert expected[1]["bytes"] == len(data)
    for size in (1, 3, 20, 64, 1024, 65536):
        for accelerated in (False, True):
            assert decode(pieces_of(data, size), last_seq, accelerated) == expected, size
    for accelerated in (False, True):
        assert decode(cut(data, cuts), last_seq, accelerated) == expected


def _mutated(data: bytes, edits: list[tuple[int, int, int]]) -> bytes:
    """``data`` with each edit (where, what, byte) applied: 0 set the byte, 1 insert it,
    2 delete one, 3 insert a run of it."""
    out = bytearray(data)
    for where, what, byte in edits:
        at = where % (len(out) + 1)
        if what == 0 and at < len(out):
            out[at] = byte
        elif what == 1:
            out.insert(at, byte)
        elif what == 2 and at < len(out):
            del out[at]
        elif what == 3:
            out[at:at] = bytes([byte]) * (byte % 97)
    return bytes(out)


def _assert_paths_agree(data: bytes, pieces: list[bytes], last_seq: int | None) -> None:
    """The C accelerator and the pure-Python fast paths give the plain path's messages,
    counters (every one of them), last seq and pending bytes, for these pieces."""
    with plain_path():
        expected = decode(pieces_of(data, 1), last_seq)
    for accelerated in (False, True):
        got = decode(pieces, last_seq, accelerated)
        assert got[0] == expected[0], accelerated
        assert got[1] == expected[1], (accelerated, got[1], expected[1])
        assert got[2:] == expected[2:], accelerated


@settings(suppress_health_check=[HealthCheck.too_slow], max_examples=150, deadline=None)
@given(
    st.lists(item, max_size=25),
    st.lists(
        st.tuples(
            st.integers(0, 10_000),
            st.integers(0, 3),
            st.sampled_from([0, 0, 1, 2, 0xFF, 0xFE, 0x13, 0x02]) | st.integers(0, 255),
        ),
        max_size=8,
    ),
    st.sampled_from([None, 0, 37]),
    st.lists(st.integers(0, 10_000), max_size=12),
)
def test_the_c_accelerator_decodes_mutated_streams_as_python(
    items: list[Any], edits: list[tuple[int, int, int]], last_seq: int | None, cuts: list[int]
) -> None:
    data = _mutated(build_stream(items, 0), edits)
    _assert_paths_agree(data, cut(data, cuts), last_seq)


@settings(suppress_health_check=[HealthCheck.too_slow], max_examples=150, deadline=None)
@given(
    st.binary(max_size=400)
    | st.lists(
        st.sampled_from(
            [
                b"\x00",
                b"\x00" * 3,
                b"\x01",
                b"\xff",
                b"\x02\x02",
                b"\x13\x02\x05",
                bytes(range(1, 60)),
                b"\xff" * 60,
            ]
        ),
        max_size=40,
    ).map(b"".join),
    st.sampled_from([None, 0, 254]),
    st.lists(st.integers(0, 10_000), max_size=12),
)
def test_the_c_accelerator_decodes_random_bytes_as_python(
    data: bytes, last_seq: int | None, cuts: list[int]
) -> None:
    _assert_paths_agree(data, cut(data, cuts), last_seq)
    _assert_paths_agree(data, pieces_of(data, 7), last_seq)


@settings(max_examples=400, deadline=None)
@given(
    st.binary(max_size=255)
    | st.lists(
        st.sampled_from(
            [
                b"\x01",
                b"\x02x",
                b"\xffy",
                b"\x03ab",
                b"\xfe",
                b"\xfe" + b"w" * 253,
                b"\xff" + b"z" * 254,
            ]
        ),
        max_size=6,
    )
    .map(b"".join)
    .map(lambda b: b[:255]),
    st.integers(0, 0xFFFF),
)
def test_the_c_cobs_and_crc_are_the_cobs_packages_and_binascii(data: bytes, seed: int) -> None:
    """The C COBS decoder accepts and gives what the cobs package does; it reads nothing
    past its buffer (given a view of the first bytes of a longer one)."""
    c = _cdecode()
    try:
        want: bytes | None = bytes(cobs.decode(data))
    except cobs.DecodeError:
        want = None
    try:
        got: bytes | None = c.cobs_decode(memoryview(data + b"\x07\x07")[: len(data)])
    except ValueError:
        got = None
    assert got == want
    assert c.crc16(data, seed) == binascii.crc_hqx(data, seed)


def test_the_accelerator_is_the_default_and_builds_every_fixed_frame_itself() -> None:
    """A clean chunk of RANGE goes through the C scan alone: no frame-by-frame step (_one),
    no decode_body; a HELLO (left to Python) goes through _one."""
    _cdecode()
    decoder = StreamDecoder()
    assert decoder.accelerated and not StreamDecoder(accelerated=False).accelerated
    frames = b"".join(
        encode(
            Range(measurement=i, sensor_id=1, trigger_us=7 * i, echo_ticks=i, status=i % 4),
            (i + 3) & 0xFF,
        )
        for i in range(300)
    )
    scans: list[int] = []
    ones: list[bytes] = []
    real_scan, real_one = decoder._scan, decoder._one

    def scan_spy(data: bytes, last: int | None) -> Any:
        scans.append(len(data))
        return real_scan(data, last)  # type: ignore[misc]

    def one_spy(part: bytes) -> Any:
        ones.append(part)
        return real_one(part)

    decoder._scan = scan_spy
    decoder._one = one_spy  # type: ignore[method-assign]
    got = decoder.feed(frames[:4010]) + decoder.feed(frames[4010:])
    assert got == [
        Range(measurement=i, sensor_id=1, trigger_us=7 * i, echo_ticks=i, status=i % 4)
        for i in range(300)
    ]
    assert scans == [4010, len(frames) - 4000] and ones == []  # the 10 pending bytes again
    assert decoder.last_seq == (299 + 3) & 0xFF and decoder.stats.frames == 300
    hello = encode(
        Hello(
            protocol_version=1,
            schema_fingerprint=2,
            fw_major=0,
            fw_minor=1,
            fw_patch=2,
            board=0,
            cpu_hz=16_000_000,
            timer_hz=2_000_000,
            sensor_count=1,
        ),
        0,
    )
    assert len(decoder.feed(hello)) == 1 and ones == [hello[:-1]]


def test_the_environment_variable_makes_pure_python_the_default() -> None:
    _cdecode()
    code = (
        "from obstacle_fusion.protocol import StreamDecoder, stream; "
        "print(StreamDecoder().accelerated, stream.ACCELERATOR is not None)"
    )
    env = {k: v for k, v in os.environ.items() if k != stream.PURE_PYTHON_ENV}
    for value, expected in ((None, "True True"), ("1", "False True"), ("0", "True True")):
        if value is not None:
            env[stream.PURE_PYTHON_ENV] = value
        done = subprocess.run(
            [sys.executable, "-c", code],
            env=env,
            capture_output=True,
            text=True,
            timeout=60,
            check=True,
        )
        assert done.stdout.split() == expected.split(), value


def test_without_the_module_the_decoder_runs_pure_python_and_says_so() -> None:
    """An install whose extension failed to compile: the import fails, a debug note says
    so, the decoder runs its pure path, and accelerated=True is refused."""
    code = """
import logging, sys
class Block:
    def find_spec(self, name, path=None, target=None):
        if name == "obstacle_fusion.protocol._cdecode":
            raise ImportError("blocked for the test")
sys.meta_path.insert(0, Block())
logging.basicConfig(level=logging.DEBUG, format="%(name)s %(message)s")
from obstacle_fusion.protocol import StreamDecoder, encode
from obstacle_fusion.protocol.generated import Range
d = StreamDecoder()
msg = Range(measurement=1, sensor_id=0, trigger_us=2, echo_ticks=3, status=0)
assert d.feed(encode(msg, 5) * 20) == [msg] * 20 and not d.accelerated
try:
    StreamDecoder(accelerated=True)
except RuntimeError as exc:
    print("refused:", exc)
"""
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=True
    )
    assert "obstacle_fusion.protocol.stream stream decoder: no C accelerator" in done.stderr
    assert "refused: the stream decoder's C accelerator is not built" in done.stdout


def test_the_fast_paths_are_taken_and_the_plain_path_is_not() -> None:
    """The comparison above means something only if the fast paths ran: a clean run of
    RANGE goes whole, a short chunk is decoded by the lean loop without decode_body, and
    the plain path sends every frame through decode_body."""
    frames = b"".join(
        encode(Range(measurement=i, sensor_id=0, trigger_us=i, echo_ticks=i, status=0), i)
        for i in range(40)
    )
    calls: list[int] = []
    real_run = StreamDecoder._decode_run
    real_body = stream.decode_body

    def run_spy(self: StreamDecoder, *args: Any) -> Any:
        got = real_run(self, *args)
        calls.append(-1 if got is None else len(got))
        return got

    def body_spy(body: bytes) -> Message:
        calls.append(0)
        return real_body(body)

    saved = StreamDecoder._decode_run, stream.decode_body
    StreamDecoder._decode_run = run_spy  # type: ignore[method-assign]
    stream.decode_body = body_spy
    try:
        decoder = StreamDecoder(accelerated=False)
        assert len(decoder.feed(frames)) == 40 and calls == [40]  # one whole-chunk run
        calls.clear()
        assert len(decoder.feed(frames[:60])) == 3 and calls == []  # lean loop, inline
        with plain_path():
            calls.clear()
            assert len(StreamDecoder(accelerated=False).feed(frames)) == 40
            assert calls == [0] * 40
    finally:
        StreamDecoder._decode_run, stream.decode_body = saved


class _RecordingGC:
    """Stands for the gc module in stream: records what the decoder asks of it."""

    def __init__(self, enabled: bool) -> None:
        self.enabled = enabled
        self.calls: list[str] = []

    def isenabled(self) -> bool:
        self.calls.append("isenabled")
        return self.enabled

    def disable(self) -> None:
        self.calls.append("disable")
        self.enabled = False

    def enable(self) -> None:
        self.calls.append("enable")
        self.enabled = True


def test_a_long_chunk_pauses_the_gc_and_restores_it(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    frames = [
        encode(Range(measurement=i, sensor_id=0, trigger_us=i, echo_ticks=i, status=0), i)
        for i in range(40)
    ]
    fake = _RecordingGC(enabled=True)
    monkeypatch.setattr(stream, "gc", fake)
    decoder = StreamDecoder(accelerated=False)
    assert len(decoder.feed(b"".join(frames))) == 40
    assert fake.calls == ["isenabled", "disable", "enable"] and fake.enabled
    fake.calls.clear()
    assert len(decoder.feed(b"".join(frames[:7]))) == 7  # fewer than PAUSE_GC_FRAMES
    assert fake.calls == []
    assert len(decoder.feed(b"\x01" * 500 + b"".join(frames[:8]))) == 8  # general path, paused
    assert fake.calls == ["isenabled", "disable", "enable"] and fake.enabled
    fake = _RecordingGC(enabled=False)  # collection off: left off
    monkeypatch.setattr(stream, "gc", fake)
    assert len(decoder.feed(b"".join(frames))) == 40
    assert fake.calls == ["isenabled"] and not fake.enabled


@pytest.mark.parametrize("accelerated", [False, True])
def test_no_collection_runs_while_a_long_chunk_is_decoded(accelerated: bool) -> None:
    """With a collection due at every other allocation, 32 frames in one chunk are decoded
    with at most the few collections before and after the pause, the same frames in chunks
    of 4 (no pause) with one at least every other message; the collection is on after."""
    if accelerated:
        _cdecode()
    frames = [
        encode(Range(measurement=i, sensor_id=0, trigger_us=i, echo_ticks=i, status=0), i)
        for i in range(65)
    ]
    decoder = StreamDecoder(accelerated=accelerated)
    decoder.feed(frames[0])
    runs: list[str] = []

    def seen(phase: str, info: dict[str, int]) -> None:
        if phase == "start":
            runs.append(phase)

    threshold = gc.get_threshold()
    gc.callbacks.append(seen)
    gc.set_threshold(1)
    try:
        assert len(decoder.feed(b"".join(frames[1:33]))) == 32
        paused = len(runs)
        for first in range(33, 65, 4):
            assert len(decoder.feed(b"".join(frames[first : first + 4]))) == 4
        unpaused = len(runs) - paused
    finally:
        gc.set_threshold(*threshold)
        gc.callbacks.remove(seen)
    assert gc.isenabled() and decoder.stats.frames == 65
    assert paused <= 3 and unpaused >= 16, (paused, unpaused)


@dataclasses.dataclass(slots=True)
class _EveryCode:
    """A message with a field of each struct code the accelerator reads (the spec's fixed
    messages use only unsigned ones)."""

    s8: int
    s16: int
    s32: int
    u8: int
    u16: int
    u32: int


@settings(max_examples=60, deadline=None)
@given(
    st.tuples(*[st.integers(*_INT_RANGES[code]) for code in "bhiBHI"]),
    st.sampled_from([None, 0, 200]),
)
def test_the_c_accelerator_reads_every_field_code(
    values: tuple[int, ...], last_seq: int | None
) -> None:
    c = _cdecode()
    seed = 0x1D0F
    slots = tuple(getattr(_EveryCode, f.name) for f in dataclasses.fields(_EveryCode))
    body = bytes((0xEE, 9)) + struct.pack("<bhiBHI", *values)
    frame = bytes(cobs.encode(body + binascii.crc_hqx(body, seed).to_bytes(2, "big"))) + b"\0"
    try:
        c.configure([(0xEE, _EveryCode, b"bhiBHI", slots, seed)], stream.LONGEST_RUN, 8)
        got = c.scan(frame * 3 + b"\x05", last_seq)
        with pytest.raises(ValueError):  # a code it cannot read
            c.configure([(0xEE, _EveryCode, b"bhiBHq", slots, seed)], stream.LONGEST_RUN, 8)
        with pytest.raises(ValueError):  # a body longer than any frame
            c.configure([(0xEE, _EveryCode, b"bhiBHI", slots, seed)], 10, 8)
    finally:
        c.configure(stream._accelerated_entries(), stream.LONGEST_RUN, stream.PAUSE_GC_FRAMES)
    gaps = (0 if last_seq is None else (9 - last_seq - 1) & 0xFF) + 2 * 255  # seq 9 repeated
    assert got == ([_EveryCode(*values)] * 3, b"\x05", 9, 3, gaps, 0, None)


@pytest.mark.parametrize(
    "data",
    [
        b"",
        b"\x01",
        b"\x01\x01",
        b"\x02",
        b"\x03a",
        b"\x02a\x01",
        b"\x05abcd\x02e",
        b"\xfe" + b"w" * 253 + b"\x01",  # a 253-byte block: a 0x00 follows it
        b"\xff" + b"z" * 254,  # a 254-byte block: no 0x00 after it (nothing may follow here)
        b"\xff" + b"z" * 253,
        b"\xfe" + b"w" * 252,  # one byte short
    ],
)
def test_the_c_cobs_edge_cases(data: bytes) -> None:
    try:
        want: bytes | None = bytes(cobs.decode(data))
    except cobs.DecodeError:
        want = None
    try:
        got: bytes | None = _cdecode().cobs_decode(data)
    except ValueError:
        got = None
    assert got == want


def test_the_c_scan_pauses_the_collection_from_pause_gc_frames_on() -> None:
    """Inside the C scan, with a collection due at every other allocation: none while a
    chunk of PAUSE_GC_FRAMES frames is scanned, some in a chunk of one frame fewer."""
    _cdecode()
    n = stream.PAUSE_GC_FRAMES
    frames = [
        encode(Range(measurement=i, sensor_id=0, trigger_us=i, echo_ticks=i, status=0), i)
        for i in range(2 * n)
    ]
    decoder = StreamDecoder(accelerated=True)
    runs: list[int] = []
    inside: list[int] = []
    real_scan = decoder._scan

    def scan_spy(data: bytes, last: int | None) -> Any:
        before = len(runs)
        got = real_scan(data, last)  # type: ignore[misc]
        inside.append(len(runs) - before)
        return got

    def seen(phase: str, info: dict[str, int]) -> None:
        if phase == "start":
            runs.append(1)

    decoder._scan = scan_spy
    threshold = gc.get_threshold()
    gc.callbacks.append(seen)
    gc.set_threshold(1)
    try:
        assert len(decoder.feed(b"".join(frames[:n]))) == n
        assert len(decoder.feed(b"".join(frames[n : 2 * n - 1]))) == n - 1
    finally:
        gc.set_threshold(*threshold)
        gc.callbacks.remove(seen)
    assert gc.isenabled()
    assert inside[0] == 0 and inside[1] > 0, inside
