"""A framed face found as its bottom rail: the frame's sides carry the rail's colour up to
the face's top (``region.raise_top_along_frame``)."""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import method, region
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import View

from tests.vision_fixtures import room_size_errors

H, W = 240, 320
TOP, BOTTOM, LEFT, RIGHT = 80, 200, 60, 260  # the drawn face; its foot is row BOTTOM
RAIL_TOP = 180  # the bottom rail's top: the inner panel's lower edge (a 20-row strip)
DEPTH = 1.0  # metres: fy = 300
WALL = (150, 130, 60)  # BGR: a teal wall
FLOOR = (60, 90, 160)  # a brown floor
FRAME = (190, 60, 180)  # a magenta frame
PANEL = (220, 190, 160)  # a light blue panel


def level_view() -> View:
    """A distortion-free camera with no pitch: the levelled view is the image itself."""
    k = np.array([[300.0, 0.0, W / 2], [0.0, 300.0, H / 2], [0.0, 0.0, 1.0]])
    return View(CameraModel(k, np.zeros(5), W, H), Rig(), "level")


def framed(
    side: int = 3,
    inset: int = 0,
    top: int = TOP,
    band: int = 0,
    panel: tuple[int, int, int] = PANEL,
) -> npt.NDArray[np.uint8]:
    """Wall above, floor below BOTTOM; a face LEFT..RIGHT x ``top``..BOTTOM in a frame of
    ``side`` columns at each side (``inset`` columns of a dark line outside the left one), a 6-row
    top margin and the rail from RAIL_TOP down, round a ``panel``; ``band``: rows of the
    frame's colour across the panel just above the rail."""
    rng = np.random.default_rng(0)
    img = np.empty((H, W, 3), np.float64)
    img[:BOTTOM] = WALL
    img[BOTTOM:] = FLOOR
    img[top:BOTTOM, LEFT:RIGHT] = FRAME
    inner = slice(LEFT + inset + side, RIGHT - side)
    img[top + 6 : RAIL_TOP, inner] = panel
    if band:
        img[RAIL_TOP - band : RAIL_TOP, inner] = FRAME
    if inset:
        img[top:BOTTOM, LEFT : LEFT + inset] = (40, 40, 40)
    img += rng.normal(0, 1.5, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def low_box(wall: tuple[int, int, int] = WALL) -> npt.NDArray[np.uint8]:
    """A low box of the frame's colour, RAIL_TOP..BOTTOM, in front of ``wall``."""
    rng = np.random.default_rng(0)
    img = np.empty((H, W, 3), np.float64)
    img[:BOTTOM] = wall
    img[BOTTOM:] = FLOOR
    img[RAIL_TOP:BOTTOM, LEFT:RIGHT] = FRAME
    img += rng.normal(0, 1.5, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def raised(img: npt.NDArray[np.uint8], top: int = RAIL_TOP) -> int:
    grey = cv2.cvtColor(img, cv2.COLOR_BGR2GRAY)
    dx = np.empty(grey.shape, np.int16)
    dy = np.empty(grey.shape, np.int16)
    cv2.spatialGradient(grey, dx, dy)
    ay = np.abs(dy).astype(np.float32)
    return region.raise_top_along_frame(img, level_view(), ay, BOTTOM, top, LEFT, RIGHT, DEPTH)


def test_a_frames_bottom_rail_is_raised_to_the_frames_top() -> None:
    assert abs(raised(framed()) - TOP) <= 2


def test_the_frames_top_stays() -> None:
    assert raised(framed(), top=TOP) == TOP


def test_a_low_box_keeps_its_top() -> None:
    """No colour of the box's above its top at its sides: the wall is there."""
    assert raised(low_box()) == RAIL_TOP


def test_a_wall_of_the_boxs_colour_is_no_frame() -> None:
    """Above a low box in front of a wall of its own colour the sides hold that colour,
    but so does the middle: no inner panel, no frame."""
    assert raised(low_box(wall=FRAME)) == RAIL_TOP


def test_a_grey_frame_is_left_alone() -> None:
    img = cv2.cvtColor(framed(), cv2.COLOR_BGR2GRAY)
    ay = np.zeros(img.shape, np.float32)
    top = region.raise_top_along_frame(img, level_view(), ay, BOTTOM, RAIL_TOP, LEFT, RIGHT, DEPTH)
    assert top == RAIL_TOP


@pytest.mark.parametrize(("side", "moves"), [(2, False), (3, True)])
def test_a_frame_side_shows_in_min_columns(side: int, moves: bool) -> None:
    """The side column is the edge's (LEFT): a frame ``side`` columns wide holds the rail's
    colour in side - 1 columns inside it (FRAME_SIDE_MIN_COLUMNS = 2)."""
    assert (raised(framed(side=side)) < RAIL_TOP) is moves


@pytest.mark.parametrize(("inset", "moves"), [(5, True), (6, False)])
def test_the_frame_side_lies_next_to_the_faces_side(inset: int, moves: bool) -> None:
    """A frame's left side set ``inset`` columns in (a dark line outside it) is read within
    FRAME_SIDE_COLUMNS (6) columns of the side column: at 5 two of its columns, at 6 one."""
    assert (raised(framed(inset=inset)) < RAIL_TOP) is moves


@pytest.mark.parametrize(("rise", "moves"), [(19, False), (20, True)])
def test_the_frame_rises_at_least_the_rails_height(rise: int, moves: bool) -> None:
    """Sides of the rail's colour running on fewer rows than the 20-row rail
    (FRAME_RISE_SHARE = 1.0): a box's corner posts, not a frame (no top margin here)."""
    img = framed(top=RAIL_TOP - rise - 6)  # the 6 margin rows painted as the panel
    img[: RAIL_TOP - rise] = low_box()[: RAIL_TOP - rise]  # the wall above the sides
    assert (raised(img) < RAIL_TOP) is moves


@pytest.mark.parametrize(("band", "moves"), [(13, True), (14, True), (15, False), (16, False)])
def test_the_middle_above_the_rail_is_another_colour(band: int, moves: bool) -> None:
    """A band of the rail's colour across the panel over ``band`` of the 100 rows up to
    the frame's top, and its 6-row top margin: the middle is off the rail's colour in
    (94 - band) % of them (FRAME_INNER_SHARE = 0.8: at 14, 80 % exactly, it still is)."""
    assert (raised(framed(band=band)) < RAIL_TOP) is moves


@pytest.mark.parametrize(("rows", "moves"), [(18, True), (20, True), (21, False), (22, False)])
@pytest.mark.parametrize("side", ["left", "right"])
def test_beside_the_sides_is_no_more_rail(side: str, rows: int, moves: bool) -> None:
    """A stripe of the rail's colour on the wall beside one side over ``rows`` of the 100
    rows up to the frame's top (FRAME_INNER_SHARE = 0.8 off it, 80 % exactly at 20): a
    band of that colour running on past the sides, as a background stripe behind a strip
    does, is no frame."""
    img = framed().astype(np.int16)
    cols = slice(LEFT - 12, LEFT) if side == "left" else slice(RIGHT, RIGHT + 12)
    img[RAIL_TOP - rows : RAIL_TOP, cols] = FRAME
    assert (raised(img.astype(np.uint8)) < RAIL_TOP) is moves


@pytest.mark.parametrize("posts", [2, 3, 4])
def test_the_top_is_the_row_edge_across_the_face(posts: int) -> None:
    """The frame's sides stand ``posts`` rows above its top margin (posts with finials, or
    a side's colour bled into the wall): the sides' walk ends there, but the face's top is
    the strongest row edge across the face within SNAP_ROWS of it: the top margin's."""
    img = framed()
    img[TOP - posts : TOP, LEFT : LEFT + 3] = FRAME
    img[TOP - posts : TOP, RIGHT - 3 : RIGHT] = FRAME
    assert abs(raised(img) - TOP) <= 1


def test_only_a_thin_strip_is_read_for_a_frame(monkeypatch: pytest.MonkeyPatch) -> None:
    """The rule reads faces found as a thin strip at the foot (under THIN_STRIP_SHARE of
    their width high): a face found whole (procedural/100 ordinary, within 5 %) is not
    asked, the rail of procedural/1416 hard is."""
    calls: list[tuple[int, int, int, int]] = []

    def spy(
        image: object,
        view: View,
        ay: object,
        bottom: int,
        top: int,
        left: int,
        right: int,
        depth_m: float,
    ) -> int:
        calls.append((bottom, top, left, right))
        return top

    monkeypatch.setattr(method, "raise_top_along_frame", spy)
    assert max(room_size_errors("procedural", 100, False)) < 0.05
    assert not calls
    room_size_errors("procedural", 1416, True)
    assert calls
    for bottom, top, left, right in calls:
        assert bottom - top < method.THIN_STRIP_SHARE * (right - left)


# a magenta frame round a light print, its right side faint in grey against a green bar
# beside it: the strip of its bottom rail was measured, -89 % (hard; with the rig and
# with none)
ROOMS = [("procedural", 1416, True)]


@pytest.mark.parametrize(("fam", "seed", "hard"), ROOMS)
def test_a_framed_face_is_measured_to_its_top(fam: str, seed: int, hard: bool) -> None:
    assert max(room_size_errors(fam, seed, hard)) < 0.05


@pytest.mark.parametrize(("fam", "seed", "hard"), ROOMS)
def test_without_the_rule_the_rail_is_the_face(
    monkeypatch: pytest.MonkeyPatch, fam: str, seed: int, hard: bool
) -> None:
    monkeypatch.setattr(method, "FRAME_RAIL_RAISE", False)
    # the frame closing over the print (test_fused_frame_closes_top) finds this face too
    monkeypatch.setattr(method, "FRAME_CLOSES_TOP", False)
    assert room_size_errors(fam, seed, hard)[0] > 0.4
