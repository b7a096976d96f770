"""A face whose sides run on up the edges of what stands in line behind it keeps the top
where its own surface starts.

Photo 3255 (hard, with the rig): a narrow green seamed face (0.16 x 0.72 m at 2.7 m) in
front of a photographed rocket of the same width; the face's sides run on up the rocket's
to the image's top. The surface rule (``method.SURFACE_UP_TO_TOP``) lowers the top from
the rocket's nose to row 121, where the face's green begins; then:

- the outline read from the face's foot (``foot_outline.outline_from_foot``) raised it
  back to row 18 up the rocket's edges (+85 %): the outline's top is now lowered to where
  the face's surface starts as well (``method.OUTLINE_SURFACE_TOP``);
- the rig check's no-rig search (``measure._checked_by_search``) then found the same face
  (its foot, its sides) with its top up the rocket (+76 %), less than CHECK_SAME_FACE over
  the rig's box, and took it: a search face on the rig face's foot and sides, only taller,
  is one surface read twice, and the rig's top stands (``measure.CHECK_SAME_SIDES``,
  ``measure._same_sides_taller``).

With both, +0.7 % high (the width +7 % as before). The room tests run with the rig
check on (``rig_checked``): the second rule is the check's. Without the check, the first
rule alone fixes the room (also tested).
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.fused import method
from obstacle_fusion.vision.measure import _same_sides_taller

from tests.vision_fixtures import room_size_errors


@pytest.mark.rig_checked
def test_the_face_under_the_rocket_keeps_its_top() -> None:
    eh, ew = room_size_errors("photo", 3255, True, with_rig=True)
    assert eh < 0.1 and ew < 0.1


@pytest.mark.rig_checked
def test_without_the_outline_rule_the_top_runs_up_the_rocket(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(method, "OUTLINE_SURFACE_TOP", False)
    eh, _ = room_size_errors("photo", 3255, True, with_rig=True)
    assert eh > 0.5


@pytest.mark.rig_checked
def test_without_the_check_rule_the_search_face_is_taken(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(measure, "CHECK_SAME_SIDES", False)
    eh, _ = room_size_errors("photo", 3255, True, with_rig=True)
    assert eh > 0.5


def test_the_outline_rule_alone_without_the_check() -> None:
    # (the vision tests' default: measure.RIG_CHECKED_BY_SEARCH off)
    eh, _ = room_size_errors("photo", 3255, True, with_rig=True)
    assert eh < 0.1


def test_without_the_check_the_outline_rule_still_needed(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(method, "OUTLINE_SURFACE_TOP", False)
    eh, _ = room_size_errors("photo", 3255, True, with_rig=True)
    assert eh > 0.5


RIG = (100.0, 120.0, 200.0, 240.0)  # 100 px wide: slack max(2, 0.1 * 100) = 10 px


@pytest.mark.parametrize(
    ("found", "same"),
    [
        ((100.0, 30.0, 200.0, 240.0), True),  # the same foot and sides, taller
        ((90.0, 30.0, 210.0, 250.0), True),  # each 10 px off: within the slack
        ((89.9, 30.0, 200.0, 240.0), False),  # left side past CHECK_SAME_SIDES_SHARE
        ((100.0, 30.0, 210.1, 240.0), False),  # right side past it
        ((100.0, 30.0, 200.0, 250.1), False),  # foot past it: another surface
        ((100.0, 30.0, 200.0, 229.9), False),  # foot higher past it
        ((100.0, 119.9, 200.0, 240.0), True),  # any higher top
        ((100.0, 120.0, 200.0, 240.0), False),  # not taller: the overlap rule's case
        ((100.0, 130.0, 200.0, 240.0), False),  # lower: a shorter reading, weighed as ever
    ],
)
def test_the_limits(found: tuple[float, float, float, float], same: bool) -> None:
    assert _same_sides_taller(RIG, found) is same


@pytest.mark.parametrize(("right", "same"), [(112.0, True), (112.1, False)])
def test_a_narrow_face_keeps_the_pixel_slack(right: float, same: bool) -> None:
    # 10 px wide: 0.1 of it is 1 px, under CHECK_SAME_SIDES_PX (2 px)
    assert _same_sides_taller((100.0, 50.0, 110.0, 90.0), (100.0, 10.0, right, 90.0)) is same


def test_no_box_is_no_same_face() -> None:
    assert not _same_sides_taller(None, RIG)
    assert not _same_sides_taller(RIG, None)
