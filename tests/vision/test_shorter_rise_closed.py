"""Sides rising from the foot apart: the shorter one's end is the face's top where the
colour steps across nearly the whole width there (foot_outline.SHORTER_RISE_CLOSED)."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import foot_outline

from tests.vision_fixtures import LOW_H, LOW_W, low_box_view, measured_room

#: A green face (rows FACE_TOP-FOOT, columns LEFT-RIGHT) on a grey floor before a wall,
#: found as a piece (FOUND, top FOUND_TOP) inside it.
FACE_TOP, FOOT, LEFT, RIGHT = 120, 200, 100, 220
FOUND, FOUND_TOP = (130, 210), 185
GREEN = (40, 160, 40)
#: The outline's sides (98, 223) hold 120 columns between their strips: a post behind
#: the face of its green, in line with its right side, 12 columns wide leaves the colour
#: stepping across 0.90 of them at the face's top, 13 columns 0.89.
OUTLINE = (FOOT, FACE_TOP, 98, 223)


def post_behind(columns: int) -> npt.NDArray[np.uint8]:
    """The face with a post of its green ``columns`` wide rising behind it from its top to
    row 30 in line with its right side: the left side rises 80 rows, the right 170."""
    img = np.full((LOW_H, LOW_W, 3), 110, np.uint8)
    img[:170] = (170, 150, 120)
    img[FACE_TOP:FOOT, LEFT : RIGHT + 1] = GREEN
    img[30:FACE_TOP, RIGHT + 1 - columns : RIGHT + 1] = GREEN
    return img


def outline(columns: int) -> tuple[int, int, int, int] | None:
    return foot_outline.outline_from_foot(
        post_behind(columns), low_box_view(), FOOT, FOOT, FOUND_TOP, *FOUND, 3.0
    )


def test_the_shorter_side_ends_at_the_top_across() -> None:
    assert outline(8) == OUTLINE


def test_without_the_rule_sides_apart_give_no_outline(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(foot_outline, "SHORTER_RISE_CLOSED", False)
    assert outline(8) is None


def test_a_top_not_closed_across_gives_no_outline() -> None:
    # a post 40 columns wide: the colour steps across 0.67 of the width at the top
    assert outline(40) is None


def test_step_share_limit() -> None:
    assert foot_outline.SHORTER_RISE_STEP_SHARE == 0.9
    assert outline(12) == OUTLINE  # 0.90
    assert outline(13) is None  # 0.89


def test_photo_3405_print_before_a_tripod() -> None:
    # a print in a cyan frame before a tripod, its right side rising on up a leg behind
    res, truth = measured_room("photo", 3405, True, True)
    assert res.detected and res.height_m is not None and res.width_m is not None
    assert abs(res.height_m / truth["height_m"] - 1) <= 0.05
    assert abs(res.width_m / truth["width_m"] - 1) <= 0.05


def test_photo_3405_without_the_rule_stops_at_a_text_line(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(foot_outline, "SHORTER_RISE_CLOSED", False)
    res, truth = measured_room("photo", 3405, True, True)
    assert res.detected and res.height_m is not None
    assert res.height_m / truth["height_m"] - 1 < -0.5
