"""A strip the foot's walk took in that shows, in the face's upper rows, what stands over
the face's top in the same columns is the background beside the face, even where what
lies beyond the walked side differs (`region.RISES_OVER_TOP`, `RISE_OVER_ROWS`): the
face's top edge parts its own columns from what is over them, beside the face nothing
does.

The room is a diagnosis room (new5). Photo 3216 (hard): a grey text print in a dark blue
frame before a dark sky, an orange can standing farther back to its left, the grey floor
in the box's shadow of the face's grey: the colour rescue found the face (222-271), the
walk along the foot from its top ran over the shadow to the can's edge (200), and the
rising check compared the strip (the sky) with the can beyond it, unlike it, so the side
stood: w +37 % with the rig and without; with the rule +1.4 / +1.5 %.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import region
from obstacle_fusion.vision.fused.profiles import median_of
from obstacle_fusion.vision.fused.region import _over_top_colour

from tests.vision.test_fused_region import BOTTOM, LEFT, RIGHT, TOP, H, W, level_view
from tests.vision.test_fused_rises_as_face import (
    SHADOW_COLUMNS,
    WALL,
    lab_shifted,
    shadow_scene,
    widen,
)
from tests.vision_fixtures import room_size_errors

CAN = (40, 140, 230)  # BGR: an orange can standing farther back beyond the shadow
CAN_COLUMNS = 30
CAN_FOOT = BOTTOM - 4  # its foot meets the floor higher up than the face's


def can_scene(over: tuple[int, int, int] = WALL, rng_seed: int = 5) -> npt.NDArray[np.uint8]:
    """:func:`shadow_scene` (a face, its shadow beside its right side, the wall above) with
    a can just beyond the shadow, its foot a few rows over the contact row; ``over``: the
    colour over the face's top in the shadow's columns (the wall's by default)."""
    img = shadow_scene(noise=0.0).astype(np.float64)
    c0 = RIGHT + SHADOW_COLUMNS
    img[:CAN_FOOT, c0 : c0 + CAN_COLUMNS] = CAN
    img[:TOP, RIGHT:c0] = over
    img += np.random.default_rng(rng_seed).normal(0, 2.0, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def test_without_the_rule_the_can_beyond_keeps_the_walks_side(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The scene is the failure: the walk runs over the shadow to the can; the strip's
    upper rows (the wall) are unlike the can beyond, so the side stands."""
    monkeypatch.setattr(region, "RISES_OVER_TOP", False)
    left, right = widen(can_scene(), LEFT, RIGHT, rises=True)
    assert left == LEFT and right >= RIGHT + SHADOW_COLUMNS - 3


def test_a_strip_showing_what_is_over_the_top_is_no_face() -> None:
    assert widen(can_scene(), LEFT, RIGHT, rises=True) == (LEFT, RIGHT)


def test_the_face_found_in_part_is_still_widened() -> None:
    """The search found the face's left part only: the columns taken in are the face's
    own up to its top (its top edge parts them from the wall over them), so the side
    moves out to the face's own side, not past it."""
    left, right = widen(can_scene(), LEFT, RIGHT - 80, rises=True)
    assert left == LEFT and abs(right - RIGHT) <= 2


@pytest.mark.parametrize(("apart", "kept"), [(8.0, True), (12.0, False)])
def test_over_the_top_within_rise_near_is_what_the_strip_shows(apart: float, kept: bool) -> None:
    """Over the top, the shadow's columns show a wall 8 (Lab) off the wall under the top:
    under RISE_NEAR (10) that is what the strip shows, the side stays; 12 off, a top edge
    parts them and the strip may be the face's own: the walk's side stands."""
    img = can_scene(over=lab_shifted(WALL, (apart, 0.0, 0.0)))
    left, right = widen(img, LEFT, RIGHT, rises=True)
    assert (right == RIGHT) is kept
    assert kept or right >= RIGHT + SHADOW_COLUMNS - 3


def test_the_rows_over_the_top_are_read_clear_of_its_blur() -> None:
    """Each row its own grey: the colour read is the median of exactly the RISE_OVER_ROWS
    (6) rows ending RISE_SKIP (2) over the top (one row more, one less, or one row
    nearer the top, and the median moves)."""
    rows = np.arange(H, dtype=np.float64)[:, None, None] * 2.0 * np.ones((1, W, 3))
    img = rows.astype(np.uint8)
    band = (RIGHT, RIGHT + 10)
    got = _over_top_colour(img, level_view(), TOP, band)
    assert got is not None
    lab = level_view().lab(img, 0, H, band[0], band[1], 1)

    def median_rows(r0: int, r1: int) -> npt.NDArray[np.float32]:
        return np.asarray(median_of(lab[r0:r1].reshape(-1, 3).astype(np.float32), axis=0))

    assert np.allclose(got, median_rows(TOP - 8, TOP - 2))
    for r0, r1 in ((TOP - 9, TOP - 2), (TOP - 7, TOP - 2), (TOP - 7, TOP - 1)):
        assert not np.allclose(got, median_rows(r0, r1))


def test_no_rows_over_the_top_in_view_reads_nothing() -> None:
    img = can_scene()
    assert _over_top_colour(img, level_view(), 7, (RIGHT, RIGHT + 10)) is None
    assert _over_top_colour(img, level_view(), 8, (RIGHT, RIGHT + 10)) is not None


@pytest.mark.parametrize("with_rig", [True, False])
def test_the_room_is_measured_to_the_faces_sides(with_rig: bool) -> None:
    assert room_size_errors("photo", 3216, True, with_rig=with_rig)[1] < 0.05


@pytest.mark.parametrize("with_rig", [True, False])
def test_without_the_rule_the_room_is_wide(with_rig: bool, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "RISES_OVER_TOP", False)
    assert room_size_errors("photo", 3216, True, with_rig=with_rig)[1] > 0.3


@pytest.mark.parametrize(
    ("family", "seed", "hard"), [("procedural", 711, True), ("procedural", 2022, False)]
)
def test_a_strip_of_one_surface_from_its_foot_up_stands(
    family: str, seed: int, hard: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Procedural 711 (hard) and 2022 (ordinary), no rig: a print in a margin of the face's
    own colour, the core walk's top the print's; the margin beside the print shows over
    the print's top too, but it is one colour from its foot up (RISES_OVER_ONE_SURFACE):
    it stands. Without that guard the sides come in to the print's: -20 % and -10 %."""
    assert max(room_size_errors(family, seed, hard, with_rig=False)) < 0.02
    monkeypatch.setattr(region, "RISES_OVER_ONE_SURFACE", False)
    assert max(room_size_errors(family, seed, hard, with_rig=False)) > 0.08


MARGIN = (170, 170, 170)  # BGR: a light grey margin, the face's own colour
GREY_FLOOR = (90, 90, 90)  # a dark grey floor: the margin's chroma
PRINT = (40, 140, 230)  # BGR: an orange print inset in the margin
F_LEFT, F_RIGHT, F_TOP = 60, 260, 60  # the face (margin) over the contact row BOTTOM
P_LEFT, P_RIGHT, P_TOP, P_BOTTOM = 80, 240, 90, BOTTOM - 20  # the print in it


def margin_scene(foot_shift: float = 0.0) -> npt.NDArray[np.uint8]:
    """The wall over a grey floor; the face a grey margin, an orange print inset in it
    20 columns in from each side, 30 rows under the face's top and 20 over its foot;
    the margin's lowest 9 rows (its foot's) ``foot_shift`` lighter (Lab L)."""
    img = np.empty((H, W, 3), np.float64)
    img[:BOTTOM] = WALL
    img[BOTTOM:] = GREY_FLOOR
    img[F_TOP:BOTTOM, F_LEFT:F_RIGHT] = MARGIN
    img[BOTTOM - 9 : BOTTOM, F_LEFT:F_RIGHT] = lab_shifted(MARGIN, (foot_shift, 0.0, 0.0))
    img[P_TOP:P_BOTTOM, P_LEFT:P_RIGHT] = PRINT
    img += np.random.default_rng(3).normal(0, 1.0, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def margin_side_rises(img: npt.NDArray[np.uint8]) -> bool:
    # the walk found the print (its top the face's), then walked the foot out to the
    # margin's right side: does the strip of margin beside the print rise as the face?
    return region._rises_as_face(img, level_view(), BOTTOM, P_TOP, (P_LEFT, P_RIGHT), F_RIGHT, 1)


def test_a_margin_over_the_prints_top_is_one_surface_and_stands(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The margin beside the print shows over the print's top too (what is over the top
    shows in the strip), but it is the same colour from its foot up: one surface, the
    face's; the side stands (RISES_OVER_ONE_SURFACE). Without the guard the strip reads
    as the background over the top, its foot of the floor's chroma, and the side goes."""
    img = margin_scene()
    assert margin_side_rises(img)
    monkeypatch.setattr(region, "RISES_OVER_ONE_SURFACE", False)
    assert not margin_side_rises(img)


@pytest.mark.parametrize(("shift", "stands"), [(10.0, True), (11.0, False)])
def test_one_surface_is_its_foot_within_rise_near(shift: float, stands: bool) -> None:
    """The margin's foot ``shift`` (Lab L, read back exactly) lighter than the strip up
    in the face's rows: 10, RISE_NEAR (the guard reuses it), is still one surface, the
    side stands; 11 parts them (something else at the foot, of the floor's chroma): the
    strip is what is over the top, the side goes."""
    assert margin_side_rises(margin_scene(shift)) is stands
