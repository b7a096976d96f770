"""Helpers for command-line tests."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest


def _cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "obstacle_fusion", *args],
        capture_output=True,
        text=True,
        timeout=120,
    )


def unreadable_run(path: Path, *args: str) -> subprocess.CompletedProcess[str]:
    """Make path unreadable and run the CLI on it (as nobody when we are root, who reads
    anything), from a folder everyone may enter."""
    path.chmod(0)
    if os.geteuid() != 0:
        return _cli(*args)
    if shutil.which("setpriv") is None:
        pytest.fail("running as root without setpriv: cannot test a permission error")
    return subprocess.run(
        [
            "setpriv",
            "--reuid=65534",
            "--regid=65534",
            "--clear-groups",
            sys.executable,
            "-m",
            "obstacle_fusion",
            *args,
        ],
        capture_output=True,
        text=True,
        timeout=60,
    )
