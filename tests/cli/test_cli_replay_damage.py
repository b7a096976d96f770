"""replay and recover on damaged, cut, foreign and unreadable recordings: every intact
message used, what was lost counted and said, an exit code that says it, no traceback."""

from __future__ import annotations

import base64
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import pytest
from obstacle_fusion.outputs.mcap_file import McapRecorder, read_recording
from obstacle_fusion.protocol.generated import Range
from obstacle_fusion.sonar import SonarConverter
from obstacle_fusion.sources.frames import Frame

from tests.cli_fixtures import unreadable_run

#: one xdist worker builds the module fixture once (run_tests.sh: --dist loadgroup)
pytestmark = [pytest.mark.cpu_only, pytest.mark.xdist_group("replay_damage")]

N_FRAMES = 117


def _cli(*args: str, stdin: Any = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "obstacle_fusion", *args],
        capture_output=True,
        text=True,
        timeout=120,
        stdin=stdin,
    )


def _image(i: int) -> np.ndarray:
    img = np.full((120, 160, 3), 90, np.uint8)
    cv2.rectangle(img, (50 + i % 7, 30), (110, 100), (200, 200, 200), -1)
    return img


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """117 frames at 15 fps and a range every 1/16 s, written by the recorder, chunks closed
    about every 10 frames (so damage in the middle hits one chunk of many)."""
    path = tmp_path_factory.mktemp("rec") / "whole.mcap"
    conv = SonarConverter(timer_hz=2_000_000)
    rec = McapRecorder(path, flush_interval_s=0.0, chunk_size=40_000)
    t0 = 100.0
    k = 0
    for i in range(N_FRAMES):
        t = t0 + i / 15
        while t0 + k / 16 <= t + 0.1:
            tr = t0 + k / 16
            r = conv.convert(Range(k, 0, 1000 + k * 62_500, 7000, 0), tr, tr + 0.01)
            rec.write_range(r, 2_000_000, 1, log_t=tr + 0.01)
            k += 1
        rec.write_frame(Frame(_image(i), t, i, "test"), log_t=t + 0.005)
    rec.close()
    return path


def _damage_middle(src: Path, dst: Path, n: int = 40) -> None:
    """n bytes overwritten inside the middle camera image's data (as a bad sector would)."""
    data = bytearray(src.read_bytes())
    hits = [i for i in range(len(data)) if data.startswith(b'"data":"', i)]
    mid = hits[len(hits) // 2] + 100
    data[mid : mid + n] = b"\xa5" * n
    dst.write_bytes(bytes(data))


def test_the_fixture_replays_whole(recording: Path) -> None:
    res = _cli("replay", str(recording))
    assert res.returncode == 0, res.stderr
    assert f"from {N_FRAMES} frames" in res.stderr
    assert len(res.stdout.splitlines()) == N_FRAMES


def test_damage_in_the_middle_is_reported_and_everything_after_it_replayed(
    recording: Path, tmp_path: Path
) -> None:
    bad = tmp_path / "damaged.mcap"
    _damage_middle(recording, bad)
    res = _cli("replay", str(bad))
    assert res.returncode == 3, res.stderr
    assert "Traceback" not in res.stderr
    assert "lost data" in res.stderr and "damaged region" in res.stderr
    assert "messages lost:" in res.stderr
    frames = [json.loads(line)["frame_index"] for line in res.stdout.splitlines()]
    # One image at most is lost with 40 bytes, and the frames after the damage are all back.
    assert N_FRAMES - 2 <= len(frames) < N_FRAMES or "/camera/image" not in res.stderr
    assert len(frames) >= N_FRAMES - 2
    assert max(frames) == len(frames) - 1  # replay numbers what it read; the last one is there
    rec = read_recording(bad)
    assert rec.complete and rec.damage
    assert sum(m.topic == "/camera/image" for m in rec.messages) >= N_FRAMES - 2


def test_a_cut_recording_is_recovered_into_a_file_the_indexed_reader_reads(
    recording: Path, tmp_path: Path
) -> None:
    from mcap.reader import make_reader

    cut = tmp_path / "cut.mcap"
    data = recording.read_bytes()
    cut.write_bytes(data[: int(len(data) * 0.6)])  # as a SIGKILL leaves it: no summary
    with open(cut, "rb") as fh, pytest.raises(Exception):  # noqa: B017 - any failure
        assert sum(1 for _ in make_reader(fh).iter_messages()) > 0
    fixed = tmp_path / "fixed.mcap"
    res = _cli("recover", str(cut), str(fixed))
    assert res.returncode == 0, res.stderr
    assert "cut short" in res.stderr
    with open(fixed, "rb") as fh:
        reader = make_reader(fh)
        summary = reader.get_summary()
        assert summary is not None and summary.chunk_indexes  # indexed
        topics = [ch.topic for _, ch, _ in reader.iter_messages()]
    whole = read_recording(recording).messages
    assert 0.5 * len(whole) < len(topics) < len(whole)
    back = read_recording(fixed)
    assert back.complete and not back.damage
    assert back.metadata.get("obstacle_fusion")  # metadata carried over
    # The messages before the cut, as recorded (written in log-time order).
    assert [m.data for m in back.messages] == [
        m.data for m in sorted(whole[: len(topics)], key=lambda m: m.log_time_ns)
    ]
    again = _cli("recover", str(cut), str(fixed))
    assert again.returncode == 2 and "already exists" in again.stderr


def test_recover_of_a_damaged_file_keeps_what_follows_the_damage(
    recording: Path, tmp_path: Path
) -> None:
    bad = tmp_path / "damaged.mcap"
    _damage_middle(recording, bad)
    fixed = tmp_path / "fixed.mcap"
    res = _cli("recover", str(bad), str(fixed))
    assert res.returncode == 3 and "damaged" in res.stderr, res.stderr
    res = _cli("replay", str(fixed))
    # A whole file now, but the recorder's sequence numbers still show what is missing.
    assert res.returncode == 3, res.stderr
    assert "damaged region" not in res.stderr and "messages lost: 1 on /camera/image" in res.stderr
    assert len(res.stdout.splitlines()) == N_FRAMES - 1


def _foreign(path: Path) -> None:
    """A file another tool wrote: /sonar/range with other JSON, images without data."""
    from mcap.writer import Writer

    with open(path, "wb") as fh:
        w = Writer(fh)
        w.start()
        sid = w.register_schema("x", "jsonschema", b"{}")
        rng = w.register_channel("/sonar/range", "json", sid)
        img = w.register_channel("/camera/image", "json", sid)
        raw = w.register_channel("/other", "cdr", 0)
        for i in range(5):
            t = 1_000_000_000 + i * 50_000_000
            w.add_message(rng, t, json.dumps({"range": 1.5, "status": "ok"}).encode(), t)
            w.add_message(img, t, json.dumps({"format": "jpeg", "frame_id": "cam"}).encode(), t)
            w.add_message(raw, t, b"\x00\x01\x02", t)
        w.finish()


def test_a_recording_from_another_tool_is_refused_with_counts_not_a_traceback(
    tmp_path: Path,
) -> None:
    path = tmp_path / "foreign.mcap"
    _foreign(path)
    res = _cli("replay", str(path))
    assert res.returncode == 2, res.stderr
    assert "Traceback" not in res.stderr and "KeyError" not in res.stderr
    assert "5 on /camera/image (no image data)" in res.stderr
    assert "5 on /sonar/range (not an obstacle-fusion range)" in res.stderr


def test_foreign_messages_mixed_into_a_recording_are_skipped_and_counted(
    recording: Path, tmp_path: Path
) -> None:
    from mcap.writer import Writer

    whole = read_recording(recording)
    path = tmp_path / "mixed.mcap"
    with open(path, "wb") as fh:
        w = Writer(fh)
        w.start()
        sid = w.register_schema("x", "jsonschema", b"{}")
        chans = {t: w.register_channel(t, "json", sid) for t in ("/sonar/range", "/camera/image")}
        for m in whole.messages:
            if m.topic in chans:
                w.add_message(
                    chans[m.topic], m.log_time_ns, json.dumps(m.data).encode(), m.publish_time_ns
                )
        t = whole.messages[10].log_time_ns
        w.add_message(chans["/sonar/range"], t, b'{"range": "far"}', t)
        bad_jpeg = base64.b64encode(b"not a jpeg").decode()
        w.add_message(chans["/camera/image"], t, json.dumps({"data": bad_jpeg}).encode(), t)
        w.finish()
    res = _cli("replay", str(path))
    assert res.returncode == 0, res.stderr
    assert "skipped 2 messages" in res.stderr
    assert len(res.stdout.splitlines()) == N_FRAMES


def test_replay_of_an_unreadable_file_says_so(recording: Path) -> None:
    import tempfile

    with tempfile.TemporaryDirectory(dir="/tmp") as folder:
        os.chmod(folder, 0o755)
        locked = Path(folder) / "locked.mcap"
        shutil.copy(recording, locked)
        res = unreadable_run(locked, "replay", str(locked))
    assert res.returncode == 2, res.stderr
    assert "permission denied" in res.stderr and "Traceback" not in res.stderr
    res = _cli("replay", "-")
    assert res.returncode == 2 and "not standard input" in res.stderr
