"""The C codec, compiled natively with the host's gcc: golden vectors and a noisy stream."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest

pytestmark = pytest.mark.cpu_only

ROOT = Path(__file__).resolve().parents[2]
CORE = ROOT / "firmware" / "core"
CFLAGS = [
    "-std=c99",
    "-Wall",
    "-Wextra",
    "-Werror",
    "-pedantic",
    "-O1",
    "-fsanitize=address,undefined",
]


def build_and_run(source: Path, tmp_path: Path) -> str:
    cc = shutil.which("gcc") or shutil.which("cc")
    if cc is None:
        pytest.fail("no C compiler: run `make setup` (installs gcc)")
    exe = tmp_path / source.stem
    subprocess.run(
        [cc, *CFLAGS, f"-I{CORE}", str(source), str(CORE / "of_frame.c"), "-o", str(exe)],
        check=True,
        capture_output=True,
        text=True,
    )
    result = subprocess.run([str(exe)], capture_output=True, text=True, timeout=30)
    assert result.returncode == 0, result.stdout + result.stderr
    return result.stdout


def test_c_golden_vectors(tmp_path: Path) -> None:
    out = build_and_run(ROOT / "tests" / "protocol_c" / "golden_test.c", tmp_path)
    vectors = json.loads((ROOT / "protocol" / "vectors" / "golden.json").read_text())
    assert f"{len(vectors)} vectors, 0 failures" in out


def test_c_stream_decoder(tmp_path: Path) -> None:
    out = build_and_run(ROOT / "tests" / "protocol_c" / "stream_test.c", tmp_path)
    assert "stream test: 0 failures" in out
