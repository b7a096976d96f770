"""A side the face's colour run moved out moves on along the face's outline
(``region.OUTLINE_PAST_COLOUR``, with the rig only: ``widen_by_colour(outline_past=True)``),
to a side that parts two colours (``region.OUTLINE_COLOUR_SIDE``, ``_colour_side``) and
stands on the contact row.

A face of planks of several colours ends its colour run at the first plank of another
colour; its outline (a foot that stands out from the floor, a top against what is behind)
runs on to the face's side. Before, the outline was read only where the colour run had not
moved the side, and its end taken only at a grey edge as strong as the side it started from
(a seam's, several times a grey plank's against a wall of its lightness). The room is
photo 2060 ordinary (a tuning room, with the rig): grey planks before a green wall, the
last plank darker, its side a colour step only (width -24 % -> +1 %).
"""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import region
from obstacle_fusion.vision.fused.region import widen_by_colour

from tests.vision.test_fused_region import (
    BOTTOM,
    DEPTH,
    FACE,
    FLOOR,
    LEFT,
    RIGHT,
    TOP,
    H,
    W,
    level_view,
    side_strength,
)
from tests.vision_fixtures import room_size_errors

SEAMS = (100, 140, 180, 220)
LAST = (200, 100, 60)  # BGR: the last plank (220..RIGHT), another colour than FACE
BEYOND = (60, 100, 200)  # the wall: the last plank's grey, another chroma
WALL_FOOT = 30  # rows over the face's contact row where the wall meets the floor


def planks(floor_rows: int = 0) -> npt.NDArray[np.uint8]:
    """Green planks with black seams, the last plank of another colour whose grey is the
    wall's and the floor's; ``floor_rows``: that plank's lowest rows show the floor (it stands farther
    back, on a row above the face's contact row)."""
    rng = np.random.default_rng(0)
    img = np.empty((H, W, 3), np.float64)
    img[: BOTTOM - WALL_FOOT] = BEYOND
    img[BOTTOM - WALL_FOOT :] = FLOOR  # the floor runs on behind the face to the wall
    img[TOP:BOTTOM, LEFT:RIGHT] = FACE
    edges = [LEFT, *SEAMS, RIGHT]
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        img[TOP:BOTTOM, a:b] += rng.uniform(-6, 6)
    img[TOP:BOTTOM, SEAMS[-1] : RIGHT] = LAST
    if floor_rows:
        img[BOTTOM - floor_rows : BOTTOM, SEAMS[-1] : RIGHT] = FLOOR
    for s in SEAMS:
        img[TOP:BOTTOM, s : s + 2] = 0
    img += rng.normal(0, 12.0, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def widen(img: npt.NDArray[np.uint8], outline_past: bool = True) -> tuple[int, int]:
    return widen_by_colour(
        img,
        level_view(),
        side_strength(img),
        BOTTOM,
        TOP,
        142,
        180,
        DEPTH,
        outline_past=outline_past,
    )


def test_the_side_grey_alone_does_not_show() -> None:
    # the last plank's side has the wall's grey on both sides: no grey edge to snap to
    assert float(np.mean(LAST)) == float(np.mean(BEYOND))


def test_the_outline_carries_the_side_past_the_colour_run() -> None:
    left, right = widen(planks())
    assert abs(left - LEFT) <= 2 and abs(right - RIGHT) <= 3


def test_without_the_rule_the_side_stays_where_the_colour_ends(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(region, "OUTLINE_PAST_COLOUR", False)
    _, right = widen(planks())
    assert abs(right - SEAMS[-1]) <= 3


def test_with_no_rig_the_side_stays_where_the_colour_ends() -> None:
    _, right = widen(planks(), outline_past=False)
    assert abs(right - SEAMS[-1]) <= 3


def test_without_the_colour_side_the_grey_edge_is_too_weak(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(region, "OUTLINE_COLOUR_SIDE", False)
    _, right = widen(planks())
    assert abs(right - SEAMS[-1]) <= 3


def test_a_plank_standing_farther_back_is_not_taken_in() -> None:
    # its foot 4 rows above the contact row: the outline's foot (a median over 5 rows)
    # still stands out from the floor, the side does not stand on the contact row
    _, right = widen(planks(floor_rows=4))
    assert abs(right - SEAMS[-1]) <= 3


def two_colours(
    a: tuple[int, int, int], b: tuple[int, int, int], rows: int
) -> npt.NDArray[np.uint8]:
    """Colour ``a`` left of column 100; right of it ``b`` over the first ``rows`` of the
    rows 20..120 and ``a`` below them."""
    img = np.empty((H, W, 3), np.uint8)
    img[:] = a
    img[20 : 20 + rows, 100:] = b
    return img


def lab_step(a: tuple[int, int, int], b: tuple[int, int, int]) -> float:
    pair = cv2.cvtColor(np.array([[a, b]], np.uint8), cv2.COLOR_BGR2LAB).astype(np.float32)
    return float(np.linalg.norm(pair[0, 0] - pair[0, 1]))


def test_the_colour_side_row_share_decides() -> None:
    a, b = (60, 100, 200), (200, 100, 60)
    # over 85 of 100 rows it stands (COLOUR_SIDE_ROWS 0.8), over 75 not
    assert region._colour_side(two_colours(a, b, 85), level_view(), 20, 120, 100)
    assert not region._colour_side(two_colours(a, b, 75), level_view(), 20, 120, 100)


def test_the_colour_side_step_decides() -> None:
    # greys whose Lab steps stand just over and just under MIN_BESIDE_STEP (12)
    base = (100, 100, 100)
    over = next(g for g in range(100, 160) if lab_step(base, (g, g, g)) >= 13.0)
    under = next(g for g in range(160, 100, -1) if lab_step(base, (g, g, g)) <= 11.0)
    assert lab_step(base, (over,) * 3) < 15.0 and lab_step(base, (under,) * 3) > 9.0
    assert region._colour_side(two_colours(base, (over,) * 3, 100), level_view(), 20, 120, 100)
    assert not region._colour_side(two_colours(base, (under,) * 3, 100), level_view(), 20, 120, 100)


def test_a_room_of_planks_gets_its_last_plank() -> None:
    eh, ew = room_size_errors("photo", 2060, False)
    assert ew < 0.03 and eh < 0.03


def test_without_the_rule_the_room_loses_its_last_plank(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "OUTLINE_PAST_COLOUR", False)
    _, ew = room_size_errors("photo", 2060, False)
    assert ew > 0.2
