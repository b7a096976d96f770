"""The fused method's extent stage on drawn faces: seams, labels and prints do not shrink a face."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import extent, foot_outline, method, past_seam, region
from obstacle_fusion.vision.fused.extent import (
    enclose_inner_frame,
    raise_top_past_inner_edges,
    widen_across_seams,
)
from obstacle_fusion.vision.fused.profiles import walk_on

from tests.vision_fixtures import gradients, room_size_errors

H, W = 240, 320
TOP, BOTTOM, LEFT, RIGHT = 80, 200, 60, 260  # the drawn face


def room(seams: list[int] = (), rng_seed: int = 0) -> npt.NDArray[np.uint8]:
    """Wall above row 130, floor below; a face of planks of different shades and dark seams."""
    rng = np.random.default_rng(rng_seed)
    img = np.full((H, W), 170, np.float64)
    img[130:] = 90
    img[TOP:BOTTOM, LEFT:RIGHT] = 130
    edges = [LEFT, *seams, RIGHT]
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        img[TOP:BOTTOM, a:b] += rng.uniform(-12, 12)
    for s in seams:
        img[TOP:BOTTOM, s - 1 : s + 1] = 60
    img += rng.normal(0, 1.5, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def test_a_face_of_planks_is_widened_from_one_plank_to_its_sides() -> None:
    seams = [100, 140, 180, 220]
    ay, ax3, noise = gradients(room(seams))
    left, right = widen_across_seams(ay, ax3, BOTTOM, TOP, 140, 180, noise)
    assert abs(left - LEFT) <= 2 and abs(right - RIGHT) <= 2


def test_a_face_found_whole_keeps_its_sides() -> None:
    ay, ax3, noise = gradients(room([100, 140, 180, 220]))
    assert widen_across_seams(ay, ax3, BOTTOM, TOP, LEFT, RIGHT, noise) == (LEFT, RIGHT)


def test_edges_running_on_to_no_vertical_side_do_not_widen() -> None:
    """A shelf line and a floor seam on the face's rows, beyond it, end at nothing."""
    img = room([160]).astype(np.int16)
    img[TOP - 1 : TOP + 1, :] = 60  # a line across the whole image on the top row
    img[BOTTOM - 1 : BOTTOM + 1, :] = 60  # and on the floor-contact row
    img[:, :LEFT] = 150  # no side left of the face: all one shade
    ay, ax3, noise = gradients(np.clip(img, 0, 255).astype(np.uint8))
    left, _ = widen_across_seams(ay, ax3, BOTTOM, TOP, LEFT + 2, 160, noise)
    assert left == LEFT + 2


def test_the_walk_steps_over_gaps_up_to_its_limit() -> None:
    on = np.ones(40, bool)
    on[20 : 20 + extent.MAX_GAP] = False
    assert walk_on(on, 5, 1, extent.MAX_GAP) == 39
    assert walk_on(on[::-1], 34, -1, extent.MAX_GAP) == 0  # the other way
    on[20 : 20 + extent.MAX_GAP + 1] = False
    assert walk_on(on, 5, 1, extent.MAX_GAP) == 19


def test_a_label_across_the_face_does_not_become_its_top() -> None:
    img = room([]).astype(np.int16)
    img[150:170, LEFT:RIGHT] = 230  # a bright label across the lower face
    ay, ax3, noise = gradients(np.clip(img, 0, 255).astype(np.uint8))
    top = raise_top_past_inner_edges(ay, ax3, BOTTOM, 150, LEFT, RIGHT, noise)
    assert abs(top - TOP) <= 2


def test_a_top_with_the_sides_ending_there_stays() -> None:
    ay, ax3, noise = gradients(room([]))
    assert abs(raise_top_past_inner_edges(ay, ax3, BOTTOM, TOP, LEFT, RIGHT, noise) - TOP) <= 1


@pytest.mark.parametrize("margin", [8, 14])
def test_a_print_with_a_margin_is_enclosed_by_the_face(margin: int) -> None:
    img = room([]).astype(np.int16)
    p0, p1 = LEFT + margin, RIGHT - margin
    img[TOP + margin : BOTTOM - 3, p0:p1] = 40  # a dark print, its bottom near the floor
    ay, ax3, noise = gradients(np.clip(img, 0, 255).astype(np.uint8))
    left, right, top = enclose_inner_frame(ay, ax3, BOTTOM, TOP + margin, p0, p1, noise)
    assert abs(left - LEFT) <= 2 and abs(right - RIGHT) <= 2 and abs(top - TOP) <= 2


def test_a_face_standing_alone_is_not_enclosed_by_the_background() -> None:
    ay, ax3, noise = gradients(room([]))
    assert enclose_inner_frame(ay, ax3, BOTTOM, TOP, LEFT, RIGHT, noise) == (LEFT, RIGHT, TOP)


def two_shade_face(beside: str = "plain") -> npt.NDArray[np.uint8]:
    """A face of two planks: a light one the search finds, and a dark one whose top and
    foot edges are dim against the wall and floor (a fifth of the light one's), one seam
    between; ``beside`` "texture" fills the wall and floor beside the face with horizontal
    detail on every row (a textured floor or wall, no line of its own)."""
    rng = np.random.default_rng(3)
    img = np.full((H, W), 120.0)
    img[130:] = 100
    img[TOP:BOTTOM, LEFT:160] = 112  # the dark plank: 8 from the wall, 12 from the floor
    img[TOP:BOTTOM, 160:RIGHT] = 175  # the light plank
    img[TOP:BOTTOM, 158:160] = 60  # the seam
    img[TOP:BOTTOM, LEFT - 2 : LEFT] = 40  # the face's dark outer side
    if beside == "texture":
        stripes = 14.0 * ((np.arange(H) // 2) % 2)[:, None]
        outside = np.ones((H, W), bool)
        outside[TOP:BOTTOM, LEFT:RIGHT] = False
        img += np.where(outside, stripes, 0.0)
    img += rng.normal(0, 1.5, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def test_planks_of_another_shade_are_crossed_where_the_edges_stay_on_their_rows() -> None:
    """One surface at the sonar's depth: its top and foot are one row each across a plank
    of another shade, however dim they get there (photo/941: a face of dark and light
    planks measured as its light plank, -51 %)."""
    ay, ax3, noise = gradients(two_shade_face())
    left, right = widen_across_seams(ay, ax3, BOTTOM, TOP, 160, RIGHT, noise)
    assert abs(left - LEFT) <= 3 and right == RIGHT


def test_dim_edges_are_not_crossed_without_the_same_row_rule(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(extent, "SAME_ROW_EDGES", False)
    ay, ax3, noise = gradients(two_shade_face())
    left, _ = widen_across_seams(ay, ax3, BOTTOM, TOP, 160, RIGHT, noise)
    assert left >= 155


def test_detail_on_every_row_is_no_edge_on_the_faces_row() -> None:
    """Horizontal detail filling the rows above and below (a textured floor or wall) is
    as strong at the face's rows as a dim edge, but it is no line there."""
    ay, _, noise = gradients(two_shade_face("texture"))
    beside = slice(5, LEFT - 8)
    assert not extent._line_on_row(ay, BOTTOM, noise)[beside].any()
    assert not extent._line_on_row(ay, TOP, noise)[beside].any()
    ay, _, noise = gradients(two_shade_face())  # the dim plank's own edges are lines
    face = slice(LEFT + 5, 150)
    assert extent._line_on_row(ay, BOTTOM, noise)[face].mean() > 0.9
    assert extent._line_on_row(ay, TOP, noise)[face].mean() > 0.9


def lit_corner_face(gap: int = 0) -> npt.NDArray[np.uint8]:
    """Planks (seams at 100, 140, 180, 220) before a wall that is dark behind the first
    plank's left end: that plank's top edge is strong over 12 columns and three times
    fainter over the rest, uneven yet one line on the top row. ``gap``: columns of the
    first plank (from column 80) where the wall behind is the plank's own shade, so the
    top edge is no line there at all."""
    img = room([100, 140, 180, 220]).astype(np.int16)
    img[TOP - 30 : TOP, LEFT - 20 : LEFT + 12] = 30  # a dark structure behind one corner
    if gap:
        img[TOP - 30 : TOP, 80 : 80 + gap] = img[TOP + 10, 85]
    return np.clip(img, 0, 255).astype(np.uint8)


def test_an_uneven_top_edge_on_one_row_still_widens_the_face() -> None:
    """A top edge strong behind one corner only (photo/2143 ordinary: measured as its
    first plank, -75 % wide) is under EVEN_SHARE of its strong end along the plank, but
    one line on the face's row: the face's."""
    ay, ax3, noise = gradients(lit_corner_face())
    gt = extent._edge_profile(ay, TOP)[LEFT + 1 : 100]
    assert float(np.median(gt)) < extent.EVEN_SHARE * extent._p90(gt)  # uneven indeed
    left, right = widen_across_seams(ay, ax3, BOTTOM, TOP, LEFT, 100, noise)
    assert left == LEFT and abs(right - RIGHT) <= 2


def test_without_the_line_rule_an_uneven_top_edge_does_not_widen(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(extent, "UNEVEN_LINE_SHARE", 0.0)
    ay, ax3, noise = gradients(lit_corner_face())
    assert widen_across_seams(ay, ax3, BOTTOM, TOP, LEFT, 100, noise) == (LEFT, 100)


@pytest.mark.parametrize("gap, widened", [(4, True), (6, False)])
def test_an_uneven_edge_must_be_a_line_over_nine_tenths_of_the_face(
    gap: int, widened: bool
) -> None:
    """The first plank's top is a line over 39 columns less the break and its blur: a
    4-column break leaves it over 92 % of them (UNEVEN_LINE_SHARE 0.9 met), a 6-column
    one over 87 % (not met)."""
    ay, ax3, noise = gradients(lit_corner_face(gap))
    _, right = widen_across_seams(ay, ax3, BOTTOM, TOP, LEFT, 100, noise)
    assert (abs(right - RIGHT) <= 2) is widened


def test_a_plank_face_before_a_lit_structure_is_measured_whole() -> None:
    """photo/2143 ordinary (a fresh seed, not a tuning one): lilac planks before a lit
    gantry behind one corner; measured as its first plank (-75 % wide) before the rule."""
    eh, ew = room_size_errors("photo", 2143, False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_line_rule_the_plank_face_is_one_plank(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(extent, "UNEVEN_LINE_SHARE", 0.0)
    # the width read from the foot's sides (session 37) finds this face by itself
    monkeypatch.setattr(foot_outline, "WIDTH_FROM_FOOT", False)
    # and the far share off the beam's axis (method.FAR_OFF_AXIS) gives it the face too
    monkeypatch.setattr(method, "FAR_OFF_AXIS", False)
    # and so does crossing a plank's dark seam as a stripe (region.BRIDGE_STRIPES)
    monkeypatch.setattr(region, "BRIDGE_STRIPES", False)
    # and so does following the top and foot past the seam (past_seam.SIDES_PAST_SEAMS)
    monkeypatch.setattr(past_seam, "SIDES_PAST_SEAMS", False)
    _, ew = room_size_errors("photo", 2143, False)
    assert ew > 0.5
