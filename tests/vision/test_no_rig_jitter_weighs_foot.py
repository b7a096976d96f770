"""With no rig, the faces the chosen floor-contact row and its two neighbours stand are
compared with their foot doubts applied (``measure.JITTER_WEIGHS_FOOT``).

The rooms are tuning rooms (procedural and photo, seeds 100-159 and 700-759), measured
with no rig. Procedural 100 (hard): the row 2 px above the chosen one stood the face on a
line above its foot, surer by its raw confidence (0.38 against 0.28) but with its foot off
the floor (FOOT_OFF_FLOOR), height -7.6 %; weighed, the row 2 px below, standing the face
on its foot with no doubt, is taken (0.7 %). Procedural 746 (hard) goes the same way
(16.9 -> 0.9 %).
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.fused.confidence import DOUBT_FACTOR, FOOT_OFF_FLOOR, TOP_FROM_SIDES
from obstacle_fusion.vision.types import Measurement

from tests.vision_fixtures import room_size_errors


def _face(conf: float, doubts: list[str]) -> Measurement:
    return Measurement(detected=True, method="fused", range_m=1.0, confidence=conf, doubts=doubts)


def test_the_neighbour_row_standing_the_face_on_its_foot_is_taken() -> None:
    eh, ew = room_size_errors("procedural", 100, True, with_rig=False)
    assert eh < 0.05 and ew < 0.05


def test_by_raw_confidence_the_face_off_the_floor_is_taken(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(measure, "JITTER_WEIGHS_FOOT", False)
    # (the face off the floor is an unsure answer whose foot the rows read as with a rig
    # carry down to the contact: session 40's FOOT_OFF_FLOOR_LOWER catches it too)
    monkeypatch.setattr(measure, "FOOT_OFF_FLOOR_LOWER", False)
    eh, _ = room_size_errors("procedural", 100, True, with_rig=False)
    assert eh > 0.05


def test_a_second_room_goes_the_same_way(monkeypatch: pytest.MonkeyPatch) -> None:
    eh, ew = room_size_errors("procedural", 746, True, with_rig=False)
    assert eh < 0.05 and ew < 0.05
    monkeypatch.setattr(measure, "JITTER_WEIGHS_FOOT", False)
    monkeypatch.setattr(measure, "FOOT_OFF_FLOOR_LOWER", False)  # (as above)
    eh, ew = room_size_errors("procedural", 746, True, with_rig=False)
    assert max(eh, ew) > 0.1


def test_only_the_foot_doubts_weigh() -> None:
    # procedural 100's two readings: 0.38 off the floor against 0.28 on it
    off_floor = _face(0.38, [FOOT_OFF_FLOOR])
    on_floor = _face(0.28, [])
    assert measure._foot_weighed(off_floor) == pytest.approx(0.38 * DOUBT_FACTOR)
    assert measure._foot_weighed(off_floor) < measure._foot_weighed(on_floor)
    # a doubt about the top says nothing of the row the face stands on
    assert measure._foot_weighed(_face(0.38, [TOP_FROM_SIDES])) == pytest.approx(0.38)


def test_the_switch_leaves_the_raw_figure(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "JITTER_WEIGHS_FOOT", False)
    assert measure._foot_weighed(_face(0.38, [FOOT_OFF_FLOOR])) == pytest.approx(0.38)
