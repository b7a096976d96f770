"""calibrate-rig: camera height, pitch and roll from a chessboard lying on the floor."""

from __future__ import annotations

import math
import re
from pathlib import Path

import cv2
import numpy as np
import pytest
from obstacle_fusion.cli import main
from obstacle_fusion.errors import UserError
from obstacle_fusion.sim.floor_boards import FloorRig, nearest_placement, render_floor_board
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.chessboard import BoardRenderer, BoardSpec
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.rig_calibration import (
    ROLL_WARN_DEG,
    calibrate_rig,
    floor_board_pose,
    mounting_from_pose,
)

BOARD = BoardSpec(9, 6, 0.025)
#: Five mountings across what small robots use: 0.12-0.5 m, pitch -5..15 deg, roll 0-2 deg.
RIGS = [
    FloorRig(0.12, -5.0, 0.0),
    FloorRig(0.15, 12.0, 0.4),
    FloorRig(0.22, 0.0, 0.8),
    FloorRig(0.35, 6.0, 1.5),
    FloorRig(0.50, 15.0, 2.0),
]


def _camera() -> CameraModel:
    """A webcam-like 800x600 lens with strong barrel distortion (not the paper's)."""
    w, h = 800, 600
    k = np.array([[0.9 * w, 0, w / 2 + 3.3], [0, 0.9 * w * 0.998, h / 2 - 2.1], [0, 0, 1]])
    return CameraModel(k, np.array([-0.18, 0.09, 0.0008, -0.0006, -0.01]), w, h)


@pytest.fixture(scope="module")
def renderer() -> BoardRenderer:
    return BoardRenderer(_camera(), BOARD, supersample=2)


def _photo(renderer: BoardRenderer, rig: FloorRig, seed: int, yaw: float = 0.0) -> np.ndarray:
    dist = nearest_placement(renderer.camera, BOARD, rig, yaw_deg=yaw)
    assert dist is not None and 0.4 <= dist <= 1.0
    shot = render_floor_board(renderer, rig, dist, yaw_deg=yaw, rng=np.random.default_rng(seed))
    return shot.image


@pytest.mark.parametrize("pitch", [-5.0, 0.0, 7.0, 15.0])
@pytest.mark.parametrize("roll", [0.0, 1.7, -2.0])
def test_pose_of_a_floor_board_gives_back_the_mounting(pitch: float, roll: float) -> None:
    for height in (0.12, 0.5):
        for yaw, right in ((0.0, 0.0), (25.0, -0.1)):
            rvec, tvec = floor_board_pose(
                BOARD, height, pitch, roll, distance_m=0.7, right_m=right, yaw_deg=yaw
            )
            h, p, r = mounting_from_pose(rvec, tvec)
            assert h == pytest.approx(height, abs=1e-9)
            assert p == pytest.approx(pitch, abs=1e-9)
            assert r == pytest.approx(roll, abs=1e-9)


def test_five_rendered_rigs_are_recovered(renderer: BoardRenderer) -> None:
    camera = renderer.camera
    for i, rig in enumerate(RIGS):
        result = calibrate_rig(
            [(f"rig{i}", lambda i=i, rig=rig: _photo(renderer, rig, i))], BOARD, camera
        )
        assert len(result.used) == 1
        assert abs(result.height_m - rig.height_m) <= 0.005, (rig, result.height_m)
        assert abs(result.pitch_deg - rig.pitch_deg) <= 0.2, (rig, result.pitch_deg)
        assert abs(result.roll_deg - rig.roll_deg) <= 0.2, (rig, result.roll_deg)
        assert (result.roll_warning is not None) == (abs(rig.roll_deg) > ROLL_WARN_DEG)
        made = result.rig(sonar_below_m=0.03)
        assert made.camera_height_m == pytest.approx(rig.height_m, abs=0.005)
        assert made.sonar_below_m == 0.03


def test_median_outvotes_one_bad_photo(renderer: BoardRenderer) -> None:
    rig, wrong = RIGS[2], FloorRig(0.30, 4.0, 0.8)  # one photo taken with the robot tilted
    items = [
        ("a", lambda: _photo(renderer, rig, 1)),
        ("b", lambda: _photo(renderer, rig, 2, yaw=6.0)),
        ("c", lambda: _photo(renderer, wrong, 3)),
    ]
    result = calibrate_rig(items, BOARD, renderer.camera)
    assert abs(result.height_m - rig.height_m) <= 0.005
    assert abs(result.pitch_deg - rig.pitch_deg) <= 0.2
    assert [f.name for f in result.outliers()] == ["c"]


def _write(path: Path, image: np.ndarray) -> str:
    cv2.imwrite(str(path), image)
    return str(path)


def test_cli_writes_a_rig_that_loads_and_names_skipped_photos(
    renderer: BoardRenderer, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    camera = renderer.camera
    camera.save(tmp_path / "camera.yaml")
    rolled = RIGS[3]  # 1.5 degrees of roll: warned
    good = _write(tmp_path / "floor.png", _photo(renderer, rolled, 5))
    blank = _write(tmp_path / "blank.png", np.full((600, 800), 120, np.uint8))
    out = tmp_path / "rig.toml"
    code = main(
        [
            "calibrate-rig", good, blank, "--calib", str(tmp_path / "camera.yaml"),
            "--board", "9x6", "--square-mm", "25", "-o", str(out),
            "--sonar-below-m", "0.04", "--sonar-ahead-m", "0.02", "--beam-width-deg", "20",
        ]
    )  # fmt: skip
    captured = capsys.readouterr()
    assert code == 0
    assert "blank.png  no board found (skipped)" in captured.out
    assert "rolled +1.5" in captured.err and "warning" in captured.err
    rig = Rig.load(out)
    assert rig.camera_height_m == pytest.approx(rolled.height_m, abs=0.005)
    assert rig.camera_pitch_deg == pytest.approx(rolled.pitch_deg, abs=0.2)
    assert (rig.sonar_below_m, rig.sonar_ahead_m, rig.beam_width_deg) == (0.04, 0.02, 20.0)


def test_cli_level_camera_is_not_warned(
    renderer: BoardRenderer, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    renderer.camera.save(tmp_path / "camera.yaml")
    photo = _write(tmp_path / "floor.png", _photo(renderer, RIGS[2], 7))  # 0.8 deg of roll
    code = main(["calibrate-rig", photo, "--calib", str(tmp_path / "camera.yaml"),
                 "-o", str(tmp_path / "rig.toml")])  # fmt: skip
    captured = capsys.readouterr()
    assert code == 0 and "warning" not in captured.err
    assert re.search(r"\(roll \+0\.[78]\d deg", captured.out), captured.out


def test_cli_errors(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    camera = _camera()
    camera.save(tmp_path / "camera.yaml")
    blank = _write(tmp_path / "blank.png", np.full((600, 800), 120, np.uint8))
    out = tmp_path / "rig.toml"
    calib = ["--calib", str(tmp_path / "camera.yaml"), "-o", str(out)]
    assert main(["calibrate-rig", blank, *calib]) == 2
    err = capsys.readouterr().err
    assert "no photo is usable" in err and "blank.png (no board found)" in err
    assert not out.exists()
    wide = _write(tmp_path / "wide.png", np.full((450, 800), 120, np.uint8))  # 16:9
    assert main(["calibrate-rig", wide, *calib]) == 2
    assert "another aspect ratio" in capsys.readouterr().err
    assert main(["calibrate-rig", str(tmp_path / "none.png"), *calib]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert main(["calibrate-rig", blank, *calib, "--sonar-ahead-m", "3"]) == 2
    assert "no photo is usable" in capsys.readouterr().err  # photos are read first
    with pytest.raises(UserError, match="no photos"):
        calibrate_rig([], BOARD, camera)


def test_cli_refuses_an_impossible_sonar_offset(
    renderer: BoardRenderer, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    renderer.camera.save(tmp_path / "camera.yaml")
    photo = _write(tmp_path / "floor.png", _photo(renderer, RIGS[1], 9))
    out = tmp_path / "rig.toml"
    code = main(["calibrate-rig", photo, "--calib", str(tmp_path / "camera.yaml"), "-o",
                 str(out), "--sonar-ahead-m", "3"])  # fmt: skip
    assert code == 2
    assert "sonar offsets above 1 m" in capsys.readouterr().err
    assert not out.exists()
    assert math.isfinite(RIGS[1].height_m)
