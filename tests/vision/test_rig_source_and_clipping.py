"""Which rig a measurement used, the floor contact found with no rig, the colour channel,
and faces cut by the image's border."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from obstacle_fusion.sim.room_scene import RoomRenderer, RoomSpec, render_room
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import FusedMethod, floor_contact, region
from obstacle_fusion.vision.fused import method as fused_method
from obstacle_fusion.vision.fused.channel import MIN_COLOUR_STEP, face_floor_grey
from obstacle_fusion.vision.fused.confidence import (
    FOOT_OFF_FLOOR,
    NEAR_RIVALS,
    PITCH_UNREAD,
    SECOND_TOP,
    TOP_FROM_SIDES,
    TOP_RUNS_ON,
)
from obstacle_fusion.vision.fused.floor_contact import contact_rows, weak_contact_rows
from obstacle_fusion.vision.measure import CLIP_MARGIN_PX, Measurer, clipped_sides
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import SIDE_SAMPLES, UNSEEN_MARGIN_PX, Measurement, View

from tests.vision.rooms import plain_room

CAM = CameraModel.paper(500, 375)


def _assert_measured_without_rig(family: str, seed: int, hard: bool, rel: float) -> None:
    """The room measured with no rig file: detected, height and width within ``rel``."""
    image, truth, _ = render_room(family, seed, hard, CAM)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.height_m == pytest.approx(truth["height_m"], rel=rel)
    assert res.width_m == pytest.approx(truth["width_m"], rel=rel)


def clean_room(seed: int, **changes: object) -> RoomSpec:
    return plain_room(seed, **changes)


def no_rig_room(seed: int) -> tuple[np.ndarray, dict[str, float], View, float]:
    """A clean room's image and truth, the level view and the face depth a Measurer with
    no rig file works with (its default rig)."""
    image, truth = RoomRenderer(CAM).render(clean_room(seed))
    return image, truth, View(CAM, Rig(), "level"), Rig().face_depth(truth["range_m"])


def fake_face(
    truth: dict[str, float],
    detected: bool,
    confidence: float,
    height_m: float = 0.3,
    **fields: object,
) -> Measurement:
    """What a faked FusedMethod.run returns: a face 0.3 m wide (or none)."""
    return Measurement(
        detected=detected,
        method="fused",
        range_m=truth["range_m"],
        height_m=height_m,
        width_m=0.3,
        confidence=confidence,
        **fields,  # type: ignore[arg-type]
    )


def test_rig_source_says_file_estimated_or_default() -> None:
    spec = clean_room(4001)
    image, truth = RoomRenderer(CAM).render(spec)
    assert Measurer(CAM, spec.rig).measure(image, truth["range_m"]).rig_source == "file"
    assert Measurer(CAM, None).measure(image, truth["range_m"]).rig_source == "estimated"
    paper = Measurer(CAM, None, method="paper").measure(image, truth["range_m"])
    assert paper.rig_source == "default"
    assert (
        Measurer(CAM, None).measure(image, truth["range_m"]).to_dict()["rig_source"] == "estimated"
    )


def test_with_no_rig_the_floor_contact_and_camera_height_are_found() -> None:
    """The camera height is not guessed: it follows from the contact row found in the image.

    Clean rooms on planked or tiled floors, level camera; a board's edge on the floor can
    still pass for the contact, so three of four must hold."""
    held = []
    for seed in (4001, 4004, 4005, 4006):
        spec = clean_room(seed)
        spec = dataclasses.replace(spec, rig=dataclasses.replace(spec.rig, camera_pitch_deg=0.0))
        image, truth = RoomRenderer(CAM).render(spec)
        res = Measurer(CAM, None).measure(image, truth["range_m"])
        held.append(
            res.detected
            and abs(res.camera_height_m - spec.rig.camera_height_m) <= 0.02
            and abs(res.height_m / truth["height_m"] - 1) <= 0.05
            and abs(res.width_m / truth["width_m"] - 1) <= 0.05
        )
    assert sum(held) >= 3, held


def test_contact_rows_take_the_step_not_a_seam_line_below_it() -> None:
    view = View(CAM, Rig(), "level")
    h, w = 375, 500
    img = np.full((h, w, 3), 150, np.uint8)  # wall
    img[200:] = (60, 90, 120)  # floor from row 200 in the level view ...
    img[300:] = (60, 90, 120)
    img[330:332] = (20, 20, 20)  # ... with a dark seam line further down
    img[250:300, 150:350] = (200, 60, 40)  # the face, standing on row 300
    # draw in the level view, then take the view's rows as the input (no distortion)
    view_cam = CameraModel(view.k.copy(), np.zeros(5), w, h)
    flat = View(view_cam, Rig(), "level")
    rows = contact_rows(img, flat, depth_m=1.5)
    assert rows and abs(rows[0] - 300) <= 2


def test_contact_rows_reach_past_a_striped_floor_to_the_face() -> None:
    """Three wide boards of another shade on the floor give five steps below the face's
    foot (rows 312 to 360): the face's own contact, row 300, is still among the candidates
    tried, the sixth from the bottom (MAX_CANDIDATES = 8; with four, only board edges were
    tried)."""
    h, w = 375, 500
    img = np.full((h, w, 3), 150, np.uint8)  # wall
    img[200:] = (60, 90, 120)  # floor
    for r in (312, 336, 360):  # boards of another shade, 12 rows each
        img[r : r + 12] = (30, 140, 60)
    img[250:300, 150:350] = (200, 60, 40)  # the face, standing on row 300
    view = View(CAM, Rig(), "level")
    flat = View(CameraModel(view.k.copy(), np.zeros(5), w, h), Rig(), "level")
    rows = contact_rows(img, flat, depth_m=1.5)
    assert any(abs(r - 300) <= 2 for r in rows), rows


def test_contact_rows_find_a_foot_on_gravel_under_a_busy_room() -> None:
    """Photo room 147 (hard): a face on gravel, a launch pad at night behind. The whole
    band's steps (wall, lights, face) put the bar over the foot's step, so no row stood
    out and the face was missed with no rig; against the gravel's own texture below it
    the foot stands out. The height's bound is wider than the width's: the pitch read
    from this image is about 2 degrees steeper than the rig's, which alone shrinks the
    height by some 5 % (the answer carries that doubt and a low confidence)."""
    image, truth, _ = render_room("photo", 147, True, CAM)
    view = View(CAM, Rig(), "level")
    depth = Rig().face_depth(truth["range_m"])
    rows = contact_rows(image, view, depth)
    # the foot: image row ~311 (the renderer's corners), a row or so off in the level view
    assert any(abs(r - 312) <= 3 for r in rows), rows
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected and res.height_m is not None and res.width_m is not None
    assert abs(res.height_m / truth["height_m"] - 1) < 0.08
    assert abs(res.width_m / truth["width_m"] - 1) < 0.05
    assert res.confidence < 0.5 and "pitch_rerun_disagrees" in res.doubts


def test_a_step_with_too_little_floor_below_to_read_is_not_taken_by_the_floor_rule() -> None:
    k = floor_contact.STEP_ROWS
    n = floor_contact.FLOOR_NOISE_ROWS
    rows = np.zeros((200, 3), np.float32)
    rows[:100] = 120.0  # the face, a plain step over the floor from row 100
    v = np.arange(k, 200 - k)
    step = np.zeros(len(v))
    step[100 - k] = 60.0  # the foot's step, at row 100, over a floor with no texture
    step[101 - k] = step[99 - k] = 30.0
    steps = floor_contact._steps
    # over the band's bar: not taken; against the floor below it: taken
    assert steps(rows, v, step, k, 1e9, None) == []
    assert steps(rows, v, step, k, 1e9, n) == [100]
    # floor texture NOISE_FACTOR times under the step: still taken; at it, not
    step[100 - k + k : 100 - k + k + n] = 60.0 / floor_contact.NOISE_FACTOR - 0.01
    assert steps(rows, v, step, k, 1e9, n) == [100]
    step[100 - k + k : 100 - k + k + n] = 60.0 / floor_contact.NOISE_FACTOR + 0.01
    assert steps(rows, v, step, k, 1e9, n) == []
    # half the rows needed below to read the floor: read; fewer: not
    step[:] = 0.0
    last = len(v) - k - n // 2  # the lowest step with n // 2 rows below it
    rows[:] = 100.0
    rows[: v[last]] = 160.0
    step[last] = 60.0
    step[last - 1] = step[last + 1] = 30.0
    assert steps(rows, v, step, k, 1e9, n) == [int(v[last])]
    step[:] = 0.0
    rows[:] = 100.0
    rows[: v[last + 1]] = 160.0
    step[last + 1] = 60.0
    step[last] = step[last + 2] = 30.0
    assert steps(rows, v, step, k, 1e9, n) == []


def test_the_channel_adds_the_face_floor_colour_step_luminance_misses() -> None:
    view_cam = CameraModel(CAM.camera_matrix.copy(), np.zeros(5), 500, 375)
    view = View(view_cam, Rig(), "level")
    img = np.empty((375, 500, 3), np.uint8)
    grey_floor = np.array([120, 120, 120], np.uint8)
    green_face = np.array([60, 170, 40], np.uint8)  # about the floor's luminance
    img[:] = grey_floor
    contact = 300
    img[200:contact, 200:300] = green_face
    luma = img @ np.array([0.114, 0.587, 0.299])
    assert abs(luma[contact - 5, 250] - luma[contact + 5, 250]) < 12  # luminance: no edge
    out = face_floor_grey(img, view, float(contact), depth_m=1.5)
    assert out.ndim == 2
    assert abs(int(out[contact - 5, 250]) - int(out[contact + 5, 250])) > 25
    # a grey frame, or face and floor of one colour, is left as it is
    grey = img[:, :, 0].copy()
    assert face_floor_grey(grey, view, float(contact), 1.5) is grey
    same = np.full_like(img, 120)
    same[200:contact, 200:300] += np.uint8(MIN_COLOUR_STEP // 3)
    assert face_floor_grey(same, view, float(contact), 1.5) is same


def test_clipped_sides_at_the_margin() -> None:
    w, h = 500, 375
    m = CLIP_MARGIN_PX
    assert clipped_sides(None, w, h) == []
    assert clipped_sides((m + 0.01, m + 0.01, w - 1 - m - 0.01, h - 1 - m - 0.01), w, h) == []
    assert clipped_sides((m, 10, 100, 100), w, h) == ["left"]
    assert clipped_sides((10, 10, w - 1 - m, 100), w, h) == ["right"]
    assert clipped_sides((10, m, 100, h - 1 - m), w, h) == ["top", "bottom"]


def test_a_face_cut_by_the_border_is_never_a_confident_full_width() -> None:
    spec = clean_room(4003, width_m=1.4, face_x_m=0.45)
    image, truth = RoomRenderer(CAM).render(spec)
    assert "right" in truth["clipped"]
    res = Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    if res.detected:
        assert "right" in res.clipped
        assert res.to_dict()["width_is_lower_bound"] is True
        assert res.width_m < truth["width_m"]


def _face(left: float, right: float, top: float, bottom: float) -> np.ndarray:
    """View corners bottom-left, bottom-right, top-right, top-left."""
    return np.array([[left, bottom], [right, bottom], [right, top], [left, top]])


def test_a_side_within_the_margin_of_the_views_border_is_unseen() -> None:
    view = View(CAM, Rig(), "level")
    m = UNSEEN_MARGIN_PX
    w, h = CAM.size
    assert view.unseen_sides(_face(100, 400, 100, 300), m) == []
    assert view.unseen_sides(_face(m, 400, 100, 300), m) == []
    assert view.unseen_sides(_face(m - 1, 400, 100, 300), m) == ["left"]
    assert view.unseen_sides(_face(100, w - 1 - m, 100, 300), m) == []
    assert view.unseen_sides(_face(100, w - m, 100, 300), m) == ["right"]
    assert view.unseen_sides(_face(100, 400, m - 1, h - m), m) == ["top", "bottom"]


def test_a_side_near_where_the_view_maps_outside_the_image_is_unseen() -> None:
    # pitched down 8 degrees, the levelled view's top right corner reads past the input
    # image's right border: its last seen column is short of the view's own border
    view = View(CAM, Rig(camera_pitch_deg=8.0), "level")
    m = UNSEEN_MARGIN_PX
    top, bottom = 10, 30
    rows = np.rint(np.linspace(top, bottom, 5)).astype(int)
    src_x = view.map1[rows, :, 0].astype(int)
    last_seen = int(min(np.flatnonzero(r < CAM.size[0]).max() for r in src_x))
    assert last_seen + 1 < CAM.size[0] - 1 - m  # (the view's own border is not what cuts it)
    right = last_seen - m
    assert "right" not in view.unseen_sides(_face(400, right, top, bottom), m)
    assert "right" in view.unseen_sides(_face(400, right + 1, top, bottom), m)


def _unseen_side_by_side(view: View, corners: np.ndarray, margin: float) -> list[str]:
    """View.unseen_sides as it was, one side at a time (the reference for the one pass)."""
    c = np.asarray(corners, dtype=np.float64).reshape(4, 2)
    if not np.isfinite(c).all():
        return []
    bl, br, tr, tl = c
    t = np.linspace(0.0, 1.0, SIDE_SAMPLES)[:, None]
    outward = {
        "left": (bl + t * (tl - bl)) - (margin, 0.0),
        "right": (br + t * (tr - br)) + (margin, 0.0),
        "top": (tl + t * (tr - tl)) - (0.0, margin),
        "bottom": (bl + t * (br - bl)) + (0.0, margin),
    }
    h, w = view.map1.shape[:2]
    w_in, h_in = view.camera.size
    sides = []
    for side, pts in outward.items():
        u = np.floor(pts[:, 0]).astype(np.int64)
        v = np.floor(pts[:, 1]).astype(np.int64)
        inside = (u >= 0) & (u < w) & (v >= 0) & (v < h)
        if not inside.all():
            sides.append(side)
            continue
        src = view.map1[v, u].astype(np.int64)
        seen = (src[:, 0] >= 0) & (src[:, 0] < w_in) & (src[:, 1] >= 0) & (src[:, 1] < h_in)
        if not seen.all():
            sides.append(side)
    return sides


def test_unseen_sides_in_one_pass_are_the_side_by_side_answers() -> None:
    """The four sides' samples checked in one pass name the sides the per-side loop named:
    faces inside, across and past every border, on the edges exactly, slanted and
    upside-down outlines, pitched views that map outside the input; no outline (NaN)."""
    rng = np.random.default_rng(51)
    w, h = CAM.size
    for pitch in (0.0, 8.0, -6.0):
        view = View(CAM, Rig(camera_pitch_deg=pitch), "level")
        for margin in (UNSEEN_MARGIN_PX, 0.0, 2.5):
            for _ in range(400):
                pts = rng.uniform([-30, -30], [w + 30, h + 30], (4, 2))
                if rng.random() < 0.3:
                    pts = np.rint(pts)  # on pixel edges exactly
                assert view.unseen_sides(pts, margin) == _unseen_side_by_side(view, pts, margin)
            face = _face(margin, w - 1 - margin, margin, h - 1 - margin)
            assert view.unseen_sides(face, margin) == _unseen_side_by_side(view, face, margin)
    nan = _face(100, 400, 100, 300).astype(float)
    nan[2, 1] = np.nan
    assert view.unseen_sides(nan) == [] == _unseen_side_by_side(view, nan, UNSEEN_MARGIN_PX)


def test_a_face_running_off_the_image_short_of_its_border_in_the_view_is_flagged() -> None:
    # the levelled view loses the input's outer ~9 columns: the face's measured side ends
    # ~11 px from the image's left border, yet the face runs on off the image
    image, truth, spec = render_room("procedural", 910, False, CAM)
    assert truth["clipped"] == ["left"]
    res = Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    assert res.detected and res.box_px is not None
    assert res.box_px[0] > 2 * CLIP_MARGIN_PX  # the image border alone would not say so
    assert res.clipped == ["left"]
    assert res.to_dict()["width_is_lower_bound"] is True
    assert res.width_m is not None and res.width_m < truth["width_m"]


def test_with_no_rig_a_contact_row_too_close_to_the_horizon_is_not_tried(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A row that would put the lens 5 cm above the floor (a line on the wall, a print's
    edge) is not taken for the obstacle's foot; one at 30 cm is."""

    image, truth, view, depth = no_rig_room(4001)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (0.05, 0.30)}
    tried: list[int] = []  # the level view's rows tried
    run = FusedMethod.run

    def counting_run(self: FusedMethod, *args: object, **kwargs: object) -> object:
        if not self.view.rig.camera_pitch_deg:
            tried.append(round(view.cy + view.fy * self.view.rig.camera_height_m / depth))
        return run(self, *args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(FusedMethod, "run", counting_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[0.05], row_at[0.30]])
    monkeypatch.setattr(measure, "weak_contact_rows", lambda *a: [])  # (the last resort's)
    Measurer(CAM, None).measure(image, truth["range_m"])
    # the 30 cm row, maybe its neighbours (measure.ROW_JITTER_PX); never the 5 cm row
    assert tried and tried[0] == row_at[0.30]
    assert all(abs(r - row_at[0.30]) <= measure.ROW_JITTER_PX for r in tried), tried
    tried.clear()
    monkeypatch.setattr(measure, "MIN_ESTIMATED_CAMERA_HEIGHT_M", 0.0)
    Measurer(CAM, None).measure(image, truth["range_m"])
    assert row_at[0.05] in tried


def test_with_no_rig_a_contact_row_under_a_lens_over_1_5_m_is_not_tried(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A row that would put the lens 1.7 m above the floor (a line far below the face at the
    longest range) is no floor contact a mobile robot's camera sees: never tried, at any
    pitch; one at 1.2 m is."""
    image, truth, view, depth = no_rig_room(4001)
    far = 5.0  # the longest range: the rows of such heights lie inside the image
    depth = Rig().face_depth(far)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (1.2, 1.7)}
    assert row_at[1.7] < image.shape[0]
    heights: list[float] = []

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        heights.append(self.view.rig.camera_height_m)
        return Measurement(detected=False, method="fused", range_m=far)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[1.7], row_at[1.2]])
    monkeypatch.setattr(measure, "weak_contact_rows", lambda *a: [row_at[1.7]])
    Measurer(CAM, None).measure(image, far)
    assert any(abs(h - 1.2) < 0.01 for h in heights), heights
    assert max(heights) < measure.MAX_ESTIMATED_CAMERA_HEIGHT_M <= 1.5


def test_with_no_rig_a_stream_tries_the_last_frames_camera_height_first(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The rows are sought on the first frame; the next frame of the same scene takes the
    height the first one accepted, with no search; a frame where that height gives no face
    seeks again (and forgets it)."""

    spec = clean_room(4001)
    spec = dataclasses.replace(spec, rig=dataclasses.replace(spec.rig, camera_pitch_deg=0.0))
    image, truth = RoomRenderer(CAM).render(spec)
    sought: list[int] = []
    find = measure.contact_rows

    def counting(*args: object) -> list[int]:
        if len(args) == 3:  # the search below the horizon (not the pitched camera's above it)
            sought.append(1)
        return find(*args)  # type: ignore[arg-type]

    monkeypatch.setattr(measure, "contact_rows", counting)
    # (the blank frame's rows read as with a rig, KNOWN_RIG_ROWS, would seek them too)
    monkeypatch.setattr(measure, "KNOWN_RIG_ROWS", False)
    measurer = Measurer(CAM, None)
    first = measurer.measure(image, truth["range_m"])
    assert first.detected and len(sought) == 1
    second = measurer.measure(image, truth["range_m"])
    assert len(sought) == 1
    assert second.detected and second.camera_height_m == first.camera_height_m
    assert second.height_m == pytest.approx(first.height_m, abs=1e-9)
    blank = np.full_like(image, 128)
    assert not measurer.measure(blank, truth["range_m"]).detected
    assert len(sought) == 2
    measurer.measure(image, truth["range_m"])
    assert len(sought) == 3  # the blank frame's failure forgot the height


def test_contact_rows_above_the_centre_row_only_when_asked() -> None:
    """A camera pitched down lifts the horizon: a face standing on a row above the view's
    centre row is a candidate only when the search reaches above it."""
    h, w = 375, 500
    img = np.full((h, w, 3), 150, np.uint8)  # wall
    img[160:] = (60, 90, 120)  # floor from row 160
    img[120:175, 150:350] = (200, 60, 40)  # the face, standing on row 175
    view = View(CAM, Rig(), "level")
    flat = View(CameraModel(view.k.copy(), np.zeros(5), w, h), Rig(), "level")
    assert flat.cy > 175
    assert not any(abs(r - 175) <= 2 for r in contact_rows(img, flat, depth_m=2.0))
    rows = contact_rows(img, flat, depth_m=2.0, above_px=40.0)
    assert any(abs(r - 175) <= 2 for r in rows), rows


def test_with_no_rig_a_far_face_seen_by_a_camera_pitched_down_is_measured(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Room procedural/131 (hard): the lens 24 cm up, pitched 4.4 degrees down, the face
    2.8 m away: its foot lies 5 rows under the centre row, where a level lens would be 3 cm
    above the floor. Tried as a pitched camera's (30 cm up, pitched to put the foot there),
    it is measured within 3 %."""
    from obstacle_fusion.sim.room_scene import render_room

    image, truth, spec = render_room("procedural", 131, True)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.height_m == pytest.approx(truth["height_m"], rel=0.03)
    assert res.width_m == pytest.approx(truth["width_m"], rel=0.03)
    assert 0.0 < (res.camera_pitch_deg or 0.0) <= measure.MAX_ESTIMATED_PITCH_DEG
    # its sides, 46 columns apart, give no pitch: it stands on its own confidence (0.78)
    monkeypatch.setattr(measure, "GUESSED_PITCH_SURE", 0.8)
    assert not Measurer(CAM, None).measure(image, truth["range_m"]).detected
    monkeypatch.setattr(measure, "GUESSED_PITCH_SURE", 0.5)
    monkeypatch.setattr(measure, "MAX_ESTIMATED_PITCH_DEG", 0.0)
    assert not Measurer(CAM, None).measure(image, truth["range_m"]).detected


@pytest.mark.parametrize(
    "lower, upper, expected",
    [
        ((True, 0.10), (True, 0.15), 0.30),  # none accepted: the lowest face, not the surest
        ((False, 0.15), (True, 0.10), 0.20),  # the lower row stands no face
        ((True, 0.10), (True, 0.60), 0.20),  # the upper one accepted
    ],
)
def test_with_no_rig_and_no_row_accepted_the_lowest_face_wins(
    lower: tuple[bool, float],
    upper: tuple[bool, float],
    expected: float,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Below the face there is only floor: with no row's face confident enough to accept
    (measure.ESTIMATE_ACCEPT), the lowest row that stands one is the contact, even when a
    face on a row above it (a line on the floor behind, a print's edge) scores higher."""

    image, truth, view, depth = no_rig_room(4001)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (0.20, 0.30)}
    outcome = {0.30: lower, 0.20: upper}

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        height = round(self.view.rig.camera_height_m, 2)
        if self.view.rig.camera_pitch_deg or height not in outcome:  # other pitches, rows
            return Measurement(detected=False, method="fused", range_m=truth["range_m"])
        detected, conf = outcome[height]
        return fake_face(truth, detected, conf, height_m=0.3)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[0.30], row_at[0.20]])
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected
    assert res.camera_height_m == pytest.approx(expected, abs=0.01)


@pytest.mark.parametrize(
    "weak_conf, weak_drop, expected",
    [
        (0.30, 1.0, 0.30),  # the weaker step below stands a sure face: the nearer foot
        (0.10, 1.0, 0.20),  # an unsure face there too: the row that stood out stays
        (0.30, 0.0, 0.20),  # the same face on its own foot (the step its foot's blur)
    ],
)
def test_with_no_rig_a_weaker_step_below_an_unsure_face_is_the_nearer_foot(
    weak_conf: float, weak_drop: float, expected: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The sonar measured the nearest surface in its beam: when the only row that stands
    out of the band's steps (a wall's foot) stands an unsure face, a weaker step below it
    (a face of nearly the floor's colour) that stands a face of at least ESTIMATE_ACCEPT,
    its foot lower than the unsure face's, is the face's foot."""

    image, truth, view, depth = no_rig_room(4001)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (0.20, 0.30)}
    outcome = {0.20: 0.10, 0.30: weak_conf}
    # the faces' feet (input pixels): the weak row's lower by weak_drop of the rows' gap
    foot = {
        0.20: float(row_at[0.20]),
        0.30: row_at[0.20] + weak_drop * (row_at[0.30] - row_at[0.20]),
    }

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        height = round(self.view.rig.camera_height_m, 2)
        if self.view.rig.camera_pitch_deg or height not in outcome or kwargs.get("floor_known"):
            return Measurement(detected=False, method="fused", range_m=truth["range_m"])
        box = (100.0, foot[height] - 50.0, 200.0, foot[height])
        return fake_face(truth, True, outcome[height], height_m=0.3, box_px=box)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[0.20]])
    monkeypatch.setattr(measure, "weak_contact_rows", lambda *a: [row_at[0.30], row_at[0.20]])
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected
    assert res.camera_height_m == pytest.approx(expected, abs=0.01)


@pytest.mark.parametrize(
    "upper_doubts, weak_doubts, expected",
    [
        ([FOOT_OFF_FLOOR], [], 0.30),  # the sure face's foot is off the floor: the nearer one
        ([], [], 0.20),  # a sure face on the floor keeps its row
        ([FOOT_OFF_FLOOR], [FOOT_OFF_FLOOR], 0.20),  # the weak step's face is off it too
    ],
)
def test_with_no_rig_a_weaker_step_below_a_sure_face_off_the_floor_is_the_nearer_foot(
    upper_doubts: list[str],
    weak_doubts: list[str],
    expected: float,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A face accepted on a row whose own outline finds its foot off the floor
    (FOOT_OFF_FLOOR: a band on the wall, a print, the face's upper part) stands on no floor
    contact: a weaker step below it whose face stands on the floor is the foot (photo 1188:
    a bricked face of nearly the floor's colour, its foot a step under the noise bar)."""

    image, truth, view, depth = no_rig_room(4001)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (0.20, 0.30)}
    outcome = {0.20: (0.5, upper_doubts), 0.30: (0.3, weak_doubts)}

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        height = round(self.view.rig.camera_height_m, 2)
        if self.view.rig.camera_pitch_deg or height not in outcome or kwargs.get("floor_known"):
            return Measurement(detected=False, method="fused", range_m=truth["range_m"])
        conf, doubts = outcome[height]
        box = (100.0, row_at[height] - 50.0, 200.0, float(row_at[height]))
        return fake_face(truth, True, conf, height_m=0.3, box_px=box, doubts=list(doubts))

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[0.20]])
    monkeypatch.setattr(measure, "weak_contact_rows", lambda *a: [row_at[0.30], row_at[0.20]])
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected
    assert res.camera_height_m == pytest.approx(expected, abs=0.01)


def test_weak_contact_rows_reach_past_a_coarse_floors_steps_to_the_foot() -> None:
    """On gravel near the lens the band's rows step as much as a face's foot does, a dozen
    times under a far face: the weak steps still reach its foot (photo 1181 ordinary, a
    panelled face 3 m away, its foot the 15th step from the bottom)."""
    image, truth, spec = render_room("photo", 1181, False, CAM)
    view = View(CAM, Rig(), "level")
    depth = Rig().face_depth(truth["range_m"])
    rig = spec.rig
    # the foot in the level view: the true rig's contact row
    foot = view.cy + view.fy * np.tan(
        np.arctan(rig.camera_height_m / depth) - np.radians(rig.camera_pitch_deg)
    )
    rows = weak_contact_rows(image, view, depth)
    assert any(abs(r - foot) <= 3 for r in rows)


def boxed(x0: float, x1: float, conf: float = 0.6) -> Measurement:
    """A detected face spanning columns x0..x1 (rows 100..200)."""
    return Measurement(
        detected=True, method="fused", range_m=1.0, confidence=conf, box_px=(x0, 100, x1, 200)
    )


def test_a_sure_face_of_another_trial_beside_the_face_is_a_rival() -> None:
    """Two no-rig trials (another guessed camera height or pitch) found sure faces side by
    side: the face measured is one the unknown rig decides between (TRIAL_RIVAL); a wider
    or narrower reading of the same face, or a rival not standing on its foot, is not."""
    best = boxed(100, 160)
    beside = boxed(180, 220)
    assert measure._rival_trial(best, [best, beside], lambda r: True)
    assert not measure._rival_trial(best, [best, beside], lambda r: False)  # not standing
    assert not measure._rival_trial(best, [best, boxed(90, 175)], lambda r: True)  # same face
    assert not measure._rival_trial(best, [best, boxed(130, 200)], lambda r: True)  # half of it
    assert measure._rival_trial(best, [boxed(135, 220)], lambda r: True)  # a quarter shared


def test_with_no_rig_a_rival_trial_face_takes_the_answer_under_half(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The doubt reaches the reported confidence: a sure face (0.7) with a sure rival
    beside it from a trial at another guessed pitch is reported under 0.5."""
    # both faked faces reach into the sonar's beam (BEAM_HOLDS_FACE: at 0.9 m, columns
    # 188-309, 137-360 with no rig's mounting allowance), so the rule stays on
    image, truth, view, depth = no_rig_room(4001)
    row = int(round(view.cy + view.fy * 0.20 / depth))

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        if kwargs.get("floor_known"):
            return Measurement(detected=False, method="fused", range_m=truth["range_m"])
        pitch = self.view.rig.camera_pitch_deg
        x0 = 130.0 if pitch <= 0 else 300.0  # the guessed pitch decides which face
        return fake_face(truth, True, 0.7 if pitch == 0 else 0.3, box_px=(x0, 100, x0 + 60, 200))

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected
    assert measure.TRIAL_RIVAL in res.doubts
    assert (res.confidence or 0.0) < 0.5


def test_with_no_rig_a_face_only_the_known_floor_cues_find_is_taken_at_the_lowest_row(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """When no row stands a face while the rows are only tried (no texture search, no beam
    axis), each row is tried again with those cues, lowest first: a face whose edges are
    lost in its print is measured, not missed."""

    image, truth, view, depth = no_rig_room(4002)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (0.20, 0.30)}
    calls: list[tuple[float, bool]] = []

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        height = round(self.view.rig.camera_height_m, 2)
        known = bool(kwargs.get("floor_known", True))
        calls.append((height, known))
        return fake_face(
            truth, known, 0.1, height_m=0.3
        )  # only the known-floor cues find it, on any row

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[0.30], row_at[0.20]])
    monkeypatch.setattr(measure, "MAX_ESTIMATED_PITCH_DEG", 0.0)  # no near-horizon rows
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected
    assert res.camera_height_m == pytest.approx(0.30, abs=0.01)
    assert calls[:3] == [(0.30, False), (0.20, False), (0.30, True)]


def test_with_no_rig_a_row_whose_face_does_not_stand_on_it_is_passed_over(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A floor line below the face stands the face found on it only if the face's sides
    reach it (floor_contact.sides_reach_foot); else the next row up is tried."""

    image, truth, view, depth = no_rig_room(4003)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (0.20, 0.30)}

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        height = round(self.view.rig.camera_height_m, 2)
        if height not in row_at:  # a neighbour row (ROW_JITTER_PX): no face there
            return Measurement(detected=False, method="fused", range_m=truth["range_m"])
        foot = float(row_at[height])
        return fake_face(
            truth,
            True,
            0.6,
            height_m=0.3,
            lines=[(0, foot, 1, foot), (0, 0, 1, 0), (0, foot, 0, 0), (1, foot, 1, 0)],
        )

    def standing(image: object, lines: list[tuple[float, float, float, float]]) -> bool:
        return lines[0][1] != row_at[0.30]  # the lower row's face ends above it

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[0.30], row_at[0.20]])
    monkeypatch.setattr(measure, "sides_reach_foot", standing)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected
    assert res.camera_height_m == pytest.approx(0.20, abs=0.01)
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.camera_height_m == pytest.approx(0.30, abs=0.01)


@pytest.mark.parametrize("surest_offset", [-2, 0, 2])
def test_with_no_rig_the_surest_face_of_the_row_and_its_neighbours_is_kept(
    surest_offset: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The floor-contact row is found to a pixel or two and a level view's face can change
    with it: the rows ROW_JITTER_PX (2) above and below the chosen one are tried too, and
    the surest face of the three is kept (rows 3 px off are not tried)."""

    image, truth, view, depth = no_rig_room(4004)
    found = int(round(view.cy + view.fy * 0.25 / depth))
    tried: list[int] = []

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        row = int(round(view.cy + view.fy * self.view.rig.camera_height_m / depth))
        tried.append(row - found)
        return fake_face(
            truth,
            True,
            0.9 if row - found == surest_offset else 0.3,
            height_m=0.3 + 0.01 * (row - found),
        )

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [found])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert tried[:3] == [0, -2, 2]
    assert res.height_m == pytest.approx(0.3 + 0.01 * surest_offset)


@pytest.mark.parametrize("runs_below", [True, False])
def test_with_no_rig_a_print_accepted_above_a_lower_face_gives_way_to_it(
    runs_below: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A print on the face is found, sure, on its own lower edge; the face itself was found
    less surely on the row below: when the print's margin runs down to that row
    (floor_contact.face_runs_below), the lower face is kept."""

    image, truth, view, depth = no_rig_room(4005)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (0.20, 0.30)}
    sure = {0.30: 0.1, 0.20: 0.9}  # the lower row's face is not accepted, the print is

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        height = round(self.view.rig.camera_height_m, 2)
        if self.view.rig.camera_pitch_deg or height not in row_at:  # other pitches, rows
            return Measurement(detected=False, method="fused", range_m=truth["range_m"])
        foot = float(row_at[height])
        return fake_face(
            truth, True, sure[height], height_m=height, box_px=(100.0, 50.0, 200.0, foot)
        )

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[0.30], row_at[0.20]])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    monkeypatch.setattr(measure, "face_runs_below", lambda *a: runs_below)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.camera_height_m == pytest.approx(0.30 if runs_below else 0.20, abs=0.01)


def test_with_no_rig_a_stream_whose_last_height_stands_an_unsure_face_does_not_fail(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The second frame of a stream tries the last frame's camera height first; when that
    stands a face not sure enough to accept and no row stands another, the face is kept,
    and no neighbour row of a row never tried (a camera height under the floor) is tried."""

    image, truth, view, depth = no_rig_room(4006)
    found = int(round(view.cy + view.fy * 0.25 / depth))
    frame = [0]

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        assert self.view.rig.camera_height_m > 0.0
        sure = 0.6 if frame[0] == 0 else 0.1
        return Measurement(
            detected=frame[0] == 0
            or self.view.rig.camera_height_m == pytest.approx(0.25, abs=0.01),
            method="fused",
            range_m=truth["range_m"],
            height_m=0.3,
            width_m=0.3,
            confidence=sure,
        )

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [found])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    measurer = Measurer(CAM, None)
    first = measurer.measure(image, truth["range_m"])
    assert first.detected
    frame[0] = 1
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [])
    second = measurer.measure(image, truth["range_m"])
    assert second.detected


@pytest.mark.parametrize(("gain", "taken"), [(0.16, True), (0.15, False)])
def test_with_no_rig_the_row_is_tried_at_usual_pitches_and_a_clearly_surer_face_kept(
    gain: float, taken: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The pitch is unknown until the face's sides read it: the chosen row is tried at
    -4, -2, +2 and +4 degrees too, and a face at least 0.15 surer than the level view's is
    kept (with the camera height that row gives at that pitch)."""

    image, truth, view, depth = no_rig_room(4007)
    found = int(round(view.cy + view.fy * 0.30 / depth))
    pitches: list[float] = []

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        pitch = self.view.rig.camera_pitch_deg
        pitches.append(pitch)
        return fake_face(
            truth, True, (0.1 + gain) if pitch == 2.0 else 0.1, height_m=0.3 + 0.01 * pitch
        )

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [found])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert sorted(set(pitches)) == [-4.0, -2.0, 0.0, 2.0, 4.0]
    assert res.height_m == pytest.approx(0.32 if taken else 0.30)
    if taken:
        assert res.camera_pitch_deg == 2.0
        expected = measure.camera_height_for_row(found, depth, 2.0, view.fy, view.cy)
        assert res.camera_height_m == pytest.approx(expected)


def _fake_faces(
    truth: dict[str, float], conf_at: dict[float, float], calls: list[tuple[float, float, bool]]
) -> object:
    """A FusedMethod.run that finds a face of confidence ``conf_at[pitch]`` (none at other
    pitches) and records (camera height, pitch, floor_known) of each call."""

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        pitch = self.view.rig.camera_pitch_deg
        calls.append((self.view.rig.camera_height_m, pitch, bool(kwargs.get("floor_known", True))))
        return fake_face(
            truth, pitch in conf_at, conf_at.get(pitch, 0.0), height_m=0.3 + 0.01 * pitch
        )

    return fake_run


@pytest.mark.parametrize(
    "swept_box, taken",
    [
        ((210.0, 150.0, 310.0, 200.0), True),  # the level face read again: taken
        ((250.0, 150.0, 410.0, 200.0), True),  # half the narrower face's columns shared
        ((280.0, 150.0, 440.0, 200.0), False),  # a surer face beside it: not taken
    ],
)
def test_with_no_rig_a_swept_pitch_takes_the_level_face_read_again_not_a_face_beside_it(
    swept_box: tuple[float, float, float, float],
    taken: bool,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Room photo/102 (hard) in small: the level view finds the box (confidence 0.15); at
    +4 degrees the guessed camera height stands a wall print beside it (0.34, surer by
    more than SWEPT_PITCH_MARGIN), which was taken (width +103 %). A swept pitch moves a
    face's top and foot, not its sides: a face sharing under half the narrower face's
    columns with the level one is another face, and the level face stays."""
    # faked faces beside the axis: that rule apart
    monkeypatch.setattr(measure, "AXIS_UNSURE_TRIAL", False)
    image, truth, view, depth = no_rig_room(4007)
    found = int(round(view.cy + view.fy * 0.30 / depth))
    level_box = (200.0, 150.0, 300.0, 200.0)

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        pitch = self.view.rig.camera_pitch_deg
        if pitch == 4.0:
            return fake_face(truth, True, 0.34, height_m=0.2, box_px=swept_box)
        return fake_face(truth, True, 0.15 if pitch == 0.0 else 0.05, box_px=level_box)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [found])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected
    assert res.height_m == pytest.approx(0.2 if taken else 0.3)
    assert res.camera_pitch_deg == (4.0 if taken else 0.0)


def test_with_no_rig_photo_102_the_box_not_the_print_beside_it() -> None:
    """Room photo/102 (hard): with no rig the level view finds the gloss box (within 5 %);
    at +4 degrees a wall print beside it stood a surer face (width +103 %). The box is
    measured: within 10 % in both."""
    _assert_measured_without_rig("photo", 102, True, rel=0.10)


def test_with_no_rig_the_surest_of_the_swept_pitches_wins_in_any_order(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """-4 degrees passes the margin first, +2 is surer still: +2 is kept (each swept face
    is held to the level view's confidence, not to the one before it)."""

    image, truth, view, depth = no_rig_room(4008)
    found = int(round(view.cy + view.fy * 0.30 / depth))
    calls: list[tuple[float, float, bool]] = []
    fake = _fake_faces(truth, {0.0: 0.1, -4.0: 0.3, 2.0: 0.4}, calls)
    monkeypatch.setattr(FusedMethod, "run", fake)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [found])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.camera_pitch_deg == 2.0


def test_with_no_rig_a_stream_does_not_carry_on_a_pitch_only_guessed(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A face surest at a swept pitch whose sides read no pitch: the next frame seeks the
    rows again (level first), it does not start from the guessed pitch."""

    image, truth, view, depth = no_rig_room(4009)
    found = int(round(view.cy + view.fy * 0.30 / depth))
    calls: list[tuple[float, float, bool]] = []
    monkeypatch.setattr(FusedMethod, "run", _fake_faces(truth, {0.0: 0.3, 2.0: 0.6}, calls))
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [found])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    monkeypatch.setattr(measure.Measurer, "_with_pitch", lambda *a: None)  # sides read none
    measurer = Measurer(CAM, None)
    assert measurer.measure(image, truth["range_m"]).camera_pitch_deg == 2.0
    calls.clear()
    measurer.measure(image, truth["range_m"])
    assert calls[0][1] == 0.0  # the level view's row first, no guessed pitch carried on


def test_with_no_rig_a_stream_carries_on_a_face_found_with_the_known_floor_cues(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A face only the known-floor cues find (texture, the beam's axis) is sure enough to
    carry on: the next frame tries its camera height with those cues, one trial."""

    image, truth, view, depth = no_rig_room(4010)
    found = int(round(view.cy + view.fy * 0.30 / depth))
    calls: list[bool] = []

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        known = bool(kwargs.get("floor_known", True))
        calls.append(known)
        return fake_face(truth, known, 0.6, height_m=0.3)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [found])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    monkeypatch.setattr(measure.Measurer, "_with_pitch", lambda *a: None)
    measurer = Measurer(CAM, None)
    assert measurer.measure(image, truth["range_m"]).detected
    calls.clear()
    assert measurer.measure(image, truth["range_m"]).detected
    assert calls == [True]


@pytest.mark.parametrize("rows_stand_a_face", [True, False])
def test_with_no_rig_a_streams_unsure_face_is_kept_only_when_the_rows_stand_none(
    rows_stand_a_face: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The last frame's camera height gives a face too unsure to accept: the rows are
    sought as in a first frame (their faces win), and that face is kept only when they
    stand none."""

    image, truth, view, depth = no_rig_room(4011)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (0.20, 0.30)}
    frame = [0]

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        height = round(self.view.rig.camera_height_m, 2)
        level = not self.view.rig.camera_pitch_deg
        if frame[0] == 0:
            hit, conf = level and height == 0.30, 0.6
        elif height == 0.30:  # the last frame's rig: a face, not a sure one
            hit, conf = level, 0.1
        else:
            hit, conf = level and height == 0.20 and rows_stand_a_face, 0.1
        return fake_face(truth, hit, conf, height_m=height)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[0.30]])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    monkeypatch.setattr(measure.Measurer, "_with_pitch", lambda *a: None)
    measurer = Measurer(CAM, None)
    assert measurer.measure(image, truth["range_m"]).height_m == pytest.approx(0.30)
    frame[0] = 1
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[0.20]])
    res = measurer.measure(image, truth["range_m"])
    assert res.detected
    assert res.height_m == pytest.approx(0.20 if rows_stand_a_face else 0.30)


def test_with_no_rig_faces_that_stand_on_no_row_are_named_in_the_reason(
    monkeypatch: pytest.MonkeyPatch,
) -> None:

    image, truth, view, depth = no_rig_room(4012)
    found = int(round(view.cy + view.fy * 0.30 / depth))
    calls: list[tuple[float, float, bool]] = []
    monkeypatch.setattr(FusedMethod, "run", _fake_faces(truth, {0.0: 0.6}, calls))
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [found])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: False)
    monkeypatch.setattr(measure, "MAX_ESTIMATED_PITCH_DEG", 0.0)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert not res.detected
    assert "did not stand on them" in (res.reason or "")


@pytest.mark.parametrize("drop, taken", [(0.04, True), (0.06, False)])
def test_with_no_rig_an_unread_pitchs_face_is_measured_again_allowing_a_top_face(
    drop: float, taken: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The pitch stays unread: the face is measured once more in a view whose horizon may
    lie fy tan(5 deg) rows higher, and that face kept unless its confidence is lower by
    more than 0.05."""

    image, truth, view, depth = no_rig_room(4013)
    found = int(round(view.cy + view.fy * 0.30 / depth))
    slacks: list[float] = []

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        slack = self.view.horizon_slack_px
        slacks.append(slack)
        if slack:
            return fake_face(truth, True, 0.6 - drop, height_m=0.25)
        return fake_face(truth, self.view.rig.camera_pitch_deg == 0.0, 0.6, height_m=0.3)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [found])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    monkeypatch.setattr(measure.Measurer, "_with_pitch", lambda *a: None)  # sides read none
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.height_m == pytest.approx(0.25 if taken else 0.30)
    assert slacks[-1] == pytest.approx(view.fy * np.tan(np.radians(5.0)))
    assert slacks.count(0.0) == len(slacks) - 1  # the rows and pitches tried level as before


@pytest.mark.parametrize("read", [True, False])
def test_with_no_rig_a_stream_allows_the_top_face_while_the_pitch_stays_unread(
    read: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The next frame starts from the last one's camera height and pitch, allowing for a
    top face above the guessed horizon as the last frame did when its pitch was unread,
    and not when the face's sides read it."""

    image, truth, view, depth = no_rig_room(4014)
    found = int(round(view.cy + view.fy * 0.30 / depth))
    slacks: list[float] = []

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        slacks.append(self.view.horizon_slack_px)
        return fake_face(truth, True, 0.6, height_m=0.3)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [found])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    monkeypatch.setattr(
        measure.Measurer, "_with_pitch", lambda self, found, *a: found if read else None
    )
    measurer = Measurer(CAM, None)
    assert measurer.measure(image, truth["range_m"]).detected
    slacks.clear()
    assert measurer.measure(image, truth["range_m"]).detected
    assert len(slacks) == 1 and (slacks[0] == 0.0) == read


@pytest.mark.parametrize("down_deg, good", [(5.0, True), (0.0, False)])
def test_with_no_rig_a_low_box_seen_from_above_is_not_measured_to_its_top_faces_back(
    down_deg: float, good: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A 0.2 m box 2.5 m ahead, the lens 0.45 m high looking 4.5 degrees down: its sides
    are too short to read the pitch, and the level guess puts its top face above the
    horizon. Allowing for the unread pitch, the front top edge is found (within 3 %);
    with no allowance, the top face's back edge (13 % too tall). The top face's band moves
    the top to the front with no rig too since session 43 (fused_method.
    TOP_FACE_TO_FRONT_NO_RIG, which finds this face by itself): off here, the allowance
    alone is tested."""
    monkeypatch.setattr(measure, "UNREAD_PITCH_DOWN_DEG", down_deg)
    monkeypatch.setattr(fused_method, "TOP_FACE_TO_FRONT_NO_RIG", False)
    spec = clean_room(3, range_m=2.5, height_m=0.2, width_m=0.6)
    spec = dataclasses.replace(
        spec, rig=dataclasses.replace(spec.rig, camera_pitch_deg=4.5, camera_height_m=0.45)
    )
    image, truth = RoomRenderer(CAM).render(spec)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected
    assert (abs(res.height_m / truth["height_m"] - 1.0) <= 0.03) == good


def test_with_no_rig_an_unsure_face_near_the_horizon_is_reported_rather_than_missed() -> None:
    """Room procedural/126 (ordinary): the lens 20 cm up, pitched 4.4 degrees down, a small
    face 2 m away standing just under the centre row. The pitched view near the horizon
    finds it (0.17, under the 0.2 a row's face needs to be taken at once) and nothing
    else stands a face: it is reported, unsure, within 3 %, not missed."""
    from obstacle_fusion.sim.room_scene import render_room

    image, truth, _ = render_room("procedural", 126, False)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert (res.confidence or 0.0) < 0.2
    assert res.height_m == pytest.approx(truth["height_m"], rel=0.03)
    assert res.width_m == pytest.approx(truth["width_m"], rel=0.03)


def test_weak_contact_rows_take_the_steps_no_bar_lets_through(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A floor stepping darker every 12 rows, 15 times: each step is as strong as the
    band's and the floor's own texture, so no row stands out of :func:`contact_rows`; the
    weak steps are every one of them, lowest first, up to
    floor_contact.MAX_WEAK_CANDIDATES (all 15 at its 24; the lowest 12 under a cap of 12)."""
    h, w = 375, 500
    img = np.full((h, w, 3), 200, np.uint8)
    edges = list(range(200, 370, 12))
    assert len(edges) == 15
    for i, r in enumerate(edges):
        img[r:] = 200 - 12 * (i + 1)
    view = View(CAM, Rig(), "level")
    flat = View(CameraModel(view.k.copy(), np.zeros(5), w, h), Rig(), "level")
    assert contact_rows(img, flat, depth_m=1.5) == []
    weak = weak_contact_rows(img, flat, depth_m=1.5)
    assert len(weak) == 15
    assert all(abs(r - e) <= 1 for r, e in zip(weak, edges[::-1], strict=True)), weak
    monkeypatch.setattr(floor_contact, "MAX_WEAK_CANDIDATES", 12)
    weak = weak_contact_rows(img, flat, depth_m=1.5)
    assert len(weak) == 12
    assert all(abs(r - e) <= 1 for r, e in zip(weak, edges[::-1], strict=False)), weak


def _swept_room(
    monkeypatch: pytest.MonkeyPatch, confirm: bool, stands: bool = True, level_conf: float = 0.0
) -> tuple[Measurement, list[tuple[float, float]], dict[float, int], float]:
    """A room whose level rows stand no face: a fake method finds one only in a view
    pitched 4 degrees down, on either of two rows (a floor-contact row and a weak step
    below it); the face's sides confirm the pitch when ``confirm``. Returns the answer, the
    (camera height, pitch) of each trial, the rows and the face depth."""
    image, truth, view, depth = no_rig_room(4001)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (0.25, 0.35)}
    calls: list[tuple[float, float]] = []

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        calls.append((self.view.rig.camera_height_m, self.view.rig.camera_pitch_deg))
        if kwargs.get("floor_known"):
            return fake_face(truth, False, 0.0)
        if self.view.rig.camera_pitch_deg == 4.0:
            return fake_face(truth, True, 0.3, height_m=0.3)
        level = self.view.rig.camera_height_m == pytest.approx(row_height(row_at[0.25], depth, 0))
        return fake_face(truth, level and level_conf > 0, level_conf, height_m=0.3)

    def with_pitch(self: Measurer, found: Measurement, *args: object) -> Measurement | None:
        return found if confirm else None

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[0.25]])
    monkeypatch.setattr(measure, "weak_contact_rows", lambda *a: [row_at[0.35], row_at[0.25]])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: stands)
    monkeypatch.setattr(Measurer, "_with_pitch", with_pitch)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    return res, calls, row_at, depth


def test_with_no_rig_and_no_face_anywhere_the_rows_are_swept_over_pitches(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Nothing stands a face level (rows, neighbours, known-floor cues): the rows and the
    weak steps, lowest first, at the swept pitches, the weak step level too; the first face
    whose sides read the pitch is taken, its pitch read (no PITCH_UNREAD doubt)."""
    res, calls, row_at, depth = _swept_room(monkeypatch, confirm=True)
    assert res.detected, res.reason
    assert res.camera_height_m == pytest.approx(row_height(row_at[0.35], depth, 4.0), abs=0.01)
    assert res.camera_pitch_deg == 4.0
    assert PITCH_UNREAD not in res.doubts
    # the weak step (not a contact row) is tried level first, then at the pitches in order
    swept = [p for h, p in calls if h == pytest.approx(row_height(row_at[0.35], depth, p))]
    assert swept[:4] == [0.0, -4.0, -2.0, 2.0]


def test_with_no_rig_a_stream_that_swept_in_vain_rests_the_sweep_for_some_frames(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Nothing in view: the sweep (up to ~90 trials) finds nothing, and the stream's next
    SWEEP_REST_FRAMES frames go without it; the frame after them sweeps again, and a sweep
    that finds a face leaves the next frame free to sweep."""
    image, truth, _, _ = no_rig_room(4001)
    sweeps: list[int] = []
    found: list[Measurement | None] = [None]

    def sweep(self: Measurer, *args: object) -> tuple[Measurement | None, bool]:
        sweeps.append(frame[0])
        return found[0], True

    monkeypatch.setattr(FusedMethod, "run", lambda self, *a, **k: fake_face(truth, False, 0.0))
    monkeypatch.setattr(Measurer, "_pitch_swept_rows", sweep)
    m = Measurer(CAM, None)
    frame = [0]
    for frame[0] in range(23):
        assert not m.measure(image, truth["range_m"]).detected
    assert sweeps == [0, 11, 22]  # ten frames' rest after each vain sweep
    found[0] = dataclasses.replace(
        fake_face(truth, True, 0.3), camera_height_m=0.3, camera_pitch_deg=2.0
    )
    sweeps.clear()
    m = Measurer(CAM, None)
    for frame[0] in range(3):
        assert m.measure(image, truth["range_m"]).detected
    assert sweeps == [0, 1, 2]


def row_height(row: int, depth: float, pitch: float) -> float:
    """The camera height a level view's row gives at a pitch."""
    view = View(CAM, Rig(), "level")
    return measure.camera_height_for_row(row, depth, pitch, view.fy, view.cy)


def test_with_no_rig_a_swept_face_whose_sides_read_no_pitch_is_taken_doubted(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A face found only at a guessed pitch, its sides not reading one: the lowest row's
    sure face is measured at its guessed pitch, doubted (PITCH_UNREAD), rather than
    missed."""
    res, calls, row_at, depth = _swept_room(monkeypatch, confirm=False)
    assert res.detected, res.reason
    assert res.camera_pitch_deg == 4.0
    assert res.camera_height_m == pytest.approx(row_height(row_at[0.35], depth, 4.0), abs=0.01)
    assert PITCH_UNREAD in res.doubts


def test_with_no_rig_a_swept_face_whose_sides_end_above_the_row_is_not_taken(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    res, _, _, _ = _swept_room(monkeypatch, confirm=True, stands=False)
    assert not res.detected


def test_with_no_rig_the_sweep_is_not_tried_when_a_row_stands_a_face(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The sweep acts only where everything else found nothing: a face on the contact row,
    however unsure, is the answer, and no weak step is tried at the swept pitches (the weak
    step below it is tried level only, as a nearer foot: it stands no face here)."""
    res, calls, row_at, depth = _swept_room(monkeypatch, confirm=True, level_conf=0.1)
    assert res.detected
    # the contact row's face (its own pitch sweep takes the surer one at 4 degrees)
    at_row = [row_height(row_at[0.25], depth, p) for p in (0.0, 4.0)]
    assert any(res.camera_height_m == pytest.approx(h, abs=0.01) for h in at_row)
    weak = [row_height(row_at[0.35], depth, p) for p in measure.SWEPT_PITCHES_DEG]
    assert not any(h == pytest.approx(w) for h, _ in calls for w in weak)
    level_weak = row_height(row_at[0.35], depth, 0.0)
    assert [p for h, p in calls if h == pytest.approx(level_weak)] == [0.0]


def test_with_no_rig_a_pitched_lens_missed_level_is_found_by_the_sweep(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Room procedural/141 (ordinary): the lens pitched 5 degrees down, 0.85 m from a gloss
    face. Its foot is found (row 360) but the level guess of the camera height (0.33 m, not
    0.42) stands no face there, nor does any other cue; at a swept 4 degrees the face
    shows, its sides read 4.8 and it is measured within 1 %, unsure. Without the sweep it
    was missed. (The walk up the gloss face's hue, method.HUE_HOLDS_TOP, finds the whole
    face at the level guess already, its size at that guess's scale, -1.9 %: off here,
    the sweep is what this room tries.)"""
    monkeypatch.setattr(fused_method, "HUE_HOLDS_TOP", False)
    # (nor the frame closing over a print, FRAME_CLOSES_TOP: it finds the whole face at the
    # level guess too)
    monkeypatch.setattr(fused_method, "FRAME_CLOSES_TOP", False)
    image, truth, spec = render_room("procedural", 141, False, CAM)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.height_m == pytest.approx(truth["height_m"], rel=0.01)
    assert res.width_m == pytest.approx(truth["width_m"], rel=0.01)
    assert res.camera_pitch_deg == pytest.approx(spec.rig.camera_pitch_deg, abs=0.5)
    assert (res.confidence or 0.0) < 0.5
    monkeypatch.setattr(Measurer, "_pitch_swept_rows", lambda *a: (None, False))
    assert not Measurer(CAM, None).measure(image, truth["range_m"]).detected


def test_with_no_rig_a_foot_stepping_less_than_the_gravel_is_found_by_the_sweep(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Room photo/143 (ordinary): a purple panelled face on grey gravel, the lens pitched
    4 degrees down. The foot steps 16 in colour, the gravel's texture as much: no bar lets
    it through, and the one row that stands out (a gravel step) stands no face. Among the
    weak steps it is the seventh from the bottom; swept, its face's sides read the pitch and
    it is measured within 3 %, unsure."""
    image, truth, _ = render_room("photo", 143, False, CAM)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.height_m == pytest.approx(truth["height_m"], rel=0.03)
    assert res.width_m == pytest.approx(truth["width_m"], rel=0.03)
    assert (res.confidence or 0.0) < 0.5
    monkeypatch.setattr(floor_contact, "MAX_WEAK_CANDIDATES", 6)
    assert not Measurer(CAM, None).measure(image, truth["range_m"]).detected


@pytest.mark.parametrize(
    "band_height_px, expected",
    [
        (8.0, 0.30),  # 8 px tall, 200 wide: a band along the wall, the row below's face
        (40.0, 0.20),  # 40 px tall: a face, and the lowest row's sure face is the contact
    ],
)
def test_with_no_rig_a_band_along_the_wall_is_no_face(
    band_height_px: float, expected: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A row guessed for the floor contact that stands only a long low strip (a wall's
    foot, a skirting board: under measure.BAND_MAX_ASPECT as tall as wide) stands no
    face: the rows go on, and the next row's face is taken."""
    image, truth, view, depth = no_rig_room(4001)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (0.20, 0.30)}

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        height = round(self.view.rig.camera_height_m, 2)
        if self.view.rig.camera_pitch_deg or height not in row_at:
            return Measurement(detected=False, method="fused", range_m=truth["range_m"])
        foot = float(row_at[height])
        tall = band_height_px if height == 0.20 else 60.0
        return fake_face(truth, True, 0.8, box_px=(150.0, foot - tall, 350.0, foot))

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[0.20], row_at[0.30]])
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.camera_height_m == pytest.approx(expected, abs=0.01)
    assert measure.BAND_MAX_ASPECT * 200.0 > 8.0


@pytest.mark.parametrize(
    "sure_box, expected",
    [
        ((260.0, -60.0, 420.0, -8.0), 0.30),  # foot inside the band's rows: on the wall
        ((260.0, -60.0, 420.0, 0.0), 0.15),  # foot at the band's lower edge: kept
        ((260.0, -90.0, 420.0, -30.0), 0.15),  # band wholly below (a floor line): kept
        ((455.0, -60.0, 495.0, -8.0), 0.15),  # beside the band (no columns shared): kept
        ((150.0, -60.0, 350.0, -8.0), 0.15),  # band centred under it (its shadow): kept
    ],
)
def test_with_no_rig_a_face_standing_in_a_wall_band_is_no_face(
    sure_box: tuple[float, float, float, float],
    expected: float,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """With no rig, a row lower down stands a band along the wall (the wall's foot, a
    skirting board): a sure face found on a higher row whose foot ends inside the band's
    rows, over its columns, stands on the wall behind the obstacle (a poster, a print) and
    is no face; the lowest row's unsure face is measured instead. A face whose foot reaches
    the band's lower edge, or lies above a band wholly below it (a floor line, a contact
    shadow as photo/304 hard), or stands beside the band, or over a band under its whole
    width and centred on it (its contact shadow), is kept."""
    # faked faces beside the axis, and one wholly beside the beam: those rules apart
    monkeypatch.setattr(measure, "AXIS_UNSURE_TRIAL", False)
    monkeypatch.setattr(measure, "BEAM_HOLDS_FACE", False)
    image, truth, view, depth = no_rig_room(4001)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (0.15, 0.20, 0.30)}
    band_foot = float(row_at[0.20])

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        height = round(self.view.rig.camera_height_m, 2)
        if self.view.rig.camera_pitch_deg or height not in row_at:
            return Measurement(detected=False, method="fused", range_m=truth["range_m"])
        foot = float(row_at[height])
        if height == 0.30:  # the obstacle's own foot: a face, unsure
            return fake_face(truth, True, 0.1, box_px=(220.0, foot - 50.0, 280.0, foot))
        if height == 0.20:  # a band along the wall, 16 px tall and 400 wide
            return fake_face(truth, True, 0.8, box_px=(50.0, foot - 16.0, 450.0, foot))
        x0, y0, x1, y1 = sure_box  # a sure face, rows relative to the band's foot
        return fake_face(truth, True, 0.8, box_px=(x0, band_foot + y0, x1, band_foot + y1))

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(
        measure, "contact_rows", lambda *a: [row_at[0.30], row_at[0.20], row_at[0.15]]
    )
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.camera_height_m == pytest.approx(expected, abs=0.01)


def test_with_no_rig_a_poster_above_the_walls_foot_is_not_measured() -> None:
    """Room procedural/910 (hard): with no rig, a row above the poster-faced box's foot
    stood a face on the wall behind it, its foot in the wall's band (width +412 %); as a
    face standing in the band it stands no face, and the box's own face is measured within
    25 %."""
    _assert_measured_without_rig("procedural", 910, True, rel=0.25)


def test_with_no_rig_a_contact_shadow_below_the_face_does_not_hide_it() -> None:
    """Room photo/304 (hard): with no rig, a row below the planked face stands a band
    (its contact shadow on the floor, rows wholly below the face's foot); the face above it
    is no wall face standing in a band, and is measured within 5 %."""
    _assert_measured_without_rig("photo", 304, True, rel=0.05)


def test_with_no_rig_a_shadow_band_under_the_face_does_not_hide_it() -> None:
    """Room photo/969 (ordinary): with no rig, a row just below the panelled face stands a
    band (its contact shadow, under the whole face and centred on it) whose top reaches a
    pixel above the face's foot; the face is no wall face standing in a band, and is
    measured within 5 %."""
    _assert_measured_without_rig("photo", 969, False, rel=0.05)


def test_with_no_rig_a_skirting_band_is_passed_over_for_the_face_below(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Room procedural/346 (hard): with no rig, the rows above the planked face's foot
    stand a long low strip along the wall (15 px tall, 350 wide, confidence 0.85) that
    was taken for the face (width +108 %); as a band it stands no face, and the lowest
    row's face is measured within 5 %. (With the band taken, the face wholly under it on
    the beam's axis stands nearer, and ``NEARER_ON_AXIS`` takes it too: off here.)"""
    image, truth, _ = render_room("procedural", 346, True, CAM)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.height_m == pytest.approx(truth["height_m"], rel=0.05)
    assert res.width_m == pytest.approx(truth["width_m"], rel=0.05)
    monkeypatch.setattr(measure, "BAND_MAX_ASPECT", 0.0)
    monkeypatch.setattr(measure, "NEARER_ON_AXIS", False)
    band = Measurer(CAM, None).measure(image, truth["range_m"])
    assert band.width_m is not None and band.width_m > 1.5 * truth["width_m"]


def test_with_no_rig_an_unconfirmed_swept_face_is_measured_not_missed() -> None:
    """Room procedural/135 (ordinary): the one row that stands out is the wall's foot,
    standing only a band; no row stands a face level, and swept, the lowest sure face
    (the face's own foot, 4 degrees down) has sides that read no pitch. Taken at
    its guessed pitch: within 5 %, doubted."""
    image, truth, _ = render_room("procedural", 135, False, CAM)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.height_m == pytest.approx(truth["height_m"], rel=0.05)
    assert res.width_m == pytest.approx(truth["width_m"], rel=0.05)
    assert PITCH_UNREAD in res.doubts


@pytest.mark.parametrize(
    "upper_box, expected",
    [
        ((50.0, -60.0, 450.0, 0.0), 0.30),  # a strip along the wall (0.15 as tall as wide)
        ((150.0, -160.0, 350.0, 0.0), 0.20),  # a face as tall as wide: it stays
        ((220.0, -40.0, 480.0, 0.0), 0.20),  # a strip not spanning the lower face
    ],
)
def test_with_no_rig_an_unsure_face_under_a_strip_along_the_wall_is_the_nearer_foot(
    upper_box: tuple[float, float, float, float],
    expected: float,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Room photo/151 in small: the wall's foot stands an unsure strip (a face 0.13 as tall
    as wide, right across the room) and a weak step below it an unsure face within its
    columns (confidence 0.10, under ESTIMATE_ACCEPT). The sonar measured the nearer
    surface: the lower face, when the upper one is a strip spanning it
    (measure.SPAN_FACTOR, STRIP_MAX_ASPECT); else the upper row stays."""
    image, truth, view, depth = no_rig_room(4001)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (0.20, 0.30)}
    outcome = {0.20: 0.12, 0.30: 0.10}
    box_at = {
        0.20: tuple(v + (row_at[0.20] if i % 2 else 0.0) for i, v in enumerate(upper_box)),
        0.30: (200.0, row_at[0.30] - 50.0, 300.0, float(row_at[0.30])),
    }

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        height = round(self.view.rig.camera_height_m, 2)
        if self.view.rig.camera_pitch_deg or height not in outcome or kwargs.get("floor_known"):
            return Measurement(detected=False, method="fused", range_m=truth["range_m"])
        return fake_face(truth, True, outcome[height], height_m=0.3, box_px=box_at[height])

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[0.20]])
    monkeypatch.setattr(measure, "weak_contact_rows", lambda *a: [row_at[0.30], row_at[0.20]])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected
    assert res.camera_height_m == pytest.approx(expected, abs=0.01)


def test_with_no_rig_photo_151_the_face_below_the_wall_strip() -> None:
    """Room photo/151 (ordinary): the wall's foot stood an unsure strip 1.4 m wide taken for
    the face (width +389 %); the weak step below it stands the face, unsure: its height
    within 7 %, its width within 5 %."""
    image, truth, _ = render_room("photo", 151, False, CAM)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.height_m == pytest.approx(truth["height_m"], rel=0.07)
    assert res.width_m == pytest.approx(truth["width_m"], rel=0.05)


@pytest.mark.parametrize(
    "lower_conf, lower_doubts, expected",
    [
        (0.10, [], 0.30),  # an unsure face on the lowest row: the contact
        (0.10, ["floor_in_face"], 0.20),  # unsure, floor taken in: the face above it
        (0.40, ["floor_in_face"], 0.20),  # sure, floor taken in: the face above it
        (0.40, [], 0.30),  # sure: the contact
    ],
)
def test_with_no_rig_a_face_that_took_floor_in_settles_no_row(
    lower_conf: float,
    lower_doubts: list[str],
    expected: float,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A face whose lowest band has the colour of what lies under it (FLOOR_IN_FACE: a
    floor tile between two joints, a face's strip run down over its shadow) stands on a
    row below the true foot: the lowest face above it without that doubt is taken."""
    image, truth, view, depth = no_rig_room(4001)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (0.20, 0.30)}

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        height = round(self.view.rig.camera_height_m, 2)
        if self.view.rig.camera_pitch_deg or height not in row_at or kwargs.get("floor_known"):
            return Measurement(detected=False, method="fused", range_m=truth["range_m"])
        box = (200.0, row_at[height] - 80.0, 300.0, float(row_at[height]))
        if height == 0.30:
            return fake_face(truth, True, lower_conf, box_px=box, doubts=list(lower_doubts))
        return fake_face(truth, True, 0.12, box_px=box)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[0.30], row_at[0.20]])
    monkeypatch.setattr(measure, "weak_contact_rows", lambda *a: [row_at[0.30], row_at[0.20]])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected
    assert res.camera_height_m == pytest.approx(expected, abs=0.01)


@pytest.mark.parametrize(
    "family, seed, was",
    [
        ("photo", 126, "a panel's strip run down over its shadow, width -70 %"),
        ("procedural", 154, "a floor tile between grid lines, height -81 %"),
    ],
)
def test_with_no_rig_rooms_whose_lowest_face_took_floor_in(
    family: str, seed: int, was: str
) -> None:
    """Ordinary rooms whose lowest standing face, taken before, had floor in it (``was``):
    the face above it is measured within 3 %."""
    _assert_measured_without_rig(family, seed, False, rel=0.03)


def test_with_no_rig_a_framed_print_stands_on_the_box_foot_below_it() -> None:
    """Room procedural/143 (ordinary): a brick print in a purple frame; the only contact
    row is the print's lower edge, where the print is a sure face (0.92, framed_print),
    and the box's foot is a weak step 8 rows below (the frame's colour between them):
    there the whole box stands, measured within 3 % (the print was 13-16 % small)."""
    _assert_measured_without_rig("procedural", 143, False, rel=0.03)


@pytest.mark.parametrize(("doubts", "detected"), [(3, True), (4, False)])
def test_with_no_rig_a_face_doubted_on_every_count_is_no_answer(
    doubts: int, detected: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Rooms procedural/108, photo/327, photo/349 (hard): with no rig the guessed rig stood
    faces 67-115 % off that their own outline doubted on 4-6 counts (a stripe, a print, a
    band), reported at the floor confidence 0.05. A face whose confidence with its doubts
    applied is under measure.MIN_DOUBTED_CONFIDENCE is no answer, with the reason; with
    three doubts besides the unread pitch (0.5 x 0.45^4 = 0.02) it stays. With a rig file
    the same face is reported."""
    image, truth, view, depth = no_rig_room(4001)
    found = int(round(view.cy + view.fy * 0.30 / depth))
    names = ["top_from_sides", "uneven_sides", "skewed_edges", "second_top_edge"][:doubts]

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        return fake_face(truth, True, 0.5, doubts=list(names))

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [found])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    measurer = Measurer(CAM, None)
    res = measurer.measure(image, truth["range_m"])
    assert res.detected == detected
    if not detected:
        assert "doubted on every count" in res.reason
        assert measurer._last_rig is None  # not carried on to the next frame
    with_rig = Measurer(CAM, Rig()).measure(image, truth["range_m"])
    assert with_rig.detected


@pytest.mark.parametrize(
    ("swept_box", "swept_doubts", "answered"),
    [
        ((202.0, 101.0, 302.0, 201.0), ["top_from_sides"], True),  # the face, fewer doubts
        ((202.0, 101.0, 302.0, 201.0), ["near_rivals"], False),  # another doubt instead
        ((200.0, 40.0, 300.0, 200.0), ["top_from_sides"], False),  # a taller face: not it
        ((200.0, 100.0, 300.0, 205.0), ["top_from_sides"], False),  # on another foot row
        ((202.0, 101.0, 302.0, 201.0), ["foot_off_floor"], False),  # its foot still doubted
    ],
)
def test_with_no_rig_a_face_read_again_with_fewer_doubts_is_no_refusal(
    swept_box: tuple[float, float, float, float],
    swept_doubts: list[str],
    answered: bool,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Rooms photo/1066 (hard), 1186 (ordinary), 1169 (hard) in small: the level view's
    face (0.5) carries four outline doubts, and with the unread pitch it is under
    measure.MIN_DOUBTED_CONFIDENCE; the same face (boxes overlapping by
    measure.SAME_FACE_IOU or more, feet within measure.ROW_JITTER_PX) read at a swept pitch
    (0.3) lacks some of them: they came from the guessed rig, not from the face, and that
    reading is reported (doubted, unread pitch, not carried on). A reading with a doubt the
    level face lacks, another face, the face on another foot row (photo/1063 hard: a face
    4.5 times too tall, its reading 5 rows higher undoubted), or a reading still doubting
    the foot (measure.FOOT_DOUBTS) does not lift the refusal."""
    image, truth, view, depth = no_rig_room(4001)
    found = int(round(view.cy + view.fy * 0.30 / depth))
    level = ["top_from_sides", "uneven_sides", "skewed_edges", "foot_off_floor"]

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        if self.view.rig.camera_pitch_deg == -4.0:
            return fake_face(
                truth, True, 0.3, height_m=0.31, box_px=swept_box, doubts=list(swept_doubts)
            )
        return fake_face(truth, True, 0.5, box_px=(200.0, 100.0, 300.0, 200.0), doubts=level)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [found])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    # the taller face holding the level one on its foot is another rule's (the refused
    # face a part of it: measure.WHOLE_FACE_READING, tests/vision/test_no_rig_whole_face.py)
    monkeypatch.setattr(measure, "WHOLE_FACE_READING", False)
    measurer = Measurer(CAM, None)
    res = measurer.measure(image, truth["range_m"])
    assert res.detected == answered
    assert measurer._last_rig is None
    if answered:
        assert res.height_m == pytest.approx(0.31)
        assert res.camera_pitch_deg == -4.0
        assert res.doubts == ["top_from_sides", "pitch_unread"]
    else:
        assert "doubted on every count" in res.reason


@pytest.mark.parametrize(("seed", "hard"), [(1066, True), (1186, False), (1169, True)])
def test_with_no_rig_photo_faces_refused_on_a_guessed_pitch_are_measured(
    seed: int, hard: bool
) -> None:
    """Rooms photo/1066 (hard, seams), 1186 (ordinary, panels), 1169 (hard, planks): with
    no rig the surest trial's reading of the face was doubted on three or four counts and
    refused, while another guessed pitch read the same face with fewer doubts: measured
    within 5 % now (they were misses)."""
    _assert_measured_without_rig("photo", seed, hard, rel=0.05)


def test_with_no_rig_procedural_108_a_face_off_by_its_size_is_not_reported(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Room procedural/108 (hard): with no rig a narrow strip of the panelled wall stood a
    face +115 % in height (six doubts, confidence 0.05): no answer now, and the reason
    names the doubts. (Its rows read as with a rig, KNOWN_RIG_ROWS, find the box within
    4 %: off here.)"""
    # with KNOWN_RIG_ROWS off it takes a wrong unsure face on the axis here
    monkeypatch.setattr(measure, "AXIS_UNSURE_TRIAL", False)
    monkeypatch.setattr(measure, "KNOWN_RIG_ROWS", False)
    image, truth, _ = render_room("procedural", 108, True, CAM)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert not res.detected
    assert "doubted on every count" in res.reason


@pytest.mark.parametrize(
    "swept_box, taken",
    [
        ((200.0, 140.0, 300.0, 200.0), True),  # a top face shown: 1.2 times as tall, taken
        ((200.0, 30.0, 300.0, 200.0), False),  # 3.4 times: a wall print taken in
    ],
)
def test_with_no_rig_a_swept_pitch_does_not_take_in_a_print_above_the_face(
    swept_box: tuple[float, float, float, float],
    taken: bool,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Room photo/1065 (ordinary) in small: the level view finds the planked box (0.40);
    at -2 degrees the guessed camera height stands the box with a yellow print on the wall
    above it, in line with its sides, as one face 2.4 times as tall (0.96, height +144 %).
    A swept pitch shows or hides a box's top face, a band a fraction of the face's height:
    a face over SWEPT_MAX_GROWTH times as tall as the level one is not it read again, and
    the level face stays."""
    image, truth, view, depth = no_rig_room(4007)
    found = int(round(view.cy + view.fy * 0.30 / depth))
    level_box = (200.0, 150.0, 300.0, 200.0)

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        pitch = self.view.rig.camera_pitch_deg
        if pitch == -2.0:
            return fake_face(truth, True, 0.96, height_m=0.8, box_px=swept_box)
        return fake_face(truth, True, 0.4 if pitch == 0.0 else 0.1, box_px=level_box)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [found])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    monkeypatch.setattr(measure.Measurer, "_with_pitch", lambda self, found, *a: found)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected
    assert res.height_m == pytest.approx(0.8 if taken else 0.3)


def test_swept_max_growth_lets_a_top_face_through_and_stops_a_print() -> None:
    """The bound lies between a top face's growth (the faces the sweep took on the tuning
    rooms stood up to 1.25 times as tall) and a print above the face (2.4)."""
    assert 1.25 < measure.SWEPT_MAX_GROWTH < 2.4
    level = (200.0, 150.0, 300.0, 200.0)
    assert not measure._taller((200.0, 140.0, 300.0, 200.0), level)
    assert measure._taller((200.0, 60.0, 300.0, 200.0), level)
    assert not measure._taller(None, level)


@pytest.mark.xfail(
    strict=True,
    reason="method.SURFACE_ANY_FLOOR: photo/1065 ordinary no rig width 0.4 -> 9.6 % (session 42)",
)
def test_with_no_rig_photo_1065_the_box_not_the_print_above_it() -> None:
    """Room photo/1065 (ordinary): with no rig a swept pitch stood the planked box and the
    yellow print on the wall above it as one face (height +144 % at confidence 0.95); the
    box is measured, within 5 %. The surface rule without the rig (session 42) moves its
    width to -9.6 % (height 3.1 -> 0.1 %; the room is in no set the full runs count, so it
    was seen only here): a known regression, a strict xfail at the defaults."""
    _assert_measured_without_rig("photo", 1065, False, rel=0.05)


def test_with_no_rig_photo_1065_without_the_surface_rule(monkeypatch: pytest.MonkeyPatch) -> None:
    """The same room with method.SURFACE_ANY_FLOOR off: the box within 5 % as before."""
    monkeypatch.setattr(fused_method, "SURFACE_ANY_FLOOR", False)
    _assert_measured_without_rig("photo", 1065, False, rel=0.05)


def _face_box(
    truth: dict[str, float], conf: float, box: tuple[float, float, float, float]
) -> Measurement:
    return fake_face(truth, True, conf, box_px=box)


def test_the_sweep_replaces_an_unsure_face_only_with_a_sure_confirmed_face_above_it() -> None:
    """With no rig, over an unsure face (under ESTIMATE_ACCEPT) the last-resort sweep's
    face is taken only when it is another face above it (the unsure box wholly under its
    foot), its sides read the pitch, and it reaches SWEPT_OVER_UNSURE; with no face so far,
    any sweep's face is."""
    truth = {"range_m": 1.0}
    stone = _face_box(truth, 0.07, (95.0, 287.0, 418.0, 334.0))  # a stone of the gravel
    face = _face_box(truth, 0.94, (101.0, 72.0, 466.0, 269.0))  # the obstacle above it
    assert measure._swept_over(stone, face, True)
    assert not measure._swept_over(stone, face, False)  # its pitch not read
    weak = _face_box(truth, measure.SWEPT_OVER_UNSURE - 0.01, face.box_px)  # type: ignore[arg-type]
    assert not measure._swept_over(stone, weak, True)
    same = _face_box(truth, 0.71, (91.0, 40.0, 423.0, 300.0))  # the unsure face read again
    assert not measure._swept_over(stone, same, True)
    assert measure._swept_over(None, face, False)
    none = Measurement(detected=False, method="fused", range_m=1.0)
    assert measure._swept_over(none, weak, False)


def test_the_sweep_reads_again_an_unsure_face_with_a_doubted_top_on_its_foot() -> None:
    """With no rig, the sweep's face on the unsure face's own foot (feet under
    MIN_NEARER_DROP_PX, twice the row jitter of 2 px, apart), its sides reading the pitch,
    sure (ESTIMATE_ACCEPT) and with a clear top, replaces the unsure face when that face's
    top edge is doubted (SECOND_TOP or TOP_RUNS_ON), though under SWEPT_OVER_UNSURE."""
    truth = {"range_m": 1.7}
    level = _face_box(truth, 0.14, (179.0, 167.0, 446.0, 301.3))  # photo/1411 o's level face
    level.doubts = [SECOND_TOP, TOP_RUNS_ON]

    def swept(conf: float, foot: float, *doubts: str) -> Measurement:
        face = _face_box(truth, conf, (179.0, 106.0, 445.0, foot))
        face.doubts = list(doubts)
        return face

    right = swept(0.47, 301.3, NEAR_RIVALS)  # its top at the box's, its pitch -4.6 degrees
    assert 0.47 < measure.SWEPT_OVER_UNSURE  # the rule for a face above it would refuse it
    assert measure._swept_over(level, right, True)
    assert not measure._swept_over(level, right, False)  # its pitch not read
    assert measure._swept_over(level, swept(measure.ESTIMATE_ACCEPT, 301.3), True)
    assert not measure._swept_over(level, swept(measure.ESTIMATE_ACCEPT - 0.01, 301.3), True)
    # the feet: 3.9 px apart is the same edge (row jitter), 4 px is another foot
    assert measure._swept_over(level, swept(0.47, 301.3 - 3.9), True)
    assert not measure._swept_over(level, swept(0.47, 301.3 - 4.0), True)
    assert measure._swept_over(level, swept(0.47, 301.3 + 3.9), True)
    assert not measure._swept_over(level, swept(0.47, 301.3 + 4.0), True)
    # the sweep's top doubted too: no better reading of the top
    assert not measure._swept_over(level, swept(0.47, 301.3, SECOND_TOP), True)
    assert not measure._swept_over(level, swept(0.47, 301.3, TOP_RUNS_ON), True)
    # either top doubt alone on the unsure face is enough; other doubts are not
    for doubt in (SECOND_TOP, TOP_RUNS_ON):
        level.doubts = [doubt]
        assert measure._swept_over(level, right, True)
    for other in (TOP_FROM_SIDES, NEAR_RIVALS, FOOT_OFF_FLOOR):
        level.doubts = [other]
        assert not measure._swept_over(level, right, True)  # a clear top keeps its face
    level.doubts = []
    assert not measure._swept_over(level, right, True)


def test_with_no_rig_photo_1411_the_swept_reading_of_the_same_foot_gives_the_top() -> None:
    """Room photo/1411 (ordinary): with no rig the face found with the lens taken as level
    stopped at a line of the wall running on beside it (height -31 %, doubted:
    second_top_edge, top_runs_on, confidence 0.14); the sweep at -4.6 degrees, its sides
    confirming that pitch, read the same foot with the box's own top (0.47), which the rule
    for a face above refused. It is now measured within 5 %."""
    _assert_measured_without_rig("photo", 1411, False, rel=0.05)


@pytest.mark.parametrize("seed", [1022, 1093])
def test_with_no_rig_a_face_above_the_gravel_steps_is_found(seed: int) -> None:
    """Rooms photo/1022 and 1093 (ordinary): a plain face on coarse gravel, the lens
    pitched up about 3 degrees. The band's lowest steps are all gravel (the face's foot is
    not among the eight rows tried, or steps less than the gravel), and a stone stood an
    unsure face (height -77 %, -65 %), which ended the search. The last-resort sweep now
    runs over an unsure face, and its sure face above, whose sides read the pitch, is
    measured within 5 %."""
    _assert_measured_without_rig("photo", seed, False, rel=0.05)


@pytest.mark.parametrize(
    "lower_px, expected",
    [
        ((15.0, 27.0), 0.20),  # a stone-sized face below (factor 0.25): the face above
        ((60.0, 80.0), 0.30),  # a face of full size below: the lowest still wins
    ],
)
def test_with_no_rig_a_small_unsure_face_below_settles_no_row(
    lower_px: tuple[float, float], expected: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Room photo/1066 (hard) in small: with no row's face accepted, the lowest row that
    stood a face was taken, a 13 x 38 px face of a stone on the floor (0.06), not the face
    above it (0.20). A small face (pixel factor under SMALL_SHARE) settles no row when a
    face of full size stands above it, as a face that took floor in settles none."""

    image, truth, view, depth = no_rig_room(4001)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (0.20, 0.30)}

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        height = round(self.view.rig.camera_height_m, 2)
        if self.view.rig.camera_pitch_deg or height not in row_at or kwargs.get("floor_known"):
            return Measurement(detected=False, method="fused", range_m=truth["range_m"])
        h_px, w_px = lower_px if height == 0.30 else (150.0, 120.0)
        conf = 0.06 if height == 0.30 else 0.15
        return fake_face(truth, True, conf, height_px=h_px, width_px=w_px)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[0.30], row_at[0.20]])
    monkeypatch.setattr(measure, "weak_contact_rows", lambda *a: [])
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected
    assert res.camera_height_m == pytest.approx(expected, abs=0.01)


@pytest.mark.parametrize(
    "weak_px, expected",
    [
        ((15.0, 27.0), 0.20),  # a stone-sized face on the weak step: the face above stays
        ((60.0, 80.0), 0.30),  # a face of full size there: the nearer foot
    ],
)
def test_with_no_rig_a_small_face_on_a_weaker_step_is_no_nearer_foot(
    weak_px: tuple[float, float], expected: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Room photo/1036 (hard) in small: the face on the row that stood out was unsure
    (0.10, within 2 %); a weaker step below stood a 15 x 27 px face (0.31), a mark on the
    floor, taken as the nearer foot (height -96 %, then refused). A small face is no
    nearer foot under a face of full size."""

    image, truth, view, depth = no_rig_room(4001)
    row_at = {h: int(round(view.cy + view.fy * h / depth)) for h in (0.20, 0.30)}
    foot = {h: float(r) for h, r in row_at.items()}

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        height = round(self.view.rig.camera_height_m, 2)
        if self.view.rig.camera_pitch_deg or height not in row_at or kwargs.get("floor_known"):
            return Measurement(detected=False, method="fused", range_m=truth["range_m"])
        box = (100.0, foot[height] - 50.0, 200.0, foot[height])
        h_px, w_px = weak_px if height == 0.30 else (150.0, 120.0)
        conf = 0.31 if height == 0.30 else 0.10
        return fake_face(truth, True, conf, box_px=box, height_px=h_px, width_px=w_px)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row_at[0.20]])
    monkeypatch.setattr(measure, "weak_contact_rows", lambda *a: [row_at[0.30], row_at[0.20]])
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected
    assert res.camera_height_m == pytest.approx(expected, abs=0.01)


def test_with_no_rig_photo_1036_the_face_not_a_mark_on_the_floor_below_it() -> None:
    """Room photo/1036 (hard): a text-printed face, the lens pitched up; a weaker step
    below its foot stood a face of 15 x 27 px (a mark on the gravel), taken as the nearer
    foot and then refused (missed). The face is measured, within 5 %."""
    _assert_measured_without_rig("photo", 1036, True, rel=0.05)


@pytest.mark.parametrize("face_x_m, side", [(0.45, "right"), (-0.45, "left")])
@pytest.mark.parametrize("with_rig", [True, False])
def test_a_face_running_off_the_images_side_is_found_by_colour_and_flagged(
    monkeypatch: pytest.MonkeyPatch, face_x_m: float, side: str, with_rig: bool
) -> None:
    """A plain face 1.4 m wide running off one side: the edges give one side only, the
    colour rescue's top walk reads the other side's background alone
    (region.CLIPPED_COLOUR_WALK); the width comes back a flagged lower bound, never a
    confident one."""
    spec = clean_room(4003, width_m=1.4, face_x_m=face_x_m)
    image, truth = RoomRenderer(CAM).render(spec)
    assert truth["clipped"] == [side]
    rig = spec.rig if with_rig else None
    res = Measurer(CAM, rig).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.clipped == [side]
    assert res.to_dict()["width_is_lower_bound"] is True
    assert res.height_m == pytest.approx(truth["height_m"], rel=0.03)
    assert res.width_m is not None and res.width_m < truth["width_m"]
    assert (res.confidence or 0.0) < 0.5
    monkeypatch.setattr(region, "CLIPPED_COLOUR_WALK", False)
    assert not Measurer(CAM, rig).measure(image, truth["range_m"]).detected


def test_with_the_rig_a_face_whose_foot_lies_below_the_image_is_measured_from_its_top(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The rig puts the floor-contact row below the image: the face's colour at the view's
    foot in the beam's core, walked out to its sides and up to its top; the height from
    the predicted contact row (method.PAST_FOOT_FACE), the foot flagged clipped."""
    spec = clean_room(4003, range_m=0.6, height_m=0.4, width_m=0.3)
    spec = dataclasses.replace(
        spec, rig=dataclasses.replace(spec.rig, camera_height_m=0.45, camera_pitch_deg=0.0)
    )
    image, truth = RoomRenderer(CAM).render(spec)
    assert truth["clipped"] == ["bottom"]
    res = Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.clipped == ["bottom"]
    assert res.to_dict()["height_is_lower_bound"] is True
    assert res.height_m == pytest.approx(truth["height_m"], rel=0.02)
    assert res.width_m == pytest.approx(truth["width_m"], rel=0.03)
    assert (res.confidence or 0.0) < 0.5
    monkeypatch.setattr(fused_method, "PAST_FOOT_FACE", False)
    missed = Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    assert not missed.detected and "outside the image" in missed.reason


def swept_answer(
    monkeypatch: pytest.MonkeyPatch,
    level: tuple[float, float, tuple[float, float, float, float]],
    swept: tuple[float, float, tuple[float, float, float, float]],
    runs_up: bool,
) -> float | None:
    """The height reported when the level view reads ``level`` and every swept pitch reads
    ``swept`` (confidence, height, box) on one contact row, with sides_run_up answering
    ``runs_up``."""
    image, truth, view, depth = no_rig_room(4001)
    row = int(round(view.cy + view.fy * 0.20 / depth))

    def fake_run(self: FusedMethod, *args: object, **kwargs: object) -> Measurement:
        if kwargs.get("floor_known"):
            return Measurement(detected=False, method="fused", range_m=truth["range_m"])
        conf, height, box = level if self.view.rig.camera_pitch_deg == 0 else swept
        return fake_face(truth, True, conf, height_m=height, box_px=box)

    monkeypatch.setattr(FusedMethod, "run", fake_run)
    monkeypatch.setattr(measure, "contact_rows", lambda *a: [row])
    monkeypatch.setattr(measure, "weak_contact_rows", lambda *a: [])
    monkeypatch.setattr(measure, "sides_reach_foot", lambda *a: True)
    monkeypatch.setattr(measure, "sides_run_up", lambda *a: runs_up)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    return res.height_m if res.detected else None


#: A face's box read to a line on it, and the whole face on the same foot and columns.
SHORT_BOX = (100.0, 150.0, 200.0, 200.0)
TALL_BOX = (100.0, 50.0, 200.0, 200.0)


@pytest.mark.parametrize("runs_up", [True, False])
def test_with_no_rig_a_taller_swept_face_is_taken_only_where_its_sides_run_up(
    monkeypatch: pytest.MonkeyPatch, runs_up: bool
) -> None:
    """The level reading's top a line on the face (a print's edge): a swept pitch's face
    three times as tall, as sure, on the same columns, is the face when its sides run on
    above that top (sides_run_up), and something above the face taken in when not."""
    got = swept_answer(monkeypatch, (0.4, 0.2, SHORT_BOX), (0.4, 0.6, TALL_BOX), runs_up)
    assert got == pytest.approx(0.6 if runs_up else 0.2)


@pytest.mark.parametrize("runs_up", [True, False])
def test_with_no_rig_a_level_face_whose_sides_run_up_keeps_a_surer_short_face_out(
    monkeypatch: pytest.MonkeyPatch, runs_up: bool
) -> None:
    """A surer swept face a third as tall, its top a line on the level face (a picture's
    edge inside a framed poster): the level face stays where its sides run on above that
    line, and gives way to the surer face where they do not."""
    got = swept_answer(monkeypatch, (0.3, 0.6, TALL_BOX), (0.7, 0.2, SHORT_BOX), runs_up)
    assert got == pytest.approx(0.6 if runs_up else 0.2)
