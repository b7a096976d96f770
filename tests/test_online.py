"""The run's online estimates: rig from floor-contact rows, latency from image heights."""

from __future__ import annotations

import math
import re
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest
from obstacle_fusion.online import OnlineCalibration, bottom_row
from obstacle_fusion.sonar import SonarReading, SonarStatus
from obstacle_fusion.sources.frames import Frame
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.rig_estimator import floor_row

pytestmark = pytest.mark.cpu_only

W, H_IMG = 500, 375
FY = 459.0
CAMERA = CameraModel(np.array([[FY, 0, 249.5], [0, FY, 187.0], [0, 0, 1]]), np.zeros(5), W, H_IMG)
IMAGE = np.zeros((H_IMG, W, 3), np.uint8)


def _reading(t: float, d: float) -> SonarReading:
    return SonarReading(t, t, 0, 0, 0, 0, 0.0, SonarStatus.OK, d, d, d)


def _drive(
    online: OnlineCalibration, true_h: float, true_p: float, latency: float,
    duration: float = 12.0, confidence: float = 0.9,
) -> None:  # fmt: skip
    """A robot going back and forth before a 0.4 m box; frames stamped `latency` late."""

    def depth(t: float) -> float:
        return 1.5 + 0.8 * math.sin(2 * math.pi * t / 6.0)  # 0.7..2.3 m, up to 0.84 m/s

    rng = np.random.default_rng(0)
    t_r, t_f, k = 0.0, 0.3, 0
    while t_f < duration:
        while t_r <= t_f + 0.1:
            online.reading_in(_reading(t_r, depth(t_r) + rng.normal(0, 0.002)))
            t_r += 0.05
        seen = depth(t_f - latency)
        row = floor_row(FY, CAMERA.cy, true_h, true_p, seen) + rng.normal(0, 0.3)
        m = SimpleNamespace(
            detected=True, confidence=confidence, method="paper", lines=[],
            box_px=(200.0, row - 80.0, 300.0, row), height_px=FY * 0.4 / seen + rng.normal(0, 0.2),
        )  # fmt: skip
        frame = online.frame_in(Frame(IMAGE, t_f, k, "test"))
        online.measured(frame, depth(frame.t_host), m)
        online.update(now=t_f)
        t_f += 1 / 15
        k += 1
    online.update(now=t_f, force=True)


def test_bottom_row_undistorts_the_fused_bottom_edge() -> None:
    lens = CameraModel.paper(W, H_IMG)  # real distortion
    pts = lens.project(np.array([[-0.2, 0.25, 1.2], [0.25, 0.25, 1.2]]))  # one floor line
    m = SimpleNamespace(method="fused", lines=[tuple(pts.reshape(-1))], box_px=None)
    assert bottom_row(lens, m) == pytest.approx(lens.cy + lens.fy * 0.25 / 1.2, abs=0.01)
    box = SimpleNamespace(method="paper", lines=[], box_px=(100.0, 50.0, 300.0, 250.0))
    assert bottom_row(CAMERA, box) == pytest.approx(250.0)
    assert bottom_row(CAMERA, SimpleNamespace(method="paper", lines=[], box_px=None)) is None


def test_estimates_the_rig_and_latency_and_redates_frames() -> None:
    online = OnlineCalibration(
        Rig(camera_height_m=0.25, camera_pitch_deg=3.0), camera_of=lambda w, h: CAMERA
    )
    _drive(online, 0.25, 3.0, latency=0.08)
    lat, est = online.latency_estimate, online.rig_estimate
    assert lat is not None and abs(lat.latency_s - 0.08) < 0.005 and lat.confidence > 0.8
    assert est is not None and abs(est.height_m - 0.25) < 0.005 and abs(est.pitch_deg - 3.0) < 0.2
    assert online.applied_latency_s == pytest.approx(lat.latency_s)
    later = online.frame_in(Frame(IMAGE, 100.0, 9999, "test"))
    assert later.t_host == pytest.approx(100.0 - lat.latency_s)
    assert online.warnings == []  # the default rig is not a file: nothing to disagree with
    assert online.summary()["rig_estimate"]["n_used"] == est.n_used
    rig = online.estimated_rig()
    assert rig is not None and rig.camera_height_m == est.height_m
    assert rig.camera_pitch_deg == est.pitch_deg and rig.sonar_below_m == Rig().sonar_below_m


def test_a_wrong_rig_file_is_warned_once_the_latency_is_known() -> None:
    online = OnlineCalibration(
        Rig(camera_height_m=0.20), rig_source="file", camera_of=lambda w, h: CAMERA
    )
    _drive(online, 0.25, 3.0, latency=0.08)
    assert len(online.warnings) == 1
    assert "0.200 m high" in online.warnings[0]
    assert re.search(r"off by \+[45]\.\d cm", online.warnings[0]), online.warnings[0]


def test_a_rig_file_within_tolerance_is_not_warned() -> None:
    online = OnlineCalibration(
        Rig(camera_height_m=0.235, camera_pitch_deg=3.8), rig_source="file",
        camera_of=lambda w, h: CAMERA,
    )  # fmt: skip
    _drive(online, 0.25, 3.0, latency=0.08)
    assert online.rig_estimate is not None and online.warnings == []


def test_a_given_latency_is_not_replaced_and_low_confidence_detections_are_ignored() -> None:
    online = OnlineCalibration(
        Rig(camera_height_m=0.25, camera_pitch_deg=3.0),
        rig_source="file",
        latency_given_s=0.05,
        stamp_shift_s=0.05,
        camera_of=lambda w, h: CAMERA,
    )
    _drive(online, 0.25, 3.0, latency=0.08)
    lat = online.latency_estimate
    assert lat is not None and abs(lat.latency_s - 0.03) < 0.005  # what remains of 80 ms
    assert online.applied_latency_s == 0.0
    assert online.frame_in(Frame(IMAGE, 10.0, 1, "t")).t_host == pytest.approx(9.95)
    # the rig fit still dates each row by what remains: a right rig file is not warned about
    est = online.rig_estimate
    assert est is not None and abs(est.height_m - 0.25) < 0.005 and online.warnings == []
    shy = OnlineCalibration(Rig(), camera_of=lambda w, h: CAMERA)
    _drive(shy, 0.25, 3.0, latency=0.08, confidence=0.4)
    assert shy.detections == 0 and shy.rig_estimate is None and shy.latency_estimate is None


def test_rendered_frames_measured_by_the_fused_method() -> None:
    """The whole chain on rendered frames: a box 0.4 m tall on a pitched rig, a camera 80 ms
    late, the fused method's heights and bottom edges, stop-and-go at 0.6 m/s."""
    from obstacle_fusion.sim.scene import SceneSpec, renderer_for
    from obstacle_fusion.sim.synthetic_camera import synthetic_camera_model
    from obstacle_fusion.vision.measure import Measurer

    rig = Rig(camera_height_m=0.30, camera_pitch_deg=5.0, sonar_below_m=0.03)
    camera = synthetic_camera_model(500, 375)
    renderer = renderer_for(camera, rig, 2)
    measurer = Measurer(camera, rig)
    base = SceneSpec(noise_sigma=1.5, blur_sigma=0.5, obstacle=True, height_m=0.4, width_m=0.5)
    keys_t, keys_d = [0.0, 2.8, 3.5, 5.5], [2.5, 0.8, 0.8, 2.0]  # 0.6 m/s, stop, back off

    def depth(t: float) -> float:
        return float(np.interp(t, keys_t, keys_d))

    online = OnlineCalibration(rig, camera_of=lambda w, h: camera.scaled_to(w, h))
    rng = np.random.default_rng(11)
    t_r, t_f, k = 0.0, 0.3, 0
    while t_f < keys_t[-1]:
        while t_r <= t_f + 0.1:
            online.reading_in(_reading(t_r, depth(t_r) + rng.normal(0, 0.002)))
            t_r += 0.05
        image = renderer.render(replace(base, distance_m=depth(t_f - 0.08)), rng).image
        frame = online.frame_in(Frame(image, t_f, k, "rendered"))
        online.measured(frame, depth(t_f), measurer.measure(image, depth(t_f)))  # paired late
        t_f += 1 / 15
        k += 1
    online.update(now=t_f, force=True)
    lat, est = online.latency_estimate, online.rig_estimate
    assert online.detections > 60
    assert lat is not None and abs(lat.latency_s - 0.08) < 0.005, lat
    assert est is not None and abs(est.height_m - 0.30) < 0.01 and abs(est.pitch_deg - 5.0) < 0.5
