"""With no rig, a sure face found on a higher floor-contact row that has the top and both
sides of an unsure face found on a lower row is that face's upper part, standing on a line
across it (a panel joint, a label's or a band's lower edge): the lower face is taken when
its sides run on below the line (``measure._same_outline``,
``floor_contact.sides_run_down``)."""

from __future__ import annotations

import numpy as np
import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.fused.confidence import FLOOR_IN_FACE
from obstacle_fusion.vision.fused.floor_contact import sides_run_down
from obstacle_fusion.vision.measure import Measurer, _same_outline

from tests.vision.test_fused_floor_foot import outline
from tests.vision.test_fused_stands_on_top import fake_two_readings
from tests.vision.test_rig_source_and_clipping import CAM, no_rig_room

# --- the outline test (_same_outline): OUTLINE_MATCH 6 % of the width, at least
# OUTLINE_MATCH_PX 3 px; the lower foot OUTLINE_MIN_DROP_PX 5 px lower or more

UPPER = (100.0, 100.0, 300.0, 160.0)  # a face 200 px wide (tolerance 12 px) on row 160
LOWER = (100.0, 100.0, 300.0, 240.0)  # the whole face, down to row 240


@pytest.mark.parametrize(
    "lower",
    [
        LOWER,
        (88.0, 100.0, 300.0, 240.0),  # left side 12 px out (6 % of 200)
        (100.0, 100.0, 312.0, 240.0),  # right side 12 px out
        (112.0, 100.0, 288.0, 240.0),  # both 12 px in
        (100.0, 88.0, 300.0, 240.0),  # top 12 px higher
        (100.0, 112.0, 300.0, 240.0),  # top 12 px lower
        (100.0, 100.0, 300.0, 165.0),  # foot 5 px lower
    ],
)
def test_a_lower_face_with_the_same_top_and_sides_is_the_whole_face(
    lower: tuple[float, float, float, float],
) -> None:
    assert _same_outline(UPPER, lower)


@pytest.mark.parametrize(
    "lower",
    [
        (87.0, 100.0, 300.0, 240.0),  # left side 13 px out
        (100.0, 100.0, 313.0, 240.0),  # right side 13 px out
        (113.0, 100.0, 300.0, 240.0),  # left side 13 px in
        (100.0, 100.0, 287.0, 240.0),  # right side 13 px in
        (87.0, 100.0, 313.0, 240.0),  # both 13 px out (the upper face's width sets 12 px)
        (100.0, 87.0, 300.0, 240.0),  # top 13 px higher (something above taken in)
        (100.0, 113.0, 300.0, 240.0),  # top 13 px lower
        (100.0, 100.0, 300.0, 164.0),  # foot 4 px lower: the same edge's blur
        (100.0, 100.0, 300.0, 150.0),  # foot higher
        None,
    ],
)
def test_a_lower_face_of_another_outline_is_another_face(
    lower: tuple[float, float, float, float] | None,
) -> None:
    assert not _same_outline(UPPER, lower)


def test_a_narrow_face_keeps_a_tolerance_of_3_px() -> None:
    """40 px wide: 6 % is 2.4 px, the floor of 3 px rules."""
    upper = (100.0, 100.0, 140.0, 160.0)
    assert _same_outline(upper, (97.0, 100.0, 143.0, 240.0))
    assert not _same_outline(upper, (96.5, 100.0, 140.0, 240.0))
    assert not _same_outline(upper, (100.0, 96.5, 140.0, 240.0))


# --- the sides run on below the higher reading's foot (sides_run_down)

FLOOR = 100  # grey of the floor, from row 150 down
FOOT_ROW = 200  # the face's foot on the floor
LINE_FOOT = 130.0  # the lower edge of a band across the face: the higher reading's foot
DARK = (40, 40, 40)


def banded() -> np.ndarray:
    """A wall, a floor from row 150 down, a dark face (columns 100-199, rows 60-199) with a
    light band across it on rows 115-129 (its lower edge a step a row search finds)."""
    img = np.full((300, 300, 3), 180, np.uint8)
    img[150:] = FLOOR
    img[60:FOOT_ROW, 100:200] = DARK
    img[115:130, 100:200] = 230
    return img


def test_a_face_whose_sides_run_on_below_a_band_runs_down() -> None:
    assert sides_run_down(banded(), outline(FOOT_ROW), LINE_FOOT)


def test_a_face_over_a_wide_shadow_does_not_run_down() -> None:
    """The box ends at the band's foot (rows 60-129); under it a shadow wider than the box
    down to row 199: at the box's columns the colour is one across each side there."""
    img = banded()
    img[int(LINE_FOOT) : FOOT_ROW, 60:240] = 70
    assert not sides_run_down(img, outline(FOOT_ROW), LINE_FOOT)


def test_the_sides_must_step_on_most_rows_between_the_feet() -> None:
    """RUN_DOWN_SHARE = 0.8 of the rows between the feet (3 px left out next to each):
    rows 133-197 are read (65 rows); the floor beside the left side of the face's own grey
    on 10 of them (85 % left) keeps the run, on 16 of them (75 % left) breaks it."""
    for rows, runs in ((10, True), (16, False)):
        img = banded()
        img[140 : 140 + rows, 90:100] = DARK
        assert sides_run_down(img, outline(FOOT_ROW), LINE_FOOT) is runs


def test_the_sides_stepping_on_exactly_the_share_of_the_rows_run_down() -> None:
    """At the limit: 13 of the 65 rows read without the step leave 52, 0.8 exactly (at
    least RUN_DOWN_SHARE runs on); 14 leave 51 (0.78)."""
    for rows, runs in ((13, True), (14, False)):
        img = banded()
        img[140 : 140 + rows, 90:100] = DARK
        assert sides_run_down(img, outline(FOOT_ROW), LINE_FOOT) is runs


def test_a_side_read_over_too_few_rows_is_no_run_whatever_the_other() -> None:
    """One side ending 8 rows below the higher foot (3 rows read) tells nothing of a face
    running down: no run, though the other side steps all the way down."""
    lines = outline(FOOT_ROW)
    lines[2] = (100.0, LINE_FOOT + 8.0, 100.0, 60.0)
    assert not sides_run_down(banded(), lines, LINE_FOOT)


def test_no_sides_given_is_no_run() -> None:
    assert not sides_run_down(banded(), [], LINE_FOOT)
    assert not sides_run_down(banded(), outline(FOOT_ROW)[:2], LINE_FOOT)


def test_a_side_at_the_border_is_left_to_the_other_and_none_read_is_no_run() -> None:
    img = banded()
    lines = outline(FOOT_ROW)
    lines[2] = (1.0, FOOT_ROW, 1.0, 60)
    assert sides_run_down(img, lines, LINE_FOOT)  # the right side runs on
    lines[3] = (298.0, FOOT_ROW, 298.0, 60)
    assert not sides_run_down(img, lines, LINE_FOOT)  # no side read


def test_too_short_a_way_down_tells_nothing() -> None:
    """Under 2 x RUN_UP_SKIP_PX (6) rows between the feet read (3 left out next to each
    foot): no run."""
    assert sides_run_down(banded(), outline(FOOT_ROW), FOOT_ROW - 11.0)  # rows 192-197
    assert not sides_run_down(banded(), outline(FOOT_ROW), FOOT_ROW - 10.0)  # 193-197


# --- the search: the lower face taken over its upper part


@pytest.mark.parametrize(
    "upper_in, low_fields, runs_down, expected",
    [
        (0.0, {}, True, 0.30),
        (0.0, {}, False, 0.20),  # its sides end at the line: another face below
        (0.0, {"doubts": [FLOOR_IN_FACE]}, True, 0.20),  # the lower face took floor in
        (30.0, {}, True, 0.20),  # the upper face's sides 30 px in: another outline
    ],
)
def test_with_no_rig_the_upper_part_of_a_face_gives_way_to_the_face(
    upper_in: float,
    low_fields: dict[str, object],
    runs_down: bool,
    expected: float,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The face is found, unsure, on the lower row; its upper part, sure, on the row of a
    line across it: the lower face is taken when the outlines match, its sides run on
    down to its foot and it took no floor in."""
    image, truth, view, depth = no_rig_room(4005)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (0.20, 0.30)}
    sure = {0.30: 0.1, 0.20: 0.9}
    top = row_at[0.20] - 60.0
    boxes = {
        0.30: (100.0, top, 300.0, float(row_at[0.30])),
        0.20: (100.0 + upper_in, top, 300.0 - upper_in, float(row_at[0.20])),
    }

    fake_two_readings(monkeypatch, truth, row_at, sure, boxes, low_fields)
    # the sides are read from the upper face's foot down to the lower face's
    monkeypatch.setattr(
        measure,
        "sides_run_down",
        lambda image, lines, upper_foot: runs_down and abs(upper_foot - row_at[0.20]) < 1.0,
    )
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.camera_height_m == pytest.approx(expected, abs=0.01)


@pytest.mark.parametrize(("seed", "rule_off_error"), [(1471, 0.5), (317, 0.3)])
def test_with_no_rig_a_face_with_a_line_across_it_is_measured_whole(
    seed: int, rule_off_error: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    """procedural 1471 / 317 hard: a line across the face stands its upper part on a
    higher row (h -58 % / -37 % before the rule), while the whole face, unsure, was found
    on the floor's row below; with the rule it is measured whole. With the rule off the
    error is back (the print's-line rule, which also takes 1471's whole face, off too)."""
    image, truth, _ = render_room("procedural", seed, True, CAM)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.height_m == pytest.approx(truth["height_m"], rel=0.1)
    assert res.width_m == pytest.approx(truth["width_m"], rel=0.1)
    monkeypatch.setattr(measure, "_same_outline", lambda *a: False)
    # the print's-line rule (PRINT_LINE_FOOT) reads 1471's lower face from its foot too:
    # the line across the face has the face's texture under it
    monkeypatch.setattr(measure, "PRINT_LINE_FOOT", False)
    # ... and so do the rows read as with a rig over a small unsure face (SMALL_FACE_GROWN)
    monkeypatch.setattr(measure, "SMALL_FACE_GROWN", False)
    off = Measurer(CAM, None).measure(image, truth["range_m"])
    assert off.detected and off.height_m is not None
    assert abs(off.height_m / truth["height_m"] - 1.0) > rule_off_error
