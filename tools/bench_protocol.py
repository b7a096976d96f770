#!/usr/bin/env python3
"""Host decode throughput: a long stream of RANGE frames through StreamDecoder on one core,
side by side with a bare COBS + CRC loop over the same bytes and chunks.

The bare loop is the least any Python decoder must do per frame (split at 0x00, COBS-decode
with the `cobs` package's C code, check the CRC with binascii's) and builds no message; the
ratio says what the decoder's bookkeeping and message objects cost. The decoder is timed on
its default path (the C accelerator when it is built and OBSTACLE_FUSION_PURE_PYTHON is not
set; the first line says which) and on its pure-Python path, all in alternation, best of
--repeats, so a busy machine slows them alike. Targets: >= 200,000 frames/s, and the
decoder at >= 0.5 of the bare loop.

A fourth loop only builds the messages: the bodies each chunk completes, already decoded and
checked, turned into Range messages by the quickest Python route there is
(Struct.iter_unpack and the class), in the same groups, with the garbage collection paused
for a group as long as the decoder pauses it for. "ceiling" is the ratio a pure-Python
decoder could reach at best, doing nothing but the bare loop's work and this: bare time /
(bare time + build time). The C accelerator is not bound by it: it makes each message with
the class's tp_new and its slots, without the dataclass __init__.
"""

from __future__ import annotations

import argparse
import binascii
import gc
import random
import struct
import time
from itertools import starmap

from cobs import cobs
from obstacle_fusion.protocol import StreamDecoder, encode
from obstacle_fusion.protocol.codec import CRC_SEEDS
from obstacle_fusion.protocol.generated import Range, RangeStatus
from obstacle_fusion.protocol.stream import PAUSE_GC_FRAMES


def make_stream(n: int, seed: int = 1) -> bytes:
    rng = random.Random(seed)
    frames = []
    for i in range(n):
        msg = Range(
            measurement=i,
            sensor_id=i % 2,
            trigger_us=(i * 60_000) & 0xFFFFFFFF,
            echo_ticks=rng.randrange(100, 60_000),
            status=RangeStatus.OK,
        )
        frames.append(encode(msg, i & 0xFF))
    return b"".join(frames)


def run_decoder(stream: bytes, chunk: int, accelerated: bool | None = None) -> tuple[int, float]:
    decoder = StreamDecoder(accelerated=accelerated)
    count = 0
    start = time.perf_counter()
    for offset in range(0, len(stream), chunk):
        count += len(decoder.feed(stream[offset : offset + chunk]))
    elapsed = time.perf_counter() - start
    assert decoder.stats.bad_frames == 0 and decoder.stats.bytes_discarded == 0, decoder.stats
    return count, elapsed


def run_bare(stream: bytes, chunk: int) -> tuple[int, float]:
    """Split at 0x00, COBS-decode, check the CRC: no message, no counters."""
    crc = binascii.crc_hqx
    decode = cobs.decode
    seeds = CRC_SEEDS
    tail = b""
    count = 0
    start = time.perf_counter()
    for offset in range(0, len(stream), chunk):
        data = tail + stream[offset : offset + chunk]
        parts = data.split(b"\x00")
        tail = parts.pop()
        for part in parts:
            if part:
                body = decode(part)
                if crc(body, seeds[body[0]]) == 0:
                    count += 1
    return count, time.perf_counter() - start


def run_build(stream: bytes, chunk: int) -> tuple[int, float]:
    """Only build the messages, from bodies already COBS-decoded and CRC-checked, grouped
    as the chunks complete them."""
    row = struct.Struct("<xx" + Range.STRUCT.format.lstrip("<") + "xx")
    groups = []
    tail = b""
    for offset in range(0, len(stream), chunk):
        parts = (tail + stream[offset : offset + chunk]).split(b"\x00")
        tail = parts.pop()
        groups.append(b"".join(cobs.decode(part) for part in parts))
    count = 0
    pause = PAUSE_GC_FRAMES * row.size  # the decoder pauses the GC for this many frames
    start = time.perf_counter()
    for blob in groups:
        if len(blob) >= pause and gc.isenabled():
            gc.disable()
            try:
                count += len(list(starmap(Range, row.iter_unpack(blob))))
            finally:
                gc.enable()
        else:
            count += len(list(starmap(Range, row.iter_unpack(blob))))
    return count, time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=200_000)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    stream = make_stream(args.frames)
    path = (
        "C accelerator (obstacle_fusion.protocol._cdecode)"
        if StreamDecoder().accelerated
        else "pure Python (no C accelerator: not built, or OBSTACLE_FUSION_PURE_PYTHON set)"
    )
    print(
        f"decode throughput, {args.frames} RANGE frames ({len(stream)} bytes), best of "
        f"{args.repeats}, decoder, pure-Python decoder and bare loop alternating"
    )
    print(f"decoder path timed: {path}")
    print(
        f"{'chunk bytes':>12} {'decoder frames/s':>17} {'bare COBS+CRC/s':>16} {'ratio':>6} "
        f"{'pure Python/s':>14} {'ratio':>6} {'build only/s':>13} {'ceiling':>8}"
    )
    for chunk in (64, 1024, 65536):
        best_dec = best_pure = best_bare = best_build = 0.0
        for _ in range(args.repeats):
            n, t = run_decoder(stream, chunk)
            assert n == args.frames
            best_dec = max(best_dec, n / t)
            n, t = run_bare(stream, chunk)
            assert n == args.frames
            best_bare = max(best_bare, n / t)
            n, t = run_decoder(stream, chunk, accelerated=False)
            assert n == args.frames
            best_pure = max(best_pure, n / t)
            n, t = run_build(stream, chunk)
            assert n == args.frames
            best_build = max(best_build, n / t)
        ceiling = best_build / (best_build + best_bare)  # 1 / (1 + t_build / t_bare)
        print(
            f"{chunk:>12} {best_dec:>17,.0f} {best_bare:>16,.0f} {best_dec / best_bare:>6.2f} "
            f"{best_pure:>14,.0f} {best_pure / best_bare:>6.2f} {best_build:>13,.0f} "
            f"{ceiling:>8.2f}"
        )


if __name__ == "__main__":
    main()
