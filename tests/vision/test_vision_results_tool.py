"""tools/vision_results.py: the answers' fingerprint a speed change is checked against."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "tools" / "vision_results.py"


def run(*args: str | Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(SCRIPT), *map(str, args)], capture_output=True, text=True, timeout=300
    )


def test_the_fingerprint_is_repeatable_and_catches_a_moved_answer(tmp_path: Path) -> None:
    cache, first, again = tmp_path / "scenes.pkl", tmp_path / "a.jsonl", tmp_path / "b.jsonl"
    small = ("--ordinary", "1", "--hard", "1", "--rooms", "1", "--scenes-cache", cache)
    out = run("-o", first, *small)
    assert out.returncode == 0, out.stderr
    rows = [json.loads(line) for line in first.read_text().splitlines()]
    # 2 bench frames + 4 families x 2 kinds x (rig, no rig), each measured twice
    assert len(rows) == 2 * (2 + 4 * 2 * 2)
    assert cache.exists()
    out = run("-o", again, *small, "--compare", first)
    assert out.returncode == 0 and "identical" in out.stdout, out.stdout + out.stderr
    # a detected answer moved by 1e-6 m is a difference; by 1e-12 it is not
    i = next(k for k, r in enumerate(rows) if r["detected"])
    for shift, differs in ((1e-12, False), (1e-6, True)):
        moved = [dict(r) for r in rows]
        moved[i]["height_m"] += shift
        first.write_text("".join(json.dumps(r) + "\n" for r in moved))
        out = run("-o", again, *small, "--compare", first)
        assert out.returncode == (1 if differs else 0), out.stdout
        assert ("1 differences" in out.stdout) == differs, out.stdout
