"""A pattern of joints (a brick or plank print) is thin lines all over a face: with the
rig, where its lines took every ranked place of a side, the strongest peaks beyond the
pattern's outermost lines (where the pattern ends: the face's sides) are that side's
candidates too (`search.JOINT_PATTERN_ENDS`)."""

from __future__ import annotations

import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import search
from obstacle_fusion.vision.measure import Measurer


def _error(fam: str, seed: int, hard: bool) -> float:
    cam = CameraModel.paper(500, 375)
    image, truth, spec = render_room(fam, seed, hard, cam)
    res = Measurer(cam, spec.rig).measure(image, truth["range_m"])
    if not res.detected or res.height_m is None or res.width_m is None:
        return 9.0
    return max(abs(res.height_m / truth["height_m"] - 1), abs(res.width_m / truth["width_m"] - 1))


# brick prints whose joints took every place of a side: a pair of joints inside the face
# (photo/352 ordinary 9.7 %, photo/306 hard 21 %) or no face at all (photo/1143 ordinary)
SCENES = [("photo", 352, False, 0.09), ("photo", 306, True, 0.2), ("photo", 1143, False, 0.25)]


@pytest.mark.parametrize(("fam", "seed", "hard", "off"), SCENES)
def test_a_brick_print_is_measured_by_where_its_joints_end(
    fam: str, seed: int, hard: bool, off: float
) -> None:
    assert _error(fam, seed, hard) < 0.05


@pytest.mark.parametrize(("fam", "seed", "hard", "off"), SCENES)
def test_without_the_rule_the_joints_are_the_sides(
    monkeypatch: pytest.MonkeyPatch, fam: str, seed: int, hard: bool, off: float
) -> None:
    monkeypatch.setattr(search, "JOINT_PATTERN_ENDS", False)
    assert _error(fam, seed, hard) > off
