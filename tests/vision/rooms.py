"""Rooms for the vision tests: a tuning family's room made plain, so one cue is tried at a time."""

from __future__ import annotations

import dataclasses

from obstacle_fusion.sim.room_scene import RoomSpec

#: What makes a room plain: a one-colour face, square to the beam, centred, no clutter,
#: shadow, compression, and mild blur and noise.
PLAIN = dict(
    face_kind="plain",
    clutter=0,
    shadow=False,
    yaw_deg=0.0,
    roll_deg=0.0,
    jpeg=None,
    blur=0.3,
    noise=1.5,
    face_x_m=0.0,
)


def plain_room(seed: int, **changes: object) -> RoomSpec:
    """Room ``seed`` of the procedural family (ordinary), made plain, then ``changes``."""
    spec = RoomSpec.random("procedural", seed, False)
    return dataclasses.replace(spec, **{**PLAIN, **changes})  # type: ignore[arg-type]


def pitched_plain_room(seed: int, pitch: float) -> RoomSpec:
    """A plain face 0.35 x 0.5 m at 1 m, the camera 0.3 m high and pitched ``pitch``."""
    spec = plain_room(seed, range_m=1.0, height_m=0.35, width_m=0.5)
    return dataclasses.replace(
        spec, rig=dataclasses.replace(spec.rig, camera_pitch_deg=pitch, camera_height_m=0.3)
    )
