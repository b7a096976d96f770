"""Soak, short: 60 s of the emulated robot with 1 % UART faults both ways and a reconnect
every 20 s (tools/soak.py; the 30-minute run and its figures are in the README).

Memory flat after the warm-up, every lost frame counted (HEARTBEAT-to-HEARTBEAT: frames
received + frames the sequence numbers say were lost == frames the firmware sent, and the
link's counters agree with an independent decoder), the MCAP complete, readable by the
standard indexed reader and replayable.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from tests import emulator_fixtures

uno_elf = emulator_fixtures.uno_elf
emulator_built = emulator_fixtures.emulator_built

SOAK = Path(__file__).resolve().parents[1] / "tools" / "soak.py"


def test_soak_60_s_with_faults_and_reconnects(uno_elf: Path) -> None:
    proc = subprocess.run(
        [sys.executable, str(SOAK), "--seconds", "60", "--reconnect-every", "20", "--json"],
        capture_output=True,
        text=True,
        timeout=400,
    )
    lines = proc.stdout.strip().splitlines()
    assert lines, proc.stderr[-2000:]
    r = json.loads(lines[-1])
    assert r["problems"] == [] and r["ok"], r["problems"]
    assert proc.returncode == 0
    # At 20 s the emulator is killed, at 40 s the MCU reset (and at 60 s killed again when
    # the start-up made the run reach it).
    assert r["reconnects_done"] >= 2
    assert r["link"]["reconnects"] >= 1 and r["emulator_restarts"] >= 1
    a = r["accounting"]
    assert a["heartbeat_spans"] >= 30 and a["spans_mismatched"] == 0
    assert a["frames_lost_by_seq"] > 0, "1 % byte faults must lose some frames"
    assert r["link"]["crc_errors"] > 0
    assert r["rss_growth_pct"] <= 5.0
    assert r["records"] >= 700 and r["paired_fraction"] >= 0.95
    assert r["mcap_complete"] and r["mcap_messages_indexed"] == r["mcap_messages_ours"] > 0
    assert r["replay_exit"] == 0 and r["replay_records"] == r["mcap_frames"] == r["records"]
