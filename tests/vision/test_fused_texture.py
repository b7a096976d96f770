"""The fused method's texture rescue on drawn faces: grey bricks on grey gravel."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import texture
from obstacle_fusion.vision.fused.texture import face_from_texture
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import View

H, W = 300, 400
DEPTH = 1.5  # fx = 300: the 10 cm texture window is 21 px
TOP, BOTTOM, LEFT, RIGHT = 110, 230, 110, 290  # the face; its foot is row BOTTOM
ROWS = (BOTTOM - 8, BOTTOM + 8)  # the contact band the rig predicts


def level_view() -> View:
    k = np.array([[300.0, 0.0, W / 2], [0.0, 300.0, 100.0], [0.0, 0.0, 1.0]])
    return View(CameraModel(k, np.zeros(5), W, H), Rig(), "level")


def bricks(h: int, w: int, rng: np.random.Generator) -> npt.NDArray[np.float64]:
    """Bricks 8 px tall and 24 wide in staggered courses, 2-px dark joints, mean ~110."""
    out = np.full((h, w), 118.0) + rng.normal(0, 3.0, (h, w))
    for r in range(0, h, 8):
        out[r : r + 2] = 70.0
        shift = 12 * ((r // 8) % 2)
        for c in range(shift, w, 24):
            out[r : r + 8, c : c + 2] = 70.0
    return out


def scene(face_like_floor: bool = False) -> npt.NDArray[np.uint8]:
    """Gravel (fine noise around 110) below BOTTOM, a smooth wall of 110 above; the brick
    face is as grey as both: no colour step and no side edge stronger than its joints."""
    rng = np.random.default_rng(4)
    img = np.full((H, W), 110.0) + rng.normal(0, 2.0, (H, W))
    img[BOTTOM:] = 110.0 + rng.normal(0, 14.0, (H - BOTTOM, W))
    if face_like_floor:
        img[TOP:BOTTOM, LEFT:RIGHT] = 110.0 + rng.normal(0, 14.0, (BOTTOM - TOP, RIGHT - LEFT))
    else:
        img[TOP:BOTTOM, LEFT:RIGHT] = bricks(BOTTOM - TOP, RIGHT - LEFT, rng)
    return np.clip(img, 0, 255).astype(np.uint8)


def test_a_brick_face_as_grey_as_its_floor_is_found_by_its_texture() -> None:
    found = face_from_texture(scene(), level_view(), ROWS, DEPTH)
    assert found is not None
    contact, top, left, right, evidence = found
    assert abs(contact - BOTTOM) <= 5  # a quarter of the window
    assert abs(top - TOP) <= 6 and abs(left - LEFT) <= 6 and abs(right - RIGHT) <= 6
    assert evidence > 0.5


def test_a_face_of_the_floors_own_texture_is_not_found() -> None:
    assert face_from_texture(scene(face_like_floor=True), level_view(), ROWS, DEPTH) is None


def test_no_frame_no_face() -> None:
    assert face_from_texture(None, level_view(), ROWS, DEPTH) is None


def test_the_foot_step_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(texture, "MIN_FOOT_STEP", 50.0)
    assert face_from_texture(scene(), level_view(), ROWS, DEPTH) is None


def test_the_side_step_sets_the_evidence(monkeypatch: pytest.MonkeyPatch) -> None:
    found = face_from_texture(scene(), level_view(), ROWS, DEPTH)
    monkeypatch.setattr(texture, "FULL_SIDE_STEP", 100.0)
    weaker = face_from_texture(scene(), level_view(), ROWS, DEPTH)
    assert found is not None and weaker is not None and weaker[4] < 0.1 * found[4]


def test_a_window_under_a_course_reads_the_joints_as_another_texture(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """At 2 cm (5 px, under a brick's 8) the window sees joint and brick apart: the face is
    no longer one texture from its foot to its top."""
    monkeypatch.setattr(texture, "TEXTURE_WINDOW_M", 0.02)
    found = face_from_texture(scene(), level_view(), ROWS, DEPTH)
    assert found is None or abs(found[1] - TOP) > 6 or abs(found[3] - found[2] - (RIGHT - LEFT)) > 6


def test_the_least_height_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    """The face is 0.6 m tall here: a face must reach MIN_HEIGHT_M."""
    monkeypatch.setattr(texture, "MIN_HEIGHT_M", 0.7)
    assert face_from_texture(scene(), level_view(), ROWS, DEPTH) is None


def test_a_grey_brick_face_on_grey_paving_is_measured_by_its_texture(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Room photo/140 (a tuning scene): grey bricks before grey paving, whose joints
    outdo the face's sides and whose colour is the floor's. Found by its texture, never
    as a sure face; without the texture search it is refused."""
    from obstacle_fusion.sim.room_scene import TextureMissing, render_room
    from obstacle_fusion.vision.fused import method
    from obstacle_fusion.vision.measure import Measurer

    try:
        image, truth, spec = render_room("photo", 140, False)
    except TextureMissing as exc:
        pytest.skip(str(exc))
    cam = CameraModel.paper(500, 375)
    res = Measurer(cam, spec.rig).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.height_m == pytest.approx(truth["height_m"], rel=0.06)
    assert res.width_m == pytest.approx(truth["width_m"], rel=0.06)
    assert 0.0 < res.confidence <= method.TEXTURE_MAX_CONFIDENCE  # type: ignore[operator]
    monkeypatch.setattr(method, "face_from_texture", lambda *args: None)
    assert not Measurer(cam, spec.rig).measure(image, truth["range_m"]).detected


def test_a_print_found_by_its_texture_has_its_top_walked_up_by_the_sides(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Room photo/346 hard (a tuning scene): a print of coins covers most of a face, its
    plain margin round it. The edges' face is refused (a side on a cylinder beside it), and
    the texture finds the print's lower rows only (the texture's walk up stops at a row of
    the print). The face's margin parts it from the wall at both sides up to its top: the
    sides' walk takes the top up there (height -48 -> -19 %); without it (and without
    the frame read from the foot, region.enclose_from_foot, which encloses the print on
    its own) the height is under 60 % of the face's."""
    from obstacle_fusion.sim.room_scene import TextureMissing, render_room
    from obstacle_fusion.vision.fused import method, scoring
    from obstacle_fusion.vision.measure import Measurer

    # the edges find this face since the closing top where the print's texture ends
    # (scoring.PRINT_ENDS_TEXTURE): off here, so the texture path is the one measuring it
    monkeypatch.setattr(scoring, "PRINT_ENDS_TEXTURE", -1.0)
    try:
        image, truth, spec = render_room("photo", 346, True)
    except TextureMissing as exc:
        pytest.skip(str(exc))
    cam = CameraModel.paper(500, 375)
    res = Measurer(cam, spec.rig).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.height_m == pytest.approx(truth["height_m"], rel=0.25)
    assert 0.0 < res.confidence <= method.TEXTURE_MAX_CONFIDENCE  # type: ignore[operator]
    monkeypatch.setattr(method, "TEXTURE_SIDES_WALK", False)
    monkeypatch.setattr(method, "enclose_from_foot", lambda *a: None)
    # (and the frame closing over the print, method.FRAME_CLOSES_TOP, which finds it too)
    monkeypatch.setattr(method, "FRAME_CLOSES_TOP", False)
    short = Measurer(cam, spec.rig).measure(image, truth["range_m"])
    assert short.detected and short.height_m < 0.6 * truth["height_m"]  # type: ignore[operator]
