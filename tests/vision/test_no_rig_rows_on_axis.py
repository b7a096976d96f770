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

import numpy as np
import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.fused.confidence import FRAMED
from obstacle_fusion.vision.fused.method import FusedMethod
from obstacle_fusion.vision.measure import Measurer, _axis_face_beside
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import Measurement, Timer

from tests.vision.test_rig_source_and_clipping import CAM
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


def _answer(
    monkeypatch: pytest.MonkeyPatch,
    found_box: tuple[float, float, float, float],
    found_conf: float,
    grown_conf: float,
    doubts: tuple[str, ...] = (),
) -> tuple[float, float, float, float] | None:
    """The box :meth:`Measurer._grown_small_face` answers for a found face ``found_box``
    at ``found_conf`` (with ``doubts``) and the rows' face across the beam's axis column
    (the lens's, no rig: ``CAM.cx``), rows 120-260, at ``grown_conf`` under a lens 0.3 m
    up (neither under the found face's foot nor holding it)."""
    axis = CAM.cx
    grown = Measurement(
        True,
        "fused",
        2.0,
        height_m=0.5,
        width_m=0.3,
        box_px=(axis - 40.0, 120.0, axis + 40.0, 260.0),
        height_px=140.0,
        width_px=80.0,
        confidence=grown_conf,
        camera_height_m=0.3,
    )
    x0, y0, x1, y1 = found_box
    found = Measurement(
        True,
        "fused",
        2.0,
        height_m=0.2,
        width_m=0.2,
        box_px=found_box,
        height_px=y1 - y0,
        width_px=x1 - x0,
        confidence=found_conf,
        doubts=list(doubts),
    )
    monkeypatch.setattr(Measurer, "_known_rig_rows", lambda self, *a, **k: grown)
    measurer = Measurer(CAM, None)
    fused = measurer._method_for(500, 375)
    assert isinstance(fused, FusedMethod)
    image = np.zeros((375, 500, 3), np.uint8)
    return measurer._grown_small_face(fused, found, image, 2.0, Timer()).box_px


#: a face left of the axis (its right side 60 columns short), 100 x 100 px: not small
BESIDE = (CAM.cx - 160.0, 150.0, CAM.cx - 60.0, 250.0)


def test_an_unsure_face_beside_the_axis_gives_way(monkeypatch: pytest.MonkeyPatch) -> None:
    # the rows' face at 0.3 (under GROWN_SURE), on the found face's foot: taken for the
    # axis alone; not with the rule off, nor when the found face takes the axis in
    assert _answer(monkeypatch, BESIDE, 0.1, 0.3) != BESIDE
    on = (CAM.cx - 60.0, 150.0, CAM.cx + 40.0, 250.0)
    assert _answer(monkeypatch, on, 0.1, 0.3) == on
    monkeypatch.setattr(measure, "ROWS_ON_AXIS", False)
    assert _answer(monkeypatch, BESIDE, 0.1, 0.3) == BESIDE


def test_a_sure_framed_face_gives_way_to_no_face_beside(monkeypatch: pytest.MonkeyPatch) -> None:
    # a face read in a margin of another colour, sure (framed_only): it gives way to the
    # face round it alone (PRINT_HELD_BELOW), never to the axis's face, however surer
    assert _answer(monkeypatch, BESIDE, 0.6, 0.9, (FRAMED,)) == BESIDE


@pytest.mark.parametrize(("gap", "taken"), [(2.0, False), (2.1, True)])
@pytest.mark.parametrize("side", [-1.0, 1.0])
def test_the_mounting_unknown_widens_the_axis(gap: float, taken: bool, side: float) -> None:
    # the found face beside the axis by ROW_JITTER_PX + mount_px (the columns the unknown
    # mounting may put the axis on) is not beside it; by 0.1 more it is, either side
    mount = 20.0
    edge = AXIS + side * (mount + gap)
    found = (edge - 100.0, 200.0, edge, 260.0) if side < 0 else (edge, 200.0, edge + 100.0, 260.0)
    assert _axis_face_beside(_face(found, 0.3), _face(GROWN, 0.5), AXIS, mount) is taken


def test_no_rig_a_face_beside_rigs_axis_by_less_than_the_mounting_stays(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # with no rig the sonar may sit BEAM_MOUNT_ALLOWANCE_M either side of the lens: a
    # face whose right side is 2.1 columns short of the lens's axis may stand on the
    # sonar's axis, and stays; one 2.1 columns short of every column the axis may stand
    # on gives way, one 1.9 short stays
    mount = CAM.fx * measure.BEAM_MOUNT_ALLOWANCE_M / Rig().face_depth(2.0)
    assert mount > 10.0
    near = (CAM.cx - 102.1, 150.0, CAM.cx - 2.1, 250.0)
    assert _answer(monkeypatch, near, 0.1, 0.3) == near
    edge = CAM.cx - mount - 2.1
    far = (edge - 100.0, 150.0, edge, 250.0)
    assert _answer(monkeypatch, far, 0.1, 0.3) != far
    edge = CAM.cx - mount - 1.9
    close = (edge - 100.0, 150.0, edge, 250.0)
    assert _answer(monkeypatch, close, 0.1, 0.3) == close
