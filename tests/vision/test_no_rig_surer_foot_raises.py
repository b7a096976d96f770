"""With no rig, an unsure answer gives way to the rows' face read as with a rig standing a
few rows higher on the same top and columns when that face is surer
(``measure.SURER_FOOT_RAISES``, ``measure._foot_moves_up``).

The room is a tuning room, measured with no rig. Procedural 750 (hard): a plain face with a
shadow; the no-rig rows stand it on the shadow's lower edge four rows under the contact
(+9 %); the rows read as with a rig stand it on the contact, surer (within 3 %).
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.measure import _foot_moves_up
from obstacle_fusion.vision.types import Measurement

from tests.vision_fixtures import room_size_errors

FOUND = (100.0, 50.0, 200.0, 120.0)


def _face(box: tuple[float, float, float, float], conf: float, lens: float = 0.3) -> Measurement:
    return Measurement(True, "fused", 2.0, box_px=box, confidence=conf, camera_height_m=lens)


def test_the_foot_on_the_contact_is_taken() -> None:
    eh, ew = room_size_errors("procedural", 750, True, with_rig=False)
    assert eh < 0.03 and ew < 0.03


def test_without_the_rule_the_shadow_edge_stands(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "SURER_FOOT_RAISES", False)
    eh, _ = room_size_errors("procedural", 750, True, with_rig=False)
    assert eh > 0.06


@pytest.mark.parametrize(
    ("grown", "conf", "lens", "moves"),
    [
        ((100.0, 50.0, 200.0, 117.9), 0.5, 0.3, True),  # foot just over 2 rows higher
        ((100.0, 50.0, 200.0, 118.0), 0.5, 0.3, False),  # ROW_JITTER_PX higher: the same foot
        ((100.0, 52.0, 200.0, 115.0), 0.5, 0.3, True),  # top 2 rows under: the same top
        ((100.0, 52.1, 200.0, 115.0), 0.5, 0.3, False),  # farther: another top
        ((120.0, 50.0, 200.0, 115.0), 0.5, 0.3, True),  # columns 0.8 of the wider
        ((121.0, 50.0, 200.0, 115.0), 0.5, 0.3, False),  # under 0.8 of the wider
        ((100.0, 50.0, 140.0, 115.0), 0.5, 0.3, False),  # a plank of it: no narrower face
        ((90.0, 50.0, 215.0, 115.0), 0.5, 0.3, True),  # 100 of the wider's 125
        ((89.0, 50.0, 215.0, 115.0), 0.5, 0.3, False),  # 100 of 126
        ((100.0, 50.0, 200.0, 114.0), 0.5, 0.3, True),  # UNDER_ROWS_SLACK_PX higher
        ((100.0, 50.0, 200.0, 113.9), 0.5, 0.3, False),  # farther: a line on the face
        ((100.0, 50.0, 200.0, 115.0), 0.4, 0.3, False),  # as sure as the answer: kept
        ((100.0, 50.0, 200.0, 115.0), 0.5, 0.6, True),  # a robot's lens
        ((100.0, 50.0, 200.0, 115.0), 0.5, 0.61, False),  # higher: no robot's
    ],
)
def test_foot_moves_up_limits(
    grown: tuple[float, float, float, float], conf: float, lens: float, moves: bool
) -> None:
    assert measure.ROW_JITTER_PX == 2 and measure.LOWER_FOOT_SIDES_SHARE == 0.8
    assert measure.UNDER_MAX_CAMERA_HEIGHT_M == 0.6 and measure.UNDER_ROWS_SLACK_PX == 6.0
    assert _foot_moves_up(_face(FOUND, 0.4), _face(grown, conf, lens)) is moves


@pytest.mark.parametrize(("conf", "moves"), [(0.15, True), (0.14, False)])
def test_the_surer_face_must_be_sure_enough(conf: float, moves: bool) -> None:
    # surer than a barely-found answer is not enough: at least UNDER_SURE
    assert measure.UNDER_SURE == 0.15
    grown = _face((100.0, 50.0, 200.0, 115.0), conf)
    assert _foot_moves_up(_face(FOUND, 0.05), grown) is moves


def test_foot_moves_up_needs_both_boxes() -> None:
    assert not _foot_moves_up(_face(FOUND, 0.4), Measurement(True, "fused", 2.0))
