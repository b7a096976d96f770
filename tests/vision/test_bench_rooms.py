"""The held-out room benchmark runs end to end on a few scenes and prints its tables."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "tools" / "bench_rooms.py"


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(SCRIPT), *args], capture_output=True, text=True, timeout=300
    )


def test_rows_per_family_rig_and_kind_then_reliability() -> None:
    out = run("--families", "procedural-holdout", "--scenes", "2", "--seed", "7")
    assert out.returncode == 0, out.stderr
    rows = [x for x in out.stdout.splitlines() if x.startswith("procedural-holdout")]
    assert len(rows) == 4  # rig / no rig x ordinary / hard
    assert all("missed" in r and "gross" in r for r in rows)
    assert out.stdout.count("| confidence >= |") == 2


def test_bad_arguments_are_usage_errors() -> None:
    for args in (("--families", "kitchen"), ("--scenes", "0")):
        out = run(*args)
        assert out.returncode == 2
        assert "error:" in out.stderr and "Traceback" not in out.stderr
