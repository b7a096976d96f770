"""The camera pitch from the face's converging sides (vision/pitch.py) and its use with no rig."""

from __future__ import annotations

import math

import numpy as np
import pytest
from obstacle_fusion.sim.room_scene import RoomRenderer, RoomSpec
from obstacle_fusion.vision import measure as measure_mod
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused.confidence import PITCH_RERUN_DISAGREES
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.pitch import (
    MAX_PITCH_DEG,
    MAX_SIGMA_DEG,
    MIN_SEPARATION_PX,
    MIN_SIDE_PX,
    REFIT_MAX_SHIFT_PX,
    PitchEstimate,
    camera_height_for_row,
    level_scales,
    pitch_for_row,
    pitch_from_lines,
    pitch_from_sides,
    refit_side,
)
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import Measurement, View

from tests.vision.rooms import pitched_plain_room

CAM = CameraModel.paper(500, 375)


def project(points_robot: list[list[float]], pitch_deg: float) -> np.ndarray:
    """Robot-frame points to input-image pixels of the paper's camera pitched down."""
    rot = np.asarray(Rig(camera_pitch_deg=pitch_deg).camera_to_robot)  # camera -> robot
    return CAM.project(np.asarray(points_robot, dtype=np.float64) @ rot)  # rows: R^T p


def face_lines(
    pitch_deg: float,
    depth: float = 1.2,
    floor: float = 0.3,
    height: float = 0.3,
    x_left: float = -0.2,
    x_right: float = 0.25,
) -> list[tuple[float, float, float, float]]:
    """A face square to the beam, as Measurement.lines: bottom, top, left, right."""
    top = floor - height
    bl, br, tr, tl = project(
        [
            [x_left, floor, depth],
            [x_right, floor, depth],
            [x_right, top, depth],
            [x_left, top, depth],
        ],
        pitch_deg,
    )
    return [
        (bl[0], bl[1], br[0], br[1]),
        (tl[0], tl[1], tr[0], tr[1]),
        (bl[0], bl[1], tl[0], tl[1]),
        (br[0], br[1], tr[0], tr[1]),
    ]


@pytest.mark.parametrize("pitch", [-5.0, -1.5, 2.0, 4.5, 8.0])
def test_pitch_from_the_sides_of_an_exactly_imaged_face(pitch: float) -> None:
    est = pitch_from_lines(face_lines(pitch), CAM)
    assert est is not None
    assert est.pitch_deg == pytest.approx(pitch, abs=0.01)
    assert 0.0 < est.sigma_deg < 0.5


def test_pitch_holds_off_axis_and_at_other_depths() -> None:
    est = pitch_from_lines(face_lines(3.0, depth=2.0, floor=0.45, x_left=0.05, x_right=0.6), CAM)
    assert est is not None and est.pitch_deg == pytest.approx(3.0, abs=0.02)


def test_roll_cancels_in_the_slope_difference() -> None:
    """Rolling the image shifts both sides' slopes alike: the pitch stays within 0.1 deg."""
    lines = face_lines(4.0)
    a = math.radians(0.8)
    c, s = math.cos(a), math.sin(a)

    def roll(x: float, y: float) -> tuple[float, float]:
        dx, dy = x - CAM.cx, y - CAM.cy
        return CAM.cx + c * dx - s * dy, CAM.cy + s * dx + c * dy

    rolled = [(*roll(x0, y0), *roll(x1, y1)) for x0, y0, x1, y1 in lines]
    est = pitch_from_lines(rolled, CAM)
    assert est is not None and est.pitch_deg == pytest.approx(4.0, abs=0.1)


def test_weak_estimates_are_refused() -> None:
    # sides too short (a low face far away)
    short = face_lines(4.0, depth=3.0, height=0.2)
    assert abs(short[2][3] - short[2][1]) < MIN_SIDE_PX
    assert pitch_from_lines(short, CAM) is None
    # sides too close together
    narrow = face_lines(4.0, x_left=0.0, x_right=0.08)
    assert narrow[3][0] - narrow[2][0] < MIN_SEPARATION_PX
    assert pitch_from_lines(narrow, CAM) is None
    # a convergence no robot camera's tilt gives (a seam, a shadow): refused
    assert pitch_from_lines(face_lines(MAX_PITCH_DEG + 3.0), CAM) is None
    # not four edges
    assert pitch_from_lines(face_lines(4.0)[:3], CAM) is None


def test_side_order_does_not_matter_for_line_direction() -> None:
    lines = face_lines(-3.0)
    left, right = lines[2], lines[3]
    flipped = (left[2], left[3], left[0], left[1])
    est = pitch_from_sides(flipped, right, CAM)
    assert est is not None and est.pitch_deg == pytest.approx(-3.0, abs=0.01)


@pytest.mark.parametrize("pitch", [-4.0, 0.0, 5.0])
def test_camera_height_from_the_contact_row_and_the_pitch(pitch: float) -> None:
    h, depth = 0.33, 1.4
    ((u, v),) = CAM.undistort_points(project([[0.0, h, depth]], pitch))
    assert camera_height_for_row(v, depth, pitch, CAM.fy, CAM.cy) == pytest.approx(h, abs=1e-6)


@pytest.mark.parametrize("pitch", [-4.0, 0.0, 5.0])
def test_the_pitch_from_the_contact_row_and_the_camera_height(pitch: float) -> None:
    h, depth = 0.33, 1.4
    ((u, v),) = CAM.undistort_points(project([[0.0, h, depth]], pitch))
    assert pitch_for_row(v, depth, h, CAM.fy, CAM.cy) == pytest.approx(pitch, abs=1e-6)


@pytest.mark.parametrize("pitch", [-5.0, 4.0])
def test_level_scales_restore_the_levelled_size(pitch: float) -> None:
    """The face's pixel size in the pitch-0 view, scaled, is its size in the levelled view
    (fy H / D): without the scale it is off by over 1 %."""
    depth, floor, height = 1.0, 0.4, 0.35
    lines = face_lines(pitch, depth=depth, floor=floor, height=height)
    bl, br, tl, tr = CAM.undistort_points(
        np.array([lines[0][:2], lines[0][2:], lines[1][:2], lines[1][2:]])
    )
    h0 = 0.5 * ((bl[1] - tl[1]) + (br[1] - tr[1]))
    hs, ws = level_scales(lines, CAM, pitch)
    assert abs(h0 / (CAM.fy * height / depth) - 1.0) > 0.01
    assert h0 * hs == pytest.approx(CAM.fy * height / depth, rel=1e-6)
    w0 = 0.5 * ((br[0] + tr[0]) - (bl[0] + tl[0]))
    assert w0 * ws == pytest.approx(CAM.fx * 0.45 / depth, rel=1e-3)


def pitched_room(seed: int, pitch: float) -> RoomSpec:
    return pitched_plain_room(seed, pitch)


@pytest.mark.parametrize("pitch", [-4.0, 4.0])
def test_rendered_room_with_no_rig_gets_its_pitch(pitch: float) -> None:
    """A rendered room, camera pitched 4 degrees, no rig file: the pitch within 1 degree,
    the camera height within 2 cm, the face within 2 %; the JSON carries the pitch."""
    spec = pitched_room(4002, pitch)
    image, truth = RoomRenderer(CAM).render(spec)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected and res.rig_source == "estimated"
    assert res.camera_pitch_deg is not None
    assert abs(res.camera_pitch_deg - pitch) <= 1.0, res.camera_pitch_deg
    assert res.camera_height_m is not None and abs(res.camera_height_m - 0.3) <= 0.02
    assert abs(res.height_m / truth["height_m"] - 1.0) <= 0.02
    assert abs(res.width_m / truth["width_m"] - 1.0) <= 0.02
    assert res.to_dict()["camera_pitch_deg"] == res.camera_pitch_deg


def test_a_weak_estimate_falls_back_to_pitch_zero(monkeypatch: pytest.MonkeyPatch) -> None:
    """When the face is not found with enough confidence to read its sides, the pitch stays 0
    and the measurement is the pitch-0 one."""
    spec = pitched_room(4002, 4.0)
    image, truth = RoomRenderer(CAM).render(spec)
    monkeypatch.setattr(measure_mod, "PITCH_MIN_CONFIDENCE", 1.01)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected and res.camera_pitch_deg == 0.0
    monkeypatch.undo()
    levelled = Measurer(CAM, None).measure(image, truth["range_m"])
    assert levelled.camera_pitch_deg != 0.0
    # the pitch-0 camera height is the contact row's (h = (v - cy) D / fy), not the pitched one
    assert res.camera_height_m != levelled.camera_height_m


def test_a_rig_file_reports_no_estimated_pitch() -> None:
    spec = pitched_room(4002, 4.0)
    image, truth = RoomRenderer(CAM).render(spec)
    res = Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    assert res.rig_source == "file" and res.camera_pitch_deg is None


def test_the_side_length_and_separation_limits_are_where_stated() -> None:
    """Just under MIN_SIDE_PX: refused; just over: read (a wide face, so the expected error
    alone would not refuse it)."""
    under = face_lines(4.0, depth=1.5, floor=0.3, height=0.124, x_left=-0.5, x_right=0.5)
    over = face_lines(4.0, depth=1.5, floor=0.3, height=0.138, x_left=-0.5, x_right=0.5)
    assert abs(under[2][3] - under[2][1]) < MIN_SIDE_PX < abs(over[2][3] - over[2][1])
    assert pitch_from_lines(under, CAM) is None
    est = pitch_from_lines(over, CAM)
    assert est is not None and est.pitch_deg == pytest.approx(4.0, abs=0.01)
    near = face_lines(4.0, depth=0.6, floor=0.2, height=0.18, x_left=0.0, x_right=0.05)
    far = face_lines(4.0, depth=0.6, floor=0.2, height=0.18, x_left=0.0, x_right=0.056)
    assert near[3][0] - near[2][0] < MIN_SEPARATION_PX < far[3][0] - far[2][0]
    assert pitch_from_lines(near, CAM) is None
    assert pitch_from_lines(far, CAM) is not None


def test_the_pitch_limit_is_where_stated() -> None:
    assert MAX_PITCH_DEG == 10.0
    assert pitch_from_lines(face_lines(9.7), CAM) is not None
    assert pitch_from_lines(face_lines(10.3), CAM) is None
    assert pitch_from_lines(face_lines(-10.3), CAM) is None


def test_the_expected_error_limit_refuses_a_short_narrow_face() -> None:
    """Sides 55 px long: 0.26 m apart (expected error 0.82 deg) is refused, 0.3 m apart
    (0.71 deg) is read."""
    est = pitch_from_lines(
        face_lines(4.0, depth=1.0, floor=0.2, height=0.12, x_left=0.0, x_right=0.26), CAM
    )
    assert est is None
    est = pitch_from_lines(
        face_lines(4.0, depth=1.0, floor=0.2, height=0.12, x_left=0.0, x_right=0.3), CAM
    )
    assert est is not None and est.sigma_deg == pytest.approx(0.708, abs=0.01)
    assert est.sigma_deg <= MAX_SIGMA_DEG


def leaning_edge(lean_px: float, rows: int = 200, width: int = 120) -> np.ndarray:
    """A dark left half, a light right half, the edge moving ``lean_px`` over the rows."""
    v, u = np.mgrid[0:rows, 0:width].astype(np.float64)
    edge = 60.0 + lean_px * v / (rows - 1)
    img = 40.0 + 160.0 * np.clip(u - edge + 0.5, 0.0, 1.0)
    return np.repeat(img[:, :, None], 3, axis=2).astype(np.uint8)


def test_refit_side_reads_a_lean_the_first_fit_missed() -> None:
    img = leaning_edge(3.0)
    # found upright at the edge's mean column: the refit leans it by 3 px over the rows
    u0, v0, u1, v1 = refit_side(img, (61.5, 10.0, 61.5, 189.0))  # type: ignore[misc]
    assert (v0, v1) == (10.0, 189.0)
    assert (u1 - u0) / (v1 - v0) == pytest.approx(3.0 / 199.0, abs=0.002)
    assert u0 == pytest.approx(60.0 + 3.0 * 10 / 199, abs=0.2)


def test_refit_side_refuses_a_drift_onto_another_edge() -> None:
    img = leaning_edge(0.0)
    # the found side lies 3.5 px beside the only edge: the refit would move it too far
    assert refit_side(img, (63.0, 10.0, 63.0, 189.0)) is None
    assert REFIT_MAX_SHIFT_PX < 3.0
    # a flat image has no edge to read
    assert refit_side(np.full((200, 120, 3), 90, np.uint8), (60.0, 10.0, 60.0, 189.0)) is None


def test_refit_side_needs_the_edge_along_most_of_the_side() -> None:
    """The edge seen on 70 % of the side's rows is read; on 50 %, refused (REFIT_MIN_SHARE)."""
    img = leaning_edge(2.0)
    faded = img.copy()
    faded[10:64] = 90  # 54 of the 180 rows read (rows 10..189 less the margins): 30 % gone
    assert refit_side(faded, (61.0, 0.0, 61.0, 199.0)) is not None
    faded[10:100] = 90  # half gone
    assert refit_side(faded, (61.0, 0.0, 61.0, 199.0)) is None


def test_a_levelled_rerun_that_disagrees_gives_the_pitch_0_face_scaled(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """When the search in the levelled view settles on another face (here: forced by a
    tolerance no rerun meets), the pitch-0 face's size, scaled to the levelled view, stands."""
    spec = pitched_room(4002, 4.0)
    image, truth = RoomRenderer(CAM).render(spec)
    monkeypatch.setattr(measure_mod, "PITCH_MIN_CONFIDENCE", 1.01)
    flat = Measurer(CAM, None).measure(image, truth["range_m"])
    monkeypatch.setattr(measure_mod, "PITCH_MIN_CONFIDENCE", measure_mod.ESTIMATE_ACCEPT)
    monkeypatch.setattr(measure_mod, "RERUN_AGREE", -1.0)
    scaled = Measurer(CAM, None).measure(image, truth["range_m"])
    assert scaled.camera_pitch_deg is not None and abs(scaled.camera_pitch_deg - 4.0) <= 1.0
    hs, ws = level_scales(flat.lines, CAM, scaled.camera_pitch_deg)
    assert hs != pytest.approx(1.0, abs=0.005)
    assert scaled.height_m == pytest.approx(flat.height_m * hs, rel=1e-9)
    assert scaled.width_m == pytest.approx(flat.width_m * ws, rel=1e-9)
    assert scaled.lines == flat.lines
    assert abs(scaled.height_m / truth["height_m"] - 1.0) < abs(
        flat.height_m / truth["height_m"] - 1.0
    )


@pytest.mark.parametrize("rerun_conf, taken", [(0.31, True), (0.30, False)])
def test_a_levelled_rerun_that_disagrees_and_is_surer_is_taken_with_the_doubt(
    rerun_conf: float, taken: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The levelled view is the lens's geometry as its sides read it: when the search
    there settles on another face that is surer than the pitch-0 face (0.30), that face is
    taken, doubted (PITCH_RERUN_DISAGREES); no surer, the pitch-0 face scaled stands."""
    view = View(CAM, Rig(), "level")
    image = np.zeros((CAM.height, CAM.width, 3), np.uint8)
    lines = [(100.0, 250.0, 300.0, 250.0), (100.0, 150.0, 300.0, 150.0)]
    lines += [(100.0, 150.0, 100.0, 250.0), (300.0, 150.0, 300.0, 250.0)]
    found = Measurement(
        detected=True, method="fused", range_m=1.0, height_m=0.3, width_m=0.4,
        confidence=0.3, lines=lines, camera_height_m=0.3, camera_pitch_deg=0.0,
    )  # fmt: skip
    monkeypatch.setattr(measure_mod, "refit_side", lambda seen, side: side)
    monkeypatch.setattr(
        measure_mod, "pitch_from_undistorted", lambda *a: PitchEstimate(3.0, 0.1, 100.0, 200.0)
    )

    def trial(height: float, row: float | None, pitch: float) -> Measurement:
        return Measurement(
            detected=True, method="fused", range_m=1.0, height_m=0.5, width_m=0.4,
            confidence=rerun_conf, lines=lines, camera_height_m=height, camera_pitch_deg=pitch,
        )  # fmt: skip

    got = Measurer(CAM, None)._with_pitch(found, image, view, 1.0, trial)
    assert got is not None and got.camera_pitch_deg == 3.0
    assert got.doubts == [PITCH_RERUN_DISAGREES]
    if taken:
        assert got.height_m == 0.5
    else:
        assert got.height_m != pytest.approx(0.5, rel=0.05)
        assert got.height_m == pytest.approx(0.3, rel=0.1)  # the pitch-0 face, scaled
