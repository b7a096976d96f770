"""Integration: the real Uno firmware ELF in the emulator, talked to over its pty exactly as
the host talks to a board. Fast mode throughout; every echo is checked against the truth
log of the virtual sensor."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

import pytest
import serial
from obstacle_fusion.protocol import StreamDecoder
from obstacle_fusion.protocol.generated import (
    PROTOCOL_VERSION,
    SCHEMA_FINGERPRINT,
    Ack,
    Board,
    Config,
    Error,
    GetInfo,
    Hello,
    Message,
    Nack,
    Range,
    RangeStatus,
    RunState,
    SetConfig,
    Start,
    Stop,
    TimeSync,
    TimeSyncReply,
)
from obstacle_fusion.sim.emulator import Emulator, TruthRecord, wait_for

from tests import emulator_fixtures
from tests.emulator_fixtures import FirmwarePort

uno_elf = emulator_fixtures.uno_elf
emulator_built = emulator_fixtures.emulator_built
emulator_factory = emulator_fixtures.emulator_factory
open_port = emulator_fixtures.open_port

Factory = Callable[..., Emulator]
Opener = Callable[[Emulator], FirmwarePort]

DEFAULTS = dict(
    cycle_ms=60, sensor_mask=1, max_echo_us=23324, echo_timeout_us=40000, heartbeat_ms=1000
)


def boot(
    factory: Factory, opener: Opener, elf: Path, **config: object
) -> tuple[Emulator, FirmwarePort, Hello, Config]:
    config.setdefault("fast", True)
    emu = factory(elf=elf, **config)
    port = opener(emu)
    hello, seen = port.read_until(lambda m: isinstance(m, Hello), 5.0)
    assert isinstance(hello, Hello), f"no HELLO after power-up; got {seen[:5]}"
    cfg, seen = port.read_until(lambda m: isinstance(m, Config), 5.0)
    assert isinstance(cfg, Config), f"no CONFIG after HELLO; got {seen[:5]}"
    return emu, port, hello, cfg


def command(
    port: FirmwarePort, msg: Message, timeout_s: float = 5.0
) -> tuple[Ack | Nack, list[Message]]:
    seq = port.send(msg)
    reply, seen = port.read_until(
        lambda m: isinstance(m, Ack | Nack) and m.command_seq == seq and m.command_id == msg.MSG_ID,
        timeout_s,
    )
    assert isinstance(reply, Ack | Nack), f"no ACK/NACK for {msg} (seq {seq}); got {seen[-5:]}"
    return reply, seen


def get_config(port: FirmwarePort) -> Config:
    port.send(GetInfo())
    cfg, seen = port.read_until(lambda m: isinstance(m, Config), 5.0)
    assert isinstance(cfg, Config), f"GET_INFO gave no CONFIG; got {seen[-5:]}"
    return cfg


def ranges(msgs: list[Message]) -> list[Range]:
    return [m for m in msgs if isinstance(m, Range)]


def test_hello_after_power_up_and_reset(
    emulator_factory: Factory, open_port: Opener, uno_elf: Path
) -> None:
    emu, port, hello, cfg = boot(emulator_factory, open_port, uno_elf)
    assert hello.protocol_version == PROTOCOL_VERSION
    assert hello.schema_fingerprint == SCHEMA_FINGERPRINT
    assert hello.board == Board.UNO
    assert hello.cpu_hz == 16_000_000
    assert hello.timer_hz == 2_000_000
    assert hello.sensor_count >= 1
    assert {k: getattr(cfg, k) for k in DEFAULTS} == DEFAULTS
    assert cfg.state == RunState.RUNNING
    emu.control.reset()
    again, seen = port.read_until(lambda m: isinstance(m, Hello), 5.0)
    assert isinstance(again, Hello), f"no HELLO after reset; got {seen[-5:]}"


def test_ranging_starts_with_the_default_cycle(
    emulator_factory: Factory, open_port: Opener, uno_elf: Path
) -> None:
    _, port, _, _ = boot(emulator_factory, open_port, uno_elf, distance_m=1.0)
    _, seen = port.read_until(lambda m: isinstance(m, Range) and m.measurement >= 10, 10.0)
    rs = ranges(seen)
    assert len(rs) >= 10, f"only {len(rs)} RANGE frames"
    # From the second measurement on the cycle is steady (the first follows the boot).
    gaps = [
        (b.trigger_us - a.trigger_us) & 0xFFFFFFFF for a, b in zip(rs[1:], rs[2:], strict=False)
    ]
    # The period counts from each trigger, so a gap is never under the cycle; the main
    # loop polls TRIG, so each is a few tens of us longer (a HEARTBEAT waits for a due
    # trigger, so it never pushes one by its few hundred us).
    assert all(60_000 <= g <= 60_000 + 100 for g in gaps), gaps
    assert sum(gaps) / len(gaps) == pytest.approx(60_000 + 45, abs=40)
    assert all(r.status == RangeStatus.OK for r in rs)


def test_stop_stops_range_frames_and_start_resumes(
    emulator_factory: Factory, open_port: Opener, uno_elf: Path
) -> None:
    emu, port, _, _ = boot(emulator_factory, open_port, uno_elf, distance_m=1.0)
    port.read_until(lambda m: isinstance(m, Range), 5.0)
    reply, _ = command(port, Stop())
    assert isinstance(reply, Ack)
    # A measurement already in flight may still report; after one cycle nothing more.
    port.collect(0.1)
    t0 = emu.control.sim_time()
    quiet = port.collect(0.5)
    t1 = emu.control.sim_time()
    assert t1 - t0 > 0.5, "the simulation did not advance"
    assert ranges(quiet) == [], f"RANGE after STOP: {ranges(quiet)[:3]}"
    assert get_config(port).state == RunState.STOPPED
    reply, _ = command(port, Start())
    assert isinstance(reply, Ack)
    r, _ = port.read_until(lambda m: isinstance(m, Range), 5.0)
    assert isinstance(r, Range), "no RANGE after START"


def test_set_config_changes_the_rate(
    emulator_factory: Factory, open_port: Opener, uno_elf: Path
) -> None:
    _, port, _, _ = boot(emulator_factory, open_port, uno_elf, distance_m=0.5)
    new = dict(DEFAULTS, cycle_ms=100)
    reply, _ = command(port, SetConfig(**new))
    assert isinstance(reply, Ack), reply
    cfg, _ = port.read_until(lambda m: isinstance(m, Config), 5.0)
    assert isinstance(cfg, Config) and cfg.cycle_ms == 100
    port.read_until(lambda m: isinstance(m, Range), 5.0)  # the first may straddle the change
    rs = ranges(port.collect(0.5))
    assert len(rs) >= 5
    gaps = [(b.trigger_us - a.trigger_us) & 0xFFFFFFFF for a, b in zip(rs, rs[1:], strict=False)]
    # As above: never under the cycle, a few tens of us of polling, never a HEARTBEAT's delay.
    assert all(100_000 <= g <= 100_000 + 100 for g in gaps), gaps
    assert sum(gaps) / len(gaps) == pytest.approx(100_000 + 45, abs=40)


@pytest.mark.parametrize(
    ("change", "error"),
    [
        (dict(cycle_ms=10), Error.BAD_CYCLE),
        (dict(cycle_ms=40), Error.BAD_CYCLE),  # not longer than the 40 ms echo timeout
        (dict(echo_timeout_us=500), Error.BAD_TIMEOUT),
        (dict(max_echo_us=0), Error.BAD_MAX_ECHO),
        (dict(sensor_mask=0), Error.BAD_SENSOR_MASK),
        (dict(heartbeat_ms=50), Error.BAD_HEARTBEAT),
    ],
)
def test_bad_set_config_is_nacked_and_changes_nothing(
    emulator_factory: Factory,
    open_port: Opener,
    uno_elf: Path,
    change: dict[str, int],
    error: Error,
) -> None:
    _, port, _, _ = boot(emulator_factory, open_port, uno_elf)
    before = get_config(port)
    reply, _ = command(port, SetConfig(**dict(DEFAULTS, **change)))
    assert isinstance(reply, Nack), reply
    assert reply.error == error
    assert get_config(port) == before


def test_time_sync_is_answered(emulator_factory: Factory, open_port: Opener, uno_elf: Path) -> None:
    _, port, _, _ = boot(emulator_factory, open_port, uno_elf, distance_m=1.0)
    last, _ = port.read_until(lambda m: isinstance(m, Range), 5.0)
    assert isinstance(last, Range)
    port.send(TimeSync(token=0xC0FFEE01))
    reply, seen = port.read_until(lambda m: isinstance(m, TimeSyncReply), 5.0)
    assert isinstance(reply, TimeSyncReply), f"no TIME_SYNC_REPLY; got {seen[-5:]}"
    assert reply.token == 0xC0FFEE01
    assert 0 <= (reply.tx_us - reply.rx_us) & 0xFFFFFFFF < 10_000
    assert 0 < (reply.rx_us - last.trigger_us) & 0xFFFFFFFF < 10_000_000


def pair_with_truth(rs: list[Range], truth: list[TruthRecord]) -> list[tuple[Range, TruthRecord]]:
    """Pair RANGE frames with truth records by trigger time (the MCU's microsecond clock
    has its own origin: the offset must be the same for every pair)."""
    assert rs and truth
    by_us = sorted(truth, key=lambda r: r.trigger_s)
    offset = rs[0].trigger_us - by_us[0].trigger_s * 1e6
    pairs = []
    for r in rs:
        want = r.trigger_us - offset
        best = min(by_us, key=lambda t: abs(t.trigger_s * 1e6 - want))
        assert abs(best.trigger_s * 1e6 - want) <= 4, (r, best, offset)
        pairs.append((r, best))
    return pairs


def test_echo_ticks_equal_the_truth_over_the_whole_range(
    emulator_factory: Factory, open_port: Opener, uno_elf: Path, tmp_path: Path
) -> None:
    scene = tmp_path / "sweep.txt"
    scene.write_text("0 0.02\n13 4.0\n")
    emu, port, _, _ = boot(emulator_factory, open_port, uno_elf, scene=scene)
    _, seen = port.read_until(lambda m: isinstance(m, Range) and m.measurement >= 215, 60.0)
    rs = ranges(seen)
    assert len(rs) >= 200, f"only {len(rs)} RANGE frames"
    # No frame lost at 115200 baud: consecutive measurement and frame sequence numbers.
    assert [r.measurement - rs[0].measurement for r in rs] == list(range(len(rs)))
    stats = port.decoder.stats
    assert stats.seq_gaps == 0 and stats.bad_frames == 0, stats
    assert wait_for(lambda: len(emu.truth.read()) >= len(rs), 5.0)
    pairs = pair_with_truth(rs, emu.truth.read())
    distances = []
    for r, t in pairs:
        assert t.kind == "echo" and t.distance_m is not None
        assert r.status == RangeStatus.OK, (r, t)
        assert abs(r.echo_ticks - t.echo_ticks) <= 1.0, (r, t)
        distances.append(t.distance_m)
    assert min(distances) < 0.1 and max(distances) > 3.6


def test_no_echo_is_a_status_never_a_zero(
    emulator_factory: Factory, open_port: Opener, uno_elf: Path
) -> None:
    emu, port, _, _ = boot(emulator_factory, open_port, uno_elf, distance_m=None)
    _, seen = port.read_until(lambda m: isinstance(m, Range) and m.measurement >= 5, 10.0)
    rs = ranges(seen)
    assert len(rs) >= 5
    for r in rs:
        assert r.status == RangeStatus.NO_ECHO, r
        assert abs(r.echo_ticks - 76_000) <= 1, r
    emu.control.set_distance(6.0)  # beyond the sensor's 4 m: the same no-echo pulse
    port.collect(0.2)
    _, seen = port.read_until(lambda m: isinstance(m, Range), 5.0)
    r = ranges(seen)[-1]
    assert r.status == RangeStatus.NO_ECHO and r.echo_ticks > 0


def read_all(path: str, emu: Emulator, timeout_s: float = 60.0) -> bytes:
    """Every byte until the emulator ends (its --duration) and the pty closes."""
    port = serial.Serial(path, 115200, timeout=0.05)
    data = bytearray()
    deadline = time.monotonic() + timeout_s
    try:
        while time.monotonic() < deadline:
            try:
                # Only what is waiting: pyserial drops a partial read when the port closes.
                chunk = port.read(port.in_waiting or 1)
            except (serial.SerialException, OSError):
                break
            data += chunk
            if not chunk and not emu.running():
                break
    finally:
        port.close()
    return bytes(data)


def test_decoder_recovers_every_intact_frame_with_1pct_corruption(
    emulator_factory: Factory, uno_elf: Path
) -> None:
    # The simulation is deterministic: the same run with and without faults sends the
    # same bytes, and a corrupted byte keeps its place, so we know which frames are intact.
    common = dict(elf=uno_elf, fast=True, distance_m=1.5, duration_s=15.0)
    clean_emu = emulator_factory(**common)
    clean = read_all(clean_emu.pty_path, clean_emu)
    noisy_emu = emulator_factory(**common, uart_corrupt=0.01, seed=3)
    noisy = read_all(noisy_emu.pty_path, noisy_emu)
    assert len(clean) > 4000 and len(noisy) == len(clean)
    assert noisy != clean

    clean_dec = StreamDecoder()
    clean_msgs = clean_dec.feed(clean)
    assert clean_dec.stats.bad_frames == 0 and len(clean_msgs) >= 250
    intact: list[Message] = []
    start = 0
    for msg in clean_msgs:
        end = clean.index(b"\x00", start)
        if noisy[start : end + 1] == clean[start : end + 1]:
            intact.append(msg)
        start = end + 1
    assert len(intact) < len(clean_msgs)

    dec = StreamDecoder()
    got: list[Message] = []
    for i in range(0, len(noisy), 97):  # arbitrary chunking, as reads return it
        got.extend(dec.feed(noisy[i : i + 97]))
    it = iter(got)
    missing = [m for m in intact if not any(g == m for g in it)]
    assert missing == [], f"{len(missing)} intact frames not decoded, e.g. {missing[:2]}"
    assert dec.stats.bad_frames >= 1  # the damaged frames are counted, not returned
    assert len(got) < len(clean_msgs)
    assert clean_emu.wait(10.0) == 0 and noisy_emu.wait(10.0) == 0


def test_real_time_mode_looks_like_a_board(
    emulator_factory: Factory, open_port: Opener, uno_elf: Path
) -> None:
    _, port, _, _ = boot(emulator_factory, open_port, uno_elf, fast=False, distance_m=1.0)
    arrivals = []
    while len(arrivals) < 9:
        msg, _ = port.read_until(lambda m: isinstance(m, Range), 2.0)
        assert isinstance(msg, Range)
        arrivals.append(time.monotonic())
    spacing = [b - a for a, b in zip(arrivals, arrivals[1:], strict=False)]
    assert sum(spacing) / len(spacing) == pytest.approx(0.060, abs=0.006)
    t0 = time.monotonic()
    port.send(TimeSync(token=7))
    reply, _ = port.read_until(lambda m: isinstance(m, TimeSyncReply), 2.0)
    assert isinstance(reply, TimeSyncReply) and reply.token == 7
    # Request and reply are ~20 bytes each at 115200 baud: a few ms, as on a board.
    assert 0.003 < time.monotonic() - t0 < 0.2


def test_round_robin_over_sensors_sharing_the_echo_pin(
    emulator_factory: Factory, open_port: Opener, uno_elf: Path
) -> None:
    # Three virtual sensors on D9, D10, D11, their ECHOs OR-ed onto D8 (firmware README).
    emu, port, hello, _ = boot(emulator_factory, open_port, uno_elf, distance_m=1.0, sensors=3)
    assert hello.sensor_count >= 3
    emu.control.set_distance(2.0, sensor=1)
    emu.control.set_distance(None, sensor=2)
    reply, _ = command(port, SetConfig(**dict(DEFAULTS, sensor_mask=0b111)))
    assert isinstance(reply, Ack)
    port.read_until(lambda m: isinstance(m, Config), 5.0)
    port.read_until(lambda m: isinstance(m, Range), 5.0)  # may still be the old round
    _, seen = port.read_until(lambda m: isinstance(m, Range) and m.measurement % 50 == 0, 10.0)
    rs = ranges(seen)[-30:]
    assert len(rs) >= 12
    assert wait_for(lambda: len(emu.truth.read()) > rs[-1].measurement, 5.0)
    truth = {t.index: t for t in emu.truth.read()}
    for a, b in zip(rs, rs[1:], strict=False):
        assert b.sensor_id == (a.sensor_id + 1) % 3
    for r in rs:
        t = truth[r.measurement]
        assert t.sensor_id == r.sensor_id
        assert abs(r.echo_ticks - t.echo_ticks) <= 1
        assert r.status == (RangeStatus.NO_ECHO if r.sensor_id == 2 else RangeStatus.OK)


def test_good_crc_with_a_wrong_length_gets_nack_bad_length(
    emulator_factory: Factory, open_port: Opener, uno_elf: Path
) -> None:
    """A SET_CONFIG one byte short (CRC right) is refused by name, and changes nothing."""
    import binascii

    from cobs import cobs
    from obstacle_fusion.protocol.codec import CRC_SEEDS, pack_payload

    _, port, _, before = boot(emulator_factory, open_port, uno_elf, distance_m=1.0)
    payload = pack_payload(SetConfig(**dict(DEFAULTS, cycle_ms=200)))[:-1]
    seq = 0x33
    body = bytes((SetConfig.MSG_ID, seq)) + payload
    crc = binascii.crc_hqx(body, CRC_SEEDS[SetConfig.MSG_ID])
    port.write_raw(bytes(cobs.encode(body + crc.to_bytes(2, "big"))) + b"\x00")
    reply, _ = port.read_until(lambda m: isinstance(m, Nack | Ack) and m.command_seq == seq, 5.0)
    assert isinstance(reply, Nack), reply
    assert reply.error == Error.BAD_LENGTH
    assert get_config(port) == before


def test_unknown_ids_are_dropped_silently_and_device_ids_get_nack_unknown_command(
    emulator_factory: Factory, open_port: Opener, uno_elf: Path
) -> None:
    """As protocol/README.md's table says: an id with no schema cannot pass the CRC (its
    seed is unknown), so it is dropped and counted in rx_errors, with no answer; a known id
    that is no command (RANGE sent to the device) passes it and gets NACK(unknown_command)."""
    import binascii

    from cobs import cobs
    from obstacle_fusion.protocol.codec import CRC_SEEDS, encode
    from obstacle_fusion.protocol.generated import Heartbeat

    readme = (Path(__file__).resolve().parents[2] / "protocol" / "README.md").read_text()
    assert "| an id the firmware has no schema for | nothing:" in readme
    assert (
        "| a known id that is not a command (HELLO, RANGE, ...) | NACK(unknown_command) |" in readme
    )
    _, port, _, _ = boot(emulator_factory, open_port, uno_elf, distance_m=1.0)
    hb, _ = port.read_until(lambda m: isinstance(m, Heartbeat), 5.0)
    assert isinstance(hb, Heartbeat)
    body = bytes((0x7E, 0x44, 1, 2, 3))
    crc = binascii.crc_hqx(body, 0xFFFF)
    port.write_raw(bytes(cobs.encode(body + crc.to_bytes(2, "big"))) + b"\x00")
    later, seen = port.read_until(
        lambda m: isinstance(m, Heartbeat) and m.rx_errors > hb.rx_errors, 5.0
    )
    assert isinstance(later, Heartbeat) and later.rx_errors == hb.rx_errors + 1
    assert not [m for m in seen if isinstance(m, Nack | Ack)]
    assert 0x7E not in CRC_SEEDS
    port.write_raw(encode(Range(1, 0, 2, 3, 0), 0x45))
    reply, _ = port.read_until(lambda m: isinstance(m, Nack | Ack) and m.command_seq == 0x45, 5.0)
    assert isinstance(reply, Nack) and reply.command_id == Range.MSG_ID
    assert reply.error == Error.UNKNOWN_COMMAND
