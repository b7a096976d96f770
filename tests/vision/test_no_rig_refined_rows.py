"""With no rig, when no floor-contact row agrees as with a rig, on the beam's axis or beside
it, the rows within REFINED_ROWS_PX of the band's lowest REFINED_ROWS_STEPS steps are read
so too, nearest first (``measure.REFINED_ROWS``, ``measure.Measurer._known_rig_rows``).

The rooms are tuning rooms, measured with no rig. Procedural 709 (hard): a glossy face
whose foot blurs over a few rows. The band's only step lies at row 278; read as with a rig
there (and at 276, 277, 279 and 280) the readings take the face's lower part, whose sides
do not reach the foot, or agree fewer than KNOWN_RIG_AGREE times. Row 275, three rows up,
agrees at all four pitches on the whole face (within 1 %): found with a reach of 3, missed
with 2. Photo 715 (hard): the band's only step (219) does not agree, the row under it
does (within 3 %). Photo 2085 (hard): the band's lowest step (246) and its neighbours do
not agree; a neighbour of its second step (232) agrees on a print's face 47 % off that the
search refused as doubted on every count: refined from one step only, it stays refused.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.measure import Measurer, _refine_offsets
from obstacle_fusion.vision.types import Measurement

from tests.vision_fixtures import room_size_errors


def _measured(family: str, seed: int, hard: bool) -> Measurement:
    cam = CameraModel.paper(500, 375)
    image, truth, _ = render_room(family, seed, hard, cam)
    return Measurer(cam, None).measure(image, truth["range_m"])


def test_a_row_near_the_step_gives_the_face() -> None:
    eh, ew = room_size_errors("procedural", 709, True, with_rig=False)
    assert eh < 0.05 and ew < 0.05
    eh, ew = room_size_errors("photo", 715, True, with_rig=False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_rule_the_faces_are_missed(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "REFINED_ROWS", False)
    assert not _measured("procedural", 709, True).detected
    assert not _measured("photo", 715, True).detected


@pytest.mark.parametrize(("reach", "found"), [(3, True), (2, False)])
def test_the_reach_limit(monkeypatch: pytest.MonkeyPatch, reach: int, found: bool) -> None:
    monkeypatch.setattr(measure, "REFINED_ROWS_PX", reach)
    assert _measured("procedural", 709, True).detected is found


@pytest.mark.parametrize(("steps", "found"), [(1, False), (2, True)])
def test_only_the_lowest_step_is_refined(
    monkeypatch: pytest.MonkeyPatch, steps: int, found: bool
) -> None:
    monkeypatch.setattr(measure, "REFINED_ROWS_STEPS", steps)
    assert _measured("photo", 2085, True).detected is found


def test_neighbours_are_tried_nearest_first_lower_first() -> None:
    assert _refine_offsets(3) == [1, -1, 2, -2, 3, -3]
    assert _refine_offsets(0) == []
