"""With the rig, a face found standing above the contact band with no print round it takes
the foot in the band when its own colour runs on down to it
(``method.FACE_DOWN_TO_FOOT``, ``region.face_down_to_foot``).

Procedural 2100 (ordinary; a fresh seed, the rule was found on it and no tuning room
exercises it) is a pink gloss face whose lowest rows, a shade darker, ended the found
foot 4 rows above the floor: height -14.8 %. Its colour over those rows is within 5 Lab of
the colour over the found foot.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import method, region

from tests.vision_fixtures import room_size_errors


def test_the_face_runs_down_to_the_foot_in_the_band() -> None:
    eh, ew = room_size_errors("procedural", 2100, False)
    assert eh < 0.05 and ew < 0.02


def test_without_the_rule_the_foot_stays_on_the_shading_step(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(method, "FACE_DOWN_TO_FOOT", False)
    eh, _ = room_size_errors("procedural", 2100, False)
    assert eh > 0.1


def test_rows_off_the_face_colour_keep_the_found_foot(monkeypatch: pytest.MonkeyPatch) -> None:
    # the rows between stand 4-6 Lab from the colour over the found foot
    monkeypatch.setattr(region, "FACE_DOWN_AGREE", 4.0)
    eh, _ = room_size_errors("procedural", 2100, False)
    assert eh > 0.1
