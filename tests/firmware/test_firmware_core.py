"""Native tests of the portable firmware core: tests/native/test_core.c against a fake board.

The C file holds the scenarios (normal echo, no echo, an echo that never falls, Timer1
overflow during an echo, the 32-bit microsecond wrap, back-to-back triggers, config
validation, TX overrun, ...). This module compiles it once with the host's gcc, with the
address and undefined-behaviour sanitizers, and runs each scenario as its own test.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

#: one xdist worker builds the module fixture once (run_tests.sh: --dist loadgroup)
pytestmark = [pytest.mark.cpu_only, pytest.mark.xdist_group("firmware_core")]

ROOT = Path(__file__).resolve().parents[2]
CORE = ROOT / "firmware" / "core"
NATIVE = ROOT / "tests" / "native"
SOURCES = [
    NATIVE / "test_core.c",
    NATIVE / "fake_hal.c",
    CORE / "of_app.c",
    CORE / "of_ranger.c",
    CORE / "of_ring.c",
    CORE / "of_frame.c",
]
CFLAGS = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-O1", "-g"]
SANITIZERS = ["-fsanitize=address,undefined", "-fno-sanitize-recover=all"]


def declared_tests() -> list[str]:
    """Scenario names from the runner's table, so a new C test becomes a pytest case."""
    text = (NATIVE / "test_core.c").read_text()
    return re.findall(r'\{"(\w+)", test_\w+\}', text)


def _compile(cc: str, out: Path, extra: list[str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [cc, *CFLAGS, *extra, f"-I{NATIVE}", f"-I{CORE}", *map(str, SOURCES), "-o", str(out)],
        capture_output=True,
        text=True,
    )


@pytest.fixture(scope="module")
def test_binary(tmp_path_factory: pytest.TempPathFactory) -> Path:
    cc = shutil.which("gcc") or shutil.which("cc")
    if cc is None:
        pytest.fail("no host C compiler: install gcc (`make setup`)")
    out = tmp_path_factory.mktemp("native") / "test_core"
    result = _compile(cc, out, SANITIZERS)
    if result.returncode != 0 and "sanitize" in result.stderr:
        result = _compile(cc, out, [])  # a toolchain without sanitizer runtimes
    assert result.returncode == 0, result.stderr
    return out


def test_runner_lists_every_declared_test(test_binary: Path) -> None:
    listed = subprocess.run(
        [str(test_binary), "--list"], capture_output=True, text=True, check=True
    ).stdout.split()
    assert listed == declared_tests()
    assert len(listed) >= 10


def test_unknown_test_name_fails(test_binary: Path) -> None:
    result = subprocess.run([str(test_binary), "no_such_test"], capture_output=True, text=True)
    assert result.returncode != 0


@pytest.mark.parametrize("name", declared_tests())
def test_core(test_binary: Path, name: str) -> None:
    result = subprocess.run([str(test_binary), name], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stdout + result.stderr
    assert f"{name}: ok" in result.stdout
