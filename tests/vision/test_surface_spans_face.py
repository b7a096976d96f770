"""The face's surface, read down from a top found too high, starts on a row whose colour
spans the face: the face's own colour in the middle, or in the strips just inside both
sides (a print in a margin); one strip alone in the face's colour is what stands beside
that side (``region.SURFACE_SPANS_FACE``, in ``region.lower_top_to_surface``).

Photo 3311 (hard, new7), with the rig: a teal plank face (0.21 m at 1.2 m) before a
photographed launch pad; the top was taken 25 rows up the pad (+35 %). The rows between
are the pad's, but the strip just inside the left side held the face's colour for three
rows right under the top (the pad's shade beside that side), which started the surface
there and kept the top. With the rule the top comes down to the face's (+1.0 %). Only
on a face of one colour (the least spread in each part): on a print a strip alone may
be the print's own colour (photo 3334 hard, a poster: a pair inside the print lowered
onto the print's lower part, then grown back round it 11 % low at confidence 0.88).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import region

from tests.vision.test_fused_region import BOTTOM, FACE, LEFT, RIGHT, TOP
from tests.vision.test_fused_surface_up_to_top import POLE_TOP, drawn, lowered
from tests.vision_fixtures import measured_room, room_size_errors

#: the columns the strips just inside the sides read, and the middle between them
SKIP, BESIDE = region.SIDE_SKIP, region.BESIDE_COLUMNS
LEFT_STRIP = (LEFT, LEFT + SKIP + BESIDE)
RIGHT_STRIP = (RIGHT - SKIP - BESIDE + 1, RIGHT)
MIDDLE = (LEFT + SKIP + BESIDE, RIGHT - SKIP - BESIDE + 1)
ROWS = 4  # rows of the face's colour right under the top found (a run is 3)


def painted(
    *spans: tuple[int, int],
    rows: int = ROWS,
    print_: bool = False,
    shade: int = 30,
    print_cols: tuple[int, int] = (LEFT, RIGHT),
) -> npt.NDArray[np.uint8]:
    """The pole over the face (``drawn``), its first ``rows`` rows in the face's colour
    over the columns ``spans``; ``print_``: the face's rows over the columns
    ``print_cols`` in two shades by turns, ``shade`` apart (a print's colours changing
    row by row)."""
    img = drawn()
    if print_:
        c0, c1 = print_cols
        for r in range(TOP, BOTTOM):
            if (r // 2) % 2:
                img[r, c0:c1] = np.clip(img[r, c0:c1].astype(np.int16) + shade, 0, 255)
    for c0, c1 in spans:
        img[POLE_TOP : POLE_TOP + rows, c0:c1] = FACE
    return img


def test_one_strip_alone_starts_no_surface(monkeypatch: pytest.MonkeyPatch) -> None:
    for strip in (LEFT_STRIP, RIGHT_STRIP):
        assert abs(lowered(painted(strip)) - TOP) <= 1
        monkeypatch.setattr(region, "SURFACE_SPANS_FACE", False)
        assert lowered(painted(strip)) == POLE_TOP
        monkeypatch.setattr(region, "SURFACE_SPANS_FACE", True)


def test_on_a_print_one_strip_still_starts_the_surface(monkeypatch: pytest.MonkeyPatch) -> None:
    # the face's rows change shade by turns: its colour spreads past the least limit, and
    # a strip alone in it is read as the face's, as without the rule
    assert lowered(painted(LEFT_STRIP, print_=True)) == POLE_TOP
    monkeypatch.setattr(region, "SURFACE_SPANS_FACE", False)
    assert lowered(painted(LEFT_STRIP, print_=True)) == POLE_TOP
    # and the print alone, no strip painted, comes down to the face as ever
    assert abs(lowered(painted(print_=True)) - TOP) <= 1


def test_a_print_just_past_the_least_is_read_as_before() -> None:
    # a faint print, its two shades 12 apart: the parts' limits just past the least
    # (18.1-18.2 against MIN_FACE_DISTANCE 18), no face of one colour, and a strip alone
    # starts the surface as without the rule; 11 apart they stay at the least (a face of
    # one colour faintly banded) and a strip alone starts none
    assert lowered(painted(LEFT_STRIP, print_=True, shade=12)) == POLE_TOP
    assert abs(lowered(painted(LEFT_STRIP, print_=True, shade=11)) - TOP) <= 1


def test_a_print_in_one_part_is_no_face_of_one_colour() -> None:
    # a print over the middle and the left strip, the right strip plain: the largest
    # spread decides, the face is no face of one colour, and the right strip alone in the
    # face's colour starts the surface as without the rule
    cols = (LEFT, MIDDLE[1])
    assert lowered(painted(RIGHT_STRIP, print_=True, print_cols=cols)) == POLE_TOP


def test_one_strip_alone_keeps_no_rows_the_faces(monkeypatch: pytest.MonkeyPatch) -> None:
    # the left strip in the face's colour on every third row of the pole (never a run):
    # without the rule those rows are the face's, the rows over the face's top are under
    # SURFACE_FOREIGN_SHARE foreign (2 in 3) and the top stays on the pole; with it they
    # are foreign and the top comes down
    img = drawn()
    img[POLE_TOP:TOP:3, LEFT_STRIP[0] : LEFT_STRIP[1]] = FACE
    assert abs(lowered(img) - TOP) <= 1
    monkeypatch.setattr(region, "SURFACE_SPANS_FACE", False)
    assert lowered(img) == POLE_TOP


def test_the_print_room_gives_no_sure_wrong_answer() -> None:
    # photo 3334 hard: the poster's pair (inside the print) keeps its top, -33 / -44 % at
    # confidence 0.29 (unsure); with the strict reading on every face it came down onto
    # the print's lower part and the face grown round it was 11 % low at confidence 0.88
    # (a sure wrong answer)
    res, truth = measured_room("photo", 3334, True)
    assert res.detected and res.height_m is not None and res.width_m is not None
    off = max(abs(res.height_m / truth["height_m"] - 1), abs(res.width_m / truth["width_m"] - 1))
    assert res.confidence is not None
    assert res.confidence < 0.5 or off <= 0.05


def test_both_strips_start_the_surface() -> None:
    # a margin of the face's colour round a print: the face's surface
    assert lowered(painted(LEFT_STRIP, RIGHT_STRIP)) == POLE_TOP


def test_the_middle_starts_the_surface() -> None:
    assert lowered(painted(MIDDLE)) == POLE_TOP


def test_both_strips_together_for_a_run() -> None:
    # the left strip's colour over ROWS rows, the right's over fewer: the rows both hold
    # it make the run (SURFACE_RUN_ROWS of them start the surface)
    run = region.SURFACE_RUN_ROWS
    img = painted(LEFT_STRIP)
    img[POLE_TOP : POLE_TOP + run, RIGHT_STRIP[0] : RIGHT_STRIP[1]] = FACE
    assert lowered(img) == POLE_TOP
    img = painted(LEFT_STRIP)
    img[POLE_TOP : POLE_TOP + run - 1, RIGHT_STRIP[0] : RIGHT_STRIP[1]] = FACE
    assert abs(lowered(img) - TOP) <= 1


def test_the_plank_face_under_a_launch_pad() -> None:
    eh, ew = room_size_errors("photo", 3311, True)
    assert eh < 0.05 and ew < 0.05


def test_without_the_rule_the_top_stays_on_the_pad(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "SURFACE_SPANS_FACE", False)
    eh, _ = room_size_errors("photo", 3311, True)
    assert eh > 0.25
