"""With no rig, a band a trial found whose rows just above and just below both have the
floor's colour at the image's foot lies on the floor (a shade, a cast shadow), not along
the wall: it refuses no face standing in it (``measure.BAND_ON_FLOOR``,
``measure._band_on_floor``, ``BAND_FLOOR_MATCH``).

The room is a diagnosis room (new10), measured with no rig. Photo 3493 (ordinary): a
seamed green box on a grey gravel floor; a faint strip of the gravel under its foot,
running out to the right, read as a band along the wall refused the box's own face
(0.77), and the search took a face 15 rows low, +14 %. With the rule: 0.8 %.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.measure import _band_on_floor

from tests.vision_fixtures import room_size_errors

FLOOR = 100
WALL = 180
BAND = (100.0, 150.0, 300.0, 160.0)  # x0, y0, x1, y1: the strips read 141-147, 163-169


def _scene(
    above: int = FLOOR, below: int = FLOOR, band: int = 115, wall_foot: int = 120
) -> npt.NDArray[np.uint8]:
    """A wall (grey WALL) down to ``wall_foot``, a floor (grey FLOOR) under it, the band's
    rows grey ``band``, the strips read above and below it greys ``above`` and ``below``."""
    img = np.full((240, 320, 3), FLOOR, np.uint8)
    img[:wall_foot] = WALL
    img[150:160, 100:300] = band
    img[141:147, 100:300] = above
    img[163:169, 100:300] = below
    return img


def test_the_seamed_box_stands_on_its_foot() -> None:
    eh, ew = room_size_errors("photo", 3493, False, with_rig=False)
    assert eh < 0.03 and ew < 0.03


def test_without_the_rule_the_strip_refuses_it(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "BAND_ON_FLOOR", False)
    eh, _ = room_size_errors("photo", 3493, False, with_rig=False)
    assert eh > 0.1


def test_a_shade_on_the_floor() -> None:
    assert _band_on_floor(_scene(), BAND)


def test_a_skirting_has_the_wall_above() -> None:
    # the wall's foot at the band's top: the rows above it the wall's
    assert not _band_on_floor(_scene(above=WALL), BAND)


def test_the_floor_on_both_sides() -> None:
    assert not _band_on_floor(_scene(below=WALL), BAND)


@pytest.mark.parametrize(("grey", "on_floor"), [(108, True), (109, False)])
def test_the_colour_match(grey: int, on_floor: bool) -> None:
    # BAND_FLOOR_MATCH 8 (8-bit Lab: greys 108 and 109 are 8 and 9 over 100)
    assert _band_on_floor(_scene(above=grey), BAND) is on_floor
    assert _band_on_floor(_scene(below=grey), BAND) is on_floor


def test_the_strips_skip_the_bands_blur() -> None:
    # BAND_FLOOR_ROWS (3, 9): the 3 rows next to each edge are not read
    img = _scene()
    img[147:150, 100:300] = WALL
    img[160:163, 100:300] = WALL
    assert _band_on_floor(img, BAND)
    # the 6 rows read: the wall's over more than half of them is no floor
    img[143:147, 100:300] = WALL
    assert not _band_on_floor(img, BAND)


@pytest.mark.parametrize("side", ["above", "below"])
def test_the_strips_rows_exactly(side: str) -> None:
    # BAND_FLOOR_ROWS (3, 9): rows 141-146 read above the band, 163-168 below. The wall
    # on 70 % of the columns of the four inner rows read and on the rows just past each
    # end: 560 of the 1,200 pixels read are the wall's, the median the floor's; a row
    # more or fewer read at either end (a strip from 2 or 4, to 8 or 10) tips it.
    img = _scene()
    inner, outer = ((142, 146), (140, 147)) if side == "above" else ((164, 168), (162, 169))
    img[inner[0] : inner[1], 100:240] = WALL
    for row in outer:
        img[row, 100:300] = WALL
    assert _band_on_floor(img, BAND)


def test_the_foot_rows_exactly() -> None:
    # BAND_FLOOR_FOOT_ROWS 12: rows 228-239 read. The wall on 58 % of the columns of rows
    # 229-238 and on row 227: 1,160 of 2,400 pixels the wall's, the floor's colour read;
    # 11 rows read (1,160 of 2,200) or 13 (1,360 of 2,600) read the wall's.
    img = _scene()
    img[229:239, 100:216] = WALL
    img[227, 100:300] = WALL
    assert _band_on_floor(img, BAND)


def test_a_band_just_over_the_foot_rows() -> None:
    # its lower strip ends at row 227, just over the rows read for the floor: judged
    assert _band_on_floor(_scene(), (100.0, 209.0, 300.0, 219.0))


def test_the_floor_read_at_the_images_foot() -> None:
    # BAND_FLOOR_FOOT_ROWS 12: the rows 228-239; a band reaching down into them is kept
    img = _scene()
    img[228:240, 100:300] = WALL
    assert not _band_on_floor(img, BAND)
    img[228:229, 100:300] = FLOOR  # one row of 12 is not the median
    assert not _band_on_floor(img, BAND)
    img[:, :, :] = _scene()
    img[227:228, 100:300] = WALL  # the row above them is not read
    assert _band_on_floor(img, BAND)
    low = (100.0, 210.0, 300.0, 220.0)  # its lower strip reaches row 229
    assert not _band_on_floor(_scene(), low)


def test_a_grey_image_keeps_the_band() -> None:
    assert not _band_on_floor(_scene()[:, :, 0], BAND)
