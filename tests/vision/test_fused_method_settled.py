"""The fused method's stages in order (``fused/method.py``): where the width stages moved the
sides far from the search's pair, the top is decided again between the sides the face has
(``_settled_top``), taken only where it moves and the face stays one to report."""

from __future__ import annotations

import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import method as method_mod
from obstacle_fusion.vision.fused import top as top_mod
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.types import Measurement

CAM = CameraModel.paper(500, 375)


def measured(family: str, seed: int, hard: bool) -> tuple[Measurement, float]:
    """The fused method's answer with the room's rig on a tuning room, and the true height."""
    image, truth, spec = render_room(family, seed, hard, CAM)
    res = Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    assert res.detected and res.height_m is not None
    return res, truth["height_m"]


def height_error(family: str, seed: int, hard: bool = False) -> float:
    res, height = measured(family, seed, hard)
    assert res.height_m is not None
    return abs(res.height_m / height - 1.0)


def test_sides_moved_by_a_tenth_of_the_width_count_as_settled() -> None:
    assert method_mod._moved((100, 200), (110, 200))
    assert method_mod._moved((100, 200), (95, 195))
    assert not method_mod._moved((100, 200), (109, 200))


def test_a_top_decided_again_between_the_settled_sides() -> None:
    """A low striped box on a busy room: the search's pair took in part of it only, and its
    top there was a stripe's edge; between the sides the face has the top is its own."""
    assert height_error("procedural", 348, hard=True) < 0.05


@pytest.mark.parametrize("share", [0.25, 10.0])
def test_without_the_settled_top_the_stripe_is_taken(
    monkeypatch: pytest.MonkeyPatch, share: float
) -> None:
    """The same room with the sides' move needed raised (a step, or off altogether); the
    thin-strip rule off too (the stripe is a thin strip that the colour's face replaces)."""
    monkeypatch.setattr(method_mod, "SETTLED_MOVE_SHARE", share)
    monkeypatch.setattr(method_mod, "THIN_STRIP_MAX_CONFIDENCE", 0.0)
    assert height_error("procedural", 348, hard=True) > 0.25


def test_a_top_face_judged_between_the_settled_sides() -> None:
    """A small glossy box in front of a cup on a saucer: the search's left side stood out on
    the floor, and so the rows over the front top edge looked like the front's own colour;
    between the face's sides they are its top face's."""
    assert height_error("photo", 316) < 0.06


def test_a_top_face_is_left_out_only_with_the_settled_top(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The same room with a longer move asked of the top decided again: the first top
    (over the top face) stands."""
    monkeypatch.setattr(method_mod, "SETTLED_TOP_MOVE", 0.25)
    # (the new front top edge is no step of its own either, top.FRONT_EDGE_STEPS: without that)
    monkeypatch.setattr(top_mod, "FRONT_EDGE_STEPS", False)
    assert height_error("photo", 316) > 0.2


def test_a_short_way_down_is_taken_between_the_settled_sides() -> None:
    """A low box whose top the search's pair put at an edge over its front top edge (a
    sixth of the face up): between the face's own sides the front top edge is found."""
    assert height_error("photo", 154) < 0.05


def test_a_top_decided_again_only_where_it_moves() -> None:
    """A wide low box whose sides the seam walk moved far: the top decided again lies a
    few rows under the first (an edge inside the face); the first one stands."""
    assert height_error("procedural", 346, hard=True) < 0.05


def test_a_small_move_of_the_top_is_taken_without_that_limit(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(method_mod, "SETTLED_TOP_MOVE", 0.1)
    # (that edge is a shading ramp as well, which top.front_top skips now: without that)
    monkeypatch.setattr(top_mod, "RAMP_ROWS", 1000)
    # (the new front top edge is no step of its own either, top.FRONT_EDGE_STEPS: without that)
    monkeypatch.setattr(top_mod, "FRONT_EDGE_STEPS", False)
    assert height_error("procedural", 346, hard=True) > 0.05


def test_a_face_this_try_refuses_is_left_to_the_next_try() -> None:
    """A tall box of planks: the colour try's search took two planks and a top on the
    wall, a face it refuses; the luminance try finds the whole face, a sure one. A top
    decided again between the settled sides must not rescue the first try's weak face."""
    res, height = measured("photo", 320, True)
    assert res.height_m is not None and abs(res.height_m / height - 1.0) < 0.05
    assert (res.confidence or 0.0) >= 0.5
