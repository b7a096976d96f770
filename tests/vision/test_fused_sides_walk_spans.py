"""The sides' walk ends on the face's top only where that row is a colour line across the
face's middle (``region.SIDES_WALK_SPANS``, ``SIDES_WALK_TOP_STEP``, ``region.middle_step``).

The face's top has the face under it and what stands behind above it, from side to side.
The sides' walk (``region.raise_top_by_sides``) reads only the strips beside the two sides:
beside a pale face before a pale wall, a poster's edge next to one side and another poster
next to the other kept both sides "standing" above the face's top, and the walk ran on up
the wall (photo/3109 hard, a new3 room: +10 % with the rig, the top on a poster's lower
edge; +51 % with none, up to the image's top). Between the sides the wall runs on above and
below those rows: no line there.
"""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import region

from tests.vision.test_fused_region import (
    BOTTOM,
    DEPTH,
    FACE_TOP,
    FLOOR,
    LEFT,
    RIGHT,
    TAPE_LOW,
    H,
    W,
    level_view,
    taped_scene,
    top_strength,
)
from tests.vision_fixtures import room_size_errors

PALE_WALL = (225, 195, 170)  # BGR light blue
PALE_FACE = (185, 205, 205)  # BGR pale grey-green: close to the wall, apart in hue
POSTER_FOOT = 70  # the dark poster's lower edge beside the left side, 10 rows over the top


def poster_scene() -> npt.NDArray[np.uint8]:
    """A pale face (FACE_TOP..BOTTOM) before a pale wall, a dark poster beside its left side
    (rows 20..POSTER_FOOT) and a yellow one beside its right side (rows 10..140), blurred as
    a lens does."""
    rng = np.random.default_rng(4)
    img = np.empty((H, W, 3), np.float64)
    img[:] = PALE_WALL
    img[BOTTOM:] = FLOOR
    img[20:POSTER_FOOT, : LEFT - 2] = (60, 60, 60)
    img[10 : BOTTOM - 60, RIGHT + 2 :] = (40, 200, 200)
    img[FACE_TOP:BOTTOM, LEFT:RIGHT] = PALE_FACE
    img = cv2.GaussianBlur(img, (0, 0), 1.5)
    img += rng.normal(0, 3.0, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def walked(img: npt.NDArray[np.uint8], top: int, one_side: bool = False) -> int:
    return region.raise_top_by_sides(
        img, level_view(), top_strength(img), BOTTOM, top, LEFT, RIGHT, DEPTH, one_side=one_side
    )


def test_posters_beside_the_sides_do_not_carry_the_top() -> None:
    assert walked(poster_scene(), FACE_TOP, one_side=True) == FACE_TOP


def test_without_the_rule_the_walk_runs_up_the_wall(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "SIDES_WALK_SPANS", False)
    img = poster_scene()
    top = walked(img, FACE_TOP, one_side=True)
    assert top < POSTER_FOOT
    # between the sides the wall runs on across that row: no line
    assert region.middle_step(img, level_view(), top, LEFT, RIGHT) < 4.0


def test_a_band_across_the_face_is_still_crossed() -> None:
    # the walk's purpose: past a band of the wall's shade up to the face's real top
    assert abs(walked(taped_scene(), TAPE_LOW) - FACE_TOP) <= 2


def test_the_step_limit_decides_at_the_real_top(monkeypatch: pytest.MonkeyPatch) -> None:
    img = taped_scene()
    top = walked(img, TAPE_LOW)
    step = region.middle_step(img, level_view(), top, LEFT, RIGHT)
    monkeypatch.setattr(region, "SIDES_WALK_TOP_STEP", step - 0.5)
    assert walked(img, TAPE_LOW) == top
    monkeypatch.setattr(region, "SIDES_WALK_TOP_STEP", step + 0.5)
    assert walked(img, TAPE_LOW) == TAPE_LOW


def test_the_middle_step_reads_nothing_at_the_image_top() -> None:
    assert region.middle_step(poster_scene(), level_view(), 2, LEFT, RIGHT) == float("inf")


def test_a_pale_face_between_posters_keeps_its_top_with_the_rig() -> None:
    eh, ew = room_size_errors("photo", 3109, True)
    assert eh < 0.03 and ew < 0.03


def test_without_the_rule_the_poster_edge_is_its_top(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "SIDES_WALK_SPANS", False)
    eh, _ = room_size_errors("photo", 3109, True)
    assert eh > 0.08
