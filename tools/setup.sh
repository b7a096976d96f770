#!/usr/bin/env bash
# Make a fresh Debian machine ready: toolchains from apt (only when missing), a virtual
# environment with the package and its test tools, the firmware images and the emulator.
# Idempotent: a second run only rebuilds what changed.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
log() { printf '[setup] %s\n' "$*" >&2; }

need_apt=()
command -v avr-gcc >/dev/null || need_apt+=(gcc-avr binutils-avr)
[ -f /usr/lib/avr/include/avr/io.h ] || [ -f /usr/avr/include/avr/io.h ] || need_apt+=(avr-libc)
command -v simavr >/dev/null || need_apt+=(simavr)
[ -f /usr/include/simavr/sim_avr.h ] || need_apt+=(libsimavr-dev)
[ -f /usr/include/libelf.h ] || need_apt+=(libelf-dev)
command -v pkg-config >/dev/null || need_apt+=(pkg-config)
command -v arm-none-eabi-gcc >/dev/null || need_apt+=(gcc-arm-none-eabi)
[ -d /usr/lib/arm-none-eabi/newlib ] || need_apt+=(libnewlib-arm-none-eabi)
command -v make >/dev/null || need_apt+=(make)
command -v gcc >/dev/null || need_apt+=(gcc libc6-dev)
# clang with libFuzzer and the sanitizer runtimes: tools/fuzz_firmware.py and its 30 s test.
command -v clang >/dev/null || need_apt+=(clang)
compgen -G "/usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-*.a" >/dev/null \
  || need_apt+=(libclang-rt-dev)
# The Uno's own bootloader (Optiboot's source, built by tools/emulator) and avrdude: the
# emulator boots it and `obstacle-fusion flash` writes through it (the flashing test).
[ -f /usr/share/arduino/hardware/arduino/avr/bootloaders/optiboot/optiboot.c ] \
  || need_apt+=(arduino-core-avr)
command -v avrdude >/dev/null || need_apt+=(avrdude)
# Python's headers: the stream decoder's optional C accelerator is compiled against them (a
# pyenv or python.org build has them; Debian's python3 needs python3-dev).
pyinc="$("${PYTHON:-python3}" -c "import sysconfig; print(sysconfig.get_paths()['include'])")"
[ -f "$pyinc/Python.h" ] || need_apt+=(python3-dev)
# Optional: QEMU boots the blue pill image for a smoke test (skipped without it).
command -v qemu-system-arm >/dev/null || need_apt+=(qemu-system-arm)
if [ ${#need_apt[@]} -gt 0 ]; then
  sudo=""
  [ "$(id -u)" = 0 ] || sudo="sudo"
  log "installing Debian packages: ${need_apt[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${need_apt[@]}" >/dev/null
fi

python="${PYTHON:-python3}"
if [ ! -x .venv/bin/python ]; then
  log "creating .venv"
  "$python" -m venv .venv
fi
# pyproject.toml, setup.py and the C accelerators: a change to any of them reinstalls (rebuilds it)
stamp=.venv/.installed-$(cat pyproject.toml setup.py host/obstacle_fusion/protocol/_cdecode.c \
  host/obstacle_fusion/vision/fused/_cmiddle.c | sha1sum | cut -c1-12)
if [ ! -f "$stamp" ]; then
  log "installing the Python package and its test tools into .venv"
  .venv/bin/python -m pip install -q --upgrade pip >/dev/null
  .venv/bin/python -m pip install -q -e '.[dev,all]'
  rm -f .venv/.installed-*
  touch "$stamp"
fi

log "building the firmware (uno, bluepill) and the emulator"
for board in uno bluepill; do
  if [ -f firmware/Makefile ]; then make -s -C firmware BOARD="$board" >/dev/null; fi
done
if [ -f tools/emulator/Makefile ]; then make -s -C tools/emulator >/dev/null; fi
log "ready"
