"""Serial link against a fake board on a pty: handshake, commands, counters, reconnect."""

from __future__ import annotations

import time

import pytest
from obstacle_fusion.link.connection import Link, LinkError, Received
from obstacle_fusion.protocol.generated import (
    Ack,
    Hello,
    Range,
    SetConfig,
    Stop,
    TimeSyncReply,
)

from tests.link_fixtures import FakeBoard


def _collect(link: Link, seconds: float) -> list[Received]:
    out: list[Received] = []
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        item = link.get(timeout=0.02)
        if item is not None:
            out.append(item)
    return out


def _fast_link(port: object, **kw: object) -> Link:
    return Link(port, handshake_timeout_s=1.5, get_info_after_s=0.05, **kw)  # type: ignore[arg-type]


def test_handshake_then_ranges_with_host_times() -> None:
    with FakeBoard() as board, _fast_link(board.path) as link:
        assert isinstance(link.hello, Hello) and link.hello.timer_hz == 2_000_000
        items = _collect(link, 0.4)
        assert isinstance(items[0].msg, Hello)
        ranges = [r for r in items if isinstance(r.msg, Range)]
        assert len(ranges) >= 5
        times = [r.t_host for r in ranges]
        assert times == sorted(times)
        assert all(r.session == 1 for r in items)
        assert link.counters.frames >= len(ranges)
        assert link.counters.connected and link.counters.port == board.path


def test_schema_mismatch_is_refused_with_both_fingerprints() -> None:
    with FakeBoard(fingerprint=0x12345678) as board:
        with pytest.raises(LinkError) as info:
            _fast_link(board.path).start()
    text = str(info.value)
    assert "0x12345678" in text and "schema" in text and "Flash" in text


def test_a_silent_port_fails_the_handshake_clearly() -> None:
    with FakeBoard(silent=True) as board:
        link = _fast_link(board.path)
        t0 = time.monotonic()
        with pytest.raises(LinkError) as info:
            link.start(timeout_s=1.0)
        assert time.monotonic() - t0 < 3.0
    assert "handshake" in str(info.value) and "115200" in str(info.value)


def test_unopenable_port_fails_clearly() -> None:
    with pytest.raises(LinkError) as info:
        _fast_link("/dev/does-not-exist-obstacle").start(timeout_s=0.5)
    assert "/dev/does-not-exist-obstacle does not exist" in str(info.value)


def test_commands_are_matched_by_seq_and_nack_names_the_reason() -> None:
    with FakeBoard() as board, _fast_link(board.path) as link:
        ack = link.command(Stop())
        assert isinstance(ack, Ack) and ack.command_id == Stop.MSG_ID
        assert not board.running
        _collect(link, 0.1)  # frames already in flight
        assert not [r for r in _collect(link, 0.2) if isinstance(r.msg, Range)]
        with pytest.raises(LinkError, match="bad_cycle"):
            link.command(SetConfig(10, 1, 23324, 40000, 1000))
        pending = [link.send(SetConfig(100, 1, 23324, 40000, 1000)) for _ in range(3)]
        replies = [p.wait(1.0) for p in pending]
        assert [r.command_seq for r in replies] == [p.seq for p in pending]


def test_time_sync_replies_carry_their_send_time() -> None:
    with FakeBoard() as board, _fast_link(board.path) as link:
        syncs = [r for r in _collect(link, 0.5) if isinstance(r.msg, TimeSyncReply)]
        assert len(syncs) >= 3
        for r in syncs:
            assert r.t_send is not None and r.t_send <= r.t_host < r.t_send + 0.1
        assert link.counters.time_syncs_answered >= len(syncs)


def test_garbage_and_lost_frames_are_counted() -> None:
    with FakeBoard(skip_seq_every=5) as board, _fast_link(board.path) as link:
        board.garbage(b"\x05\x11\x22\x33\x44\x00" * 3)
        _collect(link, 0.4)
        assert link.counters.bad_frames >= 3
        assert link.counters.seq_gaps >= 2
        assert link.counters.device_tx_overruns == 3  # from HEARTBEAT


def test_reconnect_after_unplug_keeps_everything() -> None:
    with FakeBoard() as board:
        link = Link(
            board.port, handshake_timeout_s=1.5, get_info_after_s=0.05, retry_interval_s=0.05
        )
        link.start()
        try:
            before = _collect(link, 0.3)
            board.unplug()
            time.sleep(0.2)
            assert not link.connected
            board.plug()  # a new pty path, as after an emulator restart
            after = _collect(link, 1.0)
        finally:
            link.close()
    assert [r for r in before if isinstance(r.msg, Range)]
    sessions = {r.session for r in after if isinstance(r.msg, Range)}
    assert 2 in sessions
    assert any(isinstance(r.msg, Hello) and r.session == 2 for r in after)
    assert link.counters.reconnects == 1
    assert link.counters.frames > len(before)


def test_a_board_reset_on_the_same_port_starts_a_new_session() -> None:
    with FakeBoard() as board, _fast_link(board.path) as link:
        time.sleep(1.2)  # well after the handshake's GET_INFO
        _collect(link, 0.1)
        board.reboot()
        after = _collect(link, 0.4)
    hellos = [r for r in after if isinstance(r.msg, Hello)]
    assert hellos and hellos[0].session == 2
    assert all(r.session == 2 for r in after[after.index(hellos[0]) :])
    assert link.counters.board_restarts == 1 and link.counters.reconnects == 0


def test_no_reconnect_mode_reports_the_unplug() -> None:
    with FakeBoard() as board:
        link = Link(board.port, reconnect=False, handshake_timeout_s=1.5, get_info_after_s=0.05)
        link.start()
        board.unplug()
        time.sleep(0.3)
        assert link.error is not None and "disconnected" in str(link.error)
        link.close()


# ---------------------------------------------------------------------- the real firmware
from tests import emulator_fixtures  # noqa: E402

uno_elf = emulator_fixtures.uno_elf
emulator_built = emulator_fixtures.emulator_built
emulator_factory = emulator_fixtures.emulator_factory


def test_commands_against_the_real_firmware(uno_elf: object, emulator_factory: object) -> None:
    emu = emulator_factory(distance_m=1.0)  # type: ignore[operator]
    with Link(emu.pty_path) as link:
        assert link.hello is not None and link.hello.timer_hz == 2_000_000
        assert isinstance(link.command(Stop()), Ack)
        with pytest.raises(LinkError, match="bad_cycle"):
            link.command(SetConfig(10, 1, 23324, 40000, 1000))
        ack = link.command(SetConfig(100, 1, 23324, 40000, 1000))
        assert ack.command_id == SetConfig.MSG_ID
        syncs = [r for r in _collect(link, 0.5) if isinstance(r.msg, TimeSyncReply)]
        assert syncs and link.config is not None and link.config.cycle_ms == 100
        assert link.counters.crc_errors == 0 and link.counters.seq_gaps == 0


def test_a_reset_of_the_real_firmware_is_a_new_session(
    uno_elf: object, emulator_factory: object
) -> None:
    emu = emulator_factory(distance_m=1.0)  # type: ignore[operator]
    with Link(emu.pty_path) as link:
        time.sleep(1.2)
        _collect(link, 0.1)
        emu.control.reset()  # the reset button
        after = _collect(link, 0.6)
    assert link.counters.board_restarts == 1
    assert any(isinstance(r.msg, Hello) and r.session == 2 for r in after)
    assert any(isinstance(r.msg, Range) and r.session == 2 for r in after)
