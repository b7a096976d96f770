"""The vision benchmark script runs end to end on a few scenes and prints its tables."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "tools" / "bench_vision.py"


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(SCRIPT), *args], capture_output=True, text=True, timeout=300
    )


def test_per_seed_rows_and_pooled_row() -> None:
    out = run("--seeds", "5,6", "--ordinary", "3", "--hard", "3", "--repeat", "1")
    assert out.returncode == 0, out.stderr
    rows = [line for line in out.stdout.splitlines() if line.startswith("| ")]
    seeds = [row.split("|")[1].strip() for row in rows[1:]]
    assert seeds == ["5", "6", "all 2 (6 + 6 scenes)"]
    # every fused cell is a percentage pair, never nan: the scenes were measured
    assert "nan" not in out.stdout


def test_bad_arguments_are_usage_errors() -> None:
    for args in (("--seeds", "a,b"), ("--repeat", "0")):
        out = run(*args)
        assert out.returncode == 2
        assert "error:" in out.stderr and "Traceback" not in out.stderr


def test_single_seed_table_prints_the_speed_ratio() -> None:
    out = run("--ordinary", "2", "--hard", "2", "--hd", "1", "--repeat", "1")
    assert out.returncode == 0, out.stderr
    line = next(x for x in out.stdout.splitlines() if x.startswith("speed,"))
    fused_ms = float(line.split("fused ")[1].split(" ms")[0])
    paper_ms = float(line.split("OpenCV ")[1].split(" ms")[0])
    ratio = float(line.split("fused is ")[1].split("x")[0])
    assert ratio == pytest.approx(paper_ms / fused_ms, abs=0.06)


def test_speed_mode_prints_only_the_speed_line() -> None:
    out = run("--speed", "--ordinary", "2", "--repeat", "1")
    assert out.returncode == 0, out.stderr
    lines = [x for x in out.stdout.splitlines() if x.strip()]
    assert len(lines) == 1 and lines[0].startswith("speed, ordinary scenes at 500x375")
    fused_ms = float(lines[0].split("fused ")[1].split(" ms")[0])
    paper_ms = float(lines[0].split("OpenCV ")[1].split(" ms")[0])
    ratio = float(lines[0].split("fused is ")[1].split("x")[0])
    assert fused_ms > 0 and paper_ms > 0
    assert ratio == pytest.approx(paper_ms / fused_ms, abs=0.06)
