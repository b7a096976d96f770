"""With no rig, a face found at a guessed pitch and read once more at the pitch its sides
give is taken only when that reading has the same outline (boxes overlapping by
``SAME_FACE_IOU``) or is a surer face (``measure.REREAD_PITCH_SAME_FACE``,
``measure._reread_confirms``); else the pitch stays unread.

Photo 3065 (ordinary, a diagnosis room of session 41): a panelled teal box before a yellow
skirting band, no rig. The face is read whole (0.58 m) at a guessed pitch of 4 degrees;
its sides read 2.4 degrees, and the reading there puts the top on the band's upper edge
(0.28 m, -50 %) at 0.52, less sure than the whole face: without the rule that half face
is reported, with it the whole face, its pitch unread.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.measure import SAME_FACE_IOU, _reread_confirms
from obstacle_fusion.vision.types import Measurement

from tests.vision_fixtures import room_size_errors


def test_another_face_at_the_read_pitch_leaves_the_face_whole() -> None:
    eh, ew = room_size_errors("photo", 3065, False, with_rig=False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_rule_the_top_drops_to_the_band(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "REREAD_PITCH_SAME_FACE", False)
    eh, _ = room_size_errors("photo", 3065, False, with_rig=False)
    assert eh > 0.4


def _face(box: tuple[float, float, float, float], confidence: float) -> Measurement:
    return Measurement(True, "fused", 1.0, box_px=box, confidence=confidence)


FOUND = _face((100.0, 100.0, 300.0, 260.0), 0.6)


@pytest.mark.parametrize(
    ("confidence", "confirms"), [(0.6, False), (0.601, True), (0.2, False), (0.9, True)]
)
def test_another_face_confirms_only_when_surer(confidence: float, confirms: bool) -> None:
    other = _face((100.0, 180.0, 300.0, 260.0), confidence)  # its top 80 rows lower
    assert _reread_confirms(FOUND, other) is confirms


@pytest.mark.parametrize(("top", "same"), [(116.0, True), (117.0, False)])
def test_the_same_face_limit(top: float, same: bool) -> None:
    # IoU 144/160 = 0.9 at top 116 (the same outline, however much less sure), under it at 117
    assert SAME_FACE_IOU == 0.9
    other = _face((100.0, top, 300.0, 260.0), 0.3)
    assert _reread_confirms(FOUND, other) is same


def test_a_foot_a_few_rows_up_is_the_face_read_better() -> None:
    # procedural 134 hard: the sides' pitch stands the foot 5 rows up, top and sides kept
    moved = _face((100.0, 100.0, 300.0, 255.0), 0.3)
    assert _reread_confirms(FOUND, moved)


def test_with_the_rule_off_any_reading_confirms(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "REREAD_PITCH_SAME_FACE", False)
    assert _reread_confirms(FOUND, _face((100.0, 180.0, 300.0, 260.0), 0.2))
