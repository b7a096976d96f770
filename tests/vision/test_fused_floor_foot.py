"""The checks of a face found on a tried floor-contact row (no rig), vision/fused/floor_contact.py:
its sides must still step in colour just above that row; a print found on a higher row
gives way to the face found lower when the print's margin runs down to that face's foot."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from obstacle_fusion.vision.fused.floor_contact import (
    face_runs_below,
    sides_reach_foot,
    sides_run_up,
)

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


# --- a print on the face, found on a higher row than the face (floor_contact.face_runs_below)

PRINT_BOX = (120.0, 80.0, 179.0, 179.0)  # x0, y0, x1, y1: the print, over the face's margin
FACE_BOX = (100.0, 60.0, 199.0, 199.0)  # the whole face, its foot on row 199


def lab(grey: int) -> np.ndarray:
    pixel = np.full((1, 1, 3), grey, np.uint8)
    return cv2.cvtColor(pixel, cv2.COLOR_BGR2Lab)[0, 0].astype(np.float64)


def grey_at(ref: int, distance: float, step: int, reach: bool = False) -> int:
    """The first grey from ``ref`` going by ``step`` whose Lab distance from it exceeds
    ``distance`` (or ``reach``es it), so that a limit can be straddled with two neighbouring
    greys (8-bit Lab distances of greys are whole numbers)."""
    g = ref
    while True:
        d = float(np.linalg.norm(lab(g) - lab(ref)))
        if d > distance or (reach and d >= distance):
            return g
        g += step


def framed(margin: int, floor: int, strip: int | None = None) -> np.ndarray:
    """A wall (grey 230), a face of grey ``margin`` with a print (grey 20) on it, a floor of
    grey ``floor`` from row 200 down; ``strip``: the grey of the face below the print."""
    img = np.full((300, 300, 3), 230, np.uint8)
    img[200:] = floor
    img[60:200, 100:200] = margin
    img[80:180, 120:180] = 20
    if strip is not None:
        img[180:200, 120:180] = strip
    return img


def test_a_print_whose_margin_runs_down_to_the_lower_foot_gives_way() -> None:
    assert face_runs_below(framed(120, 60), PRINT_BOX, FACE_BOX)


def test_a_face_on_the_floor_does_not_give_way_to_the_floor_below_it() -> None:
    # the "strip" under a face standing on row 179 is floor, as under the lower foot
    assert not face_runs_below(framed(120, 120), PRINT_BOX, FACE_BOX)


def test_the_lower_face_must_cover_the_higher_one_and_stand_lower() -> None:
    """Covering: its sides at most 10 % of the print's width inside the print's."""
    img = framed(120, 60)
    x0, y0, x1, y1 = FACE_BOX
    width = PRINT_BOX[2] - PRINT_BOX[0]  # 59 px: covering allows 5.9 px inside it
    assert face_runs_below(img, PRINT_BOX, (PRINT_BOX[0] + 5, y0, x1, y1))
    assert not face_runs_below(img, PRINT_BOX, (PRINT_BOX[0] + 0.11 * width, y0, x1, y1))
    assert not face_runs_below(img, PRINT_BOX, (x0, y0, PRINT_BOX[2] - 0.11 * width, y1))
    # the lower foot 4 px below the print's at least: a strip of a row between them
    foot = int(PRINT_BOX[3])
    img[foot + 4 :] = 60
    assert face_runs_below(img, PRINT_BOX, (x0, y0, x1, foot + 4))
    assert not face_runs_below(img, PRINT_BOX, (x0, y0, x1, foot + 3))


@pytest.mark.parametrize("over", [False, True])
def test_the_strip_must_match_the_margin_within_15(over: bool) -> None:
    strip = grey_at(120, 15.0, -1) + (0 if over else 1)  # just over / under 15 from it
    assert face_runs_below(framed(120, 200, strip), PRINT_BOX, FACE_BOX) is not over


@pytest.mark.parametrize("over", [False, True])
def test_the_strip_must_stand_25_from_the_floor(over: bool) -> None:
    floor = grey_at(120, 25.0, 1, reach=True) - (
        0 if over else 1
    )  # strip (= margin) to floor: 25+ / 25-
    assert face_runs_below(framed(120, floor), PRINT_BOX, FACE_BOX) is over


@pytest.mark.parametrize("over", [False, True])
def test_the_margin_must_stand_20_from_the_floor(over: bool) -> None:
    floor = grey_at(120, 20.0, 1, reach=True) - (0 if over else 1)  # margin to floor: 20+ / 20-
    strip = grey_at(120, 12.0, -1)  # 12+ below the margin, so 25+ from the floor
    assert np.linalg.norm(lab(strip) - lab(floor)) >= 25.0
    assert face_runs_below(framed(120, floor, strip), PRINT_BOX, FACE_BOX) is over


# --- a margin too thin to read beside the print: the margin above it (MARGIN_ABOVE_PRINT)

THIN_PRINT_BOX = (102.0, 80.0, 197.0, 179.0)  # the print, 2 px of margin beside it


def thin_framed(above: int = 120) -> np.ndarray:
    """:func:`framed`'s face (grey 120, on a floor of grey 60) with a print (grey 20)
    leaving 2 px of margin beside it, read as the wall (230) in the columns 2-6 px out;
    ``above``: the grey of the margin above the print (rows 60-79)."""
    img = framed(120, 60)
    img[80:180, 102:198] = 20
    img[60:80, 100:200] = above
    return img


def test_a_thin_margin_beside_a_print_is_read_above_it(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from obstacle_fusion.vision.fused import floor_contact

    assert face_runs_below(thin_framed(), THIN_PRINT_BOX, FACE_BOX)
    monkeypatch.setattr(floor_contact, "MARGIN_ABOVE_PRINT", False)
    assert not face_runs_below(thin_framed(), THIN_PRINT_BOX, FACE_BOX)


@pytest.mark.parametrize("rows, runs", [(4, True), (3, False)])
def test_the_margin_above_a_thin_framed_print_is_4_rows_at_least(rows: int, runs: bool) -> None:
    """MIN_ABOVE_PX = 4: the lower face's top that far above the print's at least."""
    top = THIN_PRINT_BOX[1] - rows
    assert face_runs_below(thin_framed(), THIN_PRINT_BOX, (100.0, top, 199.0, 199.0)) is runs


@pytest.mark.parametrize("over", [False, True])
def test_the_margin_above_a_thin_framed_print_must_match_the_strip_within_15(
    over: bool,
) -> None:
    above = grey_at(120, 15.0, -1) + (0 if over else 1)  # just over / under 15 from it
    assert face_runs_below(thin_framed(above), THIN_PRINT_BOX, FACE_BOX) is not over


@pytest.mark.parametrize("below, stands", [(14, True), (17, False)])
def test_the_foot_is_read_over_the_lowest_fifth_of_the_sides(below: int, stands: bool) -> None:
    """A row ``below`` px under the face's foot: the lowest fifth of the sides (~28-30 px
    here) still shows the face's step over most of its rows at 14 px, not at 17 px."""
    assert sides_reach_foot(scene(DARK), outline(FOOT_ROW + below)) is stands


# --- a taller reading's sides run on above a shorter reading's top (sides_run_up)

SHORT_TOP = 130.0  # the shorter reading's top row


def taped(tape: int = 230) -> np.ndarray:
    """The dark face of :func:`scene` (rows 60-199) with a light tape across it on rows
    115-129: a level reading can take the tape's lower edge, row 130, for the face's top."""
    img = scene(DARK)
    img[115:130, 100:200] = tape
    return img


def test_a_face_whose_sides_run_on_above_a_tape_is_the_taller_face() -> None:
    assert sides_run_up(taped(), outline(FOOT_ROW), SHORT_TOP)


def test_a_print_on_the_wall_above_a_box_off_its_columns_does_not_run_on() -> None:
    """A box (rows 130-199) under a print on the wall (rows 40-129, columns 120-219): the
    tall reading's sides at the box's columns 100 and 199 have wall on both sides above
    the box's top (the print's own sides lie 20 px off) and do not run on."""
    img = np.full((300, 300, 3), 180, np.uint8)
    img[150:] = FLOOR
    img[130:FOOT_ROW, 100:200] = DARK
    img[40:130, 120:220] = 60
    lines = outline(FOOT_ROW)
    lines[1] = (100, 40, 199, 40)
    lines[2] = (100, FOOT_ROW, 100, 40)
    lines[3] = (199, FOOT_ROW, 199, 40)
    assert not sides_run_up(img, lines, SHORT_TOP)


def test_the_sides_must_step_on_most_rows_between_the_tops() -> None:
    """RUN_UP_SHARE = 0.8 of the rows between the tops (3 px left out next to each): the
    wall beside the face of the face's own grey on a share of them takes the step away.
    Rows 63-127 are read (65 rows); the wall matching the face on 10 of them (85 % left)
    keeps the run, on 16 of them (75 % left) breaks it."""
    for rows, runs in ((10, True), (16, False)):
        img = taped()
        img[70 : 70 + rows, 90:100] = DARK  # beside the left side
        assert sides_run_up(img, outline(FOOT_ROW), SHORT_TOP) is runs


def test_a_side_at_the_border_is_left_to_the_other_and_none_read_is_no_run() -> None:
    img = taped()
    lines = outline(FOOT_ROW)
    lines[2] = (1.0, FOOT_ROW, 1.0, 60)
    assert sides_run_up(img, lines, SHORT_TOP)  # the right side runs on
    lines[3] = (298.0, FOOT_ROW, 298.0, 60)
    assert not sides_run_up(img, lines, SHORT_TOP)  # no side read


def test_a_print_on_the_wall_in_line_with_the_box_has_another_colour_above_it() -> None:
    """The same box under a print exactly as wide (columns 100-199, rows 40-129): the
    sides step on every row, but the colour inside them above the box's top (the print,
    light yellow) is not the box's below it: no run."""
    img = np.full((300, 300, 3), 180, np.uint8)
    img[150:] = FLOOR
    img[130:FOOT_ROW, 100:200] = DARK
    img[40:130, 100:200] = (90, 220, 230)
    lines = outline(FOOT_ROW)
    lines[1] = (100, 40, 199, 40)
    lines[2] = (100, FOOT_ROW, 100, 40)
    lines[3] = (199, FOOT_ROW, 199, 40)
    assert not sides_run_up(img, lines, SHORT_TOP)
    img[40:130, 100:110] = DARK  # the box's colour runs on up its left side: it runs up
    assert sides_run_up(img, lines, SHORT_TOP)


def test_a_grey_image_tells_no_colour_and_gives_no_run() -> None:
    assert not sides_run_up(taped()[:, :, 0].copy(), outline(FOOT_ROW), SHORT_TOP)
