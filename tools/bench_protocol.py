#!/usr/bin/env python3
"""Host decode throughput: a long stream of RANGE frames through StreamDecoder on one core.

Prints frames per second for several chunk sizes (a serial port hands the reader small
chunks; a capture file, large ones). Target: >= 200,000 frames/s.
"""

from __future__ import annotations

import argparse
import random
import time

from obstacle_fusion.protocol import StreamDecoder, encode
from obstacle_fusion.protocol.generated import Range, RangeStatus


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


def bench(stream: bytes, chunk: int, n: int, repeats: int) -> float:
    best = 0.0
    for _ in range(repeats):
        decoder = StreamDecoder()
        start = time.perf_counter()
        count = 0
        for offset in range(0, len(stream), chunk):
            count += len(decoder.feed(stream[offset : offset + chunk]))
        elapsed = time.perf_counter() - start
        assert count == n and decoder.stats.bad_frames == 0, decoder.stats
        best = max(best, count / elapsed)
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=200_000)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    stream = make_stream(args.frames)
    print(f"decode throughput, {args.frames} RANGE frames ({len(stream)} bytes), best of "
          f"{args.repeats}")
    print(f"{'chunk bytes':>12} {'frames/s':>12}")
    for chunk in (64, 1024, 65536):
        rate = bench(stream, chunk, args.frames, args.repeats)
        print(f"{chunk:>12} {rate:>12,.0f}")


if __name__ == "__main__":
    main()
