"""The colour rescue's top is raised to where its sides run on up to in the gradients,
though the face's colour is not back under there, where a margin of one colour hugs both
sides from the foot up to that top (``method.MARGIN_HOLDS_RAISED_TOP``,
``region.margin_up_to_raised_top``): a poster's board frames its print on every side.

The room is a diagnosis room (new6). Photo 3297 (hard, with the rig): a cat's photograph
in a light-blue margin about 4 columns wide on gravel; the edges' face was too weak, the
colour rescue's walk stopped inside the photograph (row 192, the board's top at 121) and
face_under_raised_top's strips (3 columns in, 6 wide) read the photograph: -55 % high at
confidence 0.40; with the rule +0.5 %.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import method as method_mod
from obstacle_fusion.vision.fused import region
from obstacle_fusion.vision.fused.region import face_under_raised_top, margin_up_to_raised_top

from tests.vision.test_fused_face_under_top import POLE, drawn
from tests.vision.test_fused_region import BOTTOM, LEFT, RIGHT, TOP, level_view
from tests.vision_fixtures import room_size_errors

#: the colour walk's top inside the print, and the board's top the sides run on up to
WALKED = TOP + 60
UPPER = (40, 110, 210)  # BGR orange: the print's upper part, over the light lower part


def poster(margin: int) -> npt.NDArray[np.uint8]:
    """drawn()'s green board over a light pole, a print inside a margin ``margin`` columns
    wide, the print's part above WALKED another colour (where the colour walk stopped)."""
    img = drawn(pole=True, margin=margin)
    img[TOP + margin : WALKED, LEFT + margin : RIGHT - margin] = UPPER
    return img


def test_the_posters_board_top_is_taken() -> None:
    eh, ew = room_size_errors("photo", 3297, True)
    assert eh < 0.03 and ew < 0.03


def test_without_the_rule_the_top_stays_in_the_print(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method_mod, "MARGIN_HOLDS_RAISED_TOP", False)
    eh, _ = room_size_errors("photo", 3297, True)
    assert eh > 0.5


def test_a_narrow_margin_holds_where_the_wider_strips_read_the_print() -> None:
    img = poster(5)
    args = (level_view(), BOTTOM, WALKED, TOP, LEFT, RIGHT)
    assert margin_up_to_raised_top(img, *args)
    assert not face_under_raised_top(img, *args)


def test_sides_running_on_up_a_pole_behind_the_face_are_not_held() -> None:
    # the margin ends at the board's top: up the pole past it the strips read the pole
    img = poster(5)
    assert not margin_up_to_raised_top(img, level_view(), BOTTOM, WALKED, TOP - 40, LEFT, RIGHT)


def test_no_margin_no_hold() -> None:
    # a print right out to the sides (no margin) with its colour not under the top
    img = poster(5)
    img[TOP:WALKED, LEFT:RIGHT] = POLE
    assert not margin_up_to_raised_top(img, level_view(), BOTTOM, WALKED, TOP, LEFT, RIGHT)


@pytest.mark.parametrize(("margin", "holds"), [(4, True), (3, False)])
def test_the_strips_skip_the_sides_blur_and_stay_in_the_margin(margin: int, holds: bool) -> None:
    # MARGIN_STRIP_SKIP (2) + MARGIN_STRIP_COLUMNS (2) columns of margin are needed
    img = poster(margin)
    args = (level_view(), BOTTOM, WALKED, TOP, LEFT, RIGHT)
    assert margin_up_to_raised_top(img, *args) is holds


@pytest.mark.parametrize(("rows", "holds"), [(12, True), (13, False)])
def test_the_share_of_rows_the_margin_must_hold(rows: int, holds: bool) -> None:
    # a tape across the board in the raised way: 12 of the 120 rows (MARGIN_HOLDS_SHARE)
    img = poster(5)
    img[TOP + 20 : TOP + 20 + rows, LEFT:RIGHT] = POLE
    args = (level_view(), BOTTOM, WALKED, TOP, LEFT, RIGHT)
    assert margin_up_to_raised_top(img, *args) is holds


def test_the_margin_must_reach_the_raised_top() -> None:
    # the margin's top rows (as face_under_raised_top reads them) are another colour
    img = poster(5)
    img[TOP : TOP + 10, LEFT:RIGHT] = POLE
    assert not margin_up_to_raised_top(img, level_view(), BOTTOM, WALKED, TOP, LEFT, RIGHT)


def test_the_two_strips_are_one_margin(monkeypatch: pytest.MonkeyPatch) -> None:
    img = poster(5)
    img[TOP:BOTTOM, RIGHT - 5 : RIGHT, 0] = np.clip(
        img[TOP:BOTTOM, RIGHT - 5 : RIGHT, 0].astype(int) + 60, 0, 255
    ).astype(np.uint8)
    view = level_view()
    lab = view.lab(img, TOP, BOTTOM, LEFT + 2, RIGHT - 1)
    left = np.median(lab[:, :2].reshape(-1, 3).astype(np.float32), axis=0)
    right = np.median(lab[:, -2:].reshape(-1, 3).astype(np.float32), axis=0)
    apart = float(np.linalg.norm(left - right))
    assert apart > region.MARGIN_STRIPS_APART  # a board of two colours: not held
    args = (view, BOTTOM, WALKED, TOP, LEFT, RIGHT)
    assert not margin_up_to_raised_top(img, *args)
    monkeypatch.setattr(region, "MARGIN_STRIPS_APART", apart + 2.0)
    assert margin_up_to_raised_top(img, *args)
    monkeypatch.setattr(region, "MARGIN_STRIPS_APART", apart - 2.0)
    assert not margin_up_to_raised_top(img, *args)


@pytest.mark.parametrize(("raised", "judged"), [(WALKED - 120, True), (WALKED - 121, False)])
def test_the_raise_limit_of_face_under_raised_top(raised: int, judged: bool) -> None:
    # judged over the same raises (RETURN_MAX_RAISE: twice the 60 rows found); here the
    # board runs up to row 20
    img = drawn(margin=5)
    img[:TOP, LEFT:RIGHT] = (60, 160, 60)
    img[:TOP, LEFT + 5 : RIGHT - 5] = POLE
    args = (level_view(), BOTTOM, WALKED, raised, LEFT, RIGHT)
    assert margin_up_to_raised_top(img, *args) is judged
