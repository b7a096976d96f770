"""The face's colour reaches its sides up to its top (``region.COLOUR_REACHES_SIDES``): the
colour walk up does not climb into an object of the face's colour standing in line behind
it, narrower than the face."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import region
from obstacle_fusion.vision.measure import Measurer

from tests.vision.test_fused_region import (
    BOTTOM,
    DEPTH,
    FACE_TOP,
    LEFT,
    RIGHT,
    level_view,
    top_strength,
    wall_scene,
)
from tests.vision_fixtures import room_size_errors

BEHIND_TOP = 20  # the top of the object standing behind the face
INSET = 30  # columns the object behind stands inside each of the face's sides
BEHIND = (40, 40, 170)  # BGR: the face's red
LEFT_RUN = 12  # rows the face's colour runs up just inside one side in one test
CABINET = (100, 110, 100)  # BGR: grey, the object's body round its red panel


def behind_scene(
    full_rows: int = 0,
    inset: int = INSET,
    cabinet: tuple[int, int, int] = CABINET,
    right_inset: int | None = None,
) -> npt.NDArray[np.uint8]:
    """:func:`wall_scene` with a grey object standing behind the face, a pixel inside its
    sides, from BEHIND_TOP down (what is just inside the face's sides above its top differs
    from the wall beside them), a panel of nearly the face's colour on it ``inset`` columns
    inside each side; the panel's top ``full_rows`` rows as wide as the face (a T: its
    arms cover the strips just inside the face's sides there); ``right_inset``: the
    panel's inset from the right side, if not ``inset``."""
    img = wall_scene().astype(np.float64)
    rng = np.random.default_rng(2)
    img[BEHIND_TOP:FACE_TOP, LEFT + 1 : RIGHT - 1] = cabinet
    right = RIGHT - (inset if right_inset is None else right_inset)
    img[BEHIND_TOP:FACE_TOP, LEFT + inset : right] = BEHIND
    img[BEHIND_TOP : BEHIND_TOP + full_rows, LEFT:RIGHT] = BEHIND
    img[BEHIND_TOP:FACE_TOP] += rng.normal(0, 4.0, img[BEHIND_TOP:FACE_TOP].shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def raise_top(img: npt.NDArray[np.uint8], top: int, edge_sides: bool = True) -> int:
    return region.raise_top_by_colour(
        img,
        level_view(),
        top_strength(img),
        BOTTOM,
        top,
        LEFT,
        RIGHT,
        DEPTH,
        edge_sides=edge_sides,
    )


def test_an_object_behind_narrower_than_the_face_is_not_climbed_into() -> None:
    assert raise_top(behind_scene(), FACE_TOP) == FACE_TOP


def test_without_the_rule_the_walk_climbs_it(monkeypatch: pytest.MonkeyPatch) -> None:
    """The scene tests the rule: the middle's colour does run on up the object."""
    img = behind_scene()
    assert raise_top(img, FACE_TOP, edge_sides=False) <= BEHIND_TOP + 3
    monkeypatch.setattr(region, "COLOUR_REACHES_SIDES", False)
    assert raise_top(img, FACE_TOP) <= BEHIND_TOP + 3


def test_the_top_stops_where_the_higher_strip_ends() -> None:
    """The face's colour reaching one side higher than the other (its own colour just
    inside the left side for LEFT_RUN rows above the top: a corner post, a lid's lip):
    the face reaches as high as its colour reaches either side."""
    img = behind_scene()
    img[FACE_TOP - LEFT_RUN : FACE_TOP, LEFT : LEFT + INSET] = img[FACE_TOP + 20, LEFT + 15]
    assert abs(raise_top(img, FACE_TOP) - (FACE_TOP - LEFT_RUN)) <= 2


def test_a_wall_line_across_the_face_is_still_crossed() -> None:
    """Above a background line across the face, the face's colour reaches both sides: the
    top goes up to the face's own (the raise the walk is for)."""
    assert abs(raise_top(wall_scene(), 150) - FACE_TOP) <= 2


def test_an_object_behind_as_wide_as_the_face_is_not_told() -> None:
    """Sides running on up the object behind are the face's for all the colours say."""
    assert raise_top(behind_scene(inset=0), FACE_TOP) <= BEHIND_TOP + 3


def test_a_panel_reaching_one_side_is_climbed() -> None:
    """The face's colour reaches one side above the top: the rule stands aside (an object in
    line with that side). The panel's red fades going up (30 levels of red over its
    height): the strip inside that side loses the face's own colour part of the way up,
    ending its own walk, while the middle's walk follows the fade; that strip still shows
    the middle's colour, so it does not part from it."""
    img = behind_scene(right_inset=0).astype(np.float64)
    rows = FACE_TOP - BEHIND_TOP
    for i, row in enumerate(range(FACE_TOP - 1, BEHIND_TOP - 1, -1)):
        img[row, LEFT + INSET : RIGHT, 2] -= 30.0 * (i + 1) / rows
    faded = np.clip(img, 0, 255).astype(np.uint8)
    assert raise_top(faded, FACE_TOP) <= BEHIND_TOP + 3


#: A body round the panel a little off the face's red (8-bit Lab, as the walk reads it)
#: still parts the strips from the middle (MIN_BESIDE_STEP, 12); one nearer does not.
@pytest.mark.parametrize(("cabinet", "stays"), [((40, 60, 150), True), ((40, 60, 160), False)])
def test_the_strips_must_part_from_the_middle_by_a_clear_step(
    cabinet: tuple[int, int, int], stays: bool
) -> None:
    assert (raise_top(behind_scene(cabinet=cabinet), FACE_TOP) == FACE_TOP) is stays


#: Rows of the object's full-width top, over the rows the middle's walk climbs past the
#: strips' end (FACE_TOP - BEHIND_TOP = 60), at which the strips still part from the
#: middle in SIDE_PARTS_SHARE (0.8) of them: 12 rows of 60 leave 48 (0.80), 13 leave 47.
@pytest.mark.parametrize(("full_rows", "stays"), [(12, True), (13, False)])
def test_the_share_of_rows_the_strips_part_from_the_middle_decides(
    full_rows: int, stays: bool
) -> None:
    assert (raise_top(behind_scene(full_rows), FACE_TOP) == FACE_TOP) is stays


@pytest.mark.parametrize(
    ("seed", "hard"),
    [(1349, True), (1475, True), (1090, False)],
)
def test_photo_rooms_with_an_object_of_the_face_colour_behind(seed: int, hard: bool) -> None:
    """A rocket lit like the lit face above it (1349), a grey wall the green face's blurred
    top drifted into (1475), a rocket behind a box (1090): heights +34, +46, +95 % before."""
    eh, ew = room_size_errors("photo", seed, hard)
    assert eh < 0.05 and ew < 0.05


def test_not_while_the_rig_is_only_tried() -> None:
    """A poster face (photo/1490 hard) with no rig: measured at a tried floor row, a pair's
    strips, unlike the poster's middle, would stop its colour walk (-18 -> -43 %)."""
    cam = CameraModel.paper(500, 375)
    image, truth, _ = render_room("photo", 1490, True, cam)
    res = Measurer(cam, None).measure(image, truth["range_m"])
    assert res.detected and res.height_m is not None
    assert abs(res.height_m / truth["height_m"] - 1) < 0.25
