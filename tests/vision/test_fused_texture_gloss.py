"""The texture rescue's walk up crosses a gloss's highlight (``texture.GLOSS_CROSSED``,
:func:`.texture._past_highlight`): a highlight is light added on the face, so its rows are
lighter than the face's foot while their detail (the |d/dx| and |d/dy| features) stays
the face's, and above it the face's texture comes back. Such rows are crossed where the
face's own texture resumes above them, over at most as many rows as the walk had climbed.

Photo 3213 (hard, the new5 rooms): a grey gloss face on grey gravel before a tripod,
found by its texture alone; the highlight's rows stand 0.8 grey units over the foot's,
their detail within 0.5 of it under a tolerance of 0.63: the walk stopped under the
highlight, height -54 % with the rig (-52 % without); past it -11 % (the texture's window
still blurs the top against the gravel).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import texture
from obstacle_fusion.vision.measure import Measurer

from tests.vision_fixtures import room_size_errors

TOL = 0.6
GAP = 3  # the walk's own gaps (rows)


def test_the_walk_crosses_the_highlight() -> None:
    eh, _ = room_size_errors("photo", 3213, True)
    assert eh < 0.15
    eh, _ = room_size_errors("photo", 3213, True, with_rig=False)
    assert eh < 0.15


def test_without_the_rule_the_walk_stops_under_it(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(texture, "GLOSS_CROSSED", False)
    eh, _ = room_size_errors("photo", 3213, True)
    assert eh > 0.4


def _column(
    face: int, lit: int, above: int, lit_row: tuple[float, float, float] = (0.3, 0.2, 0.8)
) -> tuple[npt.NDArray[np.float32], list[bool], int, int]:
    """Rows' features less the face's, walked up from the last row: ``face`` rows of the
    face's texture over the foot, ``lit`` rows of a highlight (``lit_row``), ``above``
    rows of the face again, then 10 rows of the background (detail 2.0 off). Returns the
    differences, the rows of the face's texture, the walk's start and its end."""
    rows = [(2.0, 2.0, 0.0)] * 10 + [(0.1, 0.1, 0.1)] * above + [lit_row] * lit
    rows += [(0.1, 0.1, 0.1)] * face
    diff = np.array(rows, np.float32)
    on = (np.linalg.norm(diff, axis=1) <= TOL).tolist()
    start = len(rows) - 1
    top = start
    while top - 1 >= 0 and on[top - 1]:
        top -= 1
    return diff, on, start, top


def test_the_top_above_the_highlight() -> None:
    diff, on, start, top = _column(face=20, lit=15, above=5)
    assert top == 30  # the walk stopped under the highlight
    assert texture._past_highlight(diff, on, TOL, start, top, GAP) == 10


def test_no_more_highlight_than_face_walked() -> None:
    # 20 rows of the face walked (start - top = 19 after the first row): a highlight of 19
    # rows is crossed, one of 20 not
    diff, on, start, top = _column(face=20, lit=19, above=5)
    assert start - top == 19
    assert texture._past_highlight(diff, on, TOL, start, top, GAP) == 10
    diff, on, start, top = _column(face=20, lit=20, above=5)
    assert texture._past_highlight(diff, on, TOL, start, top, GAP) == top


def test_a_highlight_up_to_the_top_is_no_face_above() -> None:
    # no face's texture above the light rows: the walk ends where it stopped
    diff, on, start, top = _column(face=20, lit=10, above=0)
    assert texture._past_highlight(diff, on, TOL, start, top, GAP) == top


def test_darker_rows_are_no_highlight() -> None:
    diff, on, start, top = _column(face=20, lit=10, above=5, lit_row=(0.3, 0.2, -0.8))
    assert texture._past_highlight(diff, on, TOL, start, top, GAP) == top


def test_the_detail_stays_the_face_s() -> None:
    # detail at the tolerance: a highlight; past it: another texture
    diff, on, start, top = _column(face=20, lit=10, above=5, lit_row=(0.6, 0.0, 0.8))
    assert texture._past_highlight(diff, on, TOL, start, top, GAP) == 10
    diff, on, start, top = _column(face=20, lit=10, above=5, lit_row=(0.61, 0.0, 0.8))
    assert texture._past_highlight(diff, on, TOL, start, top, GAP) == top


def test_the_face_s_shade_comes_back_above(monkeypatch: pytest.MonkeyPatch) -> None:
    # rows lighter by 0.8 crossed: the face above them within half of that (0.4) or not
    diff, on, start, top = _column(face=20, lit=10, above=5)
    diff[10:15, 2] = 0.4
    assert texture._past_highlight(diff, on, TOL, start, top, GAP) == 10
    diff[10:15, 2] = 0.41
    assert texture._past_highlight(diff, on, TOL, start, top, GAP) == top
    monkeypatch.setattr(texture, "GLOSS_FALL_SHARE", 0.6)
    assert texture._past_highlight(diff, on, TOL, start, top, GAP) == 10


def test_a_poster_s_light_part_is_no_highlight(monkeypatch: pytest.MonkeyPatch) -> None:
    # photo/2085 hard with no rig: the face is refused (doubted on every count); with any
    # light part crossed, the walk carried up a poster's lighter part (+94 %)
    cam = CameraModel.paper(500, 375)
    image, truth, _ = render_room("photo", 2085, True, cam)
    assert not Measurer(cam, None).measure(image, truth["range_m"]).detected
    monkeypatch.setattr(texture, "GLOSS_FALL_SHARE", 1.0)
    assert Measurer(cam, None).measure(image, truth["range_m"]).detected


def _rows(
    *runs: tuple[int, tuple[float, float, float]],
) -> tuple[npt.NDArray[np.float32], list[bool]]:
    """A column from the top down: (rows, features less the face's) runs."""
    diff = np.array([f for n, f in runs for _ in range(n)], np.float32)
    return diff, (np.linalg.norm(diff, axis=1) <= TOL).tolist()


FACE = (0.1, 0.1, 0.1)
LIT = (0.3, 0.2, 0.8)


def test_a_walk_ending_in_light_rows_steps_down_to_the_face() -> None:
    # light rows over the face's texture over a highlight over the face: the top is the
    # face's texture's, not the light rows' over it
    diff, on = _rows((10, (2.0, 2.0, 0.0)), (3, LIT), (5, FACE), (5, LIT), (20, FACE))
    start, top = len(on) - 1, 23
    assert on[top] and not on[top - 1]
    assert texture._past_highlight(diff, on, TOL, start, top, GAP) == 13


def test_the_rise_is_the_light_rows_own() -> None:
    # a bright row of other detail bridged inside the highlight (its grey 2.0 over the
    # foot's) sets no rise: the face above at 0.5 is over half of the light rows' 0.8
    runs = [(10, (2.0, 2.0, 0.0)), (5, (0.1, 0.1, 0.5)), (2, LIT), (1, (0.7, 0.0, 2.0))]
    diff, on = _rows(*runs, (2, LIT), (20, FACE))
    start, top = len(on) - 1, 20
    assert texture._past_highlight(diff, on, TOL, start, top, GAP) == top
    diff[17, 2] = 0.8  # the bridged row no brighter than the highlight: nothing changes
    assert texture._past_highlight(diff, on, TOL, start, top, GAP) == top
    diff[10:15, 2] = 0.4  # the face's shade back within half of 0.8: crossed
    assert texture._past_highlight(diff, on, TOL, start, top, GAP) == 10
