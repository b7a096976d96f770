"""Argument types and checks shared by `run` and `replay`, so both accept the same values.

Each type is an argparse ``type=`` callable: a bad value ends with argparse's usage error
(exit 2) naming the option and the accepted span, before anything is opened or started.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable
from pathlib import Path

from obstacle_fusion.errors import UserError

TEMPERATURE_C = (-50.0, 80.0)  # what an HC-SR04 robot meets; the speed of sound formula's span
PAIR_TOLERANCE_MS = (0.0, 1000.0)  # beyond a second a "nearest" range is a stale one
CAMERA_LATENCY_MS = (0.0, 2000.0)
FRAME_SIDE_PX = (16, 8192)
EXIT_CODE = (1, 125)  # 0 is success; 126..255 mean "cannot run", "not found", signals


def _number(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text}")
    return value


def _integer(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None


def positive_float(text: str) -> float:
    value = _number(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be positive, got {text}")
    return value


def positive_int(text: str) -> int:
    value = _integer(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be a positive whole number, got {text}")
    return value


def float_within(lo: float, hi: float, unit: str = "") -> Callable[[str], float]:
    def parse(text: str) -> float:
        value = _number(text)
        if not lo <= value <= hi:
            raise argparse.ArgumentTypeError(f"must be within {lo:g}..{hi:g}{unit}, got {text}")
        return value

    return parse


def int_within(lo: int, hi: int) -> Callable[[str], int]:
    def parse(text: str) -> int:
        value = _integer(text)
        if not lo <= value <= hi:
            raise argparse.ArgumentTypeError(f"must be within {lo}..{hi}, got {text}")
        return value

    return parse


temperature_c = float_within(*TEMPERATURE_C, " C")
pair_tolerance_ms = float_within(*PAIR_TOLERANCE_MS, " ms")
camera_latency_ms = float_within(*CAMERA_LATENCY_MS, " ms")
frame_side_px = int_within(*FRAME_SIDE_PX)
exit_code = int_within(*EXIT_CODE)
stop_distance_m = positive_float
median_window = positive_int


def add_processing_args(parser: argparse.ArgumentParser | argparse._ArgumentGroup) -> None:
    """The options `run` and `replay` share, with the same types (no defaults that differ)."""
    parser.add_argument(
        "--median", type=median_window, default=1, help="median filter over N ranges (1 = none)"
    )
    parser.add_argument(
        "--pair-tolerance-ms",
        type=pair_tolerance_ms,
        default=50.0,
        help="nearest-range pairing tolerance when no interpolation is possible (0..1000)",
    )


def refuse_overwrite(path: Path | None, option: str, overwrite: bool) -> None:
    """An existing output is someone's data: only --overwrite replaces it."""
    if path is not None and not overwrite and path.exists():
        raise UserError(
            f"{option} {path}: the file already exists; give another name, or --overwrite "
            "to replace it"
        )
