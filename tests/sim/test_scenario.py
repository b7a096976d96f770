"""The demo scenario and its keyframe file agree with each other."""

from __future__ import annotations

from pathlib import Path

import pytest
from obstacle_fusion.errors import UserError
from obstacle_fusion.sim.scenario import (
    Obstacle,
    Scenario,
    Segment,
    demo_scenario,
    keyframe_distance,
    load_scenario,
    parse_keyframes,
)

pytestmark = pytest.mark.cpu_only


def test_demo_has_an_approach_a_gap_and_a_different_obstacle() -> None:
    s = demo_scenario()
    a, b = s.obstacle_at(1.0), s.obstacle_at(20.0)
    assert a is not None and b is not None and a != b
    assert (a.height_m, a.width_m) != (b.height_m, b.width_m)
    assert s.distance_at(0.0) > s.distance_at(11.0)  # type: ignore[operator]
    assert s.obstacle_at(13.0) is None and s.distance_at(13.0) is None


def test_keyframe_file_plays_the_same_distances(tmp_path: Path) -> None:
    s = demo_scenario()
    path = s.write_keyframes(tmp_path / "scene.txt")
    frames, temperature = parse_keyframes(path.read_text())
    assert temperature == s.temperature_c
    t = 0.0
    while t < s.duration_s + 2:
        steps = [seg.t1 for seg in s.segments]
        if all(abs(t - x) > 0.01 for x in steps):
            assert keyframe_distance(frames, t) == pytest.approx(s.distance_at(t)), t
        t += 0.05


def test_gap_between_segments_becomes_none_and_steps_are_explicit() -> None:
    box = Obstacle("b", 0.3, 0.3)
    s = Scenario((Segment(0.0, 2.0, box, 1.0, 2.0), Segment(3.0, 4.0, box, 0.5, 0.5)))
    frames = s.keyframes()
    assert frames[0] == (0.0, 1.0) and frames[1] == (2.0, 2.0)
    assert frames[2][1] is None and frames[2][0] > 2.0
    assert keyframe_distance(frames, 2.5) is None
    assert keyframe_distance(frames, 3.5) == pytest.approx(0.5)


def test_bad_scenarios_and_files_are_refused() -> None:
    box = Obstacle("b", 0.3, 0.3)
    with pytest.raises(ValueError):
        Scenario(())
    with pytest.raises(ValueError, match="overlap"):
        Scenario((Segment(0.0, 2.0, box, 1, 1), Segment(1.0, 3.0, box, 1, 1)))
    with pytest.raises(ValueError, match="line 1"):
        parse_keyframes("1.0 2.0 3.0\n")


def test_a_scenario_file_loads_and_bad_ones_are_named(tmp_path: Path) -> None:
    from obstacle_fusion.errors import UserError
    from obstacle_fusion.sim.scenario import load_scenario

    good = tmp_path / "s.toml"
    good.write_text(
        'name = "hall"\ntemperature_c = 25\n'
        "[[segment]]\nt0 = 0\nt1 = 4\nd0 = 2.0\nd1 = 1.0\nheight_m = 0.3\nwidth_m = 0.6\n"
        "[[segment]]\nt0 = 4\nt1 = 6\n"
    )
    s = load_scenario(good)
    assert s.name == "hall" and s.temperature_c == 25
    assert s.distance_at(2.0) == pytest.approx(1.5)
    assert s.obstacle_at(5.0) is None
    for text, words in (
        ("[[segment]]\nt0 = 0\nt1 = 4\nd0 = 9\nheight_m = 0.3\nwidth_m = 0.6\n", "0.02..4 m"),
        ("[[segment]]\nt0 = 3\nt1 = 1\n", "before t0"),
        ("name = 1\n", "no [[segment]]"),
        ("[[segment]\n", "not readable TOML"),
    ):
        bad = tmp_path / "bad.toml"
        bad.write_text(text)
        with pytest.raises(UserError, match=words.replace("[", r"\[").replace(".", r"\.")):
            load_scenario(bad)
    with pytest.raises(UserError, match="does not exist"):
        load_scenario(tmp_path / "nope.toml")


@pytest.mark.parametrize("value", ["500.0", "nan", "-273.0", '"warm"', "true"])
def test_a_bad_scenario_temperature_names_the_file_and_key(tmp_path: Path, value: str) -> None:
    path = tmp_path / "hot.toml"
    path.write_text(
        f"temperature_c = {value}\n[[segment]]\nt0 = 0.0\nt1 = 2.0\nd0 = 1.0\n"
        "height_m = 0.4\nwidth_m = 0.5\n"
    )
    with pytest.raises(UserError, match=r"hot\.toml: temperature_c must be .*-50\.\.80") as err:
        load_scenario(path)
    assert "--temperature" not in str(err.value) and "convert" not in str(err.value)
    path.write_text(path.read_text().replace(f"temperature_c = {value}", "temperature_c = -5"))
    assert load_scenario(path).temperature_c == -5.0


def test_sonar_tables_give_other_sensors_their_own_distances(tmp_path: Path) -> None:
    p = tmp_path / "s.toml"
    p.write_text(
        "[[segment]]\nt0 = 0.0\nt1 = 4.0\nd0 = 2.0\nd1 = 1.0\nheight_m = 0.4\nwidth_m = 0.5\n"
        '[[sonar]]\nid = 1\nkeyframes = [[0.0, 1.5], [2.0, 0.5], [3.0, "none"]]\n'
        "[[sonar]]\nid = 3\ndistance = 2.5\n"
    )
    sc = load_scenario(p)
    assert sc.sensor_count == 4
    assert sc.sensor_distance_at(1, 1.0) == pytest.approx(1.0)
    assert sc.sensor_distance_at(1, 3.5) is None
    assert sc.sensor_distance_at(3, 3.9) == pytest.approx(2.5)
    assert sc.sensor_distance_at(2, 1.0) == sc.distance_at(1.0) == pytest.approx(1.75)
    files = dict(sc.write_sensor_keyframes(tmp_path))
    assert sorted(files) == [1, 3]
    frames, _ = parse_keyframes(files[1].read_text())
    for t in (0.0, 0.7, 1.9, 2.5, 3.2):
        assert keyframe_distance(frames, t) == pytest.approx(sc.sensor_distance_at(1, t))


@pytest.mark.parametrize(
    ("sonar", "match"),
    [
        ("id = 0\ndistance = 1.0", "id must be 1..3"),
        ("id = 1", "either keyframes"),
        ("id = 1\ndistance = 1.0\nkeyframes = [[0.0, 1.0]]", "either keyframes"),
        ("id = 1\ndistance = 9.0", "0.02..4"),
        ("id = 2\nkeyframes = [[1.0, 1.0], [0.5, 1.0]]", "must increase"),
        ("id = 2\nkeyframes = [[1.0]]", r"each keyframe is \[t, d\]"),
    ],
)
def test_bad_sonar_tables_are_named(tmp_path: Path, sonar: str, match: str) -> None:
    p = tmp_path / "s.toml"
    p.write_text(
        "[[segment]]\nt0 = 0.0\nt1 = 4.0\nd0 = 2.0\nheight_m = 0.4\nwidth_m = 0.5\n"
        f"[[sonar]]\n{sonar}\n"
    )
    with pytest.raises(UserError, match=match):
        load_scenario(p)
