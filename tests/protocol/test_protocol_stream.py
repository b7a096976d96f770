"""StreamDecoder: arbitrary chunks, garbage, corruption; never raises, never invents."""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from obstacle_fusion.protocol import StreamDecoder, encode
from obstacle_fusion.protocol.generated import (
    Ack,
    Heartbeat,
    Log,
    Message,
    Range,
    TimeSyncReply,
)

u32 = st.integers(0, 0xFFFFFFFF)
u8 = st.integers(0, 0xFF)
messages = st.one_of(
    st.builds(Range, measurement=u32, sensor_id=st.integers(0, 3), trigger_us=u32,
              echo_ticks=u32, status=st.integers(0, 3)),
    st.builds(Heartbeat, uptime_ms=u32, frames_sent=u32, rx_errors=u32, tx_overruns=u32,
              state=st.integers(0, 1)),
    st.builds(TimeSyncReply, token=u32, rx_us=u32, tx_us=u32),
    st.builds(Ack, command_id=u8, command_seq=u8),
    st.builds(Log, level=st.integers(0, 3),
              text=st.text(alphabet=st.characters(min_codepoint=32, max_codepoint=126), max_size=40)),
)


def chunked(data: bytes, cuts: list[int]) -> list[bytes]:
    points = sorted({c % (len(data) + 1) for c in cuts})
    pieces, last = [], 0
    for p in points + [len(data)]:
        pieces.append(data[last:p])
        last = p
    return pieces


def feed_all(decoder: StreamDecoder, pieces: list[bytes]) -> list[Message]:
    out: list[Message] = []
    for piece in pieces:
        out.extend(decoder.feed(piece))
    return out


@given(st.binary(max_size=2000), st.lists(st.integers(0, 5000), max_size=20))
def test_never_raises_on_arbitrary_bytes(data: bytes, cuts: list[int]) -> None:
    decoder = StreamDecoder()
    feed_all(decoder, chunked(data, cuts))
    assert decoder.stats.bytes == len(data)


@settings(suppress_health_check=[HealthCheck.too_slow], max_examples=200)
@given(
    st.lists(st.tuples(messages, st.booleans(), st.binary(max_size=12), st.integers(0, 60)),
             min_size=1, max_size=25),
    st.lists(st.integers(0, 5000), max_size=10),
)
def test_recovers_every_intact_frame(items: list, cuts: list[int]) -> None:  # type: ignore[type-arg]
    """Frames, some corrupted, with garbage between them: every intact frame comes out,
    in order, and nothing comes out that was not sent."""
    stream = bytearray()
    sent: list[Message] = []
    intact: list[Message] = []
    for seq, (msg, corrupt, garbage, flip_at) in enumerate(items):
        frame = bytearray(encode(msg, seq & 0xFF))
        if corrupt:
            pos = flip_at % (len(frame) - 1)  # never the delimiter
            frame[pos] ^= 0x5A
        else:
            intact.append(msg)
        sent.append(msg)
        stream += garbage.replace(b"\x00", b"") + frame
    decoder = StreamDecoder()
    got = feed_all(decoder, chunked(bytes(stream), cuts))
    for msg in got:
        assert msg in sent
    # Every intact frame is recovered, in order (a subsequence of what came out).
    it = iter(got)
    assert all(any(m == g for g in it) for m in intact)


def test_counts_errors_and_gaps() -> None:
    frames = [encode(Ack(command_id=0x41, command_seq=i), i) for i in range(10)]
    bad = bytearray(frames[3])
    bad[2] ^= 0xFF
    frames[3] = bytes(bad)
    del frames[6]  # lost on the wire
    decoder = StreamDecoder()
    got = decoder.feed(b"".join(frames))
    assert [m.command_seq for m in got] == [0, 1, 2, 4, 5, 7, 8, 9]  # type: ignore[attr-defined]
    s = decoder.stats
    assert s.frames == 8
    assert s.bad_frames == 1
    assert s.seq_gaps == 2  # frame 3 (corrupt) and frame 6 (dropped)


def test_unknown_id_is_counted() -> None:
    from cobs import cobs
    decoder = StreamDecoder()
    assert decoder.feed(bytes(cobs.encode(b"\x7f\x01\x02\x03\x04")) + b"\x00") == []
    assert decoder.stats.unknown_ids == 1


def test_long_garbage_does_not_grow_memory() -> None:
    decoder = StreamDecoder()
    for _ in range(100):
        decoder.feed(b"\x01" * 1000)
    assert decoder.pending_bytes <= 200
    msg = Ack(command_id=1, command_seq=2)
    assert decoder.feed(encode(msg, 0)) == [msg]
