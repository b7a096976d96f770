#!/usr/bin/env python3
"""Mutation testing of the firmware core: do the tests notice a one-token change?

Each mutant is a copy of firmware/ (in a temporary directory; the checkout is never
touched) with ONE change in firmware/core/of_ranger.c, of_frame.c, of_app.c or of_ring.c:

  ror     a relational operator replaced (< <=, > >=, == !=, each way)
  arith   a binary + and - swapped
  logic   && and || swapped
  const   an integer literal plus or minus one
  half    a numeric OF_* macro used in the code halved ((X / 2u))
  del     a `x++;` / `x--;` statement deleted

A mutant is run against the native core tests (tests/native/test_core.c + the fake board,
compiled with ASan/UBSan), the fuzz target's oracles on a fixed set of generated inputs
(tests/native/fuzz_replay.c) and the codec's golden-vector and stream tests
(tests/protocol_c); if they all pass, the mutated Uno image is built and the fast
emulator tests are run with it (OF_FIRMWARE_ELF). Killed: a test failed, crashed or timed
out. Stillborn: does not compile (not counted). Survived: everything passed. Prints a
table and the score; --json writes every mutant's result.

    .venv/bin/python tools/mutate_firmware.py --list                  # the mutants only
    .venv/bin/python tools/mutate_firmware.py --json mutants.json     # run them all
    .venv/bin/python tools/mutate_firmware.py --only of_ranger.c:88   # one line's mutants
    .venv/bin/python tools/mutate_firmware.py --rerun mutants.json    # those past native, again
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import asdict, dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CORE = ROOT / "firmware" / "core"
NATIVE = ROOT / "tests" / "native"
PROTOCOL_C = ROOT / "tests" / "protocol_c"
PROTOCOL_TESTS = ("golden_test.c", "stream_test.c")
TARGETS = ("of_ranger.c", "of_frame.c", "of_app.c", "of_ring.c")
NATIVE_SOURCES = ("of_app.c", "of_ranger.c", "of_ring.c", "of_frame.c")
HEADERS = ("of_ranger.h", "of_app.h", "of_frame.h", "of_protocol.h", "of_ring.h")
CFLAGS = [
    "-std=c99",
    "-Wall",
    "-Wextra",
    "-Werror",
    "-O1",
    "-g",
    "-fsanitize=address,undefined",
    "-fno-sanitize-recover=all",
]
# The emulator tests run on a native survivor: the firmware end to end, quick ones only.
EMULATOR_TESTS = [
    "tests/sim/test_emulator_firmware.py",
    "tests/sim/test_emulator_robustness.py",
    "-k",
    "not real_time and not 1pct and not published and not large_host_write",
]

ROR = {"<": "<=", "<=": "<", ">": ">=", ">=": ">", "==": "!=", "!=": "=="}


@dataclass(frozen=True)
class Mutant:
    file: str
    line: int
    op: str
    start: int  # offset in the file
    end: int
    original: str
    replacement: str

    @property
    def name(self) -> str:
        return f"{self.file}:{self.line} {self.op} {self.original!r} -> {self.replacement!r}"


@dataclass
class Result:
    mutant: str
    file: str
    line: int
    op: str
    status: str  # killed-native, killed-emulator, survived, stillborn
    detail: str
    seconds: float


def code_mask(text: str) -> str:
    """The text with comments, string/char literals and preprocessor lines blanked
    (same length, so offsets stay valid)."""
    out = list(text)
    i = 0
    n = len(text)
    line_start = True
    while i < n:
        c = text[i]
        if line_start and text[i:].lstrip(" \t").startswith("#"):
            j = text.find("\n", i)
            j = n if j < 0 else j
            while j < n and text[j - 1] == "\\":  # continued directive
                k = text.find("\n", j + 1)
                j = n if k < 0 else k
            for k in range(i, j):
                out[k] = " "
            i = j
            continue
        line_start = c == "\n"
        if text.startswith("/*", i):
            j = text.find("*/", i + 2) + 2
            for k in range(i, j):
                if text[k] != "\n":
                    out[k] = " "
            i = j
        elif text.startswith("//", i):
            j = text.find("\n", i)
            for k in range(i, j):
                out[k] = " "
            i = j
        elif c in "\"'":
            j = i + 1
            while text[j] != c:
                j += 2 if text[j] == "\\" else 1
            for k in range(i + 1, j):
                out[k] = " "
            i = j + 1
        else:
            if not c.isspace():
                line_start = False
            i += 1
    return "".join(out)


def numeric_macros() -> set[str]:
    names = set()
    for header in HEADERS:
        text = (CORE / header).read_text()
        for m in re.finditer(r"^#define (OF_[A-Z0-9_]+) \(?(\d+)[uUlL]*\)?", text, re.M):
            if not m.group(1).startswith(("OF_MSG_", "OF_PROTOCOL_", "OF_FW_")):
                names.add(m.group(1))
    return names


def mutants_of(file: str) -> list[Mutant]:
    text = (CORE / file).read_text()
    code = code_mask(text)

    def line_of(pos: int) -> int:
        return text.count("\n", 0, pos) + 1

    found: list[Mutant] = []

    def add(op: str, start: int, end: int, replacement: str) -> None:
        found.append(Mutant(file, line_of(start), op, start, end, text[start:end], replacement))

    for m in re.finditer(r"<=|>=|==|!=|<<=|>>=|<<|>>|->|<|>", code):
        tok = m.group()
        if tok in ROR:
            add("ror", m.start(), m.end(), ROR[tok])
    for m in re.finditer(r"\+\+|--|\+=|-=|->|\+|-", code):
        tok = m.group()
        if tok not in "+-":
            continue
        before = code[: m.start()].rstrip()
        if before and (before[-1].isalnum() or before[-1] in "_)]"):
            add("arith", m.start(), m.end(), "-" if tok == "+" else "+")
    for m in re.finditer(r"&&|\|\|", code):
        add("logic", m.start(), m.end(), "||" if m.group() == "&&" else "&&")
    for m in re.finditer(r"(?<![\w.])(0[xX][0-9a-fA-F]+|\d+)([uU]?[lL]{0,2})(?![\w.])", code):
        digits, suffix = m.group(1), m.group(2)
        value = int(digits, 0)
        fmt = (lambda v: f"{v:#x}") if digits.lower().startswith("0x") else str
        add("const", m.start(), m.end(), fmt(value + 1) + suffix)
        if value > 0:
            add("const", m.start(), m.end(), fmt(value - 1) + suffix)
    macros = numeric_macros()
    for m in re.finditer(r"\bOF_[A-Z0-9_]+\b", code):
        if m.group() in macros:
            add("half", m.start(), m.end(), f"({m.group()} / 2u)")
    for m in re.finditer(r"^[ \t]*[\w>\-.\[\]]+(\+\+|--);[^\n]*$", code, re.M):
        s = m.start() + len(m.group()) - len(m.group().lstrip())
        add("del", s, m.end(), ";")
    return found


def all_mutants(only: str | None = None) -> list[Mutant]:
    out = [mu for f in TARGETS for mu in mutants_of(f)]
    if only:
        file, _, line = only.partition(":")
        out = [mu for mu in out if mu.file == file and (not line or mu.line == int(line))]
    return out


def run(
    cmd: list[str], timeout: float, env: dict[str, str] | None = None, cwd: Path = ROOT
) -> tuple[int, str]:
    try:
        proc = subprocess.run(
            cmd, capture_output=True, text=True, timeout=timeout, env=env, cwd=cwd
        )
    except subprocess.TimeoutExpired:
        return -999, "timeout"
    return proc.returncode, (proc.stdout + proc.stderr)[-2000:]


def compile_objects(work: Path) -> dict[str, Path]:
    """The unmutated sources compiled once: test programs, fake board, every core file."""
    objs = work / "base"
    objs.mkdir(parents=True, exist_ok=True)
    out: dict[str, Path] = {}
    sources = [
        NATIVE / "test_core.c",
        NATIVE / "fuzz_replay.c",
        NATIVE / "fake_hal.c",
        *(PROTOCOL_C / p for p in PROTOCOL_TESTS),
        *(CORE / s for s in NATIVE_SOURCES),
    ]
    for src in sources:
        obj = objs / (src.stem + ".o")
        rc, text = run(
            ["gcc", *CFLAGS, f"-I{NATIVE}", f"-I{CORE}", "-c", str(src), "-o", str(obj)], 120
        )
        if rc != 0:
            raise SystemExit(f"mutate_firmware: the unmutated {src.name} does not build:\n{text}")
        out[src.name] = obj
    return out


def test_mutant(mu: Mutant, work: Path, emulator: bool, base: dict[str, Path]) -> Result:
    t0 = time.monotonic()
    fw = work / "firmware"
    if fw.exists():
        shutil.rmtree(fw)
    shutil.copytree(ROOT / "firmware", fw, ignore=shutil.ignore_patterns("build"))
    text = (CORE / mu.file).read_text()
    (fw / "core" / mu.file).write_text(text[: mu.start] + mu.replacement + text[mu.end :])

    def result(status: str, detail: str) -> Result:
        return Result(
            mu.name,
            mu.file,
            mu.line,
            mu.op,
            status,
            detail.strip()[-300:],
            round(time.monotonic() - t0, 1),
        )

    mutated = work / "mutated.o"
    rc, out = run(
        [
            "gcc",
            *CFLAGS,
            f"-I{NATIVE}",
            f"-I{fw / 'core'}",
            "-c",
            str(fw / "core" / mu.file),
            "-o",
            str(mutated),
        ],
        120,
    )
    if rc != 0:
        return result("stillborn", out)
    core = [str(mutated) if name == mu.file else str(base[name]) for name in NATIVE_SOURCES]
    for program in ("test_core", "fuzz_replay"):
        binary = work / program
        objs = [str(base[program + ".c"]), str(base["fake_hal.c"]), *core]
        rc, out = run(["gcc", *CFLAGS, *objs, "-o", str(binary)], 120)
        if rc != 0:
            return result("stillborn", out)
        rc, out = run([str(binary)], 120)
        if rc != 0:
            return result("killed-native", f"{program}: " + (out if rc != -999 else "timeout"))
    # The codec against the golden vectors and a noisy stream (tests/protocol_c): the
    # firmware's own decoder cannot catch a change it shares (a CRC polynomial, say).
    for program in PROTOCOL_TESTS:
        binary = work / Path(program).stem
        rc, out = run(
            [
                "gcc",
                *CFLAGS,
                str(base[program]),
                core[NATIVE_SOURCES.index("of_frame.c")],
                "-o",
                str(binary),
            ],
            120,
        )
        if rc != 0:
            return result("stillborn", out)
        rc, out = run([str(binary)], 120)
        if rc != 0:
            return result("killed-native", f"{program}: " + (out if rc != -999 else "timeout"))
    if not emulator:
        return result("survived", "native tests pass")
    # A fresh build directory: copytree keeps the files' times, so make would keep the
    # objects of an earlier mutant of another file.
    shutil.rmtree(work / "build", ignore_errors=True)
    rc, out = run(["make", "-s", "-C", str(fw), "BOARD=uno", f"BUILD_DIR={work / 'build'}"], 300)
    if rc != 0:
        return result("stillborn", "the Uno build fails: " + out)
    env = dict(os.environ, OF_FIRMWARE_ELF=str(work / "build" / "uno" / "obstacle-fusion.elf"))
    rc, out = run(
        [
            sys.executable,
            "-m",
            "pytest",
            "-q",
            "-x",
            "-p",
            "no:cacheprovider",
            "--timeout",
            "120",
            *EMULATOR_TESTS,
        ],
        900,
        env=env,
    )
    if rc != 0:
        return result("killed-emulator", out if rc != -999 else "timeout")
    return result("survived", "native and emulator tests pass")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--list", action="store_true", help="print the mutants and stop")
    parser.add_argument("--only", help="FILE or FILE:LINE (e.g. of_ranger.c:88)")
    parser.add_argument("--native-only", action="store_true", help="skip the emulator tests")
    parser.add_argument("--json", type=Path, help="write every result here")
    parser.add_argument(
        "--rerun",
        type=Path,
        help="only the mutants that reached the emulator stage (survived or "
        "killed there) in this earlier --json file",
    )
    args = parser.parse_args()
    mutants = all_mutants(args.only)
    if args.rerun:
        earlier = json.loads(args.rerun.read_text())
        survived = {r["mutant"] for r in earlier if r["status"] in ("survived", "killed-emulator")}
        mutants = [mu for mu in mutants if mu.name in survived]
    if args.list:
        for mu in mutants:
            print(mu.name)
        print(f"{len(mutants)} mutants")
        return 0
    results: list[Result] = []
    with tempfile.TemporaryDirectory(prefix="mutate-fw-") as tmp:
        base = compile_objects(Path(tmp))
        for i, mu in enumerate(mutants, 1):
            res = test_mutant(mu, Path(tmp), emulator=not args.native_only, base=base)
            results.append(res)
            print(f"[{i}/{len(mutants)}] {res.status:16} {res.seconds:6.1f}s {mu.name}", flush=True)
            if args.json:
                args.json.write_text(json.dumps([asdict(r) for r in results], indent=1))
    counts = {
        s: sum(r.status == s for r in results)
        for s in ("killed-native", "killed-emulator", "survived", "stillborn")
    }
    valid = len(results) - counts["stillborn"]
    killed = counts["killed-native"] + counts["killed-emulator"]
    print("\nsurvivors:")
    for r in results:
        if r.status == "survived":
            print(f"  {r.mutant}")
    print(f"\n{len(results)} mutants: {counts}")
    if valid:
        print(
            f"mutation score: {killed}/{valid} = {100 * killed / valid:.1f} % killed "
            "(equivalent mutants not yet excluded)"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
