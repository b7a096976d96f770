"""20 s of libFuzzer on the firmware core's frame parser and command decoder
(tools/fuzz_firmware.py, harness tests/native/fuzz_core.c): no sanitizer report, no
disagreement with the reference parser, no bad frame sent, and the seeds from
protocol/vectors/golden.json reach the command handlers (coverage well above the parser's)."""

from __future__ import annotations

import importlib.util
import shutil
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import pytest

pytestmark = pytest.mark.cpu_only

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "tools" / "fuzz_firmware.py"


def load_tool() -> ModuleType:
    spec = importlib.util.spec_from_file_location("fuzz_firmware", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


def test_seeds_are_the_golden_frames_and_valid_commands() -> None:
    tool = load_tool()
    seeds = tool.seed_inputs()
    import json

    golden = [
        bytes.fromhex(v["frame"])
        for v in json.loads((ROOT / "protocol/vectors/golden.json").read_text())
    ]
    assert all(g in seeds for g in golden)
    assert b"".join(golden) in seeds


def test_output_parsing() -> None:
    tool = load_tool()
    text = (
        "#1024\tpulse  cov: 200 ft: 900 corp: 100/2Kb exec/s: 512 rss: 40Mb\n"
        "#58742\tDONE   cov: 308 ft: 1335 corp: 316/10Kb lim: 1024 exec/s: 2797 rss: 85Mb\n"
        "stat::number_of_executed_units: 58742\nstat::average_exec_per_sec:     2797\n"
    )
    assert tool.parse_output(text) == (58742, 2797, 308, 1335, 316)


def test_fuzz_firmware_20s(tmp_path: Path) -> None:
    tool = load_tool()
    try:
        clang = tool.find_clang()
    except tool.FuzzSetupError as exc:
        pytest.skip(f"no clang: {exc} (`make setup` installs it)")
    if not tool.libfuzzer_available(clang):
        pytest.skip(
            "clang has no libFuzzer/sanitizer runtime (install libclang-rt-dev; `make setup` does)"
        )
    proc = subprocess.run(
        [sys.executable, str(SCRIPT), "--seconds", "20", "--work", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    log = (tmp_path / "last_run.log").read_text() if (tmp_path / "last_run.log").exists() else ""
    assert proc.returncode == 0, proc.stdout + proc.stderr + log[-3000:]
    assert "findings: none" in proc.stdout
    execs, _, cov, _, _ = tool.parse_output(log)
    assert execs > 10_000, proc.stdout
    # The parser alone covers well under 100 edges; the command handlers, the SET_CONFIG
    # validation and the ranger take it far beyond.
    assert cov > 200, proc.stdout


def test_fuzz_oracles_on_generated_inputs(tmp_path: Path) -> None:
    """The same oracles without libFuzzer (any gcc): 20,000 seeded streams of real frames,
    damaged as a serial line damages them, through the parser and its reference; 2,000
    through the application on the fake board."""
    gcc = shutil.which("gcc") or shutil.which("cc")
    if gcc is None:
        pytest.fail("no host C compiler: install gcc (`make setup`)")
    out = tmp_path / "fuzz_replay"
    native, core = ROOT / "tests" / "native", ROOT / "firmware" / "core"
    sources = [native / "fuzz_replay.c", native / "fake_hal.c"] + [
        core / f for f in ("of_app.c", "of_ranger.c", "of_ring.c", "of_frame.c")
    ]
    build = subprocess.run(
        [
            gcc,
            "-std=c99",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-O1",
            "-g",
            "-fsanitize=address,undefined",
            "-fno-sanitize-recover=all",
            f"-I{native}",
            f"-I{core}",
            *map(str, sources),
            "-o",
            str(out),
        ],
        capture_output=True,
        text=True,
    )
    assert build.returncode == 0, build.stderr
    run = subprocess.run([str(out)], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "20000 parser inputs, 2000 app inputs: ok" in run.stdout
