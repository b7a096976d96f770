"""With no rig, an unsure (or small) answer whose columns leave the beam's axis column out
gives way to a surer face the rows read as with a rig across that column, wherever its
foot (``measure.ROWS_ON_AXIS``, ``measure._axis_face_beside``): the sonar ranges what its
axis hits, and the obstacle stands across it.

The rooms are diagnosis rooms (new11), measured with no rig. Procedural 3520 (ordinary): a
plain box 0.78 m high, the camera pitched down 1.3 degrees; the level trials stood a stretch
of the skirting beside it (-78 %), the rows read the box at 0.70. Photo 3504 (ordinary): a
green box, the camera pitched up 2.9 degrees; the trials stood a patch of floor tiles under
and beside it (-82 %), the rows read the box at 0.27.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.measure import _axis_face_beside
from obstacle_fusion.vision.types import Measurement

from tests.vision_fixtures import room_size_errors

AXIS = 250.0
FOUND = (100.0, 200.0, 200.0, 260.0)  # right side 50 columns short of the axis
GROWN = (200.0, 80.0, 310.0, 260.0)  # across the axis


def _face(
    box: tuple[float, float, float, float], conf: float, lens: float | None = 0.4
) -> Measurement:
    return Measurement(True, "fused", 2.0, box_px=box, confidence=conf, camera_height_m=lens)


def test_the_box_across_the_axis_is_taken() -> None:
    eh, ew = room_size_errors("procedural", 3520, False, with_rig=False)
    assert eh < 0.03 and ew < 0.03


def test_without_the_rule_the_skirting_stays(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "ROWS_ON_AXIS", False)
    eh, _ = room_size_errors("procedural", 3520, False, with_rig=False)
    assert eh > 0.5


def test_a_small_patch_beside_the_axis_gives_way() -> None:
    # the rows' face under GROWN_SURE (0.27): taken for the axis alone
    eh, ew = room_size_errors("photo", 3504, False, with_rig=False)
    assert eh < 0.05 and ew < 0.05


@pytest.mark.parametrize(
    ("found", "grown", "conf", "lens", "taken"),
    [
        (FOUND, GROWN, 0.5, 0.4, True),
        ((100.0, 200.0, 247.9, 260.0), GROWN, 0.5, 0.4, True),  # 2.1 columns short
        ((100.0, 200.0, 248.0, 260.0), GROWN, 0.5, 0.4, False),  # ROW_JITTER_PX: on it
        ((252.1, 200.0, 400.0, 260.0), GROWN, 0.5, 0.4, True),  # beside, on the right
        ((252.0, 200.0, 400.0, 260.0), GROWN, 0.5, 0.4, False),
        ((100.0, 200.0, 300.0, 260.0), GROWN, 0.5, 0.4, False),  # the found face on it
        (FOUND, (200.0, 80.0, 252.1, 260.0), 0.5, 0.4, True),  # the rows' face across it
        (FOUND, (200.0, 80.0, 252.0, 260.0), 0.5, 0.4, False),  # by ROW_JITTER_PX only
        (FOUND, (247.9, 80.0, 310.0, 260.0), 0.5, 0.4, True),
        (FOUND, (248.0, 80.0, 310.0, 260.0), 0.5, 0.4, False),
        (FOUND, (260.0, 80.0, 310.0, 260.0), 0.5, 0.4, False),  # beside it too
        (FOUND, GROWN, 0.301, 0.4, True),  # surer than the found face's 0.3
        (FOUND, GROWN, 0.3, 0.4, False),
        (FOUND, GROWN, 0.5, 0.6, True),  # UNDER_MAX_CAMERA_HEIGHT_M
        (FOUND, GROWN, 0.5, 0.61, False),
        (FOUND, GROWN, 0.5, None, False),  # no lens read
    ],
)
def test_the_limits(
    found: tuple[float, float, float, float],
    grown: tuple[float, float, float, float],
    conf: float,
    lens: float | None,
    taken: bool,
) -> None:
    assert _axis_face_beside(_face(found, 0.3), _face(grown, conf, lens), AXIS) is taken


@pytest.mark.parametrize(("conf", "taken"), [(0.15, True), (0.149, False)])
def test_at_least_under_sure(conf: float, taken: bool) -> None:
    # UNDER_SURE 0.15, over a found face at 0.1
    assert _axis_face_beside(_face(FOUND, 0.1), _face(GROWN, conf), AXIS) is taken


def test_no_box_no_move() -> None:
    found = Measurement(True, "fused", 2.0, confidence=0.1)
    assert not _axis_face_beside(found, _face(GROWN, 0.9), AXIS)
    assert not _axis_face_beside(_face(FOUND, 0.1), Measurement(False, "fused", 2.0), AXIS)
