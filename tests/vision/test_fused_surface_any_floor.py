"""The face's surface reaches up to its top without the rig too, and in the colour rescue
(``method.SURFACE_ANY_FLOOR``, ``method.SURFACE_IN_RESCUE``, ``region.lower_top_to_surface``).

The face is one surface from its foot up to its top, whatever rig the floor row came from.
Photo 3026 ordinary (a new room) is a plank face in line with a rocket photographed behind
it: the no-rig search's top went up the rocket (+121 %), and with the rig that answer
was swapped in for the rig's own. Photo 3109 hard with no rig (a new3 room) is a pale panel
face before a light blue wall, a dark poster beside its left side and a yellow one beside
its right: the colour rescue's sides' walk ran on up beside the posters to the image's top
(+51 %); the wall between the top and the face is another colour from side to side.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import method

from tests.vision_fixtures import room_size_errors


@pytest.mark.parametrize("with_rig", [False, True])
def test_a_face_before_a_rocket_keeps_its_top_without_the_rig(with_rig: bool) -> None:
    eh, ew = room_size_errors("photo", 3026, False, with_rig=with_rig)
    assert eh < 0.06 and ew < 0.05


def test_without_the_rule_the_search_takes_the_rocket(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method, "SURFACE_ANY_FLOOR", False)
    eh, _ = room_size_errors("photo", 3026, False, with_rig=False)
    assert eh > 0.25


def test_the_colour_rescue_comes_down_to_the_face() -> None:
    eh, ew = room_size_errors("photo", 3109, True, with_rig=False)
    assert eh < 0.03 and ew < 0.03


def test_without_the_rule_the_rescue_walks_up_the_wall(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method, "SURFACE_IN_RESCUE", False)
    eh, _ = room_size_errors("photo", 3109, True, with_rig=False)
    assert eh > 0.25
