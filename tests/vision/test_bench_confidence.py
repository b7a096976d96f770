"""tools/bench_confidence.py: the confidence's meaning on the tuning scenes, per doubt."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from obstacle_fusion.vision.fused.confidence import (
    NEAR_RIVALS,
    SECOND_TOP,
    SMALL_FACE,
    TOP_FROM_SIDES,
)

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "tools" / "bench_confidence.py"


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(SCRIPT), *args], capture_output=True, text=True, timeout=300
    )


def test_reliability_rows_for_rig_and_no_rig() -> None:
    out = run("--first-rooms", "100", "--rooms", "1", "--generated", "3", "--threshold", "0.3")
    assert out.returncode == 0, out.stderr
    rows = [x for x in out.stdout.splitlines() if "at >= 0.3:" in x]
    assert len(rows) == 6  # rig / no rig x rooms / generated / all
    assert all("within 5 %" in r and "taken under it by doubts" in r for r in rows)


def _tool() -> Any:
    sys.path.insert(0, str(ROOT / "tools"))
    try:
        import bench_confidence
    finally:
        sys.path.remove(str(ROOT / "tools"))
    return bench_confidence


def test_only_tuning_families_are_measured() -> None:
    assert _tool().TUNING_FAMILIES == ("procedural", "photo")


def test_the_confidence_before_the_doubts_undoes_their_factors() -> None:
    undoubted = _tool().undoubted
    assert undoubted(0.45, [TOP_FROM_SIDES], 200.0, 200.0) == pytest.approx(1.0)
    assert undoubted(0.2025, [SECOND_TOP, NEAR_RIVALS], 200.0, 200.0) == pytest.approx(1.0)
    assert undoubted(0.3, [SMALL_FACE], 20.0, 200.0) == pytest.approx(0.6)
    assert undoubted(0.7, [], 20.0, 200.0) == 0.7  # no doubt recorded: nothing to undo


def test_bad_arguments_are_usage_errors() -> None:
    for args in (
        ("--rooms", "-1"),
        ("--rooms", "0", "--generated", "0"),
        ("--threshold", "2"),
        ("--first-rooms", "100,x"),
    ):
        out = run(*args)
        assert out.returncode == 2
        assert "error:" in out.stderr and "Traceback" not in out.stderr
