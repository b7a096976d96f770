"""A print lies inside its face: the frame round it (its bottom rail on the floor, its side
margins running up past the top found) closes over the print at the face's top
(``region.raise_top_to_frame``, ``method.FRAME_CLOSES_TOP``)."""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import method, region
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import View

from tests.vision_fixtures import room_size_errors

H, W = 240, 320
TOP, BOTTOM, LEFT, RIGHT = 60, 200, 60, 260  # the drawn face (200 columns); its foot BOTTOM
RAIL = 12  # the frame's bottom rail, rows
SIDE = 10  # the frame's side margins, columns
CROWN = 6  # the frame's top margin, rows
FOUND = 130  # the top found: a row of the print
DEPTH = 1.0  # metres: fy = 300
# colours in 8-bit Lab (L, a, b), drawn and converted to BGR
WALL = (90, 150, 160)  # a dark red wall
FLOOR = (120, 128, 128)  # a grey floor
FRAME = (200, 100, 136)  # a light teal frame
PRINT = (80, 128, 128)  # a dark grey print


def level_view() -> View:
    """A distortion-free camera with no pitch: the levelled view is the image itself."""
    k = np.array([[300.0, 0.0, W / 2], [0.0, 300.0, H / 2], [0.0, 0.0, 1.0]])
    return View(CameraModel(k, np.zeros(5), W, H), Rig(), "level")


def framed(
    rail: int = RAIL,
    right_side: tuple[int, int, int] = FRAME,
    wall: tuple[int, int, int] = WALL,
    print_colour: tuple[int, int, int] = PRINT,
) -> npt.NDArray[np.uint8]:
    """Wall above, floor below BOTTOM; a face LEFT..RIGHT x TOP..BOTTOM: a frame (a
    ``rail``-row bottom rail, SIDE-column side margins, a CROWN-row top margin) round a
    print of ``print_colour``; the right side margin above the rail in ``right_side``
    (a frame's paint shaded along one side)."""
    lab = np.empty((H, W, 3), np.uint8)
    lab[:BOTTOM] = wall
    lab[BOTTOM:] = FLOOR
    lab[TOP:BOTTOM, LEFT:RIGHT] = FRAME
    lab[TOP + CROWN : BOTTOM - rail, LEFT + SIDE : RIGHT - SIDE] = print_colour
    lab[TOP : BOTTOM - rail, RIGHT - SIDE : RIGHT] = right_side
    img = cv2.cvtColor(lab, cv2.COLOR_LAB2BGR).astype(np.float64)
    img += np.random.default_rng(0).normal(0, 1.0, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def closed(img: npt.NDArray[np.uint8], top: int = FOUND) -> int:
    return region.raise_top_to_frame(img, level_view(), BOTTOM, top, LEFT, RIGHT, DEPTH)


def test_a_print_s_row_gives_way_to_the_frame_s_top() -> None:
    assert abs(closed(framed()) - TOP) <= 1


def test_the_print_s_lower_edge_over_the_rail_gives_way_too() -> None:
    """The face found as the bottom rail alone, its top the print's lower edge."""
    assert abs(closed(framed(), top=BOTTOM - RAIL) - TOP) <= 1


def test_the_frame_s_top_stays() -> None:
    assert closed(framed(), top=TOP) == TOP


def test_a_plain_face_keeps_its_top() -> None:
    """A face of one colour (the print the frame's): no rail under another colour."""
    assert closed(framed(print_colour=FRAME), top=TOP) == TOP


def test_a_low_box_before_a_wall_of_its_colour_keeps_its_top() -> None:
    """The rail is the whole face; its colour runs on up the wall past the window read:
    no frame's top closes (the sides are the wall's)."""
    img = framed(wall=FRAME)
    img[: BOTTOM - RAIL] = framed(wall=FRAME)[0, 0]  # the wall down to the box's top
    assert closed(img, top=BOTTOM - RAIL) == BOTTOM - RAIL


def test_a_grey_image_is_left_alone() -> None:
    grey = cv2.cvtColor(framed(), cv2.COLOR_BGR2GRAY)
    assert closed(grey) == FOUND


def striped(shade: int = 0, sides: str = "both") -> npt.NDArray[np.uint8]:
    """The framed print under a wall stripe of the frame's colour (``shade`` Lab units
    darker), 6 rows right over the frame's top, beside ``sides`` ("both" or "left")."""
    img = framed()
    stripe = np.empty((CROWN, W, 3), np.uint8)
    stripe[:] = (FRAME[0] - shade, FRAME[1], FRAME[2])
    bgr = cv2.cvtColor(stripe, cv2.COLOR_LAB2BGR)
    cols = slice(0, W) if sides == "both" else slice(0, RIGHT)
    img[TOP - CROWN : TOP, cols] = bgr[:, cols]
    # the stripe runs on beside the frame down to its top margin's rows (CLOSE_BESIDE_ROWS)
    img[TOP : TOP + CROWN, : LEFT - 1] = bgr[:, : LEFT - 1]
    if sides == "both":
        img[TOP : TOP + CROWN, RIGHT + 1 :] = bgr[:, RIGHT + 1 :]
    return img


def test_a_wall_stripe_of_the_frame_s_colour_over_it_is_no_frame_s_top() -> None:
    """The side margins' walk runs on up into the stripe; beside both sides under where it
    ends the stripe shows, not the room: the frame's top is not read there (the top found
    stays; fresh procedural/2110 hard, a maroon stripe over a maroon frame, +8 % without)."""
    assert closed(striped()) == FOUND


def test_a_stripe_beside_one_side_only_leaves_the_frame_s_top() -> None:
    assert closed(striped(sides="left")) < FOUND


@pytest.mark.parametrize(("shade", "refused"), [(18, True), (24, False)])
def test_the_stripe_beside_is_the_frame_s_colour_within_the_agreement(
    shade: int, refused: bool
) -> None:
    assert (closed(striped(shade=shade)) == FOUND) is refused


def test_with_no_rows_read_beside_the_stripe_is_taken(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "CLOSE_BESIDE_ROWS", 0)
    assert closed(striped()) < FOUND


# RAIL_MAX_SHARE (0.35) of the 200 columns: a rail of 70 rows is one, of 71 the face
@pytest.mark.parametrize(("rail", "moves"), [(70, True), (71, False)])
def test_the_rail_is_at_most_a_share_of_the_width(rail: int, moves: bool) -> None:
    assert (closed(framed(rail=rail), top=BOTTOM - rail) < BOTTOM - rail) is moves


# FRAME_CLOSE_AGREE (20 Lab): the right side margin shaded 18 units off the rail's colour
# is still the frame's, 24 off it is not
@pytest.mark.parametrize(("shade", "moves"), [(18, True), (24, False)])
def test_a_shaded_side_margin_within_the_agreement(shade: int, moves: bool) -> None:
    side = (FRAME[0] - shade, FRAME[1], FRAME[2])
    assert (closed(framed(right_side=side)) < FOUND) is moves


# photo/3142 hard (a brick print in a teal frame on a red wall, no rig: the settled sides'
# top on the wall's line behind, -31 %) and photo/3039 hard (a print of coins in a lavender
# frame, no rig: the top on a row of the print, -44 %)
ROOMS = [("photo", 3142, True), ("photo", 3039, True)]


@pytest.mark.parametrize(("fam", "seed", "hard"), ROOMS)
def test_a_framed_print_is_measured_to_its_frame_s_top(fam: str, seed: int, hard: bool) -> None:
    assert max(room_size_errors(fam, seed, hard, with_rig=False)) < 0.05


@pytest.mark.parametrize(("fam", "seed", "hard"), ROOMS)
def test_without_the_rule_the_top_stays_low(
    monkeypatch: pytest.MonkeyPatch, fam: str, seed: int, hard: bool
) -> None:
    monkeypatch.setattr(method, "FRAME_CLOSES_TOP", False)
    # with no rig the rows read as with a rig find photo/3142's frame too, on the same foot
    # and sides, its margin's colour over the print's top (measure.SURER_TOP_RAISES,
    # session 44): that rule alone takes it to 1.3 %, so it is off here as well
    monkeypatch.setattr(measure, "SURER_TOP_RAISES", False)
    assert room_size_errors(fam, seed, hard, with_rig=False)[0] > 0.25


def test_the_rail_raise_s_room_by_this_rule_alone(monkeypatch: pytest.MonkeyPatch) -> None:
    """procedural/1416 hard (a magenta frame round a light print, its bottom rail taken for
    the face, -89 % with neither rule): the frame closes over the print at its top without
    ``FRAME_RAIL_RAISE`` (test_fused_frame_rail turns both off)."""
    monkeypatch.setattr(method, "FRAME_RAIL_RAISE", False)
    assert max(room_size_errors("procedural", 1416, True)) < 0.05


# -- the room beside the frame's top read only inside the image ---------------------------

#: Columns kept past each side of the face when the image is cut round it: fewer than the
#: SIDE_SKIP (3) + BESIDE_COLUMNS (6) read beside a side, so that side's strip lies out.
CUT = 2


def closed_cut(img: npt.NDArray[np.uint8], sides: str) -> int:
    """:func:`closed` on the image cut CUT columns past the face's right side, or past
    both ("both"): the strip beside the side(s) cut lies outside the image."""
    c0 = LEFT - CUT if sides == "both" else 0
    cut = np.ascontiguousarray(img[:, c0 : RIGHT + CUT])
    w = cut.shape[1]
    k = np.array([[300.0, 0.0, w / 2], [0.0, 300.0, H / 2], [0.0, 0.0, 1.0]])
    view = View(CameraModel(k, np.zeros(5), w, H), Rig(), "level")
    return region.raise_top_to_frame(cut, view, BOTTOM, FOUND, LEFT - c0, RIGHT - c0, DEPTH)


def test_with_one_side_in_the_image_that_side_decides() -> None:
    """The strip beside the right side lies outside the image: the stripe beside the left
    one refuses the frame's top (it was taken unchecked), the room beside it lets it."""
    assert region.SIDE_SKIP + region.BESIDE_COLUMNS > CUT
    assert closed_cut(striped(), "right") == FOUND
    assert abs(closed_cut(framed(), "right") - TOP) <= 1


def test_with_neither_side_in_the_image_the_top_found_stays() -> None:
    """No room seen beside the frame's top: it is not taken (it was, unchecked)."""
    assert closed_cut(framed(), "both") == FOUND
