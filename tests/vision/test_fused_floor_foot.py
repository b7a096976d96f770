"""The foot check of a face found on a tried floor-contact row (no rig): its sides must
still step in colour just above that row (vision/fused/floor_contact.py)."""

from __future__ import annotations

import numpy as np
import pytest
from obstacle_fusion.vision.fused.floor_contact import sides_reach_foot

FLOOR = 100  # grey level of the floor
FOOT_ROW = 200  # where the face meets the floor


def scene(face: tuple[int, int, int]) -> np.ndarray:
    """A wall, a floor from row 150 down, and a face (columns 100-199, rows 60-199)."""
    img = np.full((300, 300, 3), 180, np.uint8)  # wall
    img[150:] = FLOOR
    img[60:FOOT_ROW, 100:200] = face
    return img


DARK = (40, 40, 40)


def outline(bottom: float) -> list[tuple[float, float, float, float]]:
    """Bottom, top, left and right sides of a face from row 60 down to ``bottom``."""
    return [
        (100, bottom, 199, bottom),
        (100, 60, 199, 60),
        (100, bottom, 100, 60),
        (199, bottom, 199, 60),
    ]


def test_a_face_stands_on_its_own_foot_row() -> None:
    assert sides_reach_foot(scene(DARK), outline(FOOT_ROW))


def test_a_row_below_the_face_on_plain_floor_does_not_stand_it() -> None:
    # the face's sides end at row 200; a line at 290 leaves their lowest fifth on floor
    assert not sides_reach_foot(scene(DARK), outline(290))


def test_the_step_at_the_foot_is_held_to_the_limit() -> None:
    """The limit is 12 (8-bit BGR distance): a face (7, 7, 7) levels off the floor steps by
    12.1 across each side and stands; (7, 7, 6) levels (11.6) do not."""
    assert sides_reach_foot(scene((FLOOR + 7,) * 3), outline(FOOT_ROW))
    assert not sides_reach_foot(scene((FLOOR + 7, FLOOR + 7, FLOOR + 6)), outline(FOOT_ROW))


@pytest.mark.parametrize("at_left", [True, False])
def test_a_side_at_the_image_border_is_not_read(at_left: bool) -> None:
    img = scene(DARK)
    lines = outline(290)
    x = 1.0 if at_left else 298.0
    side = 2 if at_left else 3
    lines[side] = (x, 290, x, 60)
    assert not sides_reach_foot(img, lines)  # the other side decides: floor at its foot
    lines[5 - side] = (x, 290, x, 60)
    assert sides_reach_foot(img, lines)  # no side read: nothing tells against the row


def test_one_side_stepping_at_the_foot_is_enough() -> None:
    """A face's one side may fade into a floor of its colour at the foot (a shadow, a
    matching mat): the other side standing there keeps the row."""
    lines = outline(FOOT_ROW)
    lines[3] = (250, FOOT_ROW, 250, 60)  # a "side" over plain floor and wall
    assert sides_reach_foot(scene(DARK), lines)
