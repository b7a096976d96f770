#!/usr/bin/env python3
"""Fuzz the firmware core's input path (frame parser + command decoder) with libFuzzer.

Builds tests/native/fuzz_core.c with the firmware core and the fake board using clang
(-fsanitize=fuzzer,address,undefined), seeds a corpus from protocol/vectors/golden.json and
from valid host commands, runs for --seconds and prints the figures: executions, coverage
(edges, features), corpus size, findings. Exit status 0: no finding; 1: a finding (its
input is saved under WORK/artifacts/); 2: clang or libFuzzer missing, or the build failed.

    .venv/bin/python tools/fuzz_firmware.py --seconds 600
"""

from __future__ import annotations

import argparse
import json
import logging
import re
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CORE = ROOT / "firmware" / "core"
NATIVE = ROOT / "tests" / "native"
GOLDEN = ROOT / "protocol" / "vectors" / "golden.json"
SOURCES = [
    NATIVE / "fuzz_core.c",
    NATIVE / "fake_hal.c",
    CORE / "of_app.c",
    CORE / "of_ranger.c",
    CORE / "of_ring.c",
    CORE / "of_frame.c",
]
FLAGS = [
    "-std=c99",
    "-O1",
    "-g",
    "-Wall",
    "-Wextra",
    "-Werror",
    "-fsanitize=fuzzer,address,undefined",
    "-fno-sanitize-recover=all",
    f"-I{NATIVE}",
    f"-I{CORE}",
]
CLANGS = ("clang", "clang-19", "clang-16", "clang-15", "clang-14")

log = logging.getLogger("fuzz_firmware")


class FuzzSetupError(Exception):
    """clang/libFuzzer missing or the harness does not build."""


@dataclass(frozen=True)
class FuzzResult:
    seconds: int
    execs: int
    execs_per_s: int
    cov: int  # edges covered
    features: int
    corpus: int
    findings: list[Path]
    returncode: int

    def summary(self) -> str:
        found = ", ".join(str(p) for p in self.findings) or "none"
        return (
            f"fuzz_core: {self.seconds} s, {self.execs:,} executions ({self.execs_per_s:,}/s), "
            f"coverage {self.cov} edges / {self.features} features, corpus {self.corpus} "
            f"inputs, findings: {found}"
        )


def find_clang() -> str:
    for name in CLANGS:
        path = shutil.which(name)
        if path:
            return path
    raise FuzzSetupError(
        "clang not found: install it (apt-get install clang libclang-rt-14-dev; `make setup` does)"
    )


def libfuzzer_available(clang: str) -> bool:
    """Whether clang can link a libFuzzer target with the sanitizers."""
    with tempfile.TemporaryDirectory() as tmp:
        src = Path(tmp) / "probe.c"
        src.write_text(
            "#include <stddef.h>\n#include <stdint.h>\n"
            "int LLVMFuzzerTestOneInput(const uint8_t *d, size_t n);\n"
            "int LLVMFuzzerTestOneInput(const uint8_t *d, size_t n)"
            "{ (void)d; (void)n; return 0; }\n"
        )
        proc = subprocess.run(
            [
                clang,
                "-fsanitize=fuzzer,address,undefined",
                str(src),
                "-o",
                str(Path(tmp) / "probe"),
            ],
            capture_output=True,
            text=True,
        )
        return proc.returncode == 0


def build(work: Path) -> Path:
    clang = find_clang()
    if not libfuzzer_available(clang):
        raise FuzzSetupError(
            f"{clang} cannot link libFuzzer with the sanitizers: install "
            "libclang-rt-14-dev (or the compiler-rt of your clang)"
        )
    work.mkdir(parents=True, exist_ok=True)
    out = work / "fuzz_core"
    proc = subprocess.run(
        [clang, *FLAGS, *map(str, SOURCES), "-o", str(out)], capture_output=True, text=True
    )
    if proc.returncode != 0:
        raise FuzzSetupError(f"building the fuzz target failed:\n{proc.stderr}")
    return out


def seed_inputs() -> list[bytes]:
    """Every golden frame alone and all together, and valid host commands in a row."""
    from obstacle_fusion.protocol import encode
    from obstacle_fusion.protocol.generated import GetInfo, SetConfig, Start, Stop, TimeSync

    frames = [bytes.fromhex(v["frame"]) for v in json.loads(GOLDEN.read_text())]
    commands = [
        encode(GetInfo(), 1),
        encode(
            SetConfig(
                cycle_ms=29,
                sensor_mask=15,
                max_echo_us=1000,
                echo_timeout_us=1000,
                heartbeat_ms=100,
            ),
            2,
        ),
        encode(
            SetConfig(
                cycle_ms=60, sensor_mask=1, max_echo_us=23324, echo_timeout_us=40000, heartbeat_ms=0
            ),
            3,
        ),
        encode(TimeSync(token=0xDEADBEEF), 4),
        encode(Stop(), 5),
        encode(Start(), 6),
    ]
    return [*frames, b"".join(frames), b"".join(commands), b"\x00" + b"".join(commands)]


def parse_output(text: str) -> tuple[int, int, int, int, int]:
    """(execs, execs/s, cov, ft, corpus) from libFuzzer's last status line and stats."""
    execs = rate = cov = ft = corp = 0
    for line in text.splitlines():
        m = re.match(r"#(\d+)\s+\S+\s+cov: (\d+) ft: (\d+) corp: (\d+)", line)
        if m:
            execs, cov, ft, corp = (int(g) for g in m.groups())
            r = re.search(r"exec/s: (\d+)", line)
            rate = int(r.group(1)) if r else rate
        m = re.match(r"stat::number_of_executed_units: (\d+)", line)
        if m:
            execs = int(m.group(1))
        m = re.match(r"stat::average_exec_per_sec: (\d+)", line)
        if m:
            rate = int(m.group(1))
    return execs, rate, cov, ft, corp


def run(seconds: int, work: Path, max_len: int = 1024) -> FuzzResult:
    binary = build(work)
    seeds = work / "seeds"
    corpus = work / "corpus"
    artifacts = work / "artifacts"
    for d in (seeds, corpus, artifacts):
        d.mkdir(parents=True, exist_ok=True)
    for i, data in enumerate(seed_inputs()):
        (seeds / f"seed{i:02d}").write_bytes(data)
    before = set(artifacts.iterdir())
    proc = subprocess.run(
        [
            str(binary),
            str(corpus),
            str(seeds),
            f"-max_total_time={seconds}",
            f"-max_len={max_len}",
            "-timeout=10",
            "-rss_limit_mb=2048",
            "-print_final_stats=1",
            f"-artifact_prefix={artifacts}/",
        ],
        capture_output=True,
        text=True,
        timeout=seconds + 600,
    )
    (work / "last_run.log").write_text(proc.stderr)
    execs, rate, cov, ft, corp = parse_output(proc.stderr)
    new = sorted(set(artifacts.iterdir()) - before)
    # A "slow unit" is an input that once took over 10 s: on a loaded machine that is the
    # scheduler, not the firmware. Each is run again alone; only a slow rerun is a finding.
    findings = [p for p in new if not p.name.startswith("slow-unit-") or is_slow(binary, p)]
    return FuzzResult(seconds, execs, rate, cov, ft, corp, findings, proc.returncode)


def is_slow(binary: Path, unit: Path, limit_s: float = 1.0) -> bool:
    """Whether one input still takes over limit_s when run again alone."""
    start = time.monotonic()
    subprocess.run([str(binary), str(unit)], capture_output=True, timeout=120)
    elapsed = time.monotonic() - start
    log.info("slow unit %s: %.2f s when run again", unit.name, elapsed)
    return elapsed > limit_s


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=int, default=60, help="how long to fuzz (60)")
    parser.add_argument(
        "--work",
        type=Path,
        default=ROOT / "firmware" / "build" / "fuzz",
        help="build, corpus and artifacts directory (firmware/build/fuzz)",
    )
    args = parser.parse_args()
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    try:
        result = run(args.seconds, args.work)
    except FuzzSetupError as exc:
        print(f"fuzz_firmware: {exc}", file=sys.stderr)
        return 2
    print(result.summary())
    if result.findings or result.returncode != 0:
        print(
            f"fuzz_firmware: FINDING (libFuzzer exit {result.returncode}); log: "
            f"{args.work / 'last_run.log'}",
            file=sys.stderr,
        )
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
