"""The textured-room renderer: deterministic scenes, true sizes, disjoint held-out photographs."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from obstacle_fusion.sim.room_scene import (
    FACE_KINDS,
    FAMILIES,
    PHOTO_TEXTURES,
    RoomRenderer,
    RoomSpec,
    render_room,
)
from obstacle_fusion.vision.camera import CameraModel

pytestmark = pytest.mark.cpu_only

CAM = CameraModel.paper(500, 375)


def test_a_scene_is_fixed_by_family_seed_and_kind() -> None:
    a, truth_a, spec_a = render_room("procedural", 5, False, CAM)
    b, truth_b, _ = render_room("procedural", 5, False, CAM)
    c, _, _ = render_room("procedural", 6, False, CAM)
    assert a.shape == (375, 500, 3) and a.dtype == np.uint8
    assert np.array_equal(a, b) and truth_a == truth_b
    assert not np.array_equal(a, c)
    assert truth_a["height_m"] == spec_a.height_m and truth_a["range_m"] == spec_a.range_m


def test_random_rigs_follow_the_held_out_sets_description() -> None:
    rigs = [RoomSpec.random(f, s, h).rig for f in FAMILIES for s in range(20) for h in (0, 1)]
    heights = [r.camera_height_m for r in rigs]
    pitches = [r.camera_pitch_deg for r in rigs]
    assert 0.2 <= min(heights) and max(heights) <= 0.5
    assert -5.0 <= min(pitches) and max(pitches) <= 5.0 and min(pitches) < 0 < max(pitches)
    assert {r.sonar_below_m for r in rigs} == {0.03}


def test_held_out_photographs_are_never_the_tuning_ones() -> None:
    tuned = {n for names in PHOTO_TEXTURES["photo"].values() for n in names}
    held = {n for names in PHOTO_TEXTURES["photo-holdout"].values() for n in names}
    assert tuned and held and not tuned & held


def test_every_face_kind_renders_and_changes_the_face() -> None:
    renderer = RoomRenderer(CAM)
    base = RoomSpec.random("procedural", 3, False)
    faces = {}
    for kind in FACE_KINDS:
        image, truth = renderer.render(dataclasses.replace(base, face_kind=kind))
        assert truth["face_kind"] == kind
        faces[kind] = image
    assert len({f.tobytes() for f in faces.values()}) == len(FACE_KINDS)


def test_the_truth_says_which_borders_cut_the_face() -> None:
    renderer = RoomRenderer(CAM)
    base = dataclasses.replace(RoomSpec.random("procedural", 1, False), face_x_m=0.0)
    _, whole = renderer.render(dataclasses.replace(base, width_m=0.2))
    _, wide = renderer.render(dataclasses.replace(base, width_m=3.0 * base.range_m))
    assert whole["clipped"] == []
    assert "left" in wide["clipped"] and "right" in wide["clipped"]


def test_an_unknown_family_is_refused() -> None:
    with pytest.raises(ValueError, match="unknown family"):
        RoomSpec.random("kitchen", 1, False)
