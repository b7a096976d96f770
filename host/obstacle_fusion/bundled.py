"""The files the package ships beside its Python code, and the emulator built from them.

A wheel (``pip install .``) carries, under ``obstacle_fusion/_data/``, what the build hook in
setup.py made: the firmware images (``firmware/uno/obstacle-fusion.hex`` and ``.elf``,
``firmware/bluepill/obstacle-fusion.bin``) and the emulator's C sources
(``emulator/src/``). In a clone of the repository the same files come from the build tree
that ``make setup`` fills (``firmware/build/``, ``tools/emulator/build/``) instead.

The emulator is a native program linked against simavr, so a wheel cannot carry it built:
it is compiled on first use into a per-user cache folder (``$XDG_CACHE_HOME/obstacle-fusion``
or ``~/.cache/obstacle-fusion``), one build per version of its sources.

Environment variables: ``OF_EMULATOR`` names an emulator program to use instead,
``OF_FIRMWARE_ELF`` the Uno firmware ELF the emulator runs.
"""

from __future__ import annotations

import hashlib
import logging
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

from obstacle_fusion.errors import UserError

log = logging.getLogger(__name__)

PACKAGE_DIR = Path(__file__).resolve().parent
DATA_DIR = PACKAGE_DIR / "_data"
REPO_ROOT = PACKAGE_DIR.parents[1]  # host/obstacle_fusion -> the clone, when it is one

IMAGE_NAMES = {"uno": "obstacle-fusion.hex", "bluepill": "obstacle-fusion.bin"}
EMULATOR_DEBIAN_PACKAGES = "gcc libsimavr-dev libelf-dev"


class BundleError(UserError):
    """A file the package should ship is missing, or the emulator cannot be built."""


def checkout_root() -> Path | None:
    """The repository this package runs from (an editable install), else None."""
    if (REPO_ROOT / "tools" / "emulator" / "src").is_dir() and (
        REPO_ROOT / "firmware" / "Makefile"
    ).is_file():
        return REPO_ROOT
    return None


def firmware_sources() -> Path | None:
    """The firmware's sources (its Makefile's folder), only in a clone."""
    root = checkout_root()
    return None if root is None else root / "firmware"


def firmware_file(board: str, name: str) -> Path | None:
    """A firmware build output: the clone's build tree first, then the package's copy."""
    root = checkout_root()
    candidates = []
    if root is not None:
        candidates.append(root / "firmware" / "build" / board / name)
    candidates.append(DATA_DIR / "firmware" / board / name)
    for path in candidates:
        if path.is_file():
            return path
    return None


def firmware_image(board: str) -> Path | None:
    """The image a flasher writes: the Uno's .hex or the blue pill's .bin."""
    return firmware_file(board, IMAGE_NAMES[board])


def default_firmware_elf() -> Path:
    """The Uno ELF the emulator runs: $OF_FIRMWARE_ELF, the clone's build, or the package's."""
    env = os.environ.get("OF_FIRMWARE_ELF")
    if env:
        return Path(env)
    found = firmware_file("uno", "obstacle-fusion.elf")
    if found is not None:
        return found
    root = checkout_root()
    if root is not None:
        return root / "firmware" / "build" / "uno" / "obstacle-fusion.elf"
    return DATA_DIR / "firmware" / "uno" / "obstacle-fusion.elf"


OPTIBOOT_SOURCE = Path("/usr/share/arduino/hardware/arduino/avr/bootloaders/optiboot")


def optiboot_hex() -> Path | None:
    """The Uno's Optiboot as tools/emulator builds it from Debian's arduino-core-avr source
    (`make -C tools/emulator optiboot`), in a clone; None when not built."""
    root = checkout_root()
    if root is None:
        return None
    path = root / "tools" / "emulator" / "build" / "optiboot" / "optiboot_atmega328.hex"
    return path if path.is_file() else None


def emulator_sources() -> Path | None:
    """The emulator's C sources: the clone's tools/emulator/src or the package's copy."""
    root = checkout_root()
    for src in ([root / "tools" / "emulator" / "src"] if root else []) + [
        DATA_DIR / "emulator" / "src"
    ]:
        if any(src.glob("*.c")):
            return src
    return None


def cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "obstacle-fusion"


def _sources_digest(src: Path) -> str:
    h = hashlib.sha256()
    for path in sorted([*src.glob("*.c"), *src.glob("*.h")]):
        h.update(path.name.encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()[:12]


def cached_emulator_path(src: Path) -> Path:
    return cache_dir() / f"emulator-{_sources_digest(src)}" / "of-emulator"


def default_emulator_binary() -> Path:
    """$OF_EMULATOR, the clone's `make setup` build, or the per-user build of the shipped
    sources (which may not exist yet: ensure_emulator builds it)."""
    env = os.environ.get("OF_EMULATOR")
    if env:
        return Path(env)
    root = checkout_root()
    if root is not None:
        return root / "tools" / "emulator" / "build" / "of-emulator"
    src = emulator_sources()
    if src is None:
        return DATA_DIR / "emulator" / "of-emulator"  # missing: the caller says so
    return cached_emulator_path(src)


def _simavr_flags() -> tuple[list[str], list[str]]:
    pkg_config = shutil.which("pkg-config")
    cflags, libs = ["-isystem", "/usr/include/simavr"], ["-lsimavr"]
    if pkg_config:
        got_c = subprocess.run(
            [pkg_config, "--cflags-only-I", "simavr"], capture_output=True, text=True
        )
        got_l = subprocess.run([pkg_config, "--libs", "simavr"], capture_output=True, text=True)
        if got_c.returncode == 0 and got_l.returncode == 0 and got_l.stdout.strip():
            # third-party headers as system headers: their warnings are not ours
            cflags = []
            for word in got_c.stdout.split():
                cflags += ["-isystem", word[2:]] if word.startswith("-I") else [word]
            libs = got_l.stdout.split()
    return cflags, libs


def missing_build_tools() -> list[str]:
    """What building the emulator lacks, as Debian package names."""
    missing = []
    if shutil.which(os.environ.get("CC", "cc")) is None and shutil.which("gcc") is None:
        missing.append("gcc")
    if not any(
        Path(d, "sim_avr.h").is_file() for d in ("/usr/include/simavr", "/usr/local/include/simavr")
    ):
        missing.append("libsimavr-dev")
    if not any(Path(d, "libelf.h").is_file() for d in ("/usr/include", "/usr/local/include")):
        missing.append("libelf-dev")
    return missing


def build_emulator(src: Path, out: Path) -> Path:
    """Compile the emulator from `src` into `out` (atomically: concurrent first uses agree)."""
    missing = missing_build_tools()
    if missing:
        raise BundleError(
            "the emulator is built on first use and needs a C compiler, simavr and libelf: "
            f"apt install {EMULATOR_DEBIAN_PACKAGES} (missing: {' '.join(missing)}); or set "
            "OF_EMULATOR to an emulator program"
        )
    cc = os.environ.get("CC") or shutil.which("cc") or "gcc"
    cflags, libs = _simavr_flags()
    out.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp_name = tempfile.mkstemp(prefix=".of-emulator-", dir=out.parent)
    os.close(fd)
    tmp = Path(tmp_name)
    cmd = [
        cc, "-std=c99", "-O2", "-Wall", "-Wextra", "-D_DEFAULT_SOURCE", "-D_XOPEN_SOURCE=700",
        *cflags, "-o", str(tmp), *sorted(str(p) for p in src.glob("*.c")), *libs, "-lelf",
        "-lm",
    ]  # fmt: skip
    log.info("building the emulator (first use): %s", " ".join(cmd))
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        tmp.unlink(missing_ok=True)
        detail = done.stderr.strip().splitlines()
        raise BundleError(
            f"building the emulator from {src} failed ({detail[-1] if detail else 'no output'}); "
            f"it needs {EMULATOR_DEBIAN_PACKAGES} (apt install {EMULATOR_DEBIAN_PACKAGES})"
        )
    tmp.chmod(0o755)
    os.replace(tmp, out)
    return out


def ensure_emulator(binary: Path) -> Path:
    """`binary`, built first when it is the per-user build of the shipped sources."""
    if binary.is_file():
        return binary
    src = emulator_sources()
    if src is not None and "OF_EMULATOR" not in os.environ and checkout_root() is None:
        if binary == cached_emulator_path(src):
            return build_emulator(src, binary)
    return binary
