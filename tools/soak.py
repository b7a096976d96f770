#!/usr/bin/env python3
"""Soak: the emulated robot for a long run with UART faults both ways and reconnects.

The whole host pipeline runs in this process as `obstacle-fusion run` would (link thread,
clock model, predicted pairing, fused vision, JSON lines to a counting sink, an MCAP
recording) against the real firmware under simavr with byte faults in both directions
(--uart-drop and --uart-corrupt, half the rate each, --fault-dir both), while a schedule
takes the board away every --reconnect-every seconds, alternately killing the emulator
(SIGKILL; the robot restarts it, the link reconnects) and resetting the MCU through the
control socket. It prints:

* memory: the process's RSS sampled every few seconds; growth from the end of the warm-up
  (the first fifth of the run, at least 15 s) to the end, as a percentage (target <= 5 %);
* lost frames: an independent decoder reads a copy of every byte the link reads and, for
  each pair of HEARTBEATs of one firmware session, checks frames received + frames the
  sequence numbers say were lost == the frames the firmware says it sent (HEARTBEAT
  frames_sent); the link's own lost-frame counter is compared with the independent sum;
* the MCAP: complete for our reader, readable by the standard mcap indexed reader with
  every message, and `obstacle-fusion replay` on it exits 0 with one record per frame.

Usage: nice -n 15 .venv/bin/python tools/soak.py [--minutes 30] [--reconnect-every 300]
       [--fault-rate 0.01] [--json]   (--seconds S for short runs)
"""

from __future__ import annotations

import argparse
import io
import json
import logging
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from cobs import cobs
from obstacle_fusion.app import App, RunSettings
from obstacle_fusion.link.connection import Link
from obstacle_fusion.outputs.jsonl import JsonLinesWriter
from obstacle_fusion.outputs.mcap_file import TOPIC_IMAGE, TOPIC_OBSTACLE, McapRecorder
from obstacle_fusion.protocol.codec import FrameError, decode_body
from obstacle_fusion.protocol.generated import Heartbeat, Hello
from obstacle_fusion.sim.emulated_robot import EmulatedRobot
from obstacle_fusion.sim.scenario import Scenario, Segment, demo_scenario
from obstacle_fusion.sim.synthetic_camera import SyntheticCamera, synthetic_camera_model
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.rig import Rig

log = logging.getLogger("soak")


def looped_demo(seconds: float) -> Scenario:
    """The demo scene played again and again for at least ``seconds``."""
    demo = demo_scenario()
    span = demo.duration_s
    segs: list[Segment] = []
    k = 0
    while k * span < seconds + span:
        off = k * span
        segs += [Segment(s.t0 + off, s.t1 + off, s.obstacle, s.d0, s.d1) for s in demo.segments]
        k += 1
    return Scenario(tuple(segs), demo.temperature_c, "demo-looped")


class TeeSerial:
    """A serial port whose reads are also handed to an observer (the independent count)."""

    def __init__(self, inner: Any, sink: FrameCounter) -> None:
        self._inner = inner
        self._sink = sink
        sink.new_connection()

    def read(self, n: int = 1) -> bytes:
        data = self._inner.read(n)
        if data:
            self._sink.feed(data)
        return bytes(data)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._inner, name)


@dataclass
class FrameCounter:
    """Every good frame's sequence number, decoded apart from the link, accounted as it
    comes (nothing kept per frame: the soak must not grow by its own bookkeeping)."""

    bad: int = 0
    frames: int = 0
    lost: int = 0  # gaps in the numbering; a HELLO numbered 0 (a restart) starts it again
    lost_link_rule: int = 0  # the same with the link's rule: no gap counted into any HELLO
    spans: int = 0
    spans_mismatched: int = 0
    device: int = 0
    received: int = 0
    lost_in_spans: int = 0
    _buf: bytearray = field(default_factory=bytearray)
    _prev: int | None = None
    _prev_link: int | None = None
    _since_hb: int = 0  # frames received since the last HEARTBEAT of this firmware session
    _lost_since_hb: int = 0
    _last_hb_sent: int | None = None
    lock: threading.Lock = field(default_factory=threading.Lock)

    def new_connection(self) -> None:
        with self.lock:
            self._buf.clear()
            self._prev = self._prev_link = None
            self._last_hb_sent = None

    def feed(self, data: bytes) -> None:
        with self.lock:
            self._buf += data
            *frames, rest = bytes(self._buf).split(b"\x00")
            self._buf = bytearray(rest)
            for raw in frames:
                if not raw:
                    continue
                try:
                    body = cobs.decode(raw)
                    msg = decode_body(bytes(body))
                except (cobs.DecodeError, FrameError):
                    self.bad += 1
                    continue
                self._count(body[1], msg)

    def _count(self, seq: int, msg: Any) -> None:
        self.frames += 1
        hello = isinstance(msg, Hello)
        if hello and seq == 0:
            self._prev = None  # the firmware restarted: its numbering starts again
            self._last_hb_sent = None
        gap = 0 if self._prev is None else (seq - self._prev - 1) & 0xFF
        self._prev = seq
        self.lost += gap
        if self._prev_link is not None and not hello:
            self.lost_link_rule += (seq - self._prev_link - 1) & 0xFF
        self._prev_link = seq
        self._since_hb += 1
        self._lost_since_hb += gap
        if isinstance(msg, Heartbeat):
            last = self._last_hb_sent
            if last is not None and msg.frames_sent >= last:
                d = msg.frames_sent - last
                self.spans += 1
                self.device += d
                self.received += self._since_hb
                self.lost_in_spans += self._lost_since_hb
                if self._since_hb + self._lost_since_hb != d:
                    self.spans_mismatched += 1
            self._last_hb_sent = msg.frames_sent
            self._since_hb = self._lost_since_hb = 0

    def account(self) -> dict[str, int]:
        with self.lock:
            return {
                "heartbeat_spans": self.spans,
                "spans_mismatched": self.spans_mismatched,
                "device_frames_sent": self.device,
                "frames_received": self.received,
                "frames_lost_by_seq": self.lost_in_spans,
                "independent_seq_lost_total": self.lost,
                "independent_frames_total": self.frames,
                "independent_lost_link_rule": self.lost_link_rule,
                "bad_frames_seen": self.bad,
            }


def rss_kb(pid: int | str = "self") -> int:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    return 0


@dataclass
class SoakReport:
    seconds: float
    records: int
    paired_fraction: float
    reconnects_done: int
    link: dict[str, Any]
    accounting: dict[str, int]
    rss_kb_after_warmup: int
    rss_kb_end: int
    rss_kb_max: int
    rss_growth_pct: float
    rss_samples: list[tuple[float, int]]
    mcap_complete: bool
    mcap_messages_indexed: int
    mcap_messages_ours: int
    mcap_frames: int
    replay_exit: int
    replay_records: int
    emulator_restarts: int
    ok: bool = False
    problems: list[str] = field(default_factory=list)


def soak(
    seconds: float,
    reconnect_every_s: float,
    fault_rate: float,
    workdir: Path,
    sample_every_s: float = 5.0,
) -> SoakReport:
    scenario = looped_demo(seconds)
    robot = EmulatedRobot(
        scenario,
        extra={
            "uart_drop": fault_rate / 2,
            "uart_corrupt": fault_rate / 2,
            "fault_dir": "both",
        },
    ).start()
    counter = FrameCounter()
    camera = synthetic_camera_model(500, 375)
    source = SyntheticCamera(scenario, camera, Rig(), fps=15.0, scene_time=robot.scene_time)
    mcap = workdir / "soak.mcap"
    recorder = McapRecorder(mcap, overwrite=True)
    sink = io.StringIO()
    jsonl = JsonLinesWriter(sink)
    link = Link(
        robot.port,
        serial_factory=lambda port, baud: TeeSerial(
            __import__("serial").serial_for_url(
                port, baudrate=baud, timeout=0.02, write_timeout=1.0
            ),
            counter,
        ),
    )
    app = App(
        RunSettings(duration_s=seconds, mode="soak", temperature_c=scenario.temperature_c),
        link,
        source,
        Measurer(camera, Rig(), "fused"),
        jsonl=jsonl,
        recorder=recorder,
        robot=robot,
    )
    samples: list[tuple[float, int]] = []
    done = threading.Event()
    reconnects = [0]
    records = [0]
    publish = app._publish

    def count(batch: list[Any]) -> None:
        records[0] += len(batch)
        publish(batch)
        if sink.tell() > 1 << 20:  # keep the sink from growing: it stands for a pipe
            sink.seek(0)
            sink.truncate()

    app._publish = count  # type: ignore[method-assign,assignment]
    t_start = time.monotonic()

    def schedule() -> None:
        next_sample = t_start
        next_reconnect = t_start + reconnect_every_s
        while not done.wait(0.2):
            now = time.monotonic()
            if now >= next_sample:
                samples.append((now - t_start, rss_kb()))
                next_sample += sample_every_s
            if now >= next_reconnect:
                next_reconnect += reconnect_every_s
                emu = robot.emulator
                if emu is None or not emu.running():
                    continue
                if reconnects[0] % 2 == 0:
                    log.info("soak: killing the emulator (pid %s)", emu.pid)
                    os.kill(emu.pid or 0, signal.SIGKILL)
                else:
                    log.info("soak: resetting the MCU through the control socket")
                    try:
                        emu.control.reset()
                    except Exception as exc:  # noqa: BLE001 - reported, the soak goes on
                        log.warning("reset failed: %s", exc)
                reconnects[0] += 1

    helper = threading.Thread(target=schedule, name="soak-schedule", daemon=True)
    helper.start()
    try:
        result = app.run()
    finally:
        done.set()
        helper.join(timeout=5)
        recorder.close()
        source.close()
        robot.stop()
    samples.append((time.monotonic() - t_start, rss_kb()))
    warm = max(15.0, 0.2 * seconds)
    after = [kb for t, kb in samples if t >= warm]
    base = after[0] if after else samples[-1][1]
    end = max(kb for _, kb in samples[-3:])
    report = SoakReport(
        seconds=time.monotonic() - t_start,
        records=records[0],
        paired_fraction=result.stats["fusion"]["paired_fraction"],
        reconnects_done=reconnects[0],
        link=result.stats["link"],
        accounting=counter.account(),
        rss_kb_after_warmup=base,
        rss_kb_end=end,
        rss_kb_max=max(kb for _, kb in samples),
        rss_growth_pct=100.0 * (end - base) / base if base else 0.0,
        rss_samples=samples,
        mcap_complete=False,
        mcap_messages_indexed=0,
        mcap_messages_ours=0,
        mcap_frames=0,
        replay_exit=-1,
        replay_records=0,
        emulator_restarts=result.stats["emulator_restarts"],
    )
    check_mcap(mcap, report)
    judge(report)
    return report


def check_mcap(path: Path, report: SoakReport) -> None:
    from mcap.reader import make_reader
    from obstacle_fusion.outputs.mcap_file import read_recording

    ours = read_recording(path)
    report.mcap_complete = ours.complete
    report.mcap_messages_ours = len(ours.messages)
    report.mcap_frames = sum(m.topic == TOPIC_IMAGE for m in ours.messages)
    obstacles = sum(m.topic == TOPIC_OBSTACLE for m in ours.messages)
    with path.open("rb") as f:
        report.mcap_messages_indexed = sum(1 for _ in make_reader(f).iter_messages())
    proc = subprocess.run(
        [sys.executable, "-m", "obstacle_fusion", "replay", str(path)],
        capture_output=True,
        text=True,
        timeout=3600,
    )
    report.replay_exit = proc.returncode
    report.replay_records = len(proc.stdout.splitlines())
    if obstacles != report.mcap_frames:
        report.problems.append(f"{report.mcap_frames} frames but {obstacles} obstacle records")


def judge(r: SoakReport) -> None:
    a = r.accounting
    if r.rss_growth_pct > 5.0:
        r.problems.append(f"RSS grew {r.rss_growth_pct:.1f} % after the warm-up (limit 5 %)")
    if a["heartbeat_spans"] == 0 or a["spans_mismatched"]:
        r.problems.append(
            f"{a['spans_mismatched']} of {a['heartbeat_spans']} heartbeat spans do not add up"
        )
    # Frames received + frames lost spans the firmware's numbering whichever frames a
    # decoder recovers, so the link's sum must match the independent one counted with the
    # link's own rule (no gap into a HELLO); what that rule leaves out is reported apart.
    link_span = r.link["frames"] + r.link["seq_gaps"]
    indep_span = a["independent_frames_total"] + a["independent_lost_link_rule"]
    if link_span != indep_span:
        r.problems.append(
            f"the link's frames + lost = {link_span}, the independent decoder's {indep_span}"
        )
    if not r.mcap_complete or r.mcap_messages_indexed != r.mcap_messages_ours:
        r.problems.append(
            f"MCAP: complete={r.mcap_complete}, indexed reader {r.mcap_messages_indexed} "
            f"messages, ours {r.mcap_messages_ours}"
        )
    if r.replay_exit != 0 or r.replay_records != r.mcap_frames:
        r.problems.append(
            f"replay exit {r.replay_exit} with {r.replay_records} records for "
            f"{r.mcap_frames} frames"
        )
    r.ok = not r.problems


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--minutes", type=float, default=30.0)
    ap.add_argument("--seconds", type=float, help="run length in seconds (replaces --minutes)")
    ap.add_argument("--reconnect-every", type=float, default=300.0, help="seconds")
    ap.add_argument("--fault-rate", type=float, default=0.01, help="faulted bytes, both ways")
    ap.add_argument("--workdir", type=Path, help="keep the MCAP here")
    ap.add_argument("--json", action="store_true", help="the report as one JSON line")
    args = ap.parse_args()
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    seconds = args.seconds if args.seconds is not None else 60.0 * args.minutes
    with tempfile.TemporaryDirectory(prefix="soak-") as tmp:
        workdir = args.workdir or Path(tmp)
        workdir.mkdir(parents=True, exist_ok=True)
        r = soak(seconds, args.reconnect_every, args.fault_rate, workdir)
    if args.json:
        print(json.dumps(asdict(r)))
        return 0 if r.ok else 1
    a = r.accounting
    print(f"soak: {r.seconds:.0f} s, {r.records} records, {100 * r.paired_fraction:.2f} % paired")
    print(
        f"  reconnects: {r.reconnects_done} forced, link reconnects {r.link['reconnects']}, "
        f"board restarts {r.link['board_restarts']}, emulator restarts {r.emulator_restarts}"
    )
    print(
        f"  memory: RSS {r.rss_kb_after_warmup / 1024:.1f} MiB after warm-up, "
        f"{r.rss_kb_end / 1024:.1f} MiB at the end ({r.rss_growth_pct:+.2f} %), max "
        f"{r.rss_kb_max / 1024:.1f} MiB"
    )
    print(
        f"  link: {r.link['frames']} frames, {r.link['crc_errors']} CRC errors, "
        f"{r.link['bad_frames']} bad frames, {r.link['seq_gaps']} lost; independent decoder: "
        f"{a['independent_frames_total']} frames, {a['independent_seq_lost_total']} lost "
        f"({a['independent_lost_link_rule']} by the link's rule: "
        f"{a['independent_seq_lost_total'] - a['independent_lost_link_rule']} lost just "
        "before a HELLO that did not restart the numbering are not in the link's count)"
    )
    print(
        f"  accounting: {a['heartbeat_spans']} heartbeat spans, {a['device_frames_sent']} "
        f"frames sent by the firmware = {a['frames_received']} received + "
        f"{a['frames_lost_by_seq']} lost; {a['spans_mismatched']} spans mismatched"
    )
    print(
        f"  MCAP: complete {r.mcap_complete}, {r.mcap_messages_ours} messages "
        f"(indexed reader: {r.mcap_messages_indexed}), {r.mcap_frames} frames; replay exit "
        f"{r.replay_exit}, {r.replay_records} records"
    )
    print("  result: " + ("OK" if r.ok else "FAILED: " + "; ".join(r.problems)))
    return 0 if r.ok else 1


if __name__ == "__main__":
    sys.exit(main())
