"""With no rig, a box's top face under the top measured moves the top to its front edge as
with the rig (``method.TOP_FACE_TO_FRONT_NO_RIG``).

The room is one of session 43's new rooms, measured with no rig. Photo 3159 (hard): a planks
box 0.24 m high under a lens 0.44 m up, looking down 3.4 degrees; the trials guess the
pitch, and the top face's back edge was taken for the top (+14.4 %); its band of the face's
colour, lighter, moves the top to the front edge (within 3 %). One room rendered, measured
with the switch on and off.
"""

from __future__ import annotations

from typing import Any

import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import method
from obstacle_fusion.vision.measure import Measurer

from tests.vision_fixtures import room_size_errors


@pytest.fixture(scope="module")
def room() -> tuple[CameraModel, Any, dict[str, Any]]:
    cam = CameraModel.paper(500, 375)
    image, truth, _ = render_room("photo", 3159, True, cam)
    return cam, image, truth


def _height_error(room: tuple[CameraModel, Any, dict[str, Any]]) -> float:
    cam, image, truth = room
    res = Measurer(cam).measure(image, truth["range_m"])
    assert res.detected and res.height_m is not None, res.reason
    return float(res.height_m / truth["height_m"] - 1)


def test_the_front_top_edge_is_taken(room: tuple[CameraModel, Any, dict[str, Any]]) -> None:
    assert abs(_height_error(room)) < 0.03


def test_without_the_rule_the_back_edge_stands(
    monkeypatch: pytest.MonkeyPatch, room: tuple[CameraModel, Any, dict[str, Any]]
) -> None:
    monkeypatch.setattr(method, "TOP_FACE_TO_FRONT_NO_RIG", False)
    assert _height_error(room) > 0.10


@pytest.mark.parametrize(("family", "seed"), [("procedural", 3030), ("photo", 3034)])
def test_faces_the_lens_looks_up_at_do_not_move(family: str, seed: int) -> None:
    """The two ordinary rooms that kept the move to a given rig at session 42 (their tops
    moved 8 and 18 rows down onto a brick's and a plank's lighter rows with no rig): the
    band tests added since must keep them where they are (0.2-0.8 % by height)."""
    eh, ew = room_size_errors(family, seed, False, with_rig=False)
    assert abs(eh) < 0.03 and abs(ew) < 0.03
