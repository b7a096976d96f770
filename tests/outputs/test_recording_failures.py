"""A recording that fails (disk full) stops the recording, never the sensing."""

from __future__ import annotations

import builtins
import errno
import json
import signal
from pathlib import Path
from typing import IO, Any

import numpy as np
import pytest
from obstacle_fusion.outputs import mcap_file
from obstacle_fusion.outputs.mcap_file import TOPIC_IMAGE, McapRecorder, read_recording
from obstacle_fusion.sources.frames import Frame

from tests import emulator_fixtures

uno_elf = emulator_fixtures.uno_elf
emulator_built = emulator_fixtures.emulator_built


class FullDisk:
    """A file that takes `room` bytes, then fails every write with ENOSPC, as a full disk."""

    def __init__(self, path: Path, room: int) -> None:
        self._f: IO[bytes] = open(path, "wb")  # noqa: SIM115
        self.room = room
        self.refused = 0

    def write(self, data: bytes) -> int:
        if len(data) > self.room:
            self._f.write(bytes(data[: self.room]))
            self.room = 0
            self.refused += 1
            raise OSError(errno.ENOSPC, "No space left on device")
        self.room -= len(data)
        return self._f.write(data)

    def tell(self) -> int:
        return self._f.tell()

    def flush(self) -> None:
        self._f.flush()

    def close(self) -> None:
        self._f.close()


def _full_disk(monkeypatch: pytest.MonkeyPatch, room: int) -> list[FullDisk]:
    made: list[FullDisk] = []

    def open_file(path: Path, mode: str) -> Any:
        if "r" in mode:
            return builtins.open(path, mode)
        made.append(FullDisk(Path(path), room))
        return made[-1]

    # The recorder's module sees this `open` before the builtin one.
    monkeypatch.setattr(mcap_file, "open", open_file, raising=False)
    return made


def _frame(i: int) -> Frame:
    rng = np.random.default_rng(i)
    return Frame(rng.integers(0, 255, (120, 160, 3), dtype=np.uint8), 10.0 + i / 15, i, "test")


def test_a_full_disk_stops_the_recording_once_and_keeps_what_was_written(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    disks = _full_disk(monkeypatch, room=120_000)
    path = tmp_path / "full.mcap"
    rec = McapRecorder(path, flush_interval_s=0.0)  # every message flushed: fails early
    for i in range(200):  # ~25 KB of JPEG each: the disk fills after a few
        rec.write_frame(_frame(i))
        rec.write_event("tick", {"i": i})
    rec.close()
    rec.close()
    assert disks[0].refused == 1  # not one more write once the disk said no
    assert rec.failed is not None and "ENOSPC" in rec.failed and str(path) in rec.failed
    assert rec.dropped > 100
    errors = [r for r in caplog.records if r.levelname == "ERROR"]
    assert len(errors) == 1 and "No space left on device" in errors[0].getMessage()
    back = read_recording(path)
    assert not back.complete
    images = [m for m in back.messages if m.topic == TOPIC_IMAGE]
    assert 0 < len(images) <= rec.counts[TOPIC_IMAGE] < 200


def test_run_goes_on_when_the_recording_fails_and_exits_4(
    uno_elf: Path,
    monkeypatch: pytest.MonkeyPatch,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    caplog: pytest.LogCaptureFixture,
) -> None:
    """`run --json --record` with the disk full after 600 KB (about 2 s): the JSON lines go on to the
    end, the failure is said once on stderr and in the summary, and the exit code is 4."""
    from obstacle_fusion.cli import main

    _full_disk(monkeypatch, room=600_000)
    path = tmp_path / "run.mcap"
    old_term = signal.getsignal(signal.SIGTERM)
    try:
        code = main(["run", "--duration", "5", "--json", "--quiet", "--record", str(path)])
    finally:
        signal.signal(signal.SIGTERM, old_term)
    out, err = capsys.readouterr()
    assert code == 4, err
    records = [json.loads(line) for line in out.splitlines()]
    assert len(records) >= 55  # 15 fps for 5 s: the sensing did not stop with the file
    assert sum(r["distance_m"] is not None for r in records) > 0.9 * len(records)
    assert "Traceback" not in err
    # Said once when it happened (the log, on stderr outside pytest), once in the summary.
    errors = [r.getMessage() for r in caplog.records if r.levelname == "ERROR"]
    assert len(errors) == 1 and "No space left on device" in errors[0]
    assert err.count("No space left on device") == 1 and "recording failed" in err
    assert read_recording(path).messages  # what was written before the failure is there
