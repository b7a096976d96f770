"""Vision: the camera model, its calibration, and the obstacle measurement.

Kept import-light on purpose: submodules pull in OpenCV, so import what you need from
them directly (``from obstacle_fusion.vision.camera import CameraModel``). The names below
are resolved lazily on first access for convenience.
"""

from __future__ import annotations

import importlib
from typing import Any

_LAZY = {
    "CameraModel": "obstacle_fusion.vision.camera",
    "CameraModelError": "obstacle_fusion.vision.camera",
}

__all__ = sorted(_LAZY)


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(module), name)
