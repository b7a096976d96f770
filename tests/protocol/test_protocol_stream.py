"""StreamDecoder: arbitrary chunks, garbage, corruption; never raises, never invents.

Every test here runs twice: with the decoder's pure-Python path as the default, and with
its C accelerator (a decoder made with ``accelerated=False`` stays pure in both)."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from obstacle_fusion.protocol import StreamDecoder, encode, stream
from obstacle_fusion.protocol.generated import (
    Ack,
    Heartbeat,
    Log,
    Message,
    Range,
    TimeSyncReply,
)

pytestmark = pytest.mark.cpu_only

u32 = st.integers(0, 0xFFFFFFFF)
u8 = st.integers(0, 0xFF)
messages = st.one_of(
    st.builds(
        Range,
        measurement=u32,
        sensor_id=st.integers(0, 3),
        trigger_us=u32,
        echo_ticks=u32,
        status=st.integers(0, 3),
    ),
    st.builds(
        Heartbeat,
        uptime_ms=u32,
        frames_sent=u32,
        rx_errors=u32,
        tx_overruns=u32,
        state=st.integers(0, 1),
    ),
    st.builds(TimeSyncReply, token=u32, rx_us=u32, tx_us=u32),
    st.builds(Ack, command_id=u8, command_seq=u8),
    st.builds(
        Log,
        level=st.integers(0, 3),
        text=st.text(alphabet=st.characters(min_codepoint=32, max_codepoint=126), max_size=40),
    ),
)


@pytest.fixture(autouse=True, scope="module", params=["pure", "accelerated"])
def decoder_path(request: pytest.FixtureRequest) -> Iterator[str]:
    """The default path of every StreamDecoder() in this module (module-scoped: hypothesis
    allows no function-scoped fixture around @given)."""
    saved = stream._DEFAULT_SCAN
    if request.param == "pure":
        stream._DEFAULT_SCAN = None
    else:
        assert stream.ACCELERATOR is not None, "the C accelerator is not built (make setup)"
        stream._DEFAULT_SCAN = stream.ACCELERATOR
    try:
        yield request.param
    finally:
        stream._DEFAULT_SCAN = saved


def test_the_default_path_is_the_one_this_run_is_for(decoder_path: str) -> None:
    assert StreamDecoder().accelerated == (decoder_path == "accelerated")


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
    st.lists(
        st.tuples(messages, st.booleans(), st.binary(max_size=12), st.integers(0, 60)),
        min_size=1,
        max_size=25,
    ),
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


def _wire_len(msg: Message) -> int:
    return len(encode(msg, 0))  # COBS adds one byte below 254: the length never depends on seq


def _every_chunking(data: bytes) -> list[list[bytes]]:
    """One piece, byte by byte, and every split into two or three pieces at a stride."""
    ways = [[data], [data[i : i + 1] for i in range(len(data))]]
    for a in range(0, len(data) + 1):
        ways.append([data[:a], data[a:]])
        for b in range(a, len(data) + 1, 7):
            ways.append([data[:a], data[a:b], data[b:]])
    return ways


def test_a_too_long_run_is_oversized_however_it_is_chunked() -> None:
    """150 bytes of valid COBS with no delimiter, then 0x00: one oversized frame, whether
    the decoder saw it whole or in pieces (it used to be cobs_errors when the tail was
    trimmed between chunks), and the frame after it still comes out."""
    from cobs import cobs

    long_run = bytes(cobs.encode(bytes(range(1, 150))))
    good = Ack(command_id=0x41, command_seq=3)
    data = long_run + b"\x00" + encode(good, 5)
    for pieces in _every_chunking(data):
        decoder = StreamDecoder()
        assert feed_all(decoder, pieces) == [good], pieces
        s = decoder.stats
        assert (s.oversized, s.cobs_errors, s.crc_errors, s.frames) == (1, 0, 0, 1), pieces
        assert s.resyncs == 0 and s.bytes_discarded == len(long_run) + 1, pieces


def test_a_frame_right_after_long_noise_is_recovered_however_it_is_chunked() -> None:
    good = Range(measurement=7, sensor_id=0, trigger_us=123456, echo_ticks=4000, status=0)
    noise = bytes(range(1, 200))  # no 0x00: the frame has no delimiter before it
    data = noise + encode(good, 9)
    for pieces in _every_chunking(data):
        decoder = StreamDecoder()
        assert feed_all(decoder, pieces) == [good], pieces
        s = decoder.stats
        assert (s.resyncs, s.oversized, s.bad_frames) == (1, 0, 0), pieces
        assert s.bytes_discarded == len(noise), pieces


def test_resync_is_counted_for_a_short_noise_prefix() -> None:
    good = Ack(command_id=0x41, command_seq=3)
    decoder = StreamDecoder()
    assert decoder.feed(b"\x13\x37" + encode(good, 1)) == [good]
    assert decoder.stats.resyncs == 1 and decoder.stats.bad_frames == 0
    assert decoder.stats.bytes_discarded == 2


def test_runs_of_zeros_are_counted_as_dropped_bytes() -> None:
    good = Ack(command_id=1, command_seq=2)
    decoder = StreamDecoder()
    got = decoder.feed(b"\x00\x00\x00" + encode(good, 0) + b"\x00\x00")
    assert got == [good]
    assert decoder.stats.stray_zeros == 5 and decoder.stats.bytes_discarded == 5
    assert decoder.stats.bad_frames == 0


@settings(suppress_health_check=[HealthCheck.too_slow], max_examples=150)
@given(
    st.lists(
        st.tuples(messages, st.booleans(), st.binary(max_size=80), st.integers(0, 60)),
        min_size=1,
        max_size=12,
    ),
    st.lists(st.integers(0, 3000), max_size=10),
)
def test_every_byte_is_in_a_good_frame_pending_or_counted_as_dropped(
    items: list,
    cuts: list[int],  # type: ignore[type-arg]
) -> None:
    """Garbage (zeros included), corrupted and intact frames: the bytes of the good frames,
    the pending tail and bytes_discarded add up to the bytes fed, in every chunking."""
    stream = bytearray()
    for seq, (msg, corrupt, garbage, flip_at) in enumerate(items):
        frame = bytearray(encode(msg, seq & 0xFF))
        if corrupt:
            frame[flip_at % (len(frame) - 1)] ^= 0x5A
        stream += garbage + frame
    decoder = StreamDecoder()
    got = feed_all(decoder, chunked(bytes(stream), cuts))
    s = decoder.stats
    assert s.frames == len(got)
    good_bytes = sum(_wire_len(m) for m in got)
    assert good_bytes + decoder.pending_bytes + s.bytes_discarded == s.bytes == len(stream)
    whole = StreamDecoder()
    assert whole.feed(bytes(stream)) == got
    assert whole.stats == s


def test_the_longest_frame_is_checked_and_one_byte_more_is_oversized() -> None:
    """A run of MAX_FRAME - 1 bytes (the longest a frame can be without its 0x00) is
    decoded and checked (here: its CRC fails); one byte more is oversized, in any chunking."""
    import binascii

    from cobs import cobs
    from obstacle_fusion.protocol.codec import CRC_SEEDS
    from obstacle_fusion.protocol.generated import MAX_BODY, MAX_FRAME

    body = bytes((Log.MSG_ID, 1)) + b"y" * (MAX_BODY - 4)
    crc = binascii.crc_hqx(body, CRC_SEEDS[Log.MSG_ID]) ^ 0x0101  # a wrong CRC
    longest = bytes(cobs.encode(body + crc.to_bytes(2, "big")))
    assert len(longest) == MAX_FRAME - 1
    too_long = bytes(cobs.encode(b"z" + body + crc.to_bytes(2, "big")))
    assert len(too_long) == MAX_FRAME
    for run, counter in ((longest, "crc_errors"), (too_long, "oversized")):
        for pieces in _every_chunking(run + b"\x00"):
            decoder = StreamDecoder()
            assert feed_all(decoder, pieces) == []
            s = decoder.stats
            assert s.bad_frames == getattr(s, counter) == 1, (counter, pieces)
            assert s.bytes_discarded == len(run) + 1


def test_every_message_id_byte_is_handled() -> None:
    """A frame whose first byte is any id 0..255 (with a right-looking CRC) never raises:
    the unknown ones are counted, the known fixed-length ones decode."""
    import binascii

    from cobs import cobs
    from obstacle_fusion.protocol.codec import CRC_SEEDS
    from obstacle_fusion.protocol.generated import MESSAGES

    for msg_id in range(256):
        body = bytes((msg_id, 1)) + bytes(14)
        crc = binascii.crc_hqx(body, CRC_SEEDS.get(msg_id, 0xFFFF))
        decoder = StreamDecoder()
        decoder.feed(bytes(cobs.encode(body + crc.to_bytes(2, "big"))) + b"\x00")
        s = decoder.stats
        if msg_id not in MESSAGES:
            assert s.unknown_ids == 1 and s.frames == 0, msg_id
        else:
            assert s.frames + s.bad_lengths == 1, msg_id


def test_stats_as_dict_names_every_counter() -> None:
    decoder = StreamDecoder()
    decoder.feed(b"\x00\x03\x01\x02\x00" + encode(Ack(command_id=1, command_seq=2), 0))
    d = decoder.stats.as_dict()
    assert d["frames"] == 1 and d["stray_zeros"] == 1 and d["truncated"] == 1
    assert d["bytes"] == decoder.stats.bytes and set(d) >= {"resyncs", "bytes_discarded"}


def test_lost_frames_are_counted_for_text_messages_and_after_a_resync() -> None:
    """Sequence gaps are counted on every path, across the 255 -> 0 wrap: LOG (a text
    message, decoded off the fast path) and a frame recovered from behind noise."""
    logs = [encode(Log(level=1, text=f"m{i}"), i) for i in (0, 1, 3, 254)]
    decoder = StreamDecoder()
    assert len(decoder.feed(b"".join(logs))) == 4
    assert decoder.stats.seq_gaps == 1 + 250
    decoder.feed(b"\x13\x37" + encode(Ack(command_id=1, command_seq=1), 1))  # 255, 0 lost
    assert decoder.stats.resyncs == 1 and decoder.stats.seq_gaps == 1 + 250 + 2
    assert decoder.last_seq == 1


def test_a_short_run_that_is_no_cobs_is_a_cobs_error_not_oversized() -> None:
    from obstacle_fusion.protocol.generated import MAX_FRAME

    for run in (b"\x05\x01", b"\x40" + b"\x01" * (MAX_FRAME - 2)):  # the longest possible
        assert len(run) < MAX_FRAME
        decoder = StreamDecoder()
        assert decoder.feed(run + b"\x00") == []
        assert decoder.stats.cobs_errors == 1 and decoder.stats.oversized == 0, run


def test_a_hello_starts_a_new_count_and_only_a_hello() -> None:
    """HELLO (a new session: the device restarted its numbering) is never a gap; any other
    frame is, even one whose seq happens to equal HELLO's id."""
    from obstacle_fusion.protocol.generated import Hello

    hello = Hello(1, 2, 0, 1, 0, 1, 16_000_000, 2_000_000, 1)
    decoder = StreamDecoder()
    decoder.feed(encode(Ack(command_id=1, command_seq=0), 200) + encode(hello, 0))
    assert decoder.stats.seq_gaps == 0
    decoder.feed(encode(Ack(command_id=1, command_seq=0), 255))  # 1..254 lost
    decoder.feed(encode(Ack(command_id=1, command_seq=0), Hello.MSG_ID))  # 0 .. lost
    assert decoder.stats.seq_gaps == 254 + ((Hello.MSG_ID - 255 - 1) & 0xFF)


def test_the_shortest_frame_is_recovered_from_behind_noise() -> None:
    """STOP has no payload: its frame is 5 bytes with the 0x00, the shortest there is."""
    from obstacle_fusion.protocol.generated import Stop

    frame = encode(Stop(), 9)
    assert len(frame) == 6
    decoder = StreamDecoder()
    assert decoder.feed(b"\x13\x37\x42" + frame) == [Stop()]
    assert decoder.stats.resyncs == 1 and decoder.stats.bytes_discarded == 3


def test_gaps_use_the_sequence_byte_not_the_id_or_payload() -> None:
    """A LOG numbered like HELLO's id is no HELLO; a resynced frame's gap comes from its
    seq byte, not from its payload."""
    from obstacle_fusion.protocol.generated import Hello

    decoder = StreamDecoder()
    decoder.feed(encode(Log(level=1, text="a"), 5) + encode(Log(level=1, text="b"), Hello.MSG_ID))
    assert decoder.stats.seq_gaps == (Hello.MSG_ID - 5 - 1) & 0xFF
    decoder = StreamDecoder()
    decoder.feed(encode(Ack(command_id=0x41, command_seq=0), 3))
    decoder.feed(b"\x13\x37" + encode(Ack(command_id=0x41, command_seq=0), 6))
    assert decoder.stats.resyncs == 1 and decoder.stats.seq_gaps == 2


# --- The whole-chunk path: a chunk of frames of one fixed-length message, decoded at once ---


def _ranges(count: int, first_seq: int = 0) -> list[bytes]:
    return [
        encode(
            Range(
                measurement=i, sensor_id=i % 4, trigger_us=60_000 * i, echo_ticks=4000 + i, status=0
            ),
            (first_seq + i) & 0xFF,
        )
        for i in range(count)
    ]


def _frame_by_frame(monkeypatch: object, pieces: list[bytes]) -> StreamDecoder:
    """A pure-Python decoder fed ``pieces`` with the whole-chunk path switched off."""
    decoder = StreamDecoder(accelerated=False)
    old = stream.RUN_MIN_FRAMES
    stream.RUN_MIN_FRAMES = 10**9
    try:
        decoder.out = feed_all(decoder, pieces)  # type: ignore[attr-defined]
    finally:
        stream.RUN_MIN_FRAMES = old
    return decoder


def _same_as_frame_by_frame(pieces: list[bytes]) -> list[Message]:
    ref = _frame_by_frame(None, pieces)
    decoder = StreamDecoder()
    got = feed_all(decoder, pieces)
    assert got == ref.out  # type: ignore[attr-defined]
    assert decoder.stats == ref.stats
    assert (decoder.last_seq, decoder.pending_bytes) == (ref.last_seq, ref.pending_bytes)
    return got


def test_a_clean_run_is_decoded_whole_with_no_frame_by_frame_step(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """With the frame-by-frame decoders made to fail, a chunk of RANGE frames still comes
    out whole: the whole-chunk path decoded it, with the counters of a frame-by-frame run."""

    frames = _ranges(40, first_seq=250)  # the seq wraps inside the run
    expected = _same_as_frame_by_frame([b"".join(frames)])

    def no(*args: object) -> None:
        raise AssertionError("decoded frame by frame")

    monkeypatch.setattr(stream, "_FAST", [None] * 256)
    monkeypatch.setattr(stream, "decode_body", no)
    decoder = StreamDecoder(accelerated=False)  # the C accelerator has no whole-chunk path
    decoder.last_seq = 248  # seq 249 lost before the run
    assert decoder.feed(b"".join(frames) + frames[0][:5]) == expected
    s = decoder.stats
    assert (s.frames, s.seq_gaps, s.bad_frames, s.bytes_discarded) == (40, 1, 0, 0)
    assert decoder.last_seq == (250 + 39) & 0xFF and decoder.pending_bytes == 5


def _whole_runs(monkeypatch) -> list[int | None]:  # type: ignore[no-untyped-def]
    """Record how many messages each whole-chunk attempt returned (None: it declined)."""

    seen: list[int | None] = []
    real = stream.StreamDecoder._decode_run

    def spy(self, *args):  # type: ignore[no-untyped-def]
        got = real(self, *args)
        seen.append(None if got is None else len(got))
        return got

    monkeypatch.setattr(stream.StreamDecoder, "_decode_run", spy)
    return seen


def test_eight_frames_the_shortest_frames_and_a_run_after_an_overflow_go_whole(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """The whole-chunk path takes a chunk of 8 frames, a run of the shortest frames (STOP: no
    payload, 5 bytes), and a run that follows the end of an overflowed run in its chunk."""
    from obstacle_fusion.protocol.generated import Stop

    seen = _whole_runs(monkeypatch)
    decoder = StreamDecoder(accelerated=False)  # the C accelerator has no whole-chunk path
    assert len(decoder.feed(b"".join(_ranges(8)))) == 8
    assert decoder.feed(b"".join(encode(Stop(), seq) for seq in range(8, 20))) == [Stop()] * 12
    decoder.feed(b"\x01" * 300)  # no frame is this long: the tail overflows
    got = decoder.feed(b"\x01" * 10 + b"\x00" + b"".join(_ranges(9, first_seq=20)))
    assert len(got) == 9
    assert seen == [8, 12, 9]
    s = decoder.stats
    assert (s.oversized, s.seq_gaps, s.frames) == (1, 0, 29)


def test_frames_of_a_wrong_length_with_a_right_crc_in_a_run_are_bad_lengths() -> None:
    """Two frames with RANGE's id and a right CRC, one byte short and one byte long (the
    second's seq byte equal to RANGE's id): the chunk is as long as a run of RANGE and every
    19th body byte is RANGE's id, but its delimiters are not every 20th byte: two bad
    lengths, and the other frames decoded."""
    import binascii

    from cobs import cobs
    from obstacle_fusion.protocol.codec import CRC_SEEDS

    def frame(body: bytes) -> bytes:
        crc = binascii.crc_hqx(body, CRC_SEEDS[Range.MSG_ID]).to_bytes(2, "big")
        return bytes(cobs.encode(body + crc)) + b"\x00"

    frames = _ranges(10)
    frames[4] = frame(bytes((Range.MSG_ID, 4)) + bytes(range(1, 14)))  # 13-byte payload
    frames[5] = frame(bytes((Range.MSG_ID, Range.MSG_ID)) + bytes(range(1, 16)))  # 15 bytes
    assert len(frames[4]) + len(frames[5]) == 2 * len(frames[0])
    decoder = StreamDecoder()
    got = decoder.feed(b"".join(frames))
    assert [m.measurement for m in got] == [0, 1, 2, 3, 6, 7, 8, 9]  # type: ignore[attr-defined]
    assert decoder.stats.bad_lengths == 2 and decoder.stats.frames == 8
    # Frame by frame too: four bytes too long, four too short, a right CRC.
    for payload in (bytes(range(1, 19)), bytes(range(1, 11))):
        assert decoder.feed(frame(bytes((Range.MSG_ID, 10)) + payload)) == []
    assert decoder.stats.bad_lengths == 4 and decoder.stats.frames == 8


def test_a_run_with_gaps_counts_every_lost_frame() -> None:
    frames = _ranges(30)
    del frames[20:23]  # 3 lost
    del frames[5]  # 1 lost
    decoder = StreamDecoder()
    assert len(decoder.feed(b"".join(frames))) == 26
    assert decoder.stats.seq_gaps == 4 and decoder.last_seq == 29
    assert len(decoder.feed(b"".join(_ranges(10, first_seq=40)))) == 10  # 30..39 lost
    assert decoder.stats.seq_gaps == 4 + 10 and decoder.last_seq == 49
    _same_as_frame_by_frame([b"".join(frames), b"".join(_ranges(10, first_seq=40))])


def test_a_run_that_skips_or_repeats_its_seq_counts_the_gaps() -> None:
    """Every other frame lost (0, 2, 4, ...), and one seq sent again and again (a repeat is
    255 lost frames, as frame by frame): the consecutive-seq shortcut must not pass them."""
    evens = b"".join(_ranges(40)[0::2])
    decoder = StreamDecoder()
    assert len(decoder.feed(evens)) == 20
    assert decoder.stats.seq_gaps == 19 and decoder.last_seq == 38
    ack = Ack(command_id=1, command_seq=2)
    assert decoder.feed(encode(ack, 40) * 10) == [ack] * 10  # an even seq repeated
    assert decoder.stats.seq_gaps == 19 + 1 + 9 * 255
    assert decoder.feed(encode(ack, 41) * 10) == [ack] * 10  # an odd one
    assert decoder.stats.seq_gaps == 19 + 1 + 9 * 255 + 9 * 255
    _same_as_frame_by_frame([evens, encode(ack, 40) * 10, encode(ack, 41) * 10])


def test_a_bad_frame_in_a_run_is_counted_and_the_others_come_out() -> None:
    """One frame of a run with a wrong CRC, one that is no COBS (same length): the run falls
    back to frame by frame, which counts both and decodes the other frames."""
    from cobs import cobs

    frames = [bytearray(f) for f in _ranges(20)]
    body = bytearray(cobs.decode(bytes(frames[4][:-1])))
    body[-1] ^= 0x10  # COBS intact, CRC wrong
    frames[4] = bytearray(cobs.encode(bytes(body)) + b"\x00")
    frames[11][0] = 0x7F  # a code byte pointing past the frame's end
    decoder = StreamDecoder()
    got = decoder.feed(b"".join(frames))
    assert [m.measurement for m in got] == [i for i in range(20) if i not in (4, 11)]  # type: ignore[attr-defined]
    s = decoder.stats
    assert (s.crc_errors, s.cobs_errors, s.frames, s.seq_gaps) == (1, 1, 18, 2)
    _same_as_frame_by_frame([bytes(b"".join(frames))])


def test_a_crc_right_for_another_message_of_the_same_length_is_a_crc_error() -> None:
    """CONFIG has RANGE's length: a frame with CONFIG's id and a CRC seeded as RANGE's is
    a CRC error inside a run of RANGE too, never a RANGE."""
    import binascii

    from cobs import cobs
    from obstacle_fusion.protocol.codec import CRC_SEEDS
    from obstacle_fusion.protocol.generated import Config

    frames = _ranges(12)
    body = bytearray(cobs.decode(frames[6][:-1]))
    body[0] = Config.MSG_ID
    crc = binascii.crc_hqx(bytes(body[:-2]), CRC_SEEDS[Range.MSG_ID])
    body[-2:] = crc.to_bytes(2, "big")
    frames[6] = bytes(cobs.encode(bytes(body))) + b"\x00"
    decoder = StreamDecoder()
    got = decoder.feed(b"".join(frames))
    assert len(got) == 11 and all(isinstance(m, Range) for m in got)
    assert decoder.stats.crc_errors == 1 and decoder.stats.frames == 11


def test_frames_of_other_lengths_summing_to_a_run_are_decoded_one_by_one() -> None:
    """A SET_CONFIG (one byte shorter than RANGE) and a LOG one byte longer, in a run of
    RANGE: the chunk is as long as a run of RANGE, but its delimiters are not every 20th
    byte, so the frames are decoded one by one, each as what it is."""
    from obstacle_fusion.protocol.generated import SetConfig

    frames = _ranges(16)
    short = encode(
        SetConfig(
            cycle_ms=60, sensor_mask=1, max_echo_us=23324, echo_timeout_us=40000, heartbeat_ms=1000
        ),
        5,
    )
    long = encode(Log(level=1, text="x" * 14), 6)
    assert len(short) + len(long) == 2 * len(frames[0])
    frames[5:7] = [short, long]
    got = _same_as_frame_by_frame([b"".join(frames)])
    assert [type(m).__name__ for m in got[4:8]] == ["Range", "SetConfig", "Log", "Range"]
    assert len(got) == 16


def test_a_run_of_hello_starts_a_new_count_at_each_one() -> None:
    from obstacle_fusion.protocol.generated import Hello

    hello = Hello(1, 2, 0, 1, 0, 1, 16_000_000, 2_000_000, 1)
    decoder = StreamDecoder()
    decoder.feed(encode(Ack(command_id=1, command_seq=0), 0))
    got = decoder.feed(b"".join(encode(hello, seq) for seq in (9, 200, 3, 77, 1, 5, 100, 42, 7)))
    assert got == [hello] * 9
    assert decoder.stats.seq_gaps == 0 and decoder.last_seq == 7


def test_a_run_of_empty_frames_is_counted_not_raised() -> None:
    """b"\\x01" decodes to an empty body: eight of them are eight truncated frames."""
    decoder = StreamDecoder()
    assert decoder.feed(b"\x01\x00" * 8 + b"".join(_ranges(8))) == _same_as_frame_by_frame(
        [b"\x01\x00" * 8 + b"".join(_ranges(8))]
    )
    assert decoder.stats.truncated == 8 and decoder.stats.frames == 8


def _mutate(frame: bytes, kind: int, at: int) -> bytes:
    if len(frame) < 2:  # a frame already lost or cut to its delimiter
        return frame
    out = bytearray(frame)
    pos = at % (len(out) - 1)
    if kind == 0:
        out[pos] ^= 0x5A  # a flipped byte (maybe a new 0x00)
    elif kind == 1:
        del out[pos]  # a lost byte
    elif kind == 2:
        out.insert(pos, 0)  # a new delimiter
    elif kind == 3:
        out[pos] = 0xFF
    return bytes(out)


@settings(suppress_health_check=[HealthCheck.too_slow], max_examples=150, deadline=None)
@given(
    st.integers(8, 60),
    st.integers(0, 255),
    st.lists(st.tuples(st.integers(0, 59), st.integers(0, 4), st.integers(0, 40)), max_size=4),
    st.lists(st.integers(0, 1500), max_size=4),
    st.sampled_from(["range", "heartbeat", "config"]),
)
def test_runs_with_any_damage_decode_as_frame_by_frame(
    count: int, first_seq: int, damage: list[tuple[int, int, int]], cuts: list[int], kind: str
) -> None:
    """Runs of one message, a few frames damaged (a byte flipped, lost, turned into 0x00 or
    0xFF, a frame lost), in any chunking: the same messages, counters, last seq and pending
    bytes as the frame-by-frame decoder."""
    from obstacle_fusion.protocol.generated import Config

    if kind == "range":
        frames = _ranges(count, first_seq)
    elif kind == "heartbeat":
        frames = [
            encode(
                Heartbeat(uptime_ms=i, frames_sent=i * 3, rx_errors=0, tx_overruns=0, state=1),
                (first_seq + i) & 0xFF,
            )
            for i in range(count)
        ]
    else:
        frames = [
            encode(
                Config(
                    cycle_ms=60,
                    sensor_mask=1,
                    max_echo_us=i,
                    echo_timeout_us=40000,
                    heartbeat_ms=1000,
                    state=1,
                ),
                (first_seq + i) & 0xFF,
            )
            for i in range(count)
        ]
    for index, how, at in damage:
        index %= len(frames)
        frames[index] = b"" if how == 4 else _mutate(frames[index], how, at)
    data = b"".join(frames)
    _same_as_frame_by_frame(chunked(data, cuts))
    _same_as_frame_by_frame([data])
