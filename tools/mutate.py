#!/usr/bin/env python3
"""Mutation testing: do the tests notice when the code changes by one comparison or constant?

For each target file, every single-site mutation below is applied in turn (the file is
rewritten in place and restored afterwards, even on Ctrl-C), the chosen tests are run with
-x, and the mutant is "killed" when they fail (or time out) and "survived" when they pass:

  compare   < <=  > >=  == !=  is / is not  in / not in   (each flipped to its neighbour)
  number    an int n -> n + 1, n - 1, 2 n;  a float x -> 2 x, x / 2   (0 -> 1);
            --numbers one: only the first of these per number
  boolop    and <-> or
  bool      True <-> False
  return    return X -> return None   (X not already None)
  augassign x += k / x -= k  ->  the statement removed (a counter never counted)
  named     text replacements from --named FILE (JSON: [{"file", "name", "find", "replace"}]),
            for mutants no single-site operator makes (a median replaced by a mean ...)

Docstrings and type annotations are not mutated. Survivors are printed with their line so a
person can decide whether each is equivalent (no test could tell) or a missing test.

  python tools/mutate.py host/obstacle_fusion/protocol/stream.py \\
      --tests tests/protocol/test_protocol_stream.py
  python tools/mutate.py host/obstacle_fusion/timing/clock.py --named tools/mutants_named.json \\
      --tests "tests/timing/test_clock.py tests/timing/test_clock_incremental.py -k 'not emulated'"
"""

from __future__ import annotations

import argparse
import ast
import copy
import json
import os
import shlex
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

_FLIP: dict[type, type] = {
    ast.Lt: ast.LtE,
    ast.LtE: ast.Lt,
    ast.Gt: ast.GtE,
    ast.GtE: ast.Gt,
    ast.Eq: ast.NotEq,
    ast.NotEq: ast.Eq,
    ast.Is: ast.IsNot,
    ast.IsNot: ast.Is,
    ast.In: ast.NotIn,
    ast.NotIn: ast.In,
}
_SYMBOL: dict[type, str] = {
    ast.Lt: "<",
    ast.LtE: "<=",
    ast.Gt: ">",
    ast.GtE: ">=",
    ast.Eq: "==",
    ast.NotEq: "!=",
    ast.Is: "is",
    ast.IsNot: "is not",
    ast.In: "in",
    ast.NotIn: "not in",
}


@dataclass
class Mutant:
    file: Path
    line: int
    kind: str
    what: str
    source: str  # the whole mutated file


def _skipped_nodes(tree: ast.AST) -> set[int]:
    """ids of nodes not to mutate: docstrings and annotations."""
    skip: set[int] = set()
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if isinstance(body, list) and body and isinstance(body[0], ast.Expr):
            value = body[0].value
            if isinstance(value, ast.Constant) and isinstance(value.value, str):
                skip.update(id(n) for n in ast.walk(body[0]))
        for ann in (getattr(node, "annotation", None), getattr(node, "returns", None)):
            if isinstance(ann, ast.AST):
                skip.update(id(n) for n in ast.walk(ann))
    return skip


def _sites(tree: ast.AST, numbers: str = "all") -> Iterator[tuple[list[int], str, str, int]]:
    """(path of child indices to the node, kind, variant, line) for every mutation site."""
    skip = _skipped_nodes(tree)
    index: dict[int, list[int]] = {}

    def walk(node: ast.AST, path: list[int]) -> None:
        index[id(node)] = path
        for i, child in enumerate(ast.iter_child_nodes(node)):
            walk(child, [*path, i])

    walk(tree, [])
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        line = getattr(node, "lineno", 0)
        path = index[id(node)]
        if isinstance(node, ast.Compare):
            for k, op in enumerate(node.ops):
                if type(op) in _FLIP:
                    yield path, "compare", str(k), line
        elif (
            isinstance(node, ast.Constant)
            and isinstance(node.value, int | float)
            and not (isinstance(node.value, bool))
        ):
            values = _numbers(node.value)
            for v in values[:1] if numbers == "one" else values:
                yield path, "number", repr(v), line
        elif isinstance(node, ast.Constant) and isinstance(node.value, bool):
            yield path, "bool", "", line
        elif isinstance(node, ast.BoolOp):
            yield path, "boolop", "", line
        elif (
            isinstance(node, ast.Return)
            and node.value is not None
            and not (isinstance(node.value, ast.Constant) and node.value.value is None)
        ):
            yield path, "return", "", line
        elif isinstance(node, ast.AugAssign) and isinstance(node.op, ast.Add | ast.Sub):
            yield path, "augassign", "", line


def _numbers(value: int | float) -> list[int | float]:
    if isinstance(value, bool):
        return []
    out: list[int | float]
    if isinstance(value, int):
        out = [value + 1, value - 1, value * 2] if value else [1]
    else:
        out = [value * 2, value / 2] if value else [1.0]
    return list(dict.fromkeys(v for v in out if v != value))


def _node_at(tree: ast.AST, path: list[int]) -> ast.AST:
    node = tree
    for i in path:
        node = list(ast.iter_child_nodes(node))[i]
    return node


def _apply(tree: ast.AST, path: list[int], kind: str, variant: str) -> tuple[ast.AST, str]:
    tree = copy.deepcopy(tree)
    node = _node_at(tree, path)
    if kind == "compare":
        assert isinstance(node, ast.Compare)
        k = int(variant)
        old = type(node.ops[k])
        new = _FLIP[old]
        node.ops[k] = new()
        return tree, f"{_SYMBOL[old]} -> {_SYMBOL[new]}"
    if kind == "number":
        assert isinstance(node, ast.Constant)
        old_value = node.value
        node.value = ast.literal_eval(variant)
        return tree, f"{old_value!r} -> {variant}"
    if kind == "bool":
        assert isinstance(node, ast.Constant)
        node.value = not node.value
        return tree, f"{not node.value} -> {node.value}"
    if kind == "boolop":
        assert isinstance(node, ast.BoolOp)
        was = "and" if isinstance(node.op, ast.And) else "or"
        node.op = ast.Or() if was == "and" else ast.And()
        return tree, f"{was} -> {'or' if was == 'and' else 'and'}"
    if kind == "return":
        assert isinstance(node, ast.Return)
        text = ast.unparse(node.value) if node.value is not None else ""
        node.value = ast.Constant(None)
        return tree, f"return {text[:50]} -> return None"
    if kind == "augassign":
        assert isinstance(node, ast.AugAssign)
        text = ast.unparse(node)
        parent = _node_at(tree, path[:-1])
        for field in ("body", "orelse", "finalbody"):
            stmts = getattr(parent, field, None)
            if isinstance(stmts, list) and node in stmts:
                stmts[stmts.index(node)] = ast.Pass()
        return tree, f"{text[:50]} -> removed"
    raise ValueError(kind)


def mutants(file: Path, named: list[dict[str, str]], numbers: str = "all") -> Iterator[Mutant]:
    text = file.read_text()
    tree = ast.parse(text)
    for path, kind, variant, line in _sites(tree, numbers):
        mutated, what = _apply(tree, path, kind, variant)
        yield Mutant(file, line, kind, what, ast.unparse(mutated) + "\n")
    rel = str(file.relative_to(ROOT)) if file.is_relative_to(ROOT) else str(file)
    for entry in named:
        if entry["file"] not in (rel, str(file)):
            continue
        if text.count(entry["find"]) != 1:
            raise SystemExit(f"named mutant {entry['name']!r}: its text is not once in {rel}")
        line = text[: text.index(entry["find"])].count("\n") + 1
        yield Mutant(
            file, line, "named", entry["name"], text.replace(entry["find"], entry["replace"])
        )


def _warm_up() -> None:
    """Import the heavy third-party modules once, before forking a child per mutant."""
    import importlib

    for name in ("pytest", "hypothesis", "numpy", "cobs.cobs", "construct", "cv2", "serial"):
        try:
            importlib.import_module(name)
        except ImportError:
            pass


def run_tests_forked(tests: list[str], timeout_s: float) -> str:
    """Run pytest in a forked child of this process: the third-party imports are already
    done, the project's modules and the tests are imported afresh from the mutated file."""
    sys.dont_write_bytecode = True
    pid = os.fork()
    if pid == 0:  # the child
        code = 3
        try:
            os.chdir(ROOT)
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, 1)
            os.dup2(devnull, 2)
            for name in list(sys.modules):
                if name.split(".")[0] in ("obstacle_fusion", "tests"):
                    del sys.modules[name]
            import pytest

            code = int(pytest.main(["-x", "-q", "-p", "no:cacheprovider", *tests]))
        finally:
            os._exit(code)
    deadline = time.monotonic() + timeout_s
    while True:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            break
        if time.monotonic() > deadline:
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
            return "killed (timeout)"
        time.sleep(0.02)
    code = os.waitstatus_to_exitcode(status)
    if code == 0:
        return "survived"
    return "killed" if code == 1 else f"killed (pytest exit {code})"


def run_tests(tests: list[str], timeout_s: float) -> str:
    env = dict(os.environ, PYTHONDONTWRITEBYTECODE="1")
    cmd = [sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider", *tests]
    try:
        proc = subprocess.run(
            cmd,
            cwd=ROOT,
            env=env,
            capture_output=True,
            timeout=timeout_s,
            start_new_session=True,
        )
    except subprocess.TimeoutExpired:
        return "killed (timeout)"
    if proc.returncode == 0:
        return "survived"
    if proc.returncode in (1,):
        return "killed"
    return f"killed (pytest exit {proc.returncode})"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("targets", nargs="+", type=Path, help="source files to mutate")
    parser.add_argument("--tests", required=True, help="pytest arguments (one string)")
    parser.add_argument("--named", type=Path, help="JSON list of named text mutants")
    parser.add_argument("--timeout", type=float, default=120.0, help="seconds per mutant run")
    parser.add_argument("--list", action="store_true", help="list the mutants, run nothing")
    parser.add_argument("--only-line", type=int, action="append", help="mutants on this line")
    parser.add_argument("--json", type=Path, help="write every mutant's result here")
    parser.add_argument(
        "--rerun", type=Path, help="only the mutants that survived in this earlier --json"
    )
    parser.add_argument(
        "--numbers",
        choices=("all", "one"),
        default="all",
        help="one: a single variant per number (n + 1, or 2 x for a float) to go faster",
    )
    parser.add_argument(
        "--subprocess",
        action="store_true",
        help="a new interpreter per mutant (slower) instead of a forked child",
    )
    args = parser.parse_args()
    runner = run_tests
    if not args.subprocess and hasattr(os, "fork"):
        _warm_up()
        runner = run_tests_forked
    tests = shlex.split(args.tests)
    named = json.loads(args.named.read_text()) if args.named else []
    again: set[tuple[int, str, str]] | None = None
    if args.rerun:
        again = {
            (int(r["line"]), str(r["kind"]), str(r["what"]))
            for r in json.loads(args.rerun.read_text())
            if r["verdict"] == "survived"
        }
    results: list[dict[str, object]] = []
    originals: dict[Path, str] = {}

    def restore(*_: object) -> None:
        for path, text in originals.items():
            path.write_text(text)
        if _:
            raise SystemExit(130)

    signal.signal(signal.SIGINT, restore)
    signal.signal(signal.SIGTERM, restore)
    baseline = runner(tests, args.timeout) if not args.list else "survived"
    if baseline != "survived":
        print(f"the tests fail before any mutation ({baseline}): fix that first")
        return 2
    try:
        for target in args.targets:
            target = target.resolve()
            originals[target] = target.read_text()
            todo = [
                m
                for m in mutants(target, named, args.numbers)
                if (not args.only_line or m.line in args.only_line)
                and (again is None or (m.line, m.kind, m.what) in again)
            ]
            killed = survived = 0
            print(f"{target.relative_to(ROOT)}: {len(todo)} mutants", flush=True)
            for k, m in enumerate(todo, 1):
                if args.list:
                    print(f"  {m.line:>4} {m.kind:<9} {m.what}")
                    continue
                start = time.monotonic()
                target.write_text(m.source)
                try:
                    verdict = runner(tests, args.timeout)
                finally:
                    target.write_text(originals[target])
                if verdict == "survived":
                    survived += 1
                    print(f"  SURVIVED line {m.line:>4} {m.kind:<9} {m.what}", flush=True)
                else:
                    killed += 1
                results.append(
                    {
                        "file": str(target.relative_to(ROOT)),
                        "line": m.line,
                        "kind": m.kind,
                        "what": m.what,
                        "verdict": verdict,
                        "seconds": round(time.monotonic() - start, 1),
                    }
                )
                if k % 25 == 0:
                    print(f"  ... {k}/{len(todo)}", flush=True)
            if not args.list:
                total = killed + survived
                print(
                    f"{target.relative_to(ROOT)}: {killed} killed, {survived} survived of "
                    f"{total} ({100 * killed / max(total, 1):.1f} % killed)",
                    flush=True,
                )
    finally:
        restore()
        if args.json:
            args.json.write_text(json.dumps(results, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
