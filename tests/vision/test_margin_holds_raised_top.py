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


MARGIN_LAB = (150, 120, 110)  # the margin's 8-bit Lab in the drawn Lab images below
PRINT_LAB = (90, 160, 90)


def lab_board(right: int = RIGHT) -> npt.NDArray[np.uint8]:
    """An image already in 8-bit Lab (read as it is: see ``as_lab``): a board from TOP to
    BOTTOM between LEFT and ``right`` whose margin, 6 columns wide on each side, is
    MARGIN_LAB, the print between it PRINT_LAB."""
    img = np.zeros((BOTTOM + 20, RIGHT + 20, 3), np.uint8)
    img[TOP:BOTTOM, LEFT : right + 1] = MARGIN_LAB
    img[TOP:BOTTOM, LEFT + 6 : right - 5] = PRINT_LAB
    return img


@pytest.fixture
def as_lab(monkeypatch: pytest.MonkeyPatch) -> None:
    """The stages read the image's pixels as 8-bit Lab as they are: exact distances."""

    def read(
        image: npt.NDArray[np.uint8],
        view: object,
        r0: int,
        r1: int,
        c0: int = 0,
        c1: int | None = None,
        step: int = 1,
    ) -> npt.NDArray[np.uint8]:
        return image[r0:r1, c0:c1:step]

    monkeypatch.setattr(region, "_lab8", read)


@pytest.mark.usefixtures("as_lab")
@pytest.mark.parametrize(("lighter", "holds"), [(18, True), (19, False)])
def test_the_margin_up_the_raise_within_its_limit_inclusive(lighter: int, holds: bool) -> None:
    # the margin up the raised way (the light's fall-off) exactly MIN_FACE_DISTANCE (the
    # spread limit of a plain margin) lighter than under the walk's top: still the margin,
    # both in the share of rows (dist <= limit) and right under the raised top (not over
    # the limit); one step more is not
    img = lab_board()
    img[TOP:WALKED, LEFT : RIGHT + 1, 0] += lighter
    args = (level_view(), BOTTOM, WALKED, TOP, LEFT, RIGHT)
    assert margin_up_to_raised_top(img, *args) is holds


@pytest.mark.usefixtures("as_lab")
@pytest.mark.parametrize(("apart", "holds"), [(18, True), (19, False)])
def test_the_two_strips_at_most_margin_strips_apart(apart: int, holds: bool) -> None:
    # the right strip's margin MARGIN_STRIPS_APART (18 Lab, inclusive) bluer than the left's
    # is one margin; one step more is two colours
    img = lab_board()
    img[TOP:BOTTOM, RIGHT - 5 : RIGHT + 1, 2] -= apart
    args = (level_view(), BOTTOM, WALKED, TOP, LEFT, RIGHT)
    assert margin_up_to_raised_top(img, *args) is holds


@pytest.mark.usefixtures("as_lab")
@pytest.mark.parametrize(("width", "judged"), [(12, True), (11, False)])
def test_the_narrowest_face_judged(width: int, judged: bool) -> None:
    # both strips (MARGIN_STRIP_SKIP 2 in, MARGIN_STRIP_COLUMNS 2 wide) and 4 columns
    # between them: a face 12 columns wide (right - left) is read, 11 is not (with strips
    # 3 wide, 12 would not be)
    img = lab_board()
    img[TOP:BOTTOM, LEFT : LEFT + width + 1] = MARGIN_LAB
    args = (level_view(), BOTTOM, WALKED, TOP, LEFT, LEFT + width)
    assert margin_up_to_raised_top(img, *args) is judged


@pytest.mark.usefixtures("as_lab")
@pytest.mark.parametrize(
    ("top", "raised", "judged"),
    [
        (WALKED, WALKED - 30, True),  # RETURN_MIN_RAISE (0.5) of the 60 rows found
        (WALKED, WALKED - 29, False),  # shorter: a frame's top margin, a top face
        (BOTTOM - 4, BOTTOM - 8, True),  # the least face found read (4 rows)
        (BOTTOM - 3, BOTTOM - 6, False),
    ],
)
def test_the_shortest_raise_and_face_judged(top: int, raised: int, judged: bool) -> None:
    # judged over the same raises as face_under_raised_top (one helper, region._raise_judged)
    img = lab_board()
    img[:TOP, LEFT : RIGHT + 1] = MARGIN_LAB  # the board runs on up: only the limits say no
    args = (level_view(), BOTTOM, top, raised, LEFT, RIGHT)
    assert margin_up_to_raised_top(img, *args) is judged
