"""Types of the stream decoder's optional C accelerator (_cdecode.c)."""

from typing import Any

from obstacle_fusion.protocol.generated import Message

def scan(
    data: bytes, last_seq: int | None, /
) -> tuple[
    list[Message | bytes],
    bytes,
    int | None,
    int,
    int,
    int,
    list[tuple[int, int, int, int, int]] | None,
]: ...
def configure(
    entries: list[tuple[int, type, bytes, tuple[Any, ...], int]],
    longest_run: int,
    pause_frames: int,
    /,
) -> None: ...
def cobs_decode(run: bytes, /) -> bytes: ...
def crc16(data: bytes, seed: int, /) -> int: ...
