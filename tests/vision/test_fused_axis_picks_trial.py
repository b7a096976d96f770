"""With no rig, a face whose columns leave the beam's axis out gives way to the surest
sure trial's face on the axis (``measure.AXIS_PICKS_TRIAL``, ``Measurer._on_axis_trial``).

Procedural 740 (hard) is a tuning room: the rows' search stood a narrow face beside the
box (73 % off); another trial's face, on the axis, is the box within 2 %.
"""

from __future__ import annotations

import numpy as np
import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.fused.confidence import SECOND_TOP, SKEWED_EDGES, TOP_RUNS_ON
from obstacle_fusion.vision.measure import Measurer, _covers
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import Measurement, View

from tests.vision.test_rig_source_and_clipping import CAM
from tests.vision_fixtures import room_size_errors


def test_the_face_on_the_axis_is_taken() -> None:
    eh, ew = room_size_errors("procedural", 740, True, with_rig=False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_rule_the_face_beside_the_axis_stands(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "AXIS_PICKS_TRIAL", False)
    # (since session 41 REREAD_PITCH_SAME_FACE alone also keeps the face on the axis here:
    # the narrow face beside it is the reading at the pitch its sides gave, less sure)
    monkeypatch.setattr(measure, "REREAD_PITCH_SAME_FACE", False)
    eh, ew = room_size_errors("procedural", 740, True, with_rig=False)
    assert max(eh, ew) > 0.25


@pytest.mark.parametrize(
    "box, covered",
    [
        ((100.0, 0.0, 250.0, 10.0), True),  # its right side on the column
        ((250.0, 0.0, 300.0, 10.0), True),  # its left side on it
        ((100.0, 0.0, 249.9, 10.0), False),
        ((250.1, 0.0, 300.0, 10.0), False),
    ],
)
def test_a_box_covers_the_columns_between_its_sides(
    box: tuple[float, float, float, float], covered: bool
) -> None:
    assert _covers(box, 250.0) is covered


def _face(
    box: tuple[float, float, float, float], confidence: float, doubts: list[str]
) -> Measurement:
    return Measurement(
        detected=True,
        method="fused",
        range_m=2.0,
        height_m=0.3,
        width_m=0.3,
        confidence=confidence,
        box_px=box,
        height_px=100.0,
        width_px=100.0,
        doubts=doubts,
    )


@pytest.mark.parametrize(
    "doubts, taken",
    [
        ([], True),
        ([SKEWED_EDGES, SECOND_TOP], True),  # 0.3 * 0.45^4 = 0.012: over 0.01
        ([SKEWED_EDGES, SECOND_TOP, TOP_RUNS_ON], False),  # 0.3 * 0.45^5 = 0.006: refused
    ],
)
def test_a_face_on_the_axis_the_refusal_would_turn_down_is_not_taken(
    monkeypatch: pytest.MonkeyPatch, doubts: list[str], taken: bool
) -> None:
    monkeypatch.setattr(measure, "sides_reach_foot", lambda image, lines: True)
    view = View(CAM, Rig(), "level")
    u = CAM.cx
    beside = _face((u - 120.0, 100.0, u - 20.0, 200.0), 0.5, [])
    on_axis = _face((u - 40.0, 100.0, u + 60.0, 200.0), 0.3, doubts)
    image = np.zeros((375, 500, 3), np.uint8)
    got = Measurer(CAM, None)._on_axis_trial(beside, [beside, on_axis], view, 2.0, image)
    assert (got is on_axis) is taken


def test_a_face_on_the_axis_is_kept(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "sides_reach_foot", lambda image, lines: True)
    view = View(CAM, Rig(), "level")
    u = CAM.cx
    best = _face((u - 40.0, 100.0, u + 60.0, 200.0), 0.3, [])
    other = _face((u - 50.0, 100.0, u + 70.0, 200.0), 0.6, [])
    image = np.zeros((375, 500, 3), np.uint8)
    assert Measurer(CAM, None)._on_axis_trial(best, [best, other], view, 2.0, image) is None
