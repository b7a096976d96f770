"""Several sonars end to end: `run --sensors 4` on the emulated robot.

The scenario gives each of the four virtual HC-SR04s its own distance (sensor 0 faces the
box the camera films; sensor 1, looking 45 degrees right, a nearer wall coming closer;
sensor 2 a still wall on the left; sensor 3, looking back, a receding one); the rig lists
the four mountings. The host must send SET_CONFIG for the four, record every sonar's range
(each against the scene's truth), and take the distance from the sonar whose beam covers
the box (sensor 0), not from the nearest one (sensor 1).
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from obstacle_fusion.sim.scenario import load_scenario
from obstacle_fusion.vision.rig import Rig

from tests import emulator_fixtures

uno_elf = emulator_fixtures.uno_elf
emulator_built = emulator_fixtures.emulator_built

DATA = Path(__file__).parent / "data"
SCENARIO = DATA / "four_sonars_scenario.toml"
RIG = DATA / "four_sonars_rig.toml"


def test_the_scenario_and_rig_describe_four_sonars() -> None:
    scenario = load_scenario(SCENARIO)
    assert scenario.sensor_count == 4
    assert scenario.sensor_distance_at(1, 6.0) == pytest.approx(0.75)
    assert scenario.sensor_distance_at(2, 6.0) == pytest.approx(1.7)
    assert scenario.sensor_distance_at(0, 6.0) == pytest.approx(1.8)
    rig = Rig.load(RIG)
    assert [m.id for m in rig.sonar_mounts()] == [0, 1, 2, 3]
    assert rig.sensor_count_wanted() == 4
    # A box straight ahead at 1.8 m is in sonar 0's beam only.
    assert rig.sonar_covering(0.0, 1.8, [0, 1, 2, 3]) == 0
    assert rig.sonar_covering(1.8, 1.8, [0, 1, 2, 3]) == 1


def test_four_sonars_through_the_emulator(uno_elf: Path) -> None:
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "obstacle_fusion",
            "run",
            "--sensors",
            "4",
            "--scenario",
            str(SCENARIO),
            "--rig",
            str(RIG),
            "--duration",
            "6",
            "--json",
            "--quiet",
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    scenario = load_scenario(SCENARIO)
    records = [json.loads(line) for line in proc.stdout.splitlines()]
    assert len(records) >= 50
    complete = [r for r in records if all(r["ranges"].get(str(k)) is not None for k in range(4))]
    assert len(complete) >= 0.9 * len(records), "every sonar's range on nearly every record"
    worst = {k: 0.0 for k in range(4)}
    for r in complete:
        t = r["scene_t_s"]
        for k in range(4):
            truth = scenario.sensor_distance_at(k, t)
            assert truth is not None
            err = abs(r["ranges"][str(k)] - truth)
            worst[k] = max(worst[k], err)
            assert err <= 0.01 * truth + 0.002, (k, t, r["ranges"][str(k)], truth)
    assert all(w > 0 for w in worst.values())  # four different streams, all compared
    ok = [r for r in records if r["status"] == "ok"]
    assert len(ok) >= 0.9 * len(records)
    for r in ok:
        # Sonar 1 is nearer (0.9..0.8 m) but looks aside: the box's distance is sonar 0's.
        assert r["sensor_id"] == 0 and r["distance_m"] == r["ranges"]["0"]
        # (a record before sonar 1's first echo of the run has no range of it yet)
        if r["ranges"].get("1") is not None:
            assert r["ranges"]["1"] < r["distance_m"]
        truth = scenario.sensor_distance_at(0, r["scene_t_s"])
        assert truth is not None and abs(r["height_m"] - 0.4) / 0.4 < 0.05
    assert sum(r["ranges"].get("1") is not None for r in ok) >= 0.9 * len(ok)
