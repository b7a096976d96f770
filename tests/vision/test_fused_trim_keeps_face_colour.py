"""A face whose foot was found above the contact rows the rig predicts has no side brought
in over columns that show its own colour at the foot (``region.TRIM_KEEPS_FACE_COLOUR``,
``MAX_TRIM_FACE_SHARE``).

The room is a tuning room (procedural, seeds 2000-2099): procedural 2039 is a red gloss
face on a teal floor, its foot found about 4 rows above the real one; under that row the
"floor" band is still the face, the foot looks floor-like to the cut test over the face's
plain right half (the highlight's ramp keeps the left half), and the colour walk brought
the right side in from 287 to 221 (w -37 %).
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import foot_outline, region

from tests.vision_fixtures import room_size_errors


def test_a_foot_found_high_keeps_the_face_s_colour() -> None:
    eh, ew = room_size_errors("procedural", 2039, False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_colour_check_the_face_is_cut(monkeypatch: pytest.MonkeyPatch) -> None:
    # the width read from the foot's sides (session 37) finds this face by itself
    monkeypatch.setattr(foot_outline, "WIDTH_FROM_FOOT", False)
    monkeypatch.setattr(region, "TRIM_KEEPS_FACE_COLOUR", False)
    _, ew = room_size_errors("procedural", 2039, False)
    assert ew > 0.3


def test_the_face_share_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # the width read from the foot's sides (session 37) finds this face by itself
    monkeypatch.setattr(foot_outline, "WIDTH_FROM_FOOT", False)
    # every cut column of 2039 shows the face's colour: a limit over all of them cuts
    monkeypatch.setattr(region, "MAX_TRIM_FACE_SHARE", 1.01)
    _, ew = room_size_errors("procedural", 2039, False)
    assert ew > 0.3
