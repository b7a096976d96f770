"""The rig: range to face depth, beam bounds, the TOML file and its errors."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from obstacle_fusion.errors import UserError
from obstacle_fusion.vision.rig import Rig, RigError, check_range


def test_face_depth_and_beam() -> None:
    rig = Rig(sonar_ahead_m=0.03, sonar_right_m=0.01, beam_width_deg=15.0)
    assert rig.face_depth(1.0) == pytest.approx(1.03)
    assert rig.range_from_depth(rig.face_depth(0.7)) == pytest.approx(0.7)
    lo, hi = rig.beam_x_bounds(2.0)
    assert hi - lo == pytest.approx(2 * 2.0 * math.tan(math.radians(7.5)))
    assert (lo + hi) / 2 == pytest.approx(0.01)


def test_pitch_rotation_points_the_axis_down() -> None:
    rig = Rig(camera_pitch_deg=10.0)
    axis = rig.camera_to_robot @ np.array([0.0, 0.0, 1.0])
    assert axis[1] == pytest.approx(math.sin(math.radians(10)))  # y is down
    assert np.allclose(rig.camera_to_robot @ rig.camera_to_robot.T, np.eye(3))


def test_file_round_trip_and_errors(tmp_path: Path) -> None:
    rig = Rig(camera_height_m=0.31, camera_pitch_deg=4.5, sonar_below_m=0.02)
    path = tmp_path / "rig.toml"
    rig.save(path)
    assert Rig.load(path) == rig
    (tmp_path / "bad.toml").write_text("camera_height = 0.2\n")
    with pytest.raises(RigError, match="unknown keys"):
        Rig.load(tmp_path / "bad.toml")
    (tmp_path / "neg.toml").write_text("camera_height_m = -0.2\n")
    with pytest.raises(RigError, match="camera_height_m"):
        Rig.load(tmp_path / "neg.toml")
    (tmp_path / "junk.toml").write_text("this is = = not toml")
    with pytest.raises(RigError, match="not valid TOML"):
        Rig.load(tmp_path / "junk.toml")
    with pytest.raises(RigError, match="does not exist"):
        Rig.load(tmp_path / "none.toml")


@pytest.mark.parametrize("bad", [0.0, 0.019, 5.01, float("nan"), -1.0, "x"])
def test_check_range_rejects(bad: object) -> None:
    with pytest.raises(UserError, match="range"):
        check_range(bad)  # type: ignore[arg-type]


def test_check_range_accepts_the_span() -> None:
    assert check_range(0.02) == 0.02 and check_range(5.0) == 5.0
