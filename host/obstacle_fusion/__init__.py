"""obstacle-fusion: an HC-SR04 sonar and one camera, fused into obstacle range, height, width.

The package follows the data on a robot, in order:

1. ``protocol``  bytes <-> messages: the generated definitions, COBS+CRC framing, decoder
2. ``link``      the serial link to the board (reader thread, handshake) and port discovery
3. ``timing``    the clock model that maps MCU microseconds onto the host's monotonic clock
4. ``sonar``     echo ticks -> metres (speed of sound, filters, explicit statuses)
5. ``sources``   camera frames, stamped on the host's clock
6. ``vision``    one frame + the sonar range -> the obstacle's size in pixels and metres
7. ``fusion``    pairs each frame with the range of the same instant -> obstacle records
8. ``outputs``   console, JSON lines, MCAP recording, annotated video
9. ``app``       the live loop wiring 1-8 together (``online``: the rig and camera latency
                 learnt while running; ``api``: ObstacleSensor, the Python API over it)

Apart from the robot's path: ``sim`` (the firmware emulator wrapper, the emulated robot,
scenarios, the scene renderer and the synthetic camera), used when no board or camera is
attached and by the tests; ``cli`` is the ``obstacle-fusion`` command line; ``api`` the
Python API for robot code (``ObstacleSensor``, ``AsyncObstacleSensor``), importable from
here without loading anything heavy until it is used.
"""

from __future__ import annotations

from typing import Any

__version__ = "0.1.0"
__all__ = ["AsyncObstacleSensor", "ObstacleRecord", "ObstacleSensor", "__version__"]

_LAZY = {
    "ObstacleSensor": "obstacle_fusion.api",
    "AsyncObstacleSensor": "obstacle_fusion.api",
    "ObstacleRecord": "obstacle_fusion.fusion",
}


def __getattr__(name: str) -> Any:
    """``obstacle_fusion.ObstacleSensor`` and friends, imported on first use (PEP 562); by
    name only, so the package imports nothing of its own (no import cycle through it)."""
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'obstacle_fusion' has no attribute {name!r}")
    import importlib

    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value
