#!/usr/bin/env bash
# One-constant mutations of the decoder's C accelerator (host/obstacle_fusion/protocol/_cdecode.c):
# each is compiled in place, the decoder's tests run against it, and the verdict printed
# (killed: a test failed; SURVIVED: none did). The source and the built module are restored
# on exit. Not part of the suite (about 10 s per mutation): run it after changing the C code.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
py=.venv/bin/python
src=host/obstacle_fusion/protocol/_cdecode.c
so=host/obstacle_fusion/protocol/_cdecode$("$py" -c "import sysconfig; print(sysconfig.get_config_var('EXT_SUFFIX'))")
inc=$("$py" -c "import sysconfig; print(sysconfig.get_paths()['include'])")
[ -f "$so" ] || { echo "no $so: run make setup first" >&2; exit 1; }
keep=$(mktemp -d)
cp "$src" "$keep/src.c"
cp "$so" "$keep/module.so"
trap 'cp "$keep/src.c" "$src"; cp "$keep/module.so" "$so"; rm -rf "$keep"' EXIT
survived=0
mutate() {
  local name="$1" expr="$2"
  cp "$keep/src.c" "$src"
  sed -i "$expr" "$src"
  if cmp -s "$keep/src.c" "$src"; then echo "$name: the mutation did not apply"; exit 1; fi
  gcc -shared -std=c99 -O2 -fPIC -I"$inc" "$src" -o "$so"
  if nice -n 10 "$py" -m pytest -q -x -p no:cacheprovider tests/protocol/test_protocol_stream_paths.py \
      tests/protocol/test_protocol_stream.py >"$keep/log" 2>&1; then
    echo "$name: SURVIVED"
    survived=$((survived + 1))
  else
    echo "$name: killed by $(grep -m1 -oE 'FAILED [^ ]+' "$keep/log" | cut -d' ' -f2)"
  fi
}
mutate crc_poly 's/#define CRC_POLY 0x1021u/#define CRC_POLY 0x1023u/'
mutate gap_first 's/gaps += (Py_ssize_t)((seq - last - 1u) \& 0xFFu);/gaps += (Py_ssize_t)((seq - last - 0u) \& 0xFFu);/'
mutate gap_other 's/other.gaps += (Py_ssize_t)((seq - other.last - 1u) \& 0xFFu);/other.gaps += (Py_ssize_t)((seq - other.last - 1u) \& 0x7Fu);/'
mutate cobs_ff 's/if (code != 0xFFu) {/if (code != 0xFEu) {/'
mutate cobs_len 's/if (copy > len - in || copy > cap - out) {/if (copy > len - in + 1 || copy > cap - out) {/'
mutate size_cmp 's/|| size != e->body_size/|| size < e->body_size/'
mutate zeros 's/            zeros++;/            zeros += 2;/'
mutate u16 's/value = PyLong_FromLong((long)((unsigned)p\[0\] | ((unsigned)p\[1\] << 8)));/value = PyLong_FromLong((long)((unsigned)p[0] | ((unsigned)p[1] << 7)));/'
mutate s8 's/value = PyLong_FromLong((int8_t)p\[0\]);/value = PyLong_FromLong(p[0]);/'
mutate first_seq 's/                    other.first = seq;/                    other.first = seq + 1u;/'
mutate has_last 's/^                has_last = 1;$/                has_last = 0;/'
mutate tail 's/while (tail_at > 0 \&\& data\[tail_at - 1\] != 0) {/while (tail_at > 1 \&\& data[tail_at - 1] != 0) {/'
mutate pause 's/int paused = parts >= pause_frames/int paused = parts > pause_frames/'
mutate other_index 's/other.index = PyList_GET_SIZE(out);/other.index = PyList_GET_SIZE(out) - 1;/'
# Equivalent: a run of 54 bytes (no 0xFF code fits in it) decodes to 53 bytes, longer than
# every fixed-length body, so letting it through to the COBS decoder changes nothing.
mutate longest_equivalent 's/if (run <= longest_run \&\& run <= RUN_CAP) {/if (run <= longest_run + 1 \&\& run <= RUN_CAP) {/'
echo "$survived survived (longest_equivalent is expected to)"
