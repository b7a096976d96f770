"""With no rig, the last-resort sweep's face whose sides read its pitch replaces the unsure
face when it is that face seen whole (``measure.SWEPT_WHOLE_FACE``,
``measure._swept_whole``): the same foot and sides, over SWEPT_MAX_GROWTH times as tall,
its sides running on above the unsure face's top.

Photo 2091 (ordinary) is a tuning room: a panelled face (two rows of three panels) on
gravel, the lens looking up 3.8 degrees. The level rows stood only a strip of the lower
panels (the rescue's face, 0.13-0.14: height -74 %); the sweep read the whole face at
-3.9 degrees, its sides confirming (0.45, within 0.5 %), but it stands on the strip's
own foot, not above it, so the older clause of ``_swept_over`` did not take it.
"""

from __future__ import annotations

import numpy as np
import pytest
from obstacle_fusion.vision import measure

from tests.vision_fixtures import face_found, room_size_errors


def test_the_face_seen_whole_is_taken() -> None:
    eh, ew = room_size_errors("photo", 2091, False, with_rig=False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_rule_the_strip_stands(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "SWEPT_WHOLE_FACE", False)
    # with the sweep's whole face not taken, the strip is a band across a taller face the
    # trials found on a lower foot (NEARER_ACROSS_BAND): that face, its height right but
    # 33 % too wide, would stand instead of the strip
    monkeypatch.setattr(measure, "NEARER_ACROSS_BAND", False)
    eh, _ = room_size_errors("photo", 2091, False, with_rig=False)
    assert eh > 0.25


@pytest.fixture
def runs_up(monkeypatch: pytest.MonkeyPatch) -> None:
    # the drawn faces have no outline lines: each one's sides run on up
    monkeypatch.setattr(measure, "sides_run_up", lambda image, lines, row: True)


IMAGE = np.zeros((375, 500, 3), np.uint8)
UNSURE = (100.0, 200.0, 300.0, 250.0)  # a strip 200 px wide, 50 tall, its foot at 250


@pytest.mark.usefixtures("runs_up")
@pytest.mark.parametrize(
    "box, read, confidence, taken",
    [
        ((100.0, 100.0, 300.0, 250.0), True, 0.3, True),  # three times as tall
        ((100.0, 100.0, 300.0, 250.0), False, 0.3, False),  # its pitch not read
        ((100.0, 100.0, 300.0, 250.0), True, 0.19, False),  # under ESTIMATE_ACCEPT
        ((100.0, 175.0, 300.0, 250.0), True, 0.3, False),  # 1.5 times: not over it
        ((100.0, 174.0, 300.0, 250.0), True, 0.3, True),  # 1.52 times
        ((100.0, 100.0, 300.0, 254.0), True, 0.3, False),  # its foot 4 px lower
        ((100.0, 100.0, 300.0, 253.9), True, 0.3, True),  # under 4 px: the same foot
        ((88.0, 100.0, 300.0, 250.0), True, 0.3, True),  # a side 12 px off: 0.06 of 200
        ((87.0, 100.0, 300.0, 250.0), True, 0.3, False),  # 13 px: another side
    ],
)
def test_the_whole_face_shares_the_foot_and_sides_and_is_taller(
    box: tuple[float, float, float, float], read: bool, confidence: float, taken: bool
) -> None:
    got = measure._swept_whole(face_found(UNSURE, 0.1), face_found(box, confidence), read, IMAGE)
    assert got is taken


def test_the_sides_must_run_up_past_the_unsure_top(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "sides_run_up", lambda image, lines, row: False)
    whole = face_found((100.0, 100.0, 300.0, 250.0), 0.3)
    assert not measure._swept_whole(face_found(UNSURE, 0.1), whole, True, IMAGE)
