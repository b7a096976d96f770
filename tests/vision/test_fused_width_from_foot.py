"""An unsure face whose height is right but whose sides are inner lines of the face (a
print's frame, seams) is widened to the sides read from its foot, its top kept
(``foot_outline.WIDTH_FROM_FOOT``, the width-only reading of ``outline_from_foot``).

The rooms are tuning rooms with the rig. Photo 2070 (hard) is a poster of an astronaut on
a face before a photographed plate: the edge search's left side is a line of the picture
inside the face (width -31 %); the foot's run and the two sides rising from it (203 and 219
rows, the found face 194 rows high: 1.05 times, under the 1.3 a piece of a print must
rise) give the face, 1.48 times as wide as the found one. Procedural 2079 (hard) is a small
tape-wrapped box whose outline from the foot is 1.26 times its found width, onto its blur
beside it: WIDTH_MIN_FACTOR leaves it.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import extent, foot_outline, region

from tests.vision_fixtures import room_size_errors


def test_a_face_found_between_inner_lines_is_widened_to_its_sides() -> None:
    eh, ew = room_size_errors("photo", 2070, True)
    assert ew < 0.05 and eh < 0.1


def test_without_the_rule_the_width_is_the_inner_lines(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(foot_outline, "WIDTH_FROM_FOOT", False)
    _, ew = room_size_errors("photo", 2070, True)
    assert ew > 0.25


def test_the_rise_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # 2070's sides rise 1.05 times the found height: asked 1.0, they stand; 1.1, not
    monkeypatch.setattr(foot_outline, "WIDTH_RISE_SHARE", 1.0)
    _, ew = room_size_errors("photo", 2070, True)
    assert ew < 0.05
    monkeypatch.setattr(foot_outline, "WIDTH_RISE_SHARE", 1.1)
    _, ew = room_size_errors("photo", 2070, True)
    assert ew > 0.25


def test_the_widening_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # 2070 is widened 1.48 times: asked 1.5, it is left as found (with the top line
    # rule off: extent.TOP_LINE_SPANS first moves the found right side in to where the
    # picture's top line ends, 324 -> 295, and the widening is then over 1.5 times; and
    # with region.OUTLINE_SIDE_ON_FOOT off: there the outline's side past the colour run,
    # which ends above the contact row, is refused, and the face comes out right by
    # another path, w +1.4 %; the shipped answer is the same either way; and with
    # foot_outline.WIDTH_PAST_PLANK off: a width side lies over WIDTH_PLANK_M past the
    # found one, so the lower WIDTH_PLANK_FACTOR would take it whatever this limit)
    monkeypatch.setattr(foot_outline, "WIDTH_MIN_FACTOR", 1.5)
    monkeypatch.setattr(foot_outline, "WIDTH_PAST_PLANK", False)
    monkeypatch.setattr(extent, "TOP_LINE_SPANS", False)
    monkeypatch.setattr(region, "OUTLINE_SIDE_ON_FOOT", False)
    _, ew = room_size_errors("photo", 2070, True)
    assert ew > 0.25


def test_a_small_widening_onto_the_blur_is_not_taken(monkeypatch: pytest.MonkeyPatch) -> None:
    # procedural 2079 hard's outline is 1.26 times its found width
    eh, ew = room_size_errors("procedural", 2079, True)
    assert eh < 0.05 and ew < 0.05
    monkeypatch.setattr(foot_outline, "WIDTH_MIN_FACTOR", 1.25)
    eh, ew = room_size_errors("procedural", 2079, True)
    # widened onto the blur (+7.4 %), its found top kept: no top face's front edge read
    # again under it (that took the height to -39 %)
    assert ew > 0.05 and eh < 0.05
