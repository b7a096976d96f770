"""With no rig, the rows read as with a rig count only readings of a face no taller and no
wider than ``RAISED_FACE_MAX_M`` at the sonar's depth (``measure.KNOWN_RIG_SIZE_BOUND``,
``measure._obstacle_size``).

Photo 3083 (hard, a diagnosis room of session 41): a panelled face 0.68 m wide at 2.5 m,
no rig. The search refuses the face it settles on, and the rows read as with a rig, lowest
first, agree on a row under the face (row 290, lenses 0.5-0.8 m) on a face 2.0 m wide
(+192 %): without the rule that is the answer; with it those readings do not count, and a
higher row's readings agree on the face (within 2 %).
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.fused import region, texture
from obstacle_fusion.vision.fused.method import RAISED_FACE_MAX_M
from obstacle_fusion.vision.measure import _obstacle_size
from obstacle_fusion.vision.types import Measurement

from tests.vision_fixtures import room_size_errors


def test_a_face_wider_than_an_obstacle_does_not_count() -> None:
    eh, ew = room_size_errors("photo", 3083, True, with_rig=False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_rule_the_row_under_the_face_is_taken(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(measure, "KNOWN_RIG_SIZE_BOUND", False)
    _, ew = room_size_errors("photo", 3083, True, with_rig=False)
    assert ew > 1.0


def test_a_face_too_wide_under_a_lens_allowed_tall(monkeypatch: pytest.MonkeyPatch) -> None:
    # photo 721 hard (a tuning room): with the lens allowed 1.3 m up for the face under an
    # unsure one (UNDER_MAX_CAMERA_HEIGHT_M), the rows' face there is 1.6 m wide: not counted
    monkeypatch.setattr(measure, "UNDER_MAX_CAMERA_HEIGHT_M", 1.3)
    # (off, to test this rule alone, as each keeps 721 right with this rule off: the
    # texture walk past a highlight, texture.GLOSS_CROSSED, reads the rows' trial's face, a
    # brick floor, otherwise, and that face is not found; with the colour face's sides
    # snapped where its walk up stops, region.COLOUR_SIDES_SNAP_RETRY, the readings on
    # that row (344) do not agree)
    monkeypatch.setattr(texture, "GLOSS_CROSSED", False)
    monkeypatch.setattr(region, "COLOUR_SIDES_SNAP_RETRY", False)
    # (and measure.KNOWN_ROWS_ROBOT_LENS, session 48: the rows' readings there stand under
    # no robot's lens, so that face is not given either)
    monkeypatch.setattr(measure, "KNOWN_ROWS_ROBOT_LENS", False)
    eh, ew = room_size_errors("photo", 721, True, with_rig=False)
    assert max(eh, ew) < 0.2
    monkeypatch.setattr(measure, "KNOWN_RIG_SIZE_BOUND", False)
    eh, ew = room_size_errors("photo", 721, True, with_rig=False)
    assert max(eh, ew) > 1.0


def _face(height: float | None, width: float | None) -> Measurement:
    return Measurement(True, "fused", 1.0, height_m=height, width_m=width)


@pytest.mark.parametrize(
    ("height", "width", "counts"),
    [
        (1.5, 1.5, True),
        (1.501, 0.5, False),
        (0.5, 1.501, False),
        (0.3, 0.4, True),
        (None, 0.4, True),
    ],
)
def test_the_size_limit(height: float | None, width: float | None, counts: bool) -> None:
    assert RAISED_FACE_MAX_M == 1.5
    assert _obstacle_size(_face(height, width)) is counts


def test_with_the_rule_off_any_size_counts(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "KNOWN_RIG_SIZE_BOUND", False)
    assert _obstacle_size(_face(3.0, 3.0))
