"""What a wheel ships and the emulator built on first use (obstacle_fusion.bundled)."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest
from obstacle_fusion import bundled
from obstacle_fusion.sim.emulator import EmulatorError, check_built

pytestmark = pytest.mark.cpu_only


def test_in_the_clone_the_build_tree_is_used(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("OF_EMULATOR", raising=False)
    monkeypatch.delenv("OF_FIRMWARE_ELF", raising=False)
    root = bundled.checkout_root()
    assert root is not None and (root / "firmware" / "Makefile").is_file()
    assert (
        bundled.default_emulator_binary() == root / "tools" / "emulator" / "build" / "of-emulator"
    )
    assert (
        bundled.default_firmware_elf()
        == root / "firmware" / "build" / "uno" / "obstacle-fusion.elf"
    )
    monkeypatch.setenv("OF_EMULATOR", "/opt/x/of-emulator")
    monkeypatch.setenv("OF_FIRMWARE_ELF", "/opt/x/fw.elf")
    assert bundled.default_emulator_binary() == Path("/opt/x/of-emulator")
    assert bundled.default_firmware_elf() == Path("/opt/x/fw.elf")


def _as_installed(monkeypatch: pytest.MonkeyPatch, data: Path, cache: Path) -> None:
    monkeypatch.setattr(bundled, "checkout_root", lambda: None)
    monkeypatch.setattr(bundled, "DATA_DIR", data)
    monkeypatch.setenv("XDG_CACHE_HOME", str(cache))
    monkeypatch.delenv("OF_EMULATOR", raising=False)
    monkeypatch.delenv("OF_FIRMWARE_ELF", raising=False)


def test_installed_the_emulator_is_built_once_per_source_version(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    if bundled.missing_build_tools():
        pytest.skip(f"needs {bundled.EMULATOR_DEBIAN_PACKAGES}")
    data = tmp_path / "_data"
    src = data / "emulator" / "src"
    shutil.copytree(bundled.REPO_ROOT / "tools" / "emulator" / "src", src)
    _as_installed(monkeypatch, data, tmp_path / "cache")
    binary = bundled.default_emulator_binary()
    assert binary.parent.parent == tmp_path / "cache" / "obstacle-fusion"
    assert not binary.exists()
    built = bundled.ensure_emulator(binary)
    assert built == binary and os.access(binary, os.X_OK)
    stamp = binary.stat().st_mtime_ns
    assert bundled.ensure_emulator(binary) == binary and binary.stat().st_mtime_ns == stamp
    (src / "rng.c").write_text((src / "rng.c").read_text() + "\n/* changed */\n")
    assert bundled.default_emulator_binary() != binary  # new sources, a new build


def test_installed_without_simavr_the_message_names_the_packages(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    data = tmp_path / "_data"
    shutil.copytree(bundled.REPO_ROOT / "tools" / "emulator" / "src", data / "emulator" / "src")
    (data / "firmware" / "uno").mkdir(parents=True)
    (data / "firmware" / "uno" / "obstacle-fusion.elf").write_bytes(b"\x7fELF")
    _as_installed(monkeypatch, data, tmp_path / "cache")
    monkeypatch.setattr(bundled, "missing_build_tools", lambda: ["libsimavr-dev", "libelf-dev"])
    with pytest.raises(bundled.BundleError) as info:  # a UserError: one line, exit 2
        check_built()
    text = str(info.value)
    assert "apt install gcc libsimavr-dev libelf-dev" in text and "OF_EMULATOR" in text
    assert "\n" not in text


def test_installed_without_a_firmware_elf_says_how_to_get_one(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    _as_installed(monkeypatch, tmp_path / "_data", tmp_path / "cache")
    fake = tmp_path / "of-emulator"
    fake.write_text("#!/bin/sh\n")
    fake.chmod(0o755)
    with pytest.raises(EmulatorError, match="OF_FIRMWARE_ELF"):
        check_built(binary=fake)
