"""Types of the fused vision method's optional C accelerator (_cmiddle.c)."""

from typing import Any

def middle_u8(src: Any, network: bytes, lo: Any, hi: Any, /) -> None: ...
