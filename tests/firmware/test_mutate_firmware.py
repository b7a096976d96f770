"""tools/mutate_firmware.py: it makes the mutants issue 13 named (the ranger's cross-talk
guard halved, its timeout comparison off by one, the frame encoder's capacity check
shortened) and the native tests kill each of them."""

from __future__ import annotations

import importlib.util
import shutil
import sys
from pathlib import Path
from types import ModuleType

import pytest

pytestmark = pytest.mark.cpu_only

ROOT = Path(__file__).resolve().parents[2]


def load_tool() -> ModuleType:
    spec = importlib.util.spec_from_file_location(
        "mutate_firmware", ROOT / "tools" / "mutate_firmware.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


def test_code_mask_blanks_comments_strings_and_directives() -> None:
    tool = load_tool()
    text = '#include <a.h>\nint x = 1; /* y < 2 */ // z > 3\nchar *s = "a<b";\n'
    masked = tool.code_mask(text)
    assert len(masked) == len(text)
    assert "<" not in masked and ">" not in masked
    assert "int x = 1;" in masked


def named(tool: ModuleType) -> list[object]:
    mutants = tool.all_mutants()
    want = [
        lambda m: m.file == "of_ranger.c" and m.op == "half" and m.original == "OF_GUARD_US",
        lambda m: (
            m.file == "of_ranger.c"
            and m.op == "ror"
            and m.original == "<="
            and "echo_timeout_us"
            in (ROOT / "firmware/core/of_ranger.c").read_text().splitlines()[m.line - 1]
        ),
        lambda m: (
            m.file == "of_frame.c"
            and m.op == "const"
            and m.original == "6u"
            and m.replacement == "5u"
        ),
    ]
    found = []
    for pred in want:
        hits = [m for m in mutants if pred(m)]
        assert hits, "a named mutant is not generated"
        found.append(hits[0])
    return found


def test_named_mutants_are_generated_and_killed(tmp_path: Path) -> None:
    if shutil.which("gcc") is None:
        pytest.fail("no gcc: run `make setup`")
    tool = load_tool()
    base = tool.compile_objects(tmp_path)
    for mutant in named(tool):
        result = tool.test_mutant(mutant, tmp_path, emulator=False, base=base)
        # The guard halved is caught end to end (trigger gaps); natively it must still die.
        assert result.status == "killed-native", (mutant.name, result.detail)
