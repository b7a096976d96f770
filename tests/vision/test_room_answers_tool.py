"""tools/room_answers.py: rooms measured scene by scene, and what moved between two runs."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "tools" / "room_answers.py"
sys.path.insert(0, str(ROOT / "tools"))

import room_answers  # noqa: E402


def cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(SCRIPT), *args], capture_output=True, text=True, timeout=300
    )


def tsv(path: Path, rows: list[dict[str, str]]) -> Path:
    base = dict(
        set="own", family="photo", seed="1", kind="hard", rig="rig", detected="1",
        clipped="0", flagged="0", err_h_pct="0.0", err_w_pct="0.0", confidence="0.5",
        reason="-", doubts="-", face_kind="plain",
    )  # fmt: skip
    lines = ["\t".join(room_answers.COLUMNS)]
    for n, row in enumerate(rows):
        full = {**base, "seed": str(n), **row}
        lines.append("\t".join(full[c] for c in room_answers.COLUMNS))
    path.write_text("\n".join(lines) + "\n")
    return path


def test_run_writes_both_answers_of_each_room_and_compares_equal_to_itself(
    tmp_path: Path,
) -> None:
    out = tmp_path / "a.tsv"
    done = cli("run", "-o", str(out), "--sets", "procedural-holdout:7-7")
    assert done.returncode == 0, done.stderr
    rows = out.read_text().splitlines()
    assert rows[0].split("\t") == room_answers.COLUMNS
    assert len(rows) == 1 + 4  # ordinary and hard, with the rig and with none
    assert {r.split("\t")[4] for r in rows[1:]} == {"rig", "none"}
    same = cli("compare", str(out), str(out))
    assert same.returncode == 0, same.stderr
    assert "0 better, 0 worse" in same.stdout


def test_a_move_counts_only_past_the_points_and_a_miss_is_infinitely_wrong(
    tmp_path: Path,
) -> None:
    before = tsv(
        tmp_path / "b.tsv",
        [
            {"err_h_pct": "1.0"},  # 0: moves exactly 2 points: not counted
            {"err_h_pct": "1.0"},  # 1: moves 2.01 points: worse
            {"detected": "0", "err_h_pct": "nan", "err_w_pct": "nan"},  # 2: miss -> found
            {"err_w_pct": "-3.0"},  # 3: found -> missed
            {"err_h_pct": "40.0", "clipped": "1"},  # 4: clipped rooms are not judged
        ],
    )
    after = tsv(
        tmp_path / "a.tsv",
        [
            {"err_h_pct": "3.0"},
            {"err_h_pct": "-3.01"},
            {"err_h_pct": "30.0"},
            {"detected": "0", "err_h_pct": "nan", "err_w_pct": "nan"},
            {"err_h_pct": "0.0", "clipped": "1"},
        ],
    )
    sets, lines = room_answers.compare(room_answers.load(before), room_answers.load(after), 2.0)
    s = sets["own"]
    assert (s.unclipped, s.better, s.worse) == (4, 1, 2)
    assert (s.gross_before, s.gross_after) == (1, 2)  # the miss, then the 30 % and the miss
    assert len(lines) == 3


@pytest.mark.parametrize(("error", "gross"), [("25.0", 0), ("25.01", 1), ("-25.01", 1)])
def test_gross_is_over_25_percent_either_way(tmp_path: Path, error: str, gross: int) -> None:
    path = tsv(tmp_path / "g.tsv", [{"err_w_pct": error}])
    sets, _ = room_answers.compare(room_answers.load(path), room_answers.load(path), 2.0)
    assert sets["own"].gross_before == gross


def test_sets_parse_and_bad_ones_are_named() -> None:
    jobs = room_answers.parse_sets("photo:700-701,ho")
    assert len(jobs) == 2 * 2 + 2 * 25 * 2
    assert jobs[0] == room_answers.Job("photo:700-701", "photo", 700, False)
    for bad in ("kitchen", "photo:9-1", "garden:1-2", "photo:a-b", ""):
        with pytest.raises(ValueError):
            room_answers.parse_sets(bad)


def test_answers_missing_from_after_are_counted_and_fail_the_comparison(
    tmp_path: Path,
) -> None:
    before = tsv(tmp_path / "b.tsv", [{}, {}, {"clipped": "1"}])
    after = tsv(tmp_path / "a.tsv", [{}])
    sets, _ = room_answers.compare(room_answers.load(before), room_answers.load(after), 2.0)
    assert (sets["own"].missing, sets["own"].unclipped) == (2, 1)
    out = cli("compare", str(before), str(after))
    assert out.returncode == 1 and "2 answers missing from AFTER" in out.stdout
    full = cli("compare", str(before), str(before))
    assert full.returncode == 0


def test_bad_input_is_a_clear_error_not_a_traceback(tmp_path: Path) -> None:
    out = cli("run", "-o", str(tmp_path / "x.tsv"), "--sets", "kitchen")
    assert out.returncode == 2 and "unknown set 'kitchen'" in out.stderr
    junk = tmp_path / "junk.tsv"
    junk.write_text("not\ta\ttable\n")
    out = cli("compare", str(junk), str(junk))
    assert out.returncode == 2 and "not a room_answers.py TSV" in out.stderr
    assert "Traceback" not in out.stderr
    bad_number = tsv(tmp_path / "n.tsv", [{"err_h_pct": "lots"}])
    out = cli("compare", str(bad_number), str(bad_number))
    assert out.returncode == 2 and "not numbers" in out.stderr and "Traceback" not in out.stderr
    out = cli("run", "-o", str(tmp_path / "no" / "such" / "dir.tsv"), "--sets", "photo:1-1")
    assert out.returncode == 2 and "cannot write" in out.stderr and "Traceback" not in out.stderr


def test_summary_means_skip_misses_and_reliability_holds_sure_answers_to_five_percent(
    tmp_path: Path,
) -> None:
    path = tsv(
        tmp_path / "s.tsv",
        [
            {"err_h_pct": "-2.0", "err_w_pct": "4.0", "confidence": "0.5"},  # sure, right
            {"err_h_pct": "5.01", "confidence": "0.9"},  # sure, just wrong
            {"err_h_pct": "40.0", "confidence": "0.49"},  # unsure, gross
            {"detected": "0", "err_h_pct": "nan", "err_w_pct": "nan"},  # missed
            {"err_h_pct": "90.0", "clipped": "1"},  # clipped: not judged
        ],
    )
    lines = room_answers.summarize(room_answers.load(path), None)
    assert len(lines) == 2  # the set's line, and its family and kind's
    for line in lines:
        assert "4 rooms" in line
        assert "mean |h| / |w|  15.7 /   1.3 %" in line  # (2 + 5.01 + 40) / 3, 4 / 3
        assert "missed 1  gross 2  reliable  50.0 % of 2" in line
    assert room_answers.summarize(room_answers.load(path), {"fresh"}) == []
    done = cli("summary", str(path), "--sets", "fresh")
    assert done.returncode == 1 and "no unclipped answers" in done.stderr


def test_a_reader_that_stops_early_ends_the_tool_quietly(tmp_path: Path) -> None:
    path = tsv(tmp_path / "s.tsv", [{"err_h_pct": "1.0"}] * 3)
    tool = subprocess.Popen(
        [sys.executable, str(SCRIPT), "summary", str(path)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert tool.stdout is not None and tool.stderr is not None
    tool.stdout.close()  # `| head` gone before the tool prints
    err = tool.stderr.read()
    assert tool.wait(timeout=300) == 141
    assert "Traceback" not in err and "BrokenPipeError" not in err
