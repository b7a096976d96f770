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


# ---------------------------------------------------------------- several sonars
def test_a_single_sonar_rig_is_sensor_0_at_the_top_level_values() -> None:
    rig = Rig(sonar_right_m=0.02, sonar_below_m=0.04, beam_width_deg=20.0)
    (m,) = rig.sonar_mounts()
    assert (m.id, m.right_m, m.below_m, m.yaw_deg, m.beam_width_deg) == (0, 0.02, 0.04, 0.0, 20.0)
    assert rig.sensor_count_wanted() is None


def test_sonar_tables_round_trip_and_set_sensor_0s_mounting(tmp_path: Path) -> None:
    path = tmp_path / "rig.toml"
    path.write_text(
        "[rig]\ncamera_height_m = 0.25\n"
        "[[sonar]]\nid = 0\nright_m = 0.03\nbeam_width_deg = 12.0\n"
        "[[sonar]]\nid = 2\nyaw_deg = -30.0\n"
    )
    rig = Rig.load(path)
    assert [m.id for m in rig.sonar_mounts()] == [0, 2]
    assert rig.sonar_right_m == 0.03 and rig.beam_width_deg == 12.0  # the vision's sonar
    assert rig.sensor_count_wanted() == 3  # ids 0..2: the mask covers sensor 2
    rig.save(tmp_path / "again.toml")
    assert Rig.load(tmp_path / "again.toml") == rig
    import dataclasses

    assert Rig(**dataclasses.asdict(rig)) == rig  # as the MCAP metadata holds it


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("[[sonar]]\nid = 1\n", "must include sensor 0"),
        ("[[sonar]]\nid = 0\n[[sonar]]\nid = 0\n", "must differ"),
        ("[[sonar]]\nid = 4\n", "0..3"),
        ("[[sonar]]\nid = 0\nyaw = 3\n", "unknown keys"),
        ("[[sonar]]\nid = 0\nbeam_width_deg = 120\n", "beam_width_deg"),
    ],
)
def test_bad_sonar_tables_are_named(tmp_path: Path, text: str, match: str) -> None:
    path = tmp_path / "rig.toml"
    path.write_text(text)
    with pytest.raises(RigError, match=match):
        Rig.load(path)


def test_the_covering_sonar_is_the_one_nearest_its_axis() -> None:
    from obstacle_fusion.vision.rig import SonarMount

    rig = Rig(
        sonars=(
            SonarMount(0, beam_width_deg=15.0),
            SonarMount(1, right_m=0.1, yaw_deg=10.0, beam_width_deg=30.0),
        )
    )
    assert rig.sonar_covering(0.0, 2.0, [0, 1]) == 0  # both cover; 0 is on its axis
    assert rig.sonar_covering(0.45, 2.0, [0, 1]) == 1  # 12.7 deg right: only 1's beam
    assert rig.sonar_covering(0.45, 2.0, [0]) is None
    assert rig.sonar_covering(-1.0, 1.0, [0, 1]) is None  # 45 deg left: nobody's
    # The beam's edge: 7.5 deg is in, 7.6 is out.
    assert rig.sonar_covering(2.0 * math.tan(math.radians(7.4)), 2.0, [0]) == 0
    assert rig.sonar_covering(2.0 * math.tan(math.radians(7.6)), 2.0, [0]) is None


def test_beam_selector_places_the_box_and_knows_the_view() -> None:
    from obstacle_fusion.vision.camera import CameraModel
    from obstacle_fusion.vision.rig import BeamSelector, SonarMount

    rig = Rig(
        sonars=(
            SonarMount(0),
            SonarMount(1, yaw_deg=20.0),
            SonarMount(2, yaw_deg=60.0),
            SonarMount(3, yaw_deg=180.0),
        )
    )
    cam = CameraModel.paper(500, 375)
    sel = BeamSelector(rig, lambda: cam)
    assert sel.in_view([1, 0, 2, 3]) == [1, 0]  # the view is +-28.6 deg wide
    fx, cx = float(cam.camera_matrix[0][0]), float(cam.camera_matrix[0][2])
    u = cx + fx * math.tan(math.radians(20.0))  # a box centred 20 deg to the right
    assert sel.choose((u - 10, 100, u + 10, 200), 2.0, [0, 1]) == 1
    assert sel.choose((cx - 10, 100, cx + 10, 200), 2.0, [0, 1]) == 0
    assert BeamSelector(rig, lambda: None).choose((0, 0, 1, 1), 2.0, [0, 1]) is None
