"""The emulator itself, with its own small test firmwares (tools/emulator/testfw):
echo timing, the scene, the control channel, pacing, the UART bridge and the quirk fixes."""

from __future__ import annotations

import math
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest
import serial
from obstacle_fusion.sim.emulator import (
    Emulator,
    EmulatorConfig,
    EmulatorError,
    TruthRecord,
    check_built,
    parse_truth_line,
    wait_for,
)

from tests import emulator_fixtures
from tests.emulator_fixtures import firmware_for_tests

# Fixtures from the shared module (pytest finds them as module attributes).
emulator_built = emulator_fixtures.emulator_built
emulator_factory = emulator_fixtures.emulator_factory
uno_elf = emulator_fixtures.uno_elf

Factory = Callable[..., Emulator]


def sound_speed(t_c: float) -> float:
    return 331.3 * math.sqrt(1.0 + t_c / 273.15)


class TextPort:
    """Line-oriented reader for the test firmwares' plain-text output."""

    def __init__(self, path: str) -> None:
        self.serial = serial.Serial(path, 115200, timeout=0.05)
        self.buf = b""

    def lines(self, seconds: float, until: Callable[[list[str]], bool] | None = None) -> list[str]:
        out: list[str] = []
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            self.buf += self.serial.read(4096)
            *done, self.buf = self.buf.split(b"\n")
            out.extend(x.decode(errors="replace") for x in done)
            if until is not None and until(out):
                break
        return out

    def close(self) -> None:
        self.serial.close()


def ranges(lines: list[str]) -> dict[int, int]:
    """`R <n> <trigger_tick> <echo_ticks>` lines of echo_test -> {n: echo_ticks}."""
    out = {}
    for line in lines:
        f = line.split()
        if len(f) == 4 and f[0] == "R":
            out[int(f[1])] = int(f[3])
    return out


def run_echo_test(
    factory: Factory, count: int, **config: object
) -> tuple[dict[int, int], list[TruthRecord], Emulator]:
    emu = factory(elf=firmware_for_tests("echo_test"), fast=True, **config)
    port = TextPort(emu.pty_path)
    try:
        lines = port.lines(30.0, until=lambda ls: len(ranges(ls)) >= count)
    finally:
        port.close()
    assert lines and lines[0] == "HELLO echo_test", lines[:3]
    assert wait_for(lambda: len(emu.truth.read()) >= count, 5.0)
    return ranges(lines), emu.truth.read(), emu


def test_echo_width_exact_to_one_tick_over_the_range(
    emulator_factory: Factory, tmp_path: Path
) -> None:
    scene = tmp_path / "sweep.txt"
    scene.write_text("# sweep the whole range\ntemperature 25\n0 0.02\n15 4.0\n")
    got, truth, _ = run_echo_test(emulator_factory, 240, scene=scene)
    by_index = {r.index: r for r in truth}
    assert len(got) >= 240
    distances = []
    for n, ticks in got.items():
        rec = by_index[n]
        assert rec.kind == "echo"
        assert abs(ticks - rec.echo_ticks) <= 1.0, (n, ticks, rec)
        # The sensor's physics: width = 2 d / v(T), to one CPU cycle.
        assert rec.distance_m is not None
        assert rec.echo_s == pytest.approx(2 * rec.distance_m / sound_speed(25.0), abs=1 / 16e6)
        assert rec.temperature_c == 25.0
        distances.append(rec.distance_m)
    assert min(distances) < 0.05 and max(distances) > 3.5


def test_scene_keyframes_interpolate_and_step(emulator_factory: Factory, tmp_path: Path) -> None:
    scene = tmp_path / "scene.txt"
    scene.write_text("0 1.0\n2 2.0  # ramp\n3 none\n4 0.5\n4 0.7\n")
    _, truth, _ = run_echo_test(emulator_factory, 90, scene=scene)

    def expected(t: float) -> float | None:
        if t < 2:
            return 1.0 + (t / 2.0)
        if t < 3:
            return 2.0  # a segment ending in `none` holds its first value
        if t < 4:
            return None
        return 0.7  # equal times: the later keyframe wins

    def at_reflection(rec: TruthRecord) -> float | None:
        """The distance when the burst (leaving as ECHO rises) meets the face: d(rise + d/v)."""
        rise_s = rec.rise_cycle / 16e6
        v = sound_speed(rec.temperature_c)
        ramp = (1.0 + rise_s / 2.0) / (1.0 - 1.0 / (2.0 * v))  # d = 1 + (rise + d / v) / 2
        if rise_s + ramp / v < 2:
            return ramp
        if expected(rise_s) is None:
            return None
        return next((c for c in (2.0, 0.7) if expected(rise_s + c / v) == c), None)

    moved = 0
    for rec in truth:
        want = at_reflection(rec)
        if want is None:
            assert rec.distance_m is None and rec.kind == "none"
            assert rec.echo_ticks == pytest.approx(76000, abs=1)
        else:
            assert rec.distance_m == pytest.approx(want, abs=1e-6), rec
            at_trigger = expected(rec.trigger_s)
            moved += at_trigger is not None and abs(rec.distance_m - at_trigger) > 1e-3
    # on the 0.5 m/s ramp the face moves 2-3 mm between the trigger and the reflection
    assert moved >= 10


def test_no_obstacle_and_beyond_range_give_the_38ms_pulse(emulator_factory: Factory) -> None:
    got, truth, _ = run_echo_test(emulator_factory, 5, distance_m=None)
    assert all(r.kind == "none" and r.echo_s == pytest.approx(0.038) for r in truth)
    assert all(abs(t - 76000) <= 1 for t in got.values())
    _, truth, _ = run_echo_test(emulator_factory, 5, distance_m=4.5)
    assert all(r.kind == "beyond" and r.distance_m == 4.5 for r in truth)


def test_dropouts_and_noise(emulator_factory: Factory) -> None:
    _, truth, _ = run_echo_test(emulator_factory, 20, distance_m=1.0, dropout=1.0)
    assert all(r.kind == "dropout" and r.echo_s == pytest.approx(0.038) for r in truth)
    _, truth, _ = run_echo_test(emulator_factory, 200, distance_m=1.0, noise_mm=10.0, seed=7)
    errs = [(r.echo_distance_m or 0.0) - 1.0 for r in truth]
    sd = math.sqrt(sum(e * e for e in errs) / len(errs))
    assert 0.007 < sd < 0.013
    assert all(r.distance_m == 1.0 for r in truth)


def test_control_channel_moves_the_obstacle_live(emulator_factory: Factory) -> None:
    emu = emulator_factory(elf=firmware_for_tests("echo_test"), distance_m=1.0)
    port = TextPort(emu.pty_path)
    try:
        port.lines(0.4)
        emu.control.set_distance(2.5)
        emu.control.set_temperature(0.0)
        t_change = emu.control.sim_time()
        lines = port.lines(0.6)
    finally:
        port.close()
    truth = emu.truth.read()
    before = [r for r in truth if r.trigger_s < t_change - 0.07]
    after = [r for r in truth if r.trigger_s > t_change + 0.001]
    assert before and all(r.distance_m == 1.0 for r in before)
    assert after and all(r.distance_m == 2.5 and r.temperature_c == 0.0 for r in after)
    got = ranges(lines)
    for r in after:
        if r.index in got:
            assert abs(got[r.index] - r.echo_ticks) <= 1
    with pytest.raises(EmulatorError, match="not metres"):
        emu.control.command("distance far")
    stats = emu.control.stats()
    assert stats["measurements"] >= len(truth)


def test_real_time_pacing_and_crystal_error(emulator_factory: Factory) -> None:
    def rate(ppm: float) -> float:
        emu = emulator_factory(
            elf=firmware_for_tests("echo_test"), clock_ppm=ppm, wait_client=False
        )
        s0, w0 = emu.control.sim_time(), time.monotonic()
        time.sleep(1.0)
        s1, w1 = emu.control.sim_time(), time.monotonic()
        emu.stop()
        return (s1 - s0) / (w1 - w0)

    nominal = rate(0.0)
    fast_crystal = rate(50000.0)  # 5 % fast: 1.05 MCU seconds per wall second
    assert nominal == pytest.approx(1.0, abs=0.03)
    assert fast_crystal / nominal == pytest.approx(1.05, abs=0.02)


def test_clock_ppm_scales_the_echo_in_mcu_ticks(emulator_factory: Factory) -> None:
    got, truth, _ = run_echo_test(emulator_factory, 20, distance_m=2.0, clock_ppm=1000.0)
    for rec in truth:
        assert rec.echo_s == pytest.approx(2 * 2.0 / sound_speed(20.0), abs=1e-7)
        assert rec.echo_ticks == pytest.approx(rec.echo_s * 2e6 * 1.001, abs=0.2)
        if rec.index in got:
            assert abs(got[rec.index] - rec.echo_ticks) <= 1
    assert len(set(got) & {r.index for r in truth}) >= 20


def test_bytes_from_the_host_reach_the_firmware(emulator_factory: Factory) -> None:
    emu = emulator_factory(elf=firmware_for_tests("echo_test"), fast=True, distance_m=1.0)
    port = TextPort(emu.pty_path)
    try:
        port.lines(0.2)
        port.serial.write(b"Az\x00\xff")
        lines = port.lines(3.0, until=lambda ls: sum(x.startswith("E ") for x in ls) >= 4)
    finally:
        port.close()
    assert [x for x in lines if x.startswith("E ")] == ["E 41", "E 7a", "E 00", "E ff"]


def test_quirk_fixes_make_simavr_behave_like_the_chip(emulator_factory: Factory) -> None:
    def probe(fixes: bool) -> list[str]:
        emu = emulator_factory(elf=firmware_for_tests("quirks_test"), fast=True, quirk_fixes=fixes)
        port = TextPort(emu.pty_path)
        try:
            return port.lines(5.0, until=lambda ls: "DONE" in ls)
        finally:
            port.close()

    ok = ["TIFR ok", "SEI ok", "PCIFR ok", "EIFR ok", "INT ok", "WDT wdr ok", "WDT reset"]
    assert probe(True)[:8] == [*ok, "DONE"]
    # Without them, Debian's simavr 1.6 shows every fault (so the fixes are needed).
    bad = ["TIFR bad", "SEI bad", "PCIFR bad", "EIFR bad", "INT bad", "WDT wdr ok", "WDT bad"]
    assert probe(False)[:8] == [*bad, "DONE"]


def test_bad_scene_file_is_named_with_its_line(emulator_built: Path, tmp_path: Path) -> None:
    scene = tmp_path / "bad.txt"
    scene.write_text("0 1.0\n1 far\n")
    emu = Emulator(
        config=EmulatorConfig(elf=firmware_for_tests("echo_test"), scene=scene),
        binary=emulator_built,
    )
    with pytest.raises(EmulatorError, match=r"bad\.txt:2: bad distance 'far'"):
        emu.start()
    emu.cleanup()


def test_missing_files_say_run_make_setup(tmp_path: Path) -> None:
    with pytest.raises(EmulatorError, match="make setup"):
        check_built(tmp_path / "none.elf")
    with pytest.raises(EmulatorError, match="make setup"):
        check_built(binary=tmp_path / "no-emulator")
    proc = subprocess.run(
        [sys.executable, "-m", "obstacle_fusion", "emulate", "--elf", str(tmp_path / "none.elf")],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert proc.returncode == 2
    assert "make setup" in proc.stderr and "Traceback" not in proc.stderr


def test_truth_line_parsing() -> None:
    rec = parse_truth_line("3 0.181 0.005827 11654.500 1.000000 nan 20.00 dropout 1 2 3")
    assert rec is not None and rec.distance_m == 1.0 and rec.echo_distance_m is None
    assert not rec.has_echo
    assert parse_truth_line("# comment") is None
    with pytest.raises(ValueError):
        parse_truth_line("1 2 3")


def test_emulate_cli_prints_the_pty_and_stops_after_duration(
    emulator_built: Path, tmp_path: Path
) -> None:
    truth = tmp_path / "truth.log"
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "obstacle_fusion",
            "emulate",
            "--elf",
            str(firmware_for_tests("echo_test")),
            "--fast",
            "--duration",
            "1.5",
            "--distance",
            "0.7",
            "--truth",
            str(truth),
        ],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("/dev/pts/")
    records = [r for r in map(parse_truth_line, truth.read_text().splitlines()) if r]
    assert len(records) > 5 and all(r.distance_m == 0.7 for r in records)


def after_hello(lines: list[str]) -> list[str]:
    starts = [i for i, x in enumerate(lines) if x.endswith("HELLO echo_test")]
    return lines[starts[-1] + 1 :] if starts else []


def test_mcu_reset_reboots_the_firmware_and_the_sensor_goes_on(emulator_factory: Factory) -> None:
    emu = emulator_factory(elf=firmware_for_tests("echo_test"), fast=True, distance_m=3.0)
    port = TextPort(emu.pty_path)
    try:
        assert port.lines(0.3)[0] == "HELLO echo_test"
        emu.control.reset()
        lines = port.lines(3.0, until=lambda ls: len(ranges(after_hello(ls))) >= 3)
    finally:
        port.close()
    # A reset can cut a line short, as on a board: "R 42HELLO echo_test".
    after = ranges(after_hello(lines))
    assert min(after) == 0 and len(after) >= 3  # the counter restarted with the firmware
    assert emu.control.stats()["resets"] == 1


def test_spikes_answer_from_random_distances(emulator_factory: Factory) -> None:
    got, truth, _ = run_echo_test(emulator_factory, 30, distance_m=1.0, spike=1.0, seed=5)
    assert all(r.kind == "spike" and r.distance_m == 1.0 for r in truth)
    spikes = [r.echo_distance_m for r in truth]
    assert all(d is not None and 0.02 <= d <= 4.0 for d in spikes)
    assert len({round(d or 0, 3) for d in spikes}) > 20
    assert all(abs(got[r.index] - r.echo_ticks) <= 1 for r in truth if r.index in got)


def test_uart_faults_towards_the_mcu(emulator_factory: Factory) -> None:
    emu = emulator_factory(
        elf=firmware_for_tests("echo_test"), fast=True, uart_corrupt=1.0, fault_dir="rx"
    )
    port = TextPort(emu.pty_path)
    try:
        port.lines(0.2)
        port.serial.write(b"A" * 8)
        lines = port.lines(3.0, until=lambda ls: sum(x.startswith("E ") for x in ls) >= 8)
    finally:
        port.close()
    got = [int(x.split()[1], 16) for x in lines if x.startswith("E ")]
    assert len(got) == 8
    assert all(bin(v ^ 0x41).count("1") == 1 for v in got)  # one flipped bit each
    assert emu.control.stats()["corrupted"] == 8


def test_no_orphan_when_the_starting_process_dies(emulator_built: Path) -> None:
    script = (
        "import sys\n"
        "from pathlib import Path\n"
        "from obstacle_fusion.sim.emulator import Emulator, EmulatorConfig\n"
        f"emu = Emulator(EmulatorConfig(elf=Path({str(firmware_for_tests('echo_test'))!r})),"
        f" binary=Path({str(emulator_built)!r})).start()\n"
        "print(emu.pid, flush=True)\n"
    )
    proc = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=60
    )
    assert proc.returncode == 0, proc.stderr
    pid = int(proc.stdout.split()[0])

    def gone() -> bool:
        try:
            with open(f"/proc/{pid}/stat") as fh:
                return fh.read().split()[2] == "Z"
        except FileNotFoundError:
            return True

    assert wait_for(gone, 5.0), f"emulator {pid} outlived its parent"


def test_control_path_never_deletes_a_users_file(emulator_built: Path, tmp_path: Path) -> None:
    """A mistyped --control naming an existing file is refused, and the file is kept."""
    precious = tmp_path / "notes.txt"
    precious.write_text("keep me\n")
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "obstacle_fusion",
            "emulate",
            "--elf",
            str(firmware_for_tests("echo_test")),
            "--fast",
            "--duration",
            "0.5",
            "--control",
            str(precious),
        ],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert proc.returncode == 2
    assert "not a socket" in proc.stderr and "Traceback" not in proc.stderr
    assert precious.read_text() == "keep me\n"


def test_control_socket_of_a_running_emulator_is_not_stolen(
    emulator_factory: Factory, emulator_built: Path
) -> None:
    first = emulator_factory(elf=firmware_for_tests("echo_test"), fast=True)
    assert first.workdir is not None
    sock = first.workdir / "control.sock"
    proc = subprocess.run(
        [
            str(emulator_built),
            "--fast",
            "--duration",
            "0.2",
            "--control",
            str(sock),
            str(firmware_for_tests("echo_test")),
        ],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert proc.returncode == 2 and "another emulator is listening" in proc.stderr
    # The path still leads to the first emulator (a stolen one would be gone by now).
    assert sock.exists() and "cycle" in first.control.stats()


@pytest.mark.cpu_only  # refused before the emulator starts: on the xdist workers
def test_emulate_cli_names_folders_and_bad_durations(emulator_built: Path, tmp_path: Path) -> None:
    def emulate(*args: str) -> str:
        proc = subprocess.run(
            [sys.executable, "-m", "obstacle_fusion", "emulate", *args],
            capture_output=True,
            text=True,
            timeout=60,
        )
        assert proc.returncode == 2 and "Traceback" not in proc.stderr
        return proc.stderr

    assert "is a folder" in emulate("--elf", str(tmp_path))
    assert "scene file" in emulate("--scene", str(tmp_path)) and "is a folder" in emulate(
        "--scene", str(tmp_path)
    )
    assert "not a regular file" in emulate("--scene", "/dev/null")
    assert "--duration" in emulate("--duration", "nan")
    assert "--duration" in emulate("--duration", "inf")


def test_control_scene_that_is_a_folder_says_why(emulator_factory: Factory, tmp_path: Path) -> None:
    emu = emulator_factory(elf=firmware_for_tests("echo_test"), fast=True)
    with pytest.raises(EmulatorError, match=r"cannot read scene file .*: Is a directory"):
        emu.control.load_scene(tmp_path)


def test_emulate_cli_sensors_option_wires_a_second_sensor(uno_elf: Path, tmp_path: Path) -> None:
    """README lists `emulate --sensors N`; the real firmware then ranges on both (mask 3)."""
    from obstacle_fusion.protocol.generated import Ack, SetConfig

    from tests.emulator_fixtures import FirmwarePort

    bad = subprocess.run(
        [sys.executable, "-m", "obstacle_fusion", "emulate", "--sensors", "5"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert bad.returncode == 2 and "1 to 4 sensors" in bad.stderr
    truth = tmp_path / "truth.log"
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "obstacle_fusion",
            "emulate",
            "--elf",
            str(uno_elf),
            "--sensors",
            "2",
            "--distance",
            "1.5",
            "--truth",
            str(truth),
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert proc.stdout is not None
        port = FirmwarePort(proc.stdout.readline().strip())
        try:
            seq = port.send(
                SetConfig(
                    cycle_ms=60,
                    sensor_mask=3,
                    max_echo_us=23324,
                    echo_timeout_us=40000,
                    heartbeat_ms=1000,
                )
            )
            ack, _ = port.read_until(lambda m: isinstance(m, Ack) and m.command_seq == seq)
            assert ack is not None
            port.collect(0.6)
        finally:
            port.close()
    finally:
        proc.terminate()
        proc.wait(10)
    records = [r for r in map(parse_truth_line, truth.read_text().splitlines()) if r]
    assert {r.sensor_id for r in records} == {0, 1}


def test_a_sensor_scene_for_a_sensor_that_is_not_there_is_refused(
    emulator_built: Path, tmp_path: Path
) -> None:
    scene = tmp_path / "s1.txt"
    scene.write_text("0 1.0\n")
    for sensors, spec, match in (
        (1, (1, scene), r"--sensor-scene 1: there are only 1 sensors"),
        (2, (1, tmp_path / "missing.txt"), r"missing\.txt"),
    ):
        emu = Emulator(
            config=EmulatorConfig(
                elf=firmware_for_tests("echo_test"), sensors=sensors, sensor_scenes=(spec,)
            ),
            binary=emulator_built,
        )
        with pytest.raises(EmulatorError, match=match):
            emu.start()
        emu.cleanup()
