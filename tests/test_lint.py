"""The code stays ruff- and mypy-clean: a style or type slip fails the suite, not a review."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.cpu_only

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent


def tool(name: str) -> str:
    path = shutil.which(name, path=str(BIN)) or shutil.which(name)
    if path is None:
        pytest.fail(f"{name} is not installed: run `make setup` (it installs the dev extra)")
    return path


def test_ruff_clean() -> None:
    result = subprocess.run(
        [tool("ruff"), "check", "host", "tools", "tests"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, result.stdout + result.stderr


def test_ruff_formatted() -> None:
    """One layout for all the Python: a diff shows what changed, not how it was typed."""
    result = subprocess.run(
        [tool("ruff"), "format", "--check", "host", "tools", "tests", "setup.py"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, (
        result.stdout + result.stderr + "\nrun `.venv/bin/ruff format host tools tests setup.py`"
    )


def test_mypy_clean() -> None:
    result = subprocess.run(
        [tool("mypy")],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0, result.stdout + result.stderr
