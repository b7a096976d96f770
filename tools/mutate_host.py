#!/usr/bin/env python3
"""Mutation testing for host modules: small changes to the code must fail the tests.

Each mutant changes one token of a module (a comparison flipped or loosened, + and -
swapped, * and / swapped, and/or swapped, a `not` dropped, True/False swapped, an integer
plus one, a float doubled) or applies one of the named mutants below (defects a review
found surviving: a status published as another, a per-sensor state shared). Every mutant
runs the given tests in a forked child that holds the mutated module in sys.modules (the
files are never touched, so a run in progress elsewhere is not disturbed); a test failure,
an error or a timeout kills it. Mutants listed in the equivalence file (``id  # why``)
are reported apart and left out of the score: score = killed / (mutants - equivalent).

Usage: .venv/bin/python tools/mutate_host.py host/obstacle_fusion/fusion.py \\
           host/obstacle_fusion/sonar.py --tests tests/test_fusion.py tests/test_sonar.py \\
           [--equivalent tools/mutants_equivalent.txt] [--jobs 2] [--only ID-SUBSTRING]
"""

from __future__ import annotations

import argparse
import io
import os
import signal
import sys
import time
import tokenize
import types
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "host" / "obstacle_fusion"

SWAPS = {
    "<": "<=",
    "<=": "<",
    ">": ">=",
    ">=": ">",
    "==": "!=",
    "!=": "==",
    "+": "-",
    "-": "+",
    "*": "/",
    "/": "*",
    "and": "or",
    "or": "and",
    "True": "False",
    "False": "True",
}

# (file name, what, the exact text, its replacement): the named survivors of issue 13.
NAMED = [
    (
        "fusion.py",
        "out_of_range published as sonar_error",
        "pairing.sonar_status in (SonarStatus.NO_ECHO, SonarStatus.OUT_OF_RANGE)",
        "pairing.sonar_status in (SonarStatus.NO_ECHO,)",
    ),
    (
        "sonar.py",
        "the per-sensor median history shared",
        "self._history.setdefault(sensor_id,",
        "self._history.setdefault(0,",
    ),
    (
        "fusion.py",
        "the pairing tolerance doubled",
        "self, tolerance_s: float = 0.05,",
        "self, tolerance_s: float = 0.1,",
    ),
    (
        "fusion.py",
        "the interpolation gap limit doubled",
        "max_gap_s: float = 0.2, history_s",
        "max_gap_s: float = 0.4, history_s",
    ),
    (
        "fusion.py",
        "the extrapolation limit doubled",
        "max_extrapolation_s: float = 0.2",
        "max_extrapolation_s: float = 0.4",
    ),
]


@dataclass(frozen=True)
class Mutant:
    id: str
    file: Path
    text: str  # the whole mutated module
    what: str


def _number_mutation(tok: str) -> str | None:
    try:
        value = int(tok, 0)
        return str(value + 1)
    except ValueError:
        pass
    try:
        f = float(tok.replace("_", ""))
    except ValueError:
        return None
    return repr(f * 2.0) if f != 0.0 else "1.0"


def mutants_of(path: Path) -> list[Mutant]:
    src = path.read_text(encoding="utf-8")
    lines = src.splitlines(keepends=True)
    offsets = [0]
    for line in lines:
        offsets.append(offsets[-1] + len(line))
    out: list[Mutant] = []
    toks = list(tokenize.generate_tokens(io.StringIO(src).readline))
    for i, tok in enumerate(toks):
        if tok.type == tokenize.OP or tok.type == tokenize.NAME:
            new = SWAPS.get(tok.string)
            if tok.string == "not":
                new = ""
        elif tok.type == tokenize.NUMBER:
            new = _number_mutation(tok.string)
        else:
            continue
        if new is None:
            continue
        if tok.string == "-" and i + 1 < len(toks) and toks[i + 1].string == ">":
            continue
        line_text = lines[tok.start[0] - 1]
        if line_text.lstrip().startswith(("def ", "class ", "@", "assert ")) or "log." in line_text:
            continue  # messages, signatures (defaults are named mutants), internal invariants
        if tok.string in ("*", "/") and line_text.lstrip().startswith(("import", "from")):
            continue
        a = offsets[tok.start[0] - 1] + tok.start[1]
        b = offsets[tok.end[0] - 1] + tok.end[1]
        text = src[:a] + new + src[b:]
        mid = f"{path.name}:{tok.start[0]}:{tok.start[1]}:{tok.string}->{new or '(removed)'}"
        out.append(Mutant(mid, path, text, line_text.strip()))
    for name, what, old, new in NAMED:
        if name != path.name:
            continue
        if src.count(old) != 1:
            raise SystemExit(f"named mutant '{what}': {old!r} is not found once in {path}")
        out.append(Mutant(f"{path.name}:named:{what}", path, src.replace(old, new), what))
    return out


def _module_name(path: Path) -> str:
    rel = path.relative_to(PACKAGE).with_suffix("")
    return ".".join(("obstacle_fusion", *rel.parts))


def run_mutant(m: Mutant | None, tests: list[str], timeout: float) -> tuple[bool, str]:
    """Run the tests in a forked child with the mutant in sys.modules; True = they pass.

    The parent has imported pytest, numpy and the package's other modules once, so a child
    starts in milliseconds; the mutated module is compiled from its text (the files on disk
    are never changed)."""
    pid = os.fork()
    if pid == 0:  # the child
        code = 3
        try:
            sys.stdout.flush()
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, 1)
            os.dup2(devnull, 2)
            if m is not None:
                name = _module_name(m.file)
                mod = types.ModuleType(name)
                mod.__file__ = str(m.file)
                sys.modules[name] = mod
                parent, _, leaf = name.rpartition(".")
                setattr(sys.modules[parent], leaf, mod)
                exec(compile(m.text, str(m.file), "exec"), mod.__dict__)
            import pytest

            code = int(pytest.main(["-x", "-q", "-p", "no:cacheprovider", *tests]))
        except BaseException:  # noqa: BLE001 - a mutant that breaks the import is killed
            code = 4
        finally:
            os._exit(code)
    deadline = time.monotonic() + timeout
    while True:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            code = os.waitstatus_to_exitcode(status)
            return code == 0, f"exit {code}"
        if time.monotonic() > deadline:
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
            return False, "timeout"
        time.sleep(0.01)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("modules", nargs="+", type=Path)
    ap.add_argument("--tests", nargs="+", required=True)
    ap.add_argument("--equivalent", type=Path, default=ROOT / "tools" / "mutants_equivalent.txt")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=120.0)
    ap.add_argument("--only", help="run only mutants whose id contains this")
    args = ap.parse_args()
    equivalent: dict[str, str] = {}
    if args.equivalent.is_file():
        for raw in args.equivalent.read_text().splitlines():
            ident, _, why = raw.partition("#")
            if ident.strip():
                equivalent[ident.strip()] = why.strip()
    modules = [p.resolve() for p in args.modules]
    mutants = [m for p in modules for m in mutants_of(p)]
    if args.only:
        mutants = [m for m in mutants if args.only in m.id]
    stale = sorted(set(equivalent) - {m.id for m in mutants})
    # Import everything the tests need except the modules under test and their users.
    import numpy  # noqa: F401
    import obstacle_fusion.errors  # noqa: F401
    import obstacle_fusion.protocol.generated  # noqa: F401
    import obstacle_fusion.sources.frames  # noqa: F401
    import pytest  # noqa: F401

    mutated = {_module_name(p) for p in modules}
    for name in list(sys.modules):
        if name in mutated or name == "obstacle_fusion.fusion":
            del sys.modules[name]
    ok, last = run_mutant(None, args.tests, args.timeout)
    if not ok:
        print(f"the tests fail without any mutant: {last}", file=sys.stderr)
        return 2
    results = []
    with ThreadPoolExecutor(max_workers=max(args.jobs, 1)) as pool:
        outcomes = pool.map(lambda m: (m, *run_mutant(m, args.tests, args.timeout)), mutants)
        for m, survived, last in outcomes:
            results.append((m, survived))
            mark = "SURVIVED" if survived else "killed  "
            if survived and m.id in equivalent:
                mark = "equiv.  "
            print(f"{mark} {m.id}   [{m.what[:70]}] {'' if survived else last}", flush=True)
    survivors = [m for m, s in results if s and m.id not in equivalent]
    equiv = [m for m, s in results if s and m.id in equivalent]
    killed_equiv = [m for m, s in results if not s and m.id in equivalent]
    killed = sum(1 for _, s in results if not s)
    scored = len(results) - len(equiv)
    print()
    print(
        f"{len(results)} mutants: {killed} killed, {len(survivors)} survived, {len(equiv)} "
        f"equivalent; score {100 * killed / max(scored, 1):.1f} % of the non-equivalent"
    )
    for m in survivors:
        print(f"  survived: {m.id}   [{m.what}]")
    for m in equiv:
        print(f"  equivalent: {m.id}   ({equivalent[m.id]})")
    for m in killed_equiv:
        print(f"  listed as equivalent but killed: {m.id}")
    for ident in stale:
        print(f"  equivalence entry matches no mutant (code moved?): {ident}")
    return 0 if not survivors else 1


if __name__ == "__main__":
    sys.exit(main())
