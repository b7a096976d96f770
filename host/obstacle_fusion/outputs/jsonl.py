"""JSON lines: one obstacle record per line, flushed at once so a robot controller can
consume them live (`obstacle-fusion run --json | my_controller`)."""

from __future__ import annotations

import json
import math
from typing import Any, TextIO

from obstacle_fusion.fusion import ObstacleRecord


def _clean(value: Any) -> Any:
    """NaN and infinities are not JSON: publish null instead."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_clean(v) for v in value]
    return value


def record_json(record: ObstacleRecord, extra: dict[str, Any] | None = None) -> str:
    data = record.to_dict()
    if extra:
        data.update(extra)
    return json.dumps(_clean(data), separators=(",", ":"), allow_nan=False)


class JsonLinesWriter:
    def __init__(self, stream: TextIO) -> None:
        self.stream = stream
        self.lines = 0
        self.broken = False  # the reader went away (a closed pipe); stop writing, keep running

    def write(self, record: ObstacleRecord, extra: dict[str, Any] | None = None) -> None:
        if self.broken:
            return
        try:
            self.stream.write(record_json(record, extra) + "\n")
            self.stream.flush()
            self.lines += 1
        except BrokenPipeError:
            self.broken = True
