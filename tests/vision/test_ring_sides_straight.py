"""A print's margin is the face's own surface round it, a rectangle's band: its outer edge
is a straight, upright side of the face, so each side's margin is as wide at the print's
upper or lower rows as at its middle (``region.RING_SIDES_STRAIGHT``,
``region._ring_sides_straight``, in ``region.enclose_by_ring``): each side with a margin at
the middle must end within ``RING_SIDE_SLACK`` (3) columns of it at one of the two other
bands (``RING_SIDE_BAND_AT``, 0.25 of the print's height from its top and its foot); at the
other band anything goes (no margin seen, a run on, an end elsewhere). A "margin" that is
the room seen over and beside a plain face (the background's colour, ending on whatever
clutter stands beside the face at the middle rows) ends at other columns at other heights,
or runs on.

The room is a diagnosis room (new6), measured with the rig. Photo 3279 (ordinary): a grey-
blue seamed face on gravel before a photographed asphalt yard, an orange can left of it and
a tripod's pole right of it; the colour rescue finds the face whole (231-295), and the ring
read the asphalt over it and beside it, ending on the can and the pole 20 columns out, as a
margin: +66.6 % wide at 0.40. With the rule the face stays: +0.9 %.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import region

from tests.vision.test_fused_region import (
    BOTTOM,
    FACE,
    NARROW,
    PRINT,
    THIN,
    TOP,
    ring,
    thin_framed_scene,
)
from tests.vision_fixtures import room_size_errors


def test_the_room_is_measured_as_the_face() -> None:
    eh, ew = room_size_errors("photo", 3279, False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_rule_the_room_is_taken_for_a_margin(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "RING_SIDES_STRAIGHT", False)
    eh, ew = room_size_errors("photo", 3279, False)
    assert ew > 0.5


def test_a_thin_framed_print_photo_339_is_still_enclosed() -> None:
    # a brick print in a thin green margin, its left edge blurred wider at its lower rows
    # (the margin not seen past it there: a run of 0, no evidence either way)
    eh, ew = room_size_errors("photo", 339, False)
    assert eh < 0.08 and ew < 0.03


#: The print's rows as ring() reads them, and the upper and lower bands' centre rows (a
#: quarter of the print's height down from its top and up from its foot: the published
#: RING_SIDE_BAND_AT, written out so that the tests pin it; a tenth of its height either
#: side), as enclose_by_ring reads them.
P_TOP, P_BOTTOM = TOP + THIN["top"], BOTTOM - THIN["bottom"]
P_LEFT, P_RIGHT = NARROW[0] + THIN["left"], NARROW[1] - THIN["right"]
UPPER = P_TOP + int(0.25 * (P_BOTTOM - P_TOP))
LOWER = P_TOP + int(0.75 * (P_BOTTOM - P_TOP))
Q_V = (P_BOTTOM - P_TOP) // 10
BACKGROUND = (200, 120, 40)  # the room beside the face in thin_framed_scene


def _notched(wider: int) -> npt.NDArray[np.uint8]:
    """The thin frame with its left margin ``wider`` columns wider over the print's upper
    rows (down to just past the upper band) and its lower ones (from just over the lower
    band): its outer edge at the middle rows alone as drawn."""
    img = thin_framed_scene()
    img[TOP : UPPER + Q_V + 2, NARROW[0] - wider : NARROW[0]] = FACE
    img[LOWER - Q_V - 2 : BOTTOM, NARROW[0] - wider : NARROW[0]] = FACE
    return img


def test_a_straight_frame_is_enclosed() -> None:
    found = ring(thin_framed_scene())
    assert found is not None and abs(found[2] - NARROW[0]) <= 1


@pytest.mark.parametrize(("wider", "enclosed"), [(3, True), (4, False)])
def test_the_slack_of_a_sides_margin(wider: int, enclosed: bool) -> None:
    # RING_SIDE_SLACK (3) written out: a notch of 3 columns is a blurred edge, of 4 no side
    assert (ring(_notched(wider)) is not None) is enclosed


def test_without_the_rule_a_notched_margin_is_enclosed(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "RING_SIDES_STRAIGHT", False)
    assert ring(_notched(region.RING_SIDE_SLACK + 6)) is not None


def test_a_margin_not_seen_at_the_lower_rows_is_no_evidence() -> None:
    # the print's colour out to the face's left side over its lower rows: no margin there
    img = thin_framed_scene()
    img[LOWER - Q_V - 2 : P_BOTTOM, NARROW[0] : P_LEFT] = PRINT
    assert ring(img) is not None


def test_a_margin_seen_only_at_the_middle_is_no_frame() -> None:
    # ... and none at its upper rows either: the left margin's edge is seen nowhere else
    img = thin_framed_scene()
    img[P_TOP:P_BOTTOM, NARROW[0] : P_LEFT] = PRINT
    img[
        P_TOP + (P_BOTTOM - P_TOP) // 2 - Q_V - 2 : P_TOP + (P_BOTTOM - P_TOP) // 2 + Q_V + 2,
        NARROW[0] : P_LEFT,
    ] = FACE
    assert ring(img) is None


def test_a_background_band_ending_at_another_column_is_no_evidence() -> None:
    # procedural 2041: a green wall beside the green frame's upper right rows, ending 18
    # columns out: the lower band still shows the frame's edge
    img = thin_framed_scene()
    _band_beside(img, UPPER, slice(NARROW[0] - 15, NARROW[0]))
    assert ring(img) is not None


def _band_beside(img: npt.NDArray[np.uint8], centre: int, columns: slice) -> None:
    """The margin's colour run on through ``columns`` beside the band of rows at
    ``centre`` (a background of nearly its colour there: a skirting, a wall)."""
    img[centre - Q_V - 2 : centre + Q_V + 2, columns] = FACE


def test_a_margin_running_on_at_one_band_is_still_a_frame() -> None:
    # procedural 143 ordinary (no rig): a purple frame whose colour the blue skirting
    # beside its lower rows continues: no end there, the upper band confirms both sides
    img = thin_framed_scene()
    _band_beside(img, LOWER, slice(0, NARROW[0]))
    assert ring(img) is not None


def test_a_margin_seen_at_no_other_band_is_no_frame() -> None:
    # the left margin's colour runs on beside both the upper and the lower rows: its
    # outer edge shows only at the middle rows (clutter ending the room's colour there)
    img = thin_framed_scene()
    _band_beside(img, UPPER, slice(0, NARROW[0]))
    _band_beside(img, LOWER, slice(0, NARROW[0]))
    assert ring(img) is None


def test_a_side_with_a_run_of_one_asks_for_nothing() -> None:
    # the right margin one column wider (a run of 1 at the middle, under RING_MIN) runs on
    # beside the upper and the lower rows: still no margin read there, nothing asked
    img = thin_framed_scene()
    img[TOP:BOTTOM, NARROW[1] : NARROW[1] + 1] = FACE
    _band_beside(img, UPPER, slice(P_RIGHT, None))
    _band_beside(img, LOWER, slice(P_RIGHT, None))
    assert ring(img) is not None


def test_a_margin_of_two_running_on_at_both_bands_is_no_frame() -> None:
    # the left margin one column narrower (a run of 2 at the middle: RING_MIN, a margin
    # that asks) runs on beside both other bands: no end seen there (a run of -1, which
    # is no end 3 columns from 2)
    img = thin_framed_scene()
    img[TOP:BOTTOM, NARROW[0] : NARROW[0] + 1] = BACKGROUND
    assert ring(img) is not None  # straight, it is a frame
    _band_beside(img, UPPER, slice(0, NARROW[0] + 1))
    _band_beside(img, LOWER, slice(0, NARROW[0] + 1))
    assert ring(img) is None


def test_a_side_with_no_margin_asks_for_nothing() -> None:
    # the right margin (one column: no run past the print's blur at the middle) may run
    # on beside the upper rows (it was never read as a margin)
    img = thin_framed_scene()
    _band_beside(img, UPPER, slice(P_RIGHT, None))
    assert ring(img) is not None


def _notched_at_bands(wider: int) -> npt.NDArray[np.uint8]:
    """The thin frame with its left margin ``wider`` columns wider over 15 of the 21 rows
    of each of the upper and the lower band (their first, middle and last five): over
    most of a band read at a quarter of the print's height, over 10 of the 21 rows of one
    read 5 rows off (a twentieth of the print's height), either way."""
    img = thin_framed_scene()
    assert Q_V == 10
    for centre in (UPPER, LOWER):
        for first in (centre - Q_V, centre - 2, centre + Q_V - 4):
            img[first : first + 5, NARROW[0] - wider : NARROW[0]] = FACE
    return img


@pytest.mark.parametrize("at", [0.2, 0.3])
def test_the_bands_are_read_a_quarter_in(monkeypatch: pytest.MonkeyPatch, at: float) -> None:
    # RING_SIDE_BAND_AT one step (0.05) either way reads past the notches: straight
    img = _notched_at_bands(region.RING_SIDE_SLACK + 6)
    assert ring(img) is None
    monkeypatch.setattr(region, "RING_SIDE_BAND_AT", at)
    assert ring(img) is not None


def test_the_bands_are_read_where_the_share_puts_them(monkeypatch: pytest.MonkeyPatch) -> None:
    # the notch reaches just past the upper and the lower band: bands read nearer the
    # middle do not see it
    img = _notched(region.RING_SIDE_SLACK + 6)
    assert ring(img) is None
    monkeypatch.setattr(region, "RING_SIDE_BAND_AT", region.RING_SIDE_BAND_AT + 0.15)
    assert ring(img) is not None
