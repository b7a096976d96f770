"""The colour rescue's top past a band's edge behind the face
(:func:`~obstacle_fusion.vision.fused.region.raise_top_past_band`): a face standing in front
of a skirting steps far from the band beside its sides and little from the wall above it;
the walks up stop at the band's edge, though the face's own colour goes on (room
procedural/1113, with the rig: the rescue's top at the band's edge, height -43 %)."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import method as method_mod
from obstacle_fusion.vision.fused import region
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import View

H, W = 240, 320
BOTTOM, LEFT, RIGHT = 200, 100, 220
BAND_TOP = 170  # the skirting's top edge: rows 170..199 beside the face
DEPTH = 1.0
WALL = (100, 138, 120)  # BGR: a greyish green
FACE = (110, 148, 142)  # the face: about 12 Lab from the wall
BAND = (156, 30, 36)  # a blue skirting
FLOOR = (120, 80, 130)


def _view() -> View:
    k = np.array([[300.0, 0.0, W / 2], [0.0, 300.0, H / 2], [0.0, 0.0, 1.0]])
    return View(CameraModel(k, np.zeros(5), W, H), Rig(), "level")


def _scene(
    top: int,
    band: bool = True,
    *,
    wall: tuple[int, int, int] = WALL,
    face: tuple[int, int, int] = FACE,
    skirting: tuple[int, int, int] = BAND,
    right_band: bool = True,
) -> npt.NDArray[np.uint8]:
    """The wall, a skirting below BAND_TOP (``band``: else the wall down to the floor;
    ``right_band``: else on the face's left only), the floor below BOTTOM, the face from
    ``top`` to BOTTOM in front of them."""
    img = np.empty((H, W, 3), np.float64)
    img[:] = wall
    if band:
        img[BAND_TOP:BOTTOM, : (W if right_band else LEFT)] = skirting
    img[BOTTOM:] = FLOOR
    img[top:BOTTOM, LEFT:RIGHT] = face
    img += np.random.default_rng(0).normal(0, 2.0, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def _ay(img: npt.NDArray[np.uint8]) -> npt.NDArray[np.float32]:
    grey = img.mean(axis=2)
    ay = np.zeros(grey.shape, np.float32)
    ay[1:-1] = np.abs(grey[2:] - grey[:-2])
    return ay


def _raised(img: npt.NDArray[np.uint8], top: int) -> int:
    return region.raise_top_past_band(img, _view(), _ay(img), BOTTOM, top, LEFT, RIGHT, DEPTH)


def test_a_top_at_the_skirtings_edge_is_carried_up_to_the_face_s() -> None:
    img = _scene(120)
    assert abs(_raised(img, BAND_TOP) - 120) <= 2


def test_a_face_ending_at_the_skirtings_edge_keeps_its_top() -> None:
    """Above the band the wall lies between the sides too: no step beside."""
    img = _scene(BAND_TOP)
    assert _raised(img, BAND_TOP) == BAND_TOP


def test_no_band_edge_beside_the_top_no_move() -> None:
    """The same top with the wall beside it down to the floor: the walks' own stop is
    left alone (no change of background beside both sides at that row)."""
    img = _scene(120, band=False)
    assert _raised(img, BAND_TOP) == BAND_TOP


def _grey_step(colour: tuple[int, int, int], step: int) -> tuple[int, int, int]:
    """``colour`` lighter by ``step`` in each channel (about ``step`` Lab of lightness)."""
    b, g, r = colour
    return (b + step, g + step, r + step)


@pytest.mark.parametrize("step, carried", [(-16, False), (-24, True)])
def test_the_band_s_edge_steps_at_least_band_edge_step(step: int, carried: bool) -> None:
    """A skirting darker than the wall by about 16 Lab is no band's edge (BAND_EDGE_STEP 20
    Lab), one by about 24 is."""
    assert 16 < region.BAND_EDGE_STEP < 24
    img = _scene(120, skirting=_grey_step(WALL, step))
    raised = _raised(img, BAND_TOP)
    assert abs(raised - 120) <= 2 if carried else raised == BAND_TOP


@pytest.mark.parametrize("offset, carried", [(-2, True), (2, True), (5, False)])
def test_the_band_s_edge_lies_within_band_edge_rows_of_the_top(offset: int, carried: bool) -> None:
    """The rows compared beside the sides are BAND_EDGE_ROWS (2-6) above and below the top:
    a top 2 rows off the band's edge either way is at it, one 5 rows under it (the rows
    above it half band, half wall) is not."""
    img = _scene(120)
    raised = _raised(img, BAND_TOP + offset)
    assert abs(raised - 120) <= 2 if carried else raised == BAND_TOP + offset


def test_a_band_beside_one_side_only_is_no_band_s_edge() -> None:
    """The background must change at the top beside both sides: a step beside one side only
    (a cupboard's foot beside the face) carries nothing."""
    img = _scene(120, right_band=False)
    assert _raised(img, BAND_TOP) == BAND_TOP


@pytest.mark.parametrize("step, carried", [(4, False), (8, True)])
def test_the_face_differs_from_the_wall_beside_it_by_min_top_distance(
    step: int, carried: bool
) -> None:
    """The face above the band is carried where it differs from the wall beside both sides
    by MIN_TOP_DISTANCE (6 Lab): at about 8 Lab it is, at about 4 it is the wall's shade."""
    assert 4 < region.MIN_TOP_DISTANCE < 8
    img = _scene(120, face=_grey_step(WALL, step))
    raised = _raised(img, BAND_TOP)
    assert abs(raised - 120) <= 2 if carried else raised == BAND_TOP


def test_a_wall_of_the_face_s_colour_above_the_band_carries_nothing() -> None:
    """The face ends at the band's edge and the wall above the band has the face's colour:
    between the sides the face's colour goes on, but so it does beside them (no face)."""
    img = _scene(BAND_TOP, wall=FACE)
    assert _raised(img, BAND_TOP) == BAND_TOP


@pytest.mark.parametrize("side", ["left", "right"])
def test_a_wall_of_the_face_s_colour_beside_one_side_carries_nothing(side: str) -> None:
    """The face ends at the band's edge; above the band the wall is of the face's colour
    between its sides and beside one of them, another beside the other: the face's colour
    must differ from what is beside both sides."""
    img = _scene(BAND_TOP)
    if side == "right":
        img[:BAND_TOP, LEFT:] = FACE
    else:
        img[:BAND_TOP, :RIGHT] = FACE
    assert _raised(img, BAND_TOP) == BAND_TOP


def test_the_walk_stops_where_the_face_s_colour_ends() -> None:
    """Above the face's top (row 120) something of another colour stands between its sides
    (rows 80-120: about 18 Lab from the face, 28 from the wall beside it): it differs from
    the wall beside, but it is not the face's colour (within its spread)."""
    img = _scene(120)
    img[80:120, LEFT:RIGHT] = (90, 150, 170)
    assert abs(_raised(img, BAND_TOP) - 120) <= 2


@pytest.mark.parametrize("rows, crossed", [(4, True), (12, False)])
def test_a_stripe_across_the_face_is_crossed_up_to_max_row_gap(rows: int, crossed: bool) -> None:
    """A stripe of the wall's colour across the face above the band (from row 145 up) is
    crossed when it is at most MAX_ROW_GAP_M tall (6 rows at 300 px and 1 m), not when
    it is 12 rows tall: the walk then ends under it."""
    gap = round(300 * region.MAX_ROW_GAP_M / DEPTH)
    assert (rows <= gap) is crossed
    img = _scene(120)
    img[145 - rows : 145, LEFT:RIGHT] = WALL
    raised = _raised(img, BAND_TOP)
    assert abs(raised - 120) <= 2 if crossed else 145 - 3 <= raised < BAND_TOP


@pytest.mark.parametrize("switch", [True, False])
def test_a_face_before_a_skirting_is_measured_to_its_top(
    switch: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Room procedural/1113, ordinary, with the rig (a fresh seed): the colour rescue's top
    stopped at the skirting's edge behind the face (height -43 %); carried past it
    (method.SKIRTING_WALK) the height is within 10 %. Without it the face's own seams
    (method.SEAMS_RAISE_TOP) raise the edge search's top to the same row: that rule is off
    too when this one is."""
    monkeypatch.setattr(method_mod, "SKIRTING_WALK", switch)
    monkeypatch.setattr(method_mod, "SEAMS_RAISE_TOP", switch)
    # (and the far share off the beam's axis, method.FAR_OFF_AXIS, which finds it alone)
    monkeypatch.setattr(method_mod, "FAR_OFF_AXIS", switch)
    cam = CameraModel.paper(500, 375)
    image, truth, spec = render_room("procedural", 1113, False, cam)
    res = Measurer(cam, spec.rig).measure(image, truth["range_m"])
    assert res.detected and res.height_m is not None
    error = abs(res.height_m / truth["height_m"] - 1)
    assert error <= 0.10 if switch else error > 0.3


def test_a_carried_top_does_not_outbid_the_search_s_rows() -> None:
    """Room procedural/333, hard, no rig (tuning seed): a top carried past a band's edge up
    to a tape's lower edge took the rescue's confidence of that top alone and outbid the
    right rows of the no-rig search (height -36 %); the lesser of the two tops'
    agreements leaves the answer within 10 %."""
    assert method_mod.SKIRTING_WALK
    cam = CameraModel.paper(500, 375)
    image, truth, _ = render_room("procedural", 333, True, cam)
    res = Measurer(cam, None).measure(image, truth["range_m"])
    assert res.detected and res.height_m is not None
    assert abs(res.height_m / truth["height_m"] - 1) <= 0.10
