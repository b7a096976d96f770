"""A print standing above the floor-contact row: the face round it, by the margin under it."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import region
from obstacle_fusion.vision.fused.extent import foot_in_band
from obstacle_fusion.vision.fused.region import widen_along_margin
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import View

H, W = 240, 320
TOP, BOTTOM, LEFT, RIGHT = 80, 200, 60, 260  # the face; its foot is row BOTTOM
MARGIN_SIDE, MARGIN_FOOT = 10, 6  # the face's own colour round the print
P_LEFT, P_RIGHT, P_BOTTOM = LEFT + MARGIN_SIDE, RIGHT - MARGIN_SIDE, BOTTOM - MARGIN_FOOT
REACH = 40
FACE = (60, 160, 60)  # BGR green margin
WALL = (150, 110, 90)
FLOOR = (120, 120, 120)


def level_view() -> View:
    """A distortion-free camera with no pitch: the levelled view is the image itself."""
    k = np.array([[300.0, 0.0, W / 2], [0.0, 300.0, H / 2], [0.0, 0.0, 1.0]])
    return View(CameraModel(k, np.zeros(5), W, H), Rig(), "level")


def scene(margin: tuple[int, int, int] = FACE, foot: int = MARGIN_FOOT) -> npt.NDArray[np.uint8]:
    """Wall, floor below BOTTOM, a face of colour ``margin`` with a print of bright blocks
    (strong inner edges) inset in it, ``foot`` rows of margin under the print."""
    rng = np.random.default_rng(3)
    img = np.empty((H, W, 3), np.float64)
    img[:BOTTOM] = WALL
    img[BOTTOM:] = FLOOR
    img[TOP:BOTTOM, LEFT:RIGHT] = margin
    p_top, p_bottom = TOP + MARGIN_SIDE, BOTTOM - foot
    for c in range(P_LEFT, P_RIGHT, 20):  # a print: blocks of colours changing column-wise
        img[p_top:p_bottom, c : c + 20] = rng.uniform(0, 255, 3)
    img += rng.normal(0, 4.0, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def walk(img: npt.NDArray[np.uint8], foot: int = MARGIN_FOOT) -> tuple[int, int] | None:
    return widen_along_margin(img, level_view(), BOTTOM - foot, BOTTOM, P_LEFT, P_RIGHT, REACH)


def test_the_margin_under_a_print_leads_out_to_the_faces_sides() -> None:
    sides = walk(scene())
    assert sides is not None
    assert abs(sides[0] - LEFT) <= 2 and abs(sides[1] - RIGHT) <= 2


def test_a_print_reaching_the_foot_leaves_no_margin_to_walk() -> None:
    assert walk(scene(foot=1), foot=1) is None


def test_a_margin_of_the_walls_colour_is_no_outline() -> None:
    assert walk(scene(margin=WALL)) is None


def test_the_margin_step_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # the margin steps ~110 from the wall: a bar over that refuses it
    monkeypatch.setattr(region, "MARGIN_MIN_STEP", 200.0)
    assert walk(scene()) is None


def test_the_foot_is_the_strongest_edge_in_the_band_under_the_print() -> None:
    ay = np.ones((H, W), np.float32)
    ay[BOTTOM, LEFT:RIGHT] = 20.0  # the face's foot
    ay[P_BOTTOM, LEFT:RIGHT] = 60.0  # the print's lower edge, above the band
    assert foot_in_band(ay, P_BOTTOM, P_LEFT, P_RIGHT, (BOTTOM - 4, BOTTOM + 4), 2.0) == BOTTOM


def test_no_foot_in_the_band_gives_no_outline() -> None:
    ay = np.ones((H, W), np.float32)
    assert foot_in_band(ay, P_BOTTOM, P_LEFT, P_RIGHT, (BOTTOM - 4, BOTTOM + 4), 2.0) is None


def test_a_strip_of_edge_blur_only_is_no_margin() -> None:
    # 4 rows between the print's lower edge and the foot: only the two edges' blur
    assert walk(scene(foot=4), foot=4) is None
    assert walk(scene(foot=5), foot=5) is not None


def test_a_margin_running_on_past_the_reach_is_followed_to_its_end() -> None:
    # a small piece of the print (one block) found: the margin under it runs on far past
    # a reach scaled by that piece, out to the face's sides
    img = scene()
    c = P_LEFT + 80
    view = level_view()
    assert widen_along_margin(img, view, P_BOTTOM, BOTTOM, c, c + 20, 8) is None
    sides = widen_along_margin(img, view, P_BOTTOM, BOTTOM, c, c + 20, 8, 200)
    assert sides is not None
    assert abs(sides[0] - LEFT) <= 2 and abs(sides[1] - RIGHT) <= 2
    # ... but no farther than ``far``: a margin still running on there is no outline
    assert widen_along_margin(img, view, P_BOTTOM, BOTTOM, c, c + 20, 8, 60) is None


def test_a_thin_strip_counts_only_where_it_runs_on_far() -> None:
    # 4 rows: two clear of the blur only if the strip runs on well past the piece found
    img = scene(foot=4)
    view = level_view()
    p_bottom = BOTTOM - 4
    c = P_LEFT + 80
    sides = widen_along_margin(img, view, p_bottom, BOTTOM, c, c + 20, 8, 200)
    assert sides is not None and abs(sides[0] - LEFT) <= 2 and abs(sides[1] - RIGHT) <= 2
    # the whole print found, its strip ending within the reach: still only blur
    assert widen_along_margin(img, view, p_bottom, BOTTOM, P_LEFT, P_RIGHT, REACH, 200) is None


@pytest.mark.parametrize(
    ("family", "seed", "tol"),
    [
        ("procedural", 339, 0.05),  # a print standing above the predicted row (was -11 %)
        ("procedural", 132, 0.05),  # text on a page standing above it (was -16 %)
        # a small piece of a print covering most of the face, standing above the row
        ("procedural", 305, 0.08),  # was -83 % / -61 %
        ("procedural", 306, 0.10),  # was -71 % / -55 %
    ],
)
def test_rooms_with_a_print_in_a_thin_margin_are_measured_whole(
    family: str, seed: int, tol: float
) -> None:
    cam = CameraModel.paper(500, 375)
    image, truth, spec = render_room(family, seed, True, cam)
    res = Measurer(cam, spec.rig).measure(image, truth["range_m"])
    assert res.detected and res.height_m is not None and res.width_m is not None
    assert abs(res.height_m / truth["height_m"] - 1) < tol
    assert abs(res.width_m / truth["width_m"] - 1) < tol
