"""A top the sides ran on up to must have the face's colour under it (region.face_under_raised_top)."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import extent, region
from obstacle_fusion.vision.fused import method as method_mod
from obstacle_fusion.vision.fused.region import face_under_raised_top

from tests.vision.test_fused_region import BOTTOM, FACE, FLOOR, LEFT, RIGHT, TOP, level_view

H, W = 240, 320
SKY = (90, 40, 20)  # BGR dark blue: the wall photograph beside the face
POLE = (200, 215, 225)  # a light rocket in the photograph, in line with the face


def drawn(
    pole: bool = False, band: tuple[int, int] | None = None, margin: int = 0
) -> npt.NDArray[np.uint8]:
    """A green face from TOP to BOTTOM over a floor, the sky above; optionally a light
    pole of the face's width behind it all the way up, a light band across the face, or a
    light print over the face inside a green margin ``margin`` columns wide."""
    rng = np.random.default_rng(3)
    img = np.empty((H, W, 3), np.float64)
    img[:BOTTOM] = SKY
    img[BOTTOM:] = FLOOR
    if pole:
        img[:TOP, LEFT:RIGHT] = POLE
    img[TOP:BOTTOM, LEFT:RIGHT] = FACE
    if band is not None:
        img[band[0] : band[1], LEFT:RIGHT] = POLE
    if margin:
        img[TOP + margin : BOTTOM - margin, LEFT + margin : RIGHT - margin] = POLE
    img += rng.normal(0, 4.0, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def test_sides_running_on_up_a_pole_behind_the_face_are_not_its_sides() -> None:
    # the top found a little under the real one; the sides run on up the pole to row 5
    assert not face_under_raised_top(
        drawn(pole=True), level_view(), BOTTOM, TOP + 4, 5, LEFT, RIGHT
    )


def test_past_a_band_across_the_face_its_colour_comes_back() -> None:
    img = drawn(pole=True, band=(TOP + 30, TOP + 40))
    assert face_under_raised_top(img, level_view(), BOTTOM, TOP + 40, TOP, LEFT, RIGHT)


def test_a_print_in_a_margin_of_the_face_colour_keeps_its_margin_up_to_the_top() -> None:
    img = drawn(pole=True, margin=12)
    assert face_under_raised_top(img, level_view(), BOTTOM, TOP + 60, TOP, LEFT, RIGHT)


def test_a_strip_at_the_foot_does_not_judge_a_long_way_up() -> None:
    # a found "face" of 10 rows under 100 rows of pole: its colour may be a band's
    img = drawn(pole=True)
    assert face_under_raised_top(img, level_view(), BOTTOM, BOTTOM - 10, BOTTOM - 110, LEFT, RIGHT)


def test_the_raise_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    img = drawn(pole=True)
    monkeypatch.setattr(region, "RETURN_MAX_RAISE", 0.5)
    assert face_under_raised_top(img, level_view(), BOTTOM, TOP + 4, 5, LEFT, RIGHT)


def test_one_strip_is_enough_only_when_asked() -> None:
    # a print over the middle and the right margin; the left margin runs up to the top
    img = drawn(pole=True, margin=12)
    img[TOP : TOP + 40, RIGHT - 12 : RIGHT] = POLE
    args = (level_view(), BOTTOM, TOP + 60, TOP, LEFT, RIGHT)
    assert not face_under_raised_top(img, *args)
    assert face_under_raised_top(img, *args, one_strip=True)


def test_a_short_way_up_is_left_to_the_colour_top() -> None:
    # a way up under half the face found: a frame's top margin, a top face, blur
    img = drawn(pole=True)
    assert face_under_raised_top(img, level_view(), BOTTOM, TOP, TOP - 30, LEFT, RIGHT)
    assert not face_under_raised_top(img, level_view(), BOTTOM, TOP, TOP - 70, LEFT, RIGHT)


def test_the_short_raise_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    img = drawn(pole=True)
    monkeypatch.setattr(region, "RETURN_MIN_RAISE", 0.1)
    assert not face_under_raised_top(img, level_view(), BOTTOM, TOP, TOP - 30, LEFT, RIGHT)


def test_a_face_before_a_rocket_in_line_keeps_its_top(monkeypatch: pytest.MonkeyPatch) -> None:
    """photo/318 hard: a grey face of seams at the foot of a rocket photographed on the
    wall, as wide as the face; without the check every raise ran up the rocket (+148 %)."""
    from tests.vision.test_fused_method import height_error

    assert height_error("photo", 318, hard=True) < 0.15
    monkeypatch.setattr(method_mod, "face_under_raised_top", lambda *a, **k: True)
    # the face's top line across the rocket (extent.TOP_LINE_ACROSS) finds that top too
    monkeypatch.setattr(extent, "TOP_LINE_ACROSS", False)
    assert height_error("photo", 318, hard=True) > 0.5
