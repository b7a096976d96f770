"""`obstacle-fusion decode` on captures made of golden vectors and garbage."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.cpu_only

ROOT = Path(__file__).resolve().parents[2]
VECTORS = json.loads((ROOT / "protocol" / "vectors" / "golden.json").read_text())


def run_cli(*args: str, stdin: bytes | None = None) -> subprocess.CompletedProcess[bytes]:
    return subprocess.run(
        [sys.executable, "-m", "obstacle_fusion", "decode", *args],
        input=stdin,
        capture_output=True,
        timeout=60,
    )


def capture_bytes() -> bytes:
    garbage = [b"", b"\xff\xfe", b"\x00\x00", b"noise", b"\x01\x02\x03\x00"]
    return b"".join(
        bytes.fromhex(v["frame"]) + garbage[i % len(garbage)] for i, v in enumerate(VECTORS)
    )


def check_output(stdout: bytes) -> None:
    lines = [json.loads(line) for line in stdout.decode().splitlines()]
    messages, final = lines[:-1], lines[-1]
    assert [m["msg"] for m in messages] == [v["message"] for v in VECTORS]
    for m, v in zip(messages, VECTORS, strict=True):
        for name, value in v["fields"].items():
            if isinstance(m[name], str) and not isinstance(value, str):
                continue  # enum fields print by name
            assert m[name] == value
    assert final["stats"]["frames"] == len(VECTORS)
    assert final["stats"]["bytes_discarded"] > 0


def test_decode_file(tmp_path: Path) -> None:
    capture = tmp_path / "capture.bin"
    capture.write_bytes(capture_bytes())
    result = run_cli(str(capture))
    assert result.returncode == 0, result.stderr
    check_output(result.stdout)


def test_decode_stdin() -> None:
    result = run_cli("-", stdin=capture_bytes())
    assert result.returncode == 0, result.stderr
    check_output(result.stdout)


def test_enum_fields_by_name(tmp_path: Path) -> None:
    result = run_cli(
        "-", stdin=bytes.fromhex(next(v["frame"] for v in VECTORS if v["message"] == "range"))
    )
    first = json.loads(result.stdout.decode().splitlines()[0])
    assert first["status"] == "out_of_range"


def test_missing_file_is_a_clear_error(tmp_path: Path) -> None:
    result = run_cli(str(tmp_path / "nope.bin"))
    assert result.returncode != 0
    assert b"no such capture file" in result.stderr
    assert b"Traceback" not in result.stderr


def test_mcap_file_points_to_replay(tmp_path: Path) -> None:
    rec = tmp_path / "run.mcap"
    rec.write_bytes(b"\x89MCAP0\r\n" + b"\x00" * 64)
    result = run_cli(str(rec))
    assert result.returncode == 2
    assert b"replay" in result.stderr and b"Traceback" not in result.stderr


def test_garbage_warns_no_frame(tmp_path: Path) -> None:
    junk = tmp_path / "notes.txt"
    junk.write_text("hello, this is not a capture\n" * 10)
    result = run_cli(str(junk))
    assert result.returncode == 0
    assert json.loads(result.stdout.decode().splitlines()[-1])["stats"]["frames"] == 0
    assert b"no frame found" in result.stderr


def test_a_closed_standard_input_is_a_clear_error() -> None:
    res = subprocess.run(
        [sys.executable, "-m", "obstacle_fusion", "decode", "-"],
        stdin=subprocess.DEVNULL,
        capture_output=True,
        timeout=60,
        preexec_fn=lambda: __import__("os").close(0),
    )
    assert res.returncode == 2, res.stderr
    assert b"standard input is closed" in res.stderr and b"Traceback" not in res.stderr


def test_an_mcap_on_standard_input_gets_a_hint_replay_accepts() -> None:
    res = run_cli("-", stdin=b"\x89MCAP0\r\n" + bytes(100))
    assert res.returncode == 2
    assert b"replay -" not in res.stderr
    assert b"save it to a file, then use `obstacle-fusion replay FILE.mcap`" in res.stderr
