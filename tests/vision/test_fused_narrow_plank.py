"""A last plank narrower than the walk's minimum move is still the face's when its top and
foot lines stand on the face's own rows and end together at its side, with the rig
(extent.NARROW_PLANK_ON_ROWS)."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import extent
from obstacle_fusion.vision.fused.extent import widen_across_seams

from tests.vision_fixtures import gradients, room_size_errors

H, W = 240, 320
TOP, BOTTOM, LEFT, RIGHT = 80, 200, 60, 260  # the drawn face
PLANK = 14  # the last plank's columns: 0.07 of the face, under MIN_WIDEN_SHARE's 0.15


def plank_face(plank: int = PLANK, shelf: bool = False) -> npt.NDArray[np.uint8]:
    """Wall above row 130, floor below; a face whose last plank (left, ``plank`` columns)
    is darker than the rest, a dark seam between; ``shelf``: a dark line on the face's top
    row running on past its left side to the image's edge (a background line there)."""
    rng = np.random.default_rng(5)
    img = np.full((H, W), 170.0)
    img[130:] = 90
    img[TOP:BOTTOM, LEFT:RIGHT] = 135
    seam = LEFT + plank
    img[TOP:BOTTOM, LEFT:seam] = 118
    img[TOP:BOTTOM, seam - 1 : seam + 1] = 60
    if shelf:
        img[TOP - 1 : TOP + 1, :LEFT] = 60
    img += rng.normal(0, 1.5, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def widened(img: npt.NDArray[np.uint8], narrow: bool = True, plank: int = PLANK) -> int:
    """The left side after the walk from the seam (the search's side)."""
    ay, ax3, noise = gradients(img)
    left, right = widen_across_seams(
        ay, ax3, BOTTOM, TOP, LEFT + plank, RIGHT, noise, True, narrow=narrow
    )
    assert right == RIGHT
    return left


def test_a_narrow_last_plank_on_the_faces_rows_is_taken_in() -> None:
    assert abs(widened(plank_face()) - LEFT) <= 2


def test_without_the_switch_the_narrow_plank_is_left_out(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(extent, "NARROW_PLANK_ON_ROWS", False)
    assert widened(plank_face()) == LEFT + PLANK


def test_without_the_rig_the_narrow_plank_is_left_out() -> None:
    assert widened(plank_face(), narrow=False) == LEFT + PLANK


def test_a_top_line_running_on_past_the_side_is_no_plank_end() -> None:
    """The lines must end together at the side: a background line on the top row that
    runs on past it leaves the side where the search put it."""
    assert widened(plank_face(shelf=True)) == LEFT + PLANK


@pytest.mark.parametrize("plank, moved", [(2, False), (3, True)])
def test_the_plank_must_reach_past_the_walks_snap(plank: int, moved: bool) -> None:
    """Edges running on by at most SNAP_COLUMNS // 2 past the side are its own blur: a
    2-column strip (the walk ends 3 past the side) stays out, a 3-column one (4 past) is in."""
    assert extent.SNAP_COLUMNS // 2 == 3
    left = widened(plank_face(plank), plank=plank)
    assert (left == LEFT) == moved
    assert widened(plank_face(plank), narrow=False, plank=plank) == LEFT + plank


def test_photo_3090_with_the_rig_is_measured_whole() -> None:
    """photo/3090 ordinary (new2): a plank face whose darker leftmost plank, 15 of 153
    columns, was left out (-9.9 % wide)."""
    _, ew = room_size_errors("photo", 3090, False)
    assert ew < 0.03


def test_photo_3090_without_the_rule_is_a_plank_short(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(extent, "NARROW_PLANK_ON_ROWS", False)
    _, ew = room_size_errors("photo", 3090, False)
    assert ew > 0.08
