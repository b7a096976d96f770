"""Calibration: real photos, rendered boards with a known answer, resolution scaling, CLI."""

from __future__ import annotations

import logging
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest
from obstacle_fusion.cli import main
from obstacle_fusion.errors import UserError
from obstacle_fusion.vision.calibration import calibrate_files, calibrate_images
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.chessboard import BoardSpec

from tests.vision_fixtures import BOARD, known_camera, real_chessboard_photos, rendered_boards


def test_real_photos_give_a_sane_camera() -> None:
    photos = real_chessboard_photos()
    result = calibrate_files(photos, BOARD, progress=False)
    cam = result.camera
    assert len(result.used) == 6 and not result.skipped
    assert (cam.width, cam.height) == (640, 480)
    assert abs(cam.fx / cam.fy - 1) < 0.02
    assert abs(cam.cx - cam.width / 2) < 0.1 * cam.width
    assert abs(cam.cy - cam.height / 2) < 0.1 * cam.height
    assert cam.rms_px is not None and cam.rms_px < 0.6
    # A real lens: plausible focal length (about 62 degrees across) and barrel distortion.
    assert 450 < cam.fx < 650
    assert cam.dist_coeffs[0] < 0
    errors = [r.rms_px for r in result.images]
    assert all(e is not None and 0 < e < 0.6 for e in errors)


def test_rendered_boards_recover_known_intrinsics() -> None:
    truth = known_camera()
    images = [(f"view{i}", img) for i, img in enumerate(rendered_boards(640, 480))]
    cam = calibrate_images(images, BOARD, progress=False).camera
    assert cam.fx == pytest.approx(truth.fx, rel=0.01)
    assert cam.fy == pytest.approx(truth.fy, rel=0.01)
    assert cam.cx == pytest.approx(truth.cx, abs=3.0)
    assert cam.cy == pytest.approx(truth.cy, abs=3.0)
    assert cam.dist_coeffs[0] == pytest.approx(truth.dist_coeffs[0], abs=0.03)
    assert cam.rms_px is not None and cam.rms_px < 0.3
    # The fitted lens maps points like the true one where the boards were (within 0.5 px);
    # the extreme corners, which no board covered, are extrapolation.
    rng = np.random.default_rng(5)
    px = np.column_stack([rng.uniform(64, 576, 200), rng.uniform(48, 432, 200)])
    np.testing.assert_allclose(cam.undistort_points(px), truth.undistort_points(px), atol=0.5)


def test_calibrating_at_one_size_and_scaling_matches_calibrating_at_the_other() -> None:
    """Views at 960x720 area-downsampled to 640x480 (the camera's binning, not our model):
    calibrate both, scale the big one down, compare."""
    big_images = rendered_boards(960, 720)
    small_images = [cv2.resize(img, (640, 480), interpolation=cv2.INTER_AREA) for img in big_images]
    big = calibrate_images([(f"b{i}", im) for i, im in enumerate(big_images)], BOARD).camera
    small = calibrate_images([(f"s{i}", im) for i, im in enumerate(small_images)], BOARD).camera
    scaled = big.scaled_to(640, 480)
    assert scaled.fx == pytest.approx(small.fx, rel=0.005)
    assert scaled.fy == pytest.approx(small.fy, rel=0.005)
    assert scaled.cx == pytest.approx(small.cx, abs=1.0)
    assert scaled.cy == pytest.approx(small.cy, abs=1.0)
    truth = known_camera(640, 480)
    assert scaled.fx == pytest.approx(truth.fx, rel=0.01)


def test_boardless_image_is_named_and_skipped(caplog: pytest.LogCaptureFixture) -> None:
    images = [(f"view{i}", img) for i, img in enumerate(rendered_boards(640, 480)[:5])]
    images.insert(2, ("blank.png", np.full((480, 640), 128, np.uint8)))
    with caplog.at_level(logging.WARNING):
        result = calibrate_images(images, BOARD, progress=False)
    assert [r.name for r in result.skipped] == ["blank.png"]
    assert len(result.used) == 5
    assert "blank.png" in caplog.text
    assert [r.name for r in result.images] == [name for name, _ in images]


def test_too_few_boards_is_a_clear_error() -> None:
    views = rendered_boards(640, 480)
    blank = np.full((480, 640), 128, np.uint8)
    images = [("a", views[0]), ("b", views[1]), ("empty1", blank), ("empty2", blank)]
    with pytest.raises(UserError, match=r"only 2 of 4.*at least 3.*empty1, empty2"):
        calibrate_images(images, BOARD, progress=False)


def test_mixed_resolutions_are_refused() -> None:
    views = rendered_boards(640, 480)
    small = cv2.resize(views[1], (320, 240))
    with pytest.raises(UserError, match=r"a is 640x480 but b is 320x240"):
        calibrate_images([("a", views[0]), ("b", small), ("c", views[2])], BOARD)


def test_board_spec_parsing() -> None:
    assert BoardSpec.parse("9x6").pattern_size == (9, 6)
    assert BoardSpec.parse(" 7 X 5 ", 0.03).square_m == 0.03
    for bad in ("9", "9x", "nine by six", "9x6x2", "1x6"):
        with pytest.raises(UserError):
            BoardSpec.parse(bad)
    # OpenCV's detector raises below 3 a side; a huge grid once asked numpy for 112 GiB.
    for bad in ("2x2", "2x6", "100000x100000", "9x51"):
        with pytest.raises(UserError, match="3 to 50 inner corners"):
            BoardSpec.parse(bad)
    assert BoardSpec.parse("3x3").n_corners == 9


def test_progress_bar_does_not_break_calibration() -> None:
    images = [(f"v{i}", img) for i, img in enumerate(rendered_boards(640, 480)[:4])]
    assert calibrate_images(images, BOARD, progress=True).camera.fx > 0


# ---------------------------------------------------------------------- CLI


def test_cli_writes_a_camera_file_opencv_reads(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    photos = real_chessboard_photos()
    out = tmp_path / "camera.yaml"
    code = main(
        ["calibrate", *map(str, photos), "--board", "9x6", "--square-mm", "25", "-o", str(out)]
    )
    assert code == 0
    text = capsys.readouterr().out
    for word in ("fx", "fy", "cx", "cy", "rms", "left01.jpg", "left12.jpg"):
        assert word in text
    fs = cv2.FileStorage(str(out), cv2.FILE_STORAGE_READ)
    try:
        k = fs.getNode("camera_matrix").mat()
        assert k.shape == (3, 3) and 450 < k[0, 0] < 650
        assert fs.getNode("distortion_coefficients").mat().size == 5
        assert int(fs.getNode("image_width").real()) == 640
        rms = fs.getNode("rms").real()
    finally:
        fs.release()
    assert 0 < rms < 0.6
    assert CameraModel.load(out).rms_px == pytest.approx(rms)


def test_cli_fix_k3_writes_four_radial_tangential_terms(tmp_path: Path) -> None:
    photos = real_chessboard_photos()
    out = tmp_path / "cam.yaml"
    assert main(["calibrate", *map(str, photos), "--fix-k3", "--no-progress", "-o", str(out)]) == 0
    assert CameraModel.load(out).dist_coeffs[4] == 0.0


@pytest.mark.parametrize(
    ("extra_args", "message"),
    [
        (["missing.jpg"], "missing.jpg does not exist"),
        (["--board", "9by6"], "bad board size '9by6'"),
        (["--square-mm", "-3"], "--square-mm must be a positive"),
        (["-o", "no/such/dir/camera.yaml"], "folder no/such/dir does not exist"),
    ],
)
def test_cli_errors_are_clear(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    extra_args: list[str],
    message: str,
) -> None:
    monkeypatch.chdir(tmp_path)
    image = tmp_path / "board.png"
    cv2.imwrite(str(image), rendered_boards(640, 480)[0])
    code = main(["calibrate", str(image), *extra_args])
    assert code == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


def test_cli_unreadable_and_mixed_images(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    views = rendered_boards(640, 480)
    paths = []
    for i, img in enumerate(views[:3]):
        paths.append(tmp_path / f"v{i}.png")
        cv2.imwrite(str(paths[-1]), img)
    corrupt = tmp_path / "corrupt.jpg"
    corrupt.write_bytes(b"\xff\xd8\xff\xe0 this is not really a jpeg")
    # Too few boards once the corrupt file is set aside: both reasons are named.
    assert (
        main(["calibrate", *map(str, paths[:2]), str(corrupt), "-o", str(tmp_path / "c.yaml")]) == 2
    )
    err = capsys.readouterr().err
    assert "only 2 of 3" in err and "Set aside: " in err and "corrupt.jpg (unreadable" in err
    small = tmp_path / "small.png"
    cv2.imwrite(str(small), cv2.resize(views[3], (320, 240)))
    assert main(["calibrate", *map(str, paths), str(small), "-o", str(tmp_path / "c.yaml")]) == 2
    assert "different resolutions" in capsys.readouterr().err
    assert not (tmp_path / "c.yaml").exists()


def test_cli_missing_file_in_a_real_process(tmp_path: Path) -> None:
    proc = subprocess.run(
        [sys.executable, "-m", "obstacle_fusion", "calibrate", str(tmp_path / "nothere.jpg")],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert proc.returncode != 0
    assert "nothere.jpg does not exist" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_cli_corrupt_photo_is_named_and_skipped_not_fatal(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], caplog: pytest.LogCaptureFixture
) -> None:
    """One truncated file among good photos must not throw the session away."""
    paths = []
    for i, img in enumerate(rendered_boards(640, 480)[:4]):
        paths.append(tmp_path / f"v{i}.png")
        cv2.imwrite(str(paths[-1]), img)
    corrupt = tmp_path / "truncated.png"
    corrupt.write_bytes(paths[0].read_bytes()[:200])
    out = tmp_path / "c.yaml"
    with caplog.at_level(logging.WARNING):
        code = main(["calibrate", str(corrupt), *map(str, paths), "--no-progress", "-o", str(out)])
    assert code == 0 and out.is_file()
    text = capsys.readouterr().out
    assert "from 4 of 5 images" in text
    assert "truncated.png" in text and "unreadable image (skipped)" in text
    assert "truncated.png" in caplog.text


def test_enough_boards_but_too_few_photos_says_so() -> None:
    views = rendered_boards(640, 480)
    with pytest.raises(
        UserError, match=r"only 2 of 2.*Every image had its board.*at least 3"
    ) as info:
        calibrate_images([("a", views[0]), ("b", views[1])], BOARD, progress=False)
    assert "No board in" not in str(info.value)


def test_copies_of_one_photo_are_set_aside_not_solved() -> None:
    """Three copies of one view once gave fx 70000 px (fov 1 degree), written as a success."""
    view = rendered_boards(640, 480)[0]
    with pytest.raises(UserError, match=r"Set aside: b \(same view as a\), c \(same view as a\)"):
        calibrate_images([("a", view), ("b", view.copy()), ("c", view)], BOARD, progress=False)


def test_views_too_alike_give_a_clear_error_not_a_wild_camera() -> None:
    view = rendered_boards(640, 480)[0]
    shifted = [
        cv2.warpAffine(
            view, np.float32([[1, 0, d], [0, 1, d]]), (640, 480), borderMode=cv2.BORDER_REPLICATE
        )
        for d in (2, 4)
    ]
    images = [("a", view), ("b", shifted[0]), ("c", shifted[1])]
    with pytest.raises(UserError, match=r"not usable: .*too alike.*tilted"):
        calibrate_images(images, BOARD, progress=False)


@pytest.mark.parametrize("square", ["1e-300", "1e300", "0", "nan"])
def test_cli_absurd_square_sizes_are_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], square: str
) -> None:
    paths = []
    for i, img in enumerate(rendered_boards(640, 480)[:3]):
        paths.append(tmp_path / f"v{i}.png")
        cv2.imwrite(str(paths[-1]), img)
    code = main(
        ["calibrate", *map(str, paths), "--square-mm", square, "-o", str(tmp_path / "c.yaml")]
    )
    assert code == 2
    err = capsys.readouterr().err
    assert "--square-mm must be" in err and "Traceback" not in err


def test_a_corrupt_photo_is_named_once_without_opencvs_own_log_lines(
    tmp_path: Path, capfd: pytest.CaptureFixture[str]
) -> None:
    from obstacle_fusion.vision.calibration import read_image

    bad = tmp_path / "bad.png"
    bad.write_bytes(b"\x89PNG\r\n\x1a\nBROKEN")
    with pytest.raises(UserError, match=r"bad\.png is not a readable image"):
        read_image(bad)
    assert "grfmt" not in capfd.readouterr().err  # OpenCV's "[ERROR:0@...] grfmt_png.cpp"
