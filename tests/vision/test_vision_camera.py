"""CameraModel: resolution scaling, files OpenCV reads, undistortion, geometry."""

from __future__ import annotations

import math
from pathlib import Path

import cv2
import numpy as np
import pytest
from obstacle_fusion.errors import UserError
from obstacle_fusion.vision.calibration import find_corners
from obstacle_fusion.vision.camera import CameraModel, CameraModelError
from obstacle_fusion.vision.chessboard import BoardRenderer, default_poses

from tests.vision_fixtures import BOARD, known_camera


def test_paper_camera_at_full_resolution_is_the_papers_matrix() -> None:
    cam = CameraModel.paper(2592, 1944)
    assert (cam.fx, cam.fy, cam.cx, cam.cy) == (2378.0, 2374.0, 1291.0, 940.0)
    np.testing.assert_array_equal(cam.dist_coeffs, [-0.1356, 0.14432, -0.001021, 0.006401])


def test_paper_camera_scaled_to_500x375() -> None:
    cam = CameraModel.paper()
    s = 500 / 2592
    assert (cam.width, cam.height) == (500, 375)
    assert cam.fx == pytest.approx(2378 * s)
    assert cam.fy == pytest.approx(2374 * 375 / 1944)
    assert cam.cx == pytest.approx((1291 + 0.5) * s - 0.5)
    assert cam.cy == pytest.approx((940 + 0.5) * 375 / 1944 - 0.5)
    # Field of view does not depend on the resolution it is expressed at.
    full = CameraModel.paper(2592, 1944)
    assert cam.fov_x_rad == pytest.approx(full.fov_x_rad, rel=1e-12)
    assert cam.fov_y_rad == pytest.approx(2 * math.atan(1944 / (2 * 2374)), rel=1e-12)
    assert math.degrees(cam.fov_y_rad) == pytest.approx(44.53, abs=0.01)


def test_scaling_maps_projections_by_the_pixel_centre_rule() -> None:
    hi = known_camera(1280, 960)
    lo = hi.scaled_to(800, 600)
    pts = np.array([[0.1, -0.2, 1.5], [-0.4, 0.3, 2.0], [0.0, 0.0, 1.0], [0.5, 0.35, 1.2]])
    s = 800 / 1280
    np.testing.assert_allclose(lo.project(pts), (hi.project(pts) + 0.5) * s - 0.5, atol=1e-9)
    back = lo.scaled_to(1280, 960)
    np.testing.assert_allclose(back.camera_matrix, hi.camera_matrix, atol=1e-9)


def test_scaled_model_matches_a_physically_downsampled_image() -> None:
    """Render at 960x720, area-downsample to 640x480: corners must land where the
    scaled model puts them. Scaling c by s alone would be off by (1 - s) / 2 = 0.17 px."""
    hi = known_camera(960, 720)
    lo = hi.scaled_to(640, 480)
    renderer = BoardRenderer(hi, BOARD, supersample=2)
    offsets = []
    for pose in default_poses(hi, BOARD, 3):
        board = renderer.render(pose)
        small = cv2.resize(board.image, (640, 480), interpolation=cv2.INTER_AREA)
        found, _ = find_corners(small, BOARD)
        assert found is not None
        truth = lo.project(
            BOARD.object_points().astype(np.float64) @ pose.rotation().T + np.asarray(pose.tvec)
        )
        if np.abs(found - truth).max() > np.abs(found[::-1] - truth).max():
            found = found[::-1]
        offsets.append((found - truth).mean(axis=0))
    bias = np.abs(np.mean(offsets, axis=0))
    assert bias.max() < 0.06, f"mean corner offset {bias} px"


def test_scaling_refuses_another_aspect_ratio_but_accepts_rounding() -> None:
    cam = CameraModel.paper(2592, 1944)
    with pytest.raises(CameraModelError, match=r"2592x1944.*1280x720"):
        cam.scaled_to(1280, 720)
    assert isinstance(CameraModelError("x"), UserError)
    # 500x375 vs 2592x1944 is exact; 501x375 is 0.2 % off: accepted.
    near = cam.scaled_to(501, 375)
    assert near.fx == pytest.approx(2378 * 501 / 2592)
    assert cam.scaled_to(2592, 1944) is cam


def test_for_image_scales_to_the_image() -> None:
    cam = CameraModel.paper(2592, 1944)
    img = np.zeros((375, 500, 3), np.uint8)
    assert cam.for_image(img) == CameraModel.paper(500, 375)


def test_save_load_round_trip_and_opencv_reads_it(tmp_path: Path) -> None:
    cam = CameraModel(
        known_camera().camera_matrix, known_camera().dist_coeffs, 640, 480, rms_px=0.3125
    )
    path = tmp_path / "camera.yaml"
    cam.save(path, extra={"board_width": 9})
    loaded = CameraModel.load(path)
    assert loaded == cam and hash(loaded) == hash(cam)
    fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_READ)
    try:
        np.testing.assert_array_equal(fs.getNode("camera_matrix").mat(), cam.camera_matrix)
        np.testing.assert_array_equal(
            fs.getNode("distortion_coefficients").mat().reshape(-1), cam.dist_coeffs
        )
        assert int(fs.getNode("image_width").real()) == 640
        assert int(fs.getNode("image_height").real()) == 480
        assert fs.getNode("rms").real() == pytest.approx(0.3125)
        assert int(fs.getNode("board_width").real()) == 9
    finally:
        fs.release()
    assert path.read_text().startswith("%YAML")


def test_load_accepts_a_file_written_by_opencv_itself(tmp_path: Path) -> None:
    """As OpenCV's calibration sample writes it: avg_reprojection_error, 8 coefficients."""
    path = tmp_path / "out_camera_data.xml"
    fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
    fs.write("image_width", 1280)
    fs.write("image_height", 720)
    fs.write("camera_matrix", np.array([[900.0, 0, 640], [0, 901.0, 360], [0, 0, 1]]))
    fs.write("distortion_coefficients", np.arange(8, dtype=np.float64).reshape(8, 1) * 0.01)
    fs.write("avg_reprojection_error", 0.42)
    fs.release()
    cam = CameraModel.load(path)
    assert (cam.width, cam.height, cam.fx, cam.fy) == (1280, 720, 900.0, 901.0)
    assert cam.dist_coeffs.shape == (8,)
    assert cam.rms_px == pytest.approx(0.42)


def test_load_names_the_file_and_the_missing_key(tmp_path: Path) -> None:
    path = tmp_path / "partial.yaml"
    fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
    fs.write("image_width", 640)
    fs.write("image_height", 480)
    fs.write("camera_matrix", np.eye(3))
    fs.release()
    with pytest.raises(CameraModelError, match=r"partial\.yaml.*distortion_coefficients"):
        CameraModel.load(path)


def test_load_bad_files(tmp_path: Path) -> None:
    with pytest.raises(CameraModelError, match=r"nope\.yaml does not exist"):
        CameraModel.load(tmp_path / "nope.yaml")
    garbage = tmp_path / "garbage.yaml"
    garbage.write_text("%YAML:1.0\n---\ncamera_matrix: [1, 2\n  ]]]: {\n")
    with pytest.raises(CameraModelError, match="garbage.yaml"):
        CameraModel.load(garbage)
    wrong = tmp_path / "wrong.yaml"
    fs = cv2.FileStorage(str(wrong), cv2.FILE_STORAGE_WRITE)
    fs.write("image_width", 640)
    fs.write("image_height", 480)
    fs.write("camera_matrix", np.eye(2))
    fs.write("distortion_coefficients", np.zeros((5, 1)))
    fs.release()
    with pytest.raises(CameraModelError, match=r"wrong\.yaml.*3x3"):
        CameraModel.load(wrong)


def test_load_damaged_files_never_escape_as_opencv_errors(tmp_path: Path) -> None:
    """Files that parse but hold nonsense used to raise cv2.error (a traceback in the CLI)."""
    good = tmp_path / "good.yaml"
    known_camera().save(good)
    text = good.read_text()
    rows = tmp_path / "rows.yaml"  # distortion says 2 rows but holds 5 numbers
    rows.write_text(text.replace("rows: 5", "rows: 2"))
    with pytest.raises(CameraModelError, match=r"rows\.yaml is damaged: .*calibrate"):
        CameraModel.load(rows)
    top = tmp_path / "top.json"  # a JSON node where a map is needed
    top.write_text('{"camera_matrix": 3}')
    with pytest.raises(CameraModelError, match=r"top\.json"):
        CameraModel.load(top)
    nan = tmp_path / "nan.yaml"
    nan.write_text(text.replace("image_width: 640", "image_width: .nan"))
    with pytest.raises(CameraModelError, match=r"nan\.yaml: image size must be finite"):
        CameraModel.load(nan)
    empty = tmp_path / "empty.yaml"
    empty.write_text("")
    with pytest.raises(CameraModelError, match=r"empty\.yaml is empty"):
        CameraModel.load(empty)
    with pytest.raises(CameraModelError) as info:
        CameraModel.load(rows)
    assert "/io/opencv" not in str(info.value)  # no build paths in a user's message


def test_validation_and_immutability() -> None:
    with pytest.raises(CameraModelError, match="3x3"):
        CameraModel(np.eye(2), np.zeros(5), 10, 10)
    with pytest.raises(CameraModelError, match="dist_coeffs"):
        CameraModel(np.eye(3), np.zeros(3), 10, 10)
    with pytest.raises(CameraModelError, match="positive"):
        CameraModel(np.eye(3), np.zeros(4), 0, 10)
    cam = CameraModel.paper()
    with pytest.raises(ValueError):
        cam.camera_matrix[0, 0] = 1.0
    assert cam != CameraModel.paper(1000, 750)


def test_project_unproject_round_trip() -> None:
    cam = known_camera()
    rng = np.random.default_rng(3)
    px = np.column_stack([rng.uniform(20, 620, 50), rng.uniform(20, 460, 50)])
    rays = cam.unproject(px)
    np.testing.assert_allclose(rays[:, 2], 1.0)
    np.testing.assert_allclose(cam.project(rays * 2.5), px, atol=1e-6)


def _row_bend(corners: np.ndarray) -> float:
    """RMS distance of each board row's corners from their best line, averaged over rows."""
    bends = []
    for row in corners.reshape(BOARD.rows, BOARD.cols, 2):
        _, sv, _ = np.linalg.svd(row - row.mean(axis=0))
        bends.append(float(sv[1]) / math.sqrt(len(row)))
    return float(np.mean(bends))


def test_undistort_straightens_board_rows_and_maps_are_cached() -> None:
    cam = known_camera()
    map_a = cam.undistort_maps()
    assert cam.undistort_maps()[0] is map_a[0]
    assert map_a[0].dtype == np.int16 and map_a[0].shape == (480, 640, 2)
    renderer = BoardRenderer(cam, BOARD)
    raw_bends, straight_bends = [], []
    for pose in default_poses(cam, BOARD, 4):
        board = renderer.render(pose)
        # Sparse: the true corners, undistorted, are collinear to numerical precision.
        assert _row_bend(cam.undistort_points(board.true_corners)) < 1e-6
        raw, _ = find_corners(board.image, BOARD)
        straight, _ = find_corners(cam.undistort(board.image), BOARD)
        assert raw is not None and straight is not None
        raw_bends.append(_row_bend(raw))
        straight_bends.append(_row_bend(straight))
    # Detected corners carry ~0.1 px of noise; the lens bends rows by several times that.
    assert np.mean(straight_bends) < 0.1
    assert np.mean(raw_bends) > 2 * np.mean(straight_bends) + 0.05
    out = np.empty_like(board.image)
    assert cam.undistort(board.image, out=out) is out


def test_undistort_refuses_an_image_of_another_size() -> None:
    cam = known_camera()
    with pytest.raises(CameraModelError, match=r"1280x960.*640x480.*scaled_to"):
        cam.undistort(np.zeros((960, 1280), np.uint8))


def test_save_follows_the_extension_and_never_half_writes(tmp_path: Path) -> None:
    cam = CameraModel.paper()
    for name, head in (("cam.json", "{"), ("cam.xml", "<?xml"), ("cam.yml", "%YAML")):
        cam.save(tmp_path / name)
        assert (tmp_path / name).read_text().startswith(head)
        assert CameraModel.load(tmp_path / name) == cam
    keep = tmp_path / "keep.yaml"
    cam.save(keep)
    before = keep.read_bytes()
    with pytest.raises(cv2.error):
        CameraModel.paper(1000, 750).save(keep, extra={"not a key!": 1})
    assert keep.read_bytes() == before
    assert not list(tmp_path.glob("*.part")) and not list(tmp_path.glob(".*.part"))
    with pytest.raises(CameraModelError, match="does not exist"):
        cam.save(tmp_path / "nowhere" / "cam.yaml")
