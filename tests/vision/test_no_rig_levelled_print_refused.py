"""With no rig, the face found in the view levelled for the pitch its sides read is not
taken over the pitch-0 face, however much surer as measured, where it lies on that face
as a print: on its foot, its sides and top inside the pitch-0 face's, each by over
ROW_JITTER_PX (``measure.LEVELLED_PRINT_REFUSED``, ``measure._print_on_face``); the
pitch-0 face, scaled to the levelled view, stands.

The room is a diagnosis room (new11), measured with no rig. Procedural 3525 (ordinary): a
teal brick print on a pink box's face, the camera pitched down 3.0 degrees; the box's face
at 0.90 level, the print at 0.94 in the view levelled for the 2.9 degrees its sides read
(-8 % high, -17 % wide); with the rule the box's face, +1 % / +0.4 %.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.measure import _levelled_taken, _print_on_face
from obstacle_fusion.vision.types import Measurement

from tests.vision_fixtures import room_size_errors

FACE = (100.0, 100.0, 300.0, 200.0)


def _face(box: tuple[float, float, float, float], conf: float) -> Measurement:
    return Measurement(True, "fused", 2.0, box_px=box, confidence=conf)


def test_the_box_stays_round_its_print() -> None:
    eh, ew = room_size_errors("procedural", 3525, False, with_rig=False)
    assert eh < 0.03 and ew < 0.03


def test_without_the_rule_the_print_is_taken(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "LEVELLED_PRINT_REFUSED", False)
    _, ew = room_size_errors("procedural", 3525, False, with_rig=False)
    assert ew > 0.1


@pytest.mark.parametrize(
    ("box", "on_face"),
    [
        ((102.1, 102.1, 297.9, 200.0), True),  # in by 2.1 on three sides, the same foot
        ((102.0, 102.1, 297.9, 200.0), False),  # the left side within ROW_JITTER_PX
        ((102.1, 102.1, 298.0, 200.0), False),  # the right side within it
        ((102.1, 102.0, 297.9, 200.0), False),  # the top within it: the face read again
        ((102.1, 102.1, 297.9, 202.0), True),  # the foot ROW_JITTER_PX lower
        ((102.1, 102.1, 297.9, 198.0), True),  # ... higher
        ((102.1, 102.1, 297.9, 202.1), False),  # another foot: another reading
        ((102.1, 102.1, 297.9, 197.9), False),
        ((90.0, 120.0, 297.9, 200.0), False),  # wider on one side
    ],
)
def test_the_limits(box: tuple[float, float, float, float], on_face: bool) -> None:
    assert _print_on_face(_face(box, 0.9), _face(FACE, 0.8)) is on_face


def test_a_surer_print_is_not_taken() -> None:
    found = _face(FACE, 0.8)
    assert not _levelled_taken(found, _face((110.0, 110.0, 290.0, 200.0), 0.9))
    # a surer face read again (not inside on three sides) is taken as before
    assert _levelled_taken(found, _face((100.0, 110.0, 300.0, 200.0), 0.9))


def test_without_the_switch_the_surer_print_is_taken(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "LEVELLED_PRINT_REFUSED", False)
    assert _levelled_taken(_face(FACE, 0.8), _face((110.0, 110.0, 290.0, 200.0), 0.9))


def test_no_box_no_print() -> None:
    assert not _print_on_face(Measurement(True, "fused", 2.0, confidence=0.9), _face(FACE, 0.8))
