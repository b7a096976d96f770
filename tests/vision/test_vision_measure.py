"""Both measurement methods on rendered scenes with known answers, and their bad inputs."""

from __future__ import annotations

import json

import numpy as np
import pytest
from obstacle_fusion.errors import UserError
from obstacle_fusion.sim.scene import SceneSpec, render_scene
from obstacle_fusion.vision.camera import CameraModel, CameraModelError
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.paper import formula8_threshold
from obstacle_fusion.vision.rig import Rig

CAM = CameraModel.paper()


def fresh_seed() -> int:
    return int(np.random.SeedSequence().entropy % (1 << 31))


def clean_room(**kw: object) -> SceneSpec:
    base = dict(
        floor_style="plain",
        floor_color=(200.0, 200.0, 200.0),
        wall_color=(200.0, 200.0, 200.0),
        skirting_m=0.0,
        shadow=0.0,
        box_color=(40.0, 60.0, 90.0),
    )
    base.update(kw)
    return SceneSpec(**base)  # type: ignore[arg-type]


def test_fused_on_fresh_ordinary_scenes() -> None:
    seed = fresh_seed()
    rng = np.random.default_rng(seed)
    errs, missed = [], 0
    for _ in range(12):
        rig = Rig(
            camera_height_m=float(rng.uniform(0.12, 0.4)),
            camera_pitch_deg=float(rng.uniform(0, 10)),
        )
        spec = SceneSpec.random(rng, False, CAM, rig)
        sc = render_scene(spec, CAM, rig, rng)
        res = Measurer(CAM, rig).measure(sc.image, spec.distance_m)
        if not res.detected:
            missed += 1
            continue
        errs.append(max(abs(res.height_m / spec.height_m - 1), abs(res.width_m / spec.width_m - 1)))
    assert missed <= 1, f"seed {seed}"
    assert float(np.median(errs)) < 0.02, f"seed {seed}: {errs}"


@pytest.mark.parametrize("pitch", [0.0, 9.0])
def test_fused_is_exact_for_a_pitched_camera(pitch: float) -> None:
    """Levelling the view makes H = D h / fy exact even with a pitched camera."""
    rig = Rig(camera_height_m=0.3, camera_pitch_deg=pitch, sonar_ahead_m=0.02)
    spec = clean_room(width_m=0.45, height_m=0.5, distance_m=1.4, lateral_m=0.05, noise_sigma=1.0)
    sc = render_scene(spec, CAM, rig, 5)
    res = Measurer(CAM, rig).measure(sc.image, spec.distance_m)
    assert res.detected
    assert res.height_m == pytest.approx(spec.height_m, rel=0.01)
    assert res.width_m == pytest.approx(spec.width_m, rel=0.01)
    x0, y0, x1, y1 = res.box_px  # type: ignore[misc]
    assert np.allclose([x0, y0, x1, y1], sc.truth.box_px, atol=1.0)
    assert 0.5 < res.confidence <= 1.0  # type: ignore[operator]
    assert set(res.timings_ms) >= {"undistort", "gradients", "search", "refine", "total"}


def test_fused_skips_the_top_face_of_a_low_box() -> None:
    rig = Rig(camera_height_m=0.35)
    spec = clean_room(
        height_m=0.12,
        width_m=0.4,
        length_m=0.5,
        distance_m=1.2,
        box_color=(220.0, 170.0, 160.0),
        floor_color=(60.0, 60.0, 60.0),
    )
    sc = render_scene(spec, CAM, rig, 2)
    res = Measurer(CAM, rig).measure(sc.image, spec.distance_m)
    assert res.detected
    assert res.height_m == pytest.approx(0.12, rel=0.03)


@pytest.mark.parametrize(
    ("height", "distance", "cam_h"), [(0.14, 0.9, 0.3), (0.2, 1.3, 0.38), (0.1, 0.6, 0.25)]
)
def test_fused_low_box_whose_top_face_has_the_front_face_shade(
    height: float, distance: float, cam_h: float
) -> None:
    """Light from straight ahead-above shades top and front alike: no front top edge shows.

    The top is where the vertical sides end, not a noise ripple inside the face.
    """
    rig = Rig(camera_height_m=cam_h, camera_pitch_deg=3.0)
    spec = clean_room(
        height_m=height,
        width_m=0.45,
        length_m=0.5,
        distance_m=distance,
        light_x=0.0,
        light_z=1.0,
        noise_sigma=2.5,
        box_color=(50.0, 80.0, 60.0),
        floor_color=(190.0, 170.0, 200.0),
    )
    sc = render_scene(spec, CAM, rig, 5)
    res = Measurer(CAM, rig).measure(sc.image, distance)
    assert res.detected, res.reason
    assert res.height_m == pytest.approx(height, rel=0.03)
    assert res.width_m == pytest.approx(0.45, rel=0.03)


@pytest.mark.parametrize(("distance", "lateral"), [(2.6, 0.0), (3.2, 0.1), (2.2, -0.08)])
def test_fused_far_box_top_face_with_a_faint_front_edge(distance: float, lateral: float) -> None:
    """A far box below the lens shows a top face a few pixels tall, lit almost like its front.

    Its front edge is faint and several rows below the strong back edge; the back edge's
    own blur must not hide it.
    """
    rig = Rig(camera_height_m=0.38, camera_pitch_deg=2.0)
    spec = clean_room(
        height_m=0.17,
        width_m=0.3,
        length_m=0.6,
        distance_m=distance,
        lateral_m=lateral,
        light_x=0.0,
        light_z=0.9,
        noise_sigma=2.0,
        box_color=(235.0, 215.0, 230.0),
        floor_color=(110.0, 120.0, 100.0),
        wall_color=(245.0, 250.0, 240.0),
    )
    sc = render_scene(spec, CAM, rig, 9)
    res = Measurer(CAM, rig).measure(sc.image, distance)
    assert res.detected, res.reason
    assert res.height_m == pytest.approx(0.17, rel=0.05)


@pytest.mark.parametrize(("lateral", "length", "tolerance"), [(0.02, 0.4, 0.05), (0.12, 0.8, 0.08)])
def test_fused_far_box_front_top_edge_is_not_the_back_edges_blur_tail(
    lateral: float, length: float, tolerance: float
) -> None:
    """A far, narrow box below the lens: its top face's back edge is the strongest top edge.

    The front top edge must be taken near the row the back edge's scale predicts, not
    on the back edge's own blur tail a row below it (that kept most of the top face in
    the height: +10-15 %). Where no extremum marks it, the predicted row itself is the
    edge (sub-pixel): refining near it would slide onto that tail again.
    """
    distance = 3.1
    rig = Rig(camera_height_m=0.38, camera_pitch_deg=1.5)
    spec = SceneSpec(
        floor_style="plain",
        skirting_m=0.078,
        skirting_color=(177.0, 141.0, 163.0),
        shadow=0.1,
        noise_sigma=1.9,
        wall_gap_m=1.33,
        height_m=0.195,
        width_m=0.205,
        length_m=length,
        distance_m=distance,
        lateral_m=lateral,
        box_color=(96.0, 79.0, 63.0),
        floor_color=(130.0, 125.0, 114.0),
        wall_color=(255.0, 218.0, 255.0),
        light_x=0.33,
        light_z=0.87,
        blur_sigma=0.8,
    )
    sc = render_scene(spec, CAM, rig, 3)
    res = Measurer(CAM, rig).measure(sc.image, distance)
    assert res.detected, res.reason
    assert res.height_m == pytest.approx(0.195, rel=tolerance)
    assert res.width_m == pytest.approx(0.205, rel=0.05)


def test_fused_low_box_with_a_label_is_measured_to_its_top_not_the_label() -> None:
    """A low, flat box (6 cm) with a light label across its dark front, its top face showing.

    The label's strong edges must not become the face's top (that gave -56 % height): rows
    of another shade with the face's own shade above and below them belong to the face.
    A generated hard scene (benchmark seed 2, hard scene 9), kept with its render seed.
    """
    cam = CameraModel.paper(500, 375)
    rig = Rig(
        camera_height_m=0.23048,
        camera_pitch_deg=6.37,
        sonar_right_m=-0.01456,
        sonar_below_m=0.03674,
        sonar_ahead_m=-0.01765,
    )
    spec = SceneSpec(
        width_m=0.40786,
        height_m=0.06004,
        length_m=0.48643,
        distance_m=0.85928,
        lateral_m=0.00994,
        box_color=(43.39, 59.43, 47.54),
        floor_style="plain",
        floor_color=(195.3, 158.54, 197.27),
        wall_color=(120.78, 141.07, 140.65),
        wall_gap_m=1.3695,
        skirting_m=0.09059,
        skirting_color=(95.92, 143.86, 89.14),
        clutter=15,
        extra_boxes=1,
        label=True,
        light_gain=1.0334,
        light_gradient=0.09005,
        noise_sigma=1.3433,
        blur_sigma=0.72124,
        shadow=0.25096,
        light_x=0.05773,
        light_z=0.45977,
    )
    sc = render_scene(spec, cam, rig, 284010080)
    res = Measurer(cam, rig).measure(sc.image, 0.8578)
    assert res.detected, res.reason
    assert res.height_m == pytest.approx(sc.truth.height_m, rel=0.05)
    assert res.width_m == pytest.approx(sc.truth.width_m, rel=0.03)


def test_fused_confidence_floor_turns_a_weak_answer_into_no_detection() -> None:
    rig = Rig(camera_height_m=0.3)
    spec = clean_room(width_m=0.4, height_m=0.3, distance_m=1.5)
    image = render_scene(spec, CAM, rig, 3).image
    every = Measurer(CAM, rig, min_confidence=0.0).measure(image, 1.5)
    assert every.detected and 0.0 < (every.confidence or 0.0) < 1.0
    strict = Measurer(CAM, rig, min_confidence=1.0).measure(image, 1.5)
    assert not strict.detected and strict.height_m is None
    assert "confidence" in strict.reason and strict.confidence == every.confidence
    with pytest.raises(UserError, match="min_confidence"):
        Measurer(CAM, rig, min_confidence=1.5)


def test_paper_method_on_a_clean_scene_and_its_formula() -> None:
    """The paper assumes obstacles grey 70..210 in front of a background outside that span."""
    rig = Rig(camera_height_m=0.2)
    bright = (240.0, 240.0, 240.0)
    spec = clean_room(
        height_m=0.35,
        width_m=0.5,
        distance_m=1.5,
        noise_sigma=1.0,
        floor_color=bright,
        wall_color=bright,
        box_color=(100.0, 110.0, 120.0),
    )
    sc = render_scene(spec, CAM, rig, 4)
    res = Measurer(CAM, rig, "paper").measure(sc.image, spec.distance_m)
    assert res.detected and res.method == "paper"
    # H = 2 L tan(beta/2) h / Y1 reduces to L h / fy
    assert res.height_m == pytest.approx(spec.distance_m * res.height_px / CAM.fy, rel=1e-9)
    assert res.height_m == pytest.approx(0.35, rel=0.05)
    assert res.width_m == pytest.approx(0.5, rel=0.05)


def test_paper_method_takes_the_lines_around_the_centre_not_the_seams() -> None:
    """Floor seams and the skirting line lie outside the centred box: they are not its edges.

    With Ymin/Ymax over every horizontal line in the image the seams below and the skirting
    above would set the height; the paper's centred obstacle is bounded by the lines
    nearest the image centre, above and below it.
    """
    rig = Rig(camera_height_m=0.2)
    bright = (240.0, 240.0, 240.0)
    spec = clean_room(
        height_m=0.4,
        width_m=0.5,
        distance_m=1.2,
        noise_sigma=1.0,
        floor_style="tiles",
        floor_color=bright,
        seam_color=(40.0, 40.0, 40.0),
        wall_color=bright,
        skirting_m=0.3,
        skirting_color=(30.0, 30.0, 30.0),
        box_color=(100.0, 110.0, 120.0),
    )
    sc = render_scene(spec, CAM, rig, 5)
    res = Measurer(CAM, rig, "paper").measure(sc.image, spec.distance_m)
    assert res.detected
    assert res.height_m == pytest.approx(0.4, rel=0.08)
    # the boundary lines are the box's own (the seams and the skirting span the view);
    # the width is short where Hough splits the bottom edge at the tile seams (the paper's
    # pipeline, kept as it is)
    x0, _, x1, _ = sc.truth.box_px
    assert res.box_px is not None
    assert x0 - 5 <= res.box_px[0] and res.box_px[2] <= x1 + 5
    assert res.width_m is not None and 0.25 <= res.width_m <= 0.52


def test_formula8_threshold_is_the_mean_interval() -> None:
    rng = np.random.default_rng(0)
    img = rng.integers(0, 256, (200, 300)).astype(np.uint8)
    lo, hi = formula8_threshold(img)
    inside = img[(img >= 70) & (img <= 210)].astype(float)
    half = 2.807 * inside.std(ddof=1) / np.sqrt(inside.size)
    assert lo == int(np.floor(inside.mean() - half))
    assert hi == int(np.ceil(inside.mean() + half))


def test_no_obstacle_is_not_detected() -> None:
    bright = (240.0, 240.0, 240.0)
    spec = clean_room(obstacle=False, floor_color=bright, wall_color=bright)
    sc = render_scene(spec, CAM, Rig(), 1)
    for method in ("fused", "paper"):
        res = Measurer(CAM, Rig(), method).measure(sc.image, 1.0)
        assert not res.detected and res.reason
        assert res.height_m is None


def test_bad_inputs() -> None:
    m = Measurer(CAM, Rig())
    img = np.zeros((375, 500, 3), np.uint8)
    with pytest.raises(UserError, match="range"):
        m.measure(img, 6.0)
    with pytest.raises(CameraModelError, match="aspect"):
        m.measure(np.zeros((300, 500, 3), np.uint8), 1.0)
    with pytest.raises(UserError, match="8-bit"):
        m.measure(img.astype(np.float32), 1.0)
    with pytest.raises(UserError, match="method"):
        Measurer(CAM, Rig(), "magic")


def test_scaled_resolution_and_json() -> None:
    """A camera calibrated at 500x375 measures a 1000x750 frame of the same scene."""
    spec = clean_room(height_m=0.3, width_m=0.4, distance_m=1.2)
    big = CameraModel.paper(1000, 750)
    sc = render_scene(spec, big, Rig(), 9)
    res = Measurer(CAM, Rig()).measure(sc.image, 1.2)
    assert res.height_m == pytest.approx(0.3, rel=0.015)
    d = json.loads(json.dumps(res.to_dict()))
    for key in (
        "detected",
        "height_m",
        "width_m",
        "distance_m",
        "box_px",
        "confidence",
        "method",
        "timings_ms",
    ):
        assert key in d


def test_odd_frames_never_raise() -> None:
    """Noise, blank, binary and tiny frames with odd rigs: an answer or detected=false."""
    rng = np.random.default_rng(fresh_seed())
    for i in range(40):
        w = int(rng.choice([40, 64, 320, 500]))
        h = w * 3 // 4
        cam = CameraModel.paper(w, h)
        rig = Rig(
            camera_height_m=float(rng.uniform(0.02, 1.5)),
            camera_pitch_deg=float(rng.uniform(-30, 30)),
        )
        kind = i % 4
        if kind == 0:
            img = rng.integers(0, 256, (h, w, 3)).astype(np.uint8)
        elif kind == 1:
            img = np.zeros((h, w), np.uint8)
        elif kind == 2:
            img = np.full((h, w, 3), 200, np.uint8)
            y0, y1 = sorted(rng.integers(0, h, 2))
            x0, x1 = sorted(rng.integers(0, w, 2))
            img[y0:y1, x0:x1] = 30
        else:
            img = (rng.integers(0, 2, (h, w)) * 255).astype(np.uint8)
        for method in ("fused", "paper"):
            res = Measurer(cam, rig, method).measure(img, float(rng.uniform(0.02, 5.0)))
            d = res.to_dict()
            assert d["detected"] in (True, False)
            if res.detected:
                assert res.height_m is not None and np.isfinite(res.height_m)
            else:
                assert res.reason


@pytest.mark.parametrize("size", ["height_m", "width_m"])
def test_fused_never_reports_a_face_refined_to_a_sliver(
    size: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A refinement that ends under MIN_SIZE_M across is refused with a reason, not reported."""
    import dataclasses

    from obstacle_fusion.vision.fused import method

    rig = Rig()
    spec = clean_room()
    sc = render_scene(spec, CAM, rig, 3)
    assert Measurer(CAM, rig).measure(sc.image, spec.distance_m).detected
    refine = method.refine

    def sliver(*args: object) -> object:
        return dataclasses.replace(refine(*args), **{size: 0.9 * method.MIN_SIZE_M})  # type: ignore[arg-type]

    monkeypatch.setattr(method, "refine", sliver)
    res = Measurer(CAM, rig).measure(sc.image, spec.distance_m)
    assert not res.detected and "under the 3 cm" in (res.reason or "")


def test_the_first_colour_frame_does_not_build_opencvs_lab_tables() -> None:
    """OpenCV's first 8-bit BGR-to-Lab conversion in a process builds its tables (~90 ms of
    CPU): the per-size setup does it, not the first frame's clock (a fresh process, CPU time
    so that a loaded machine's waiting does not count)."""
    import subprocess
    import sys

    code = """
import time
import numpy as np
from obstacle_fusion.sim.scene import SceneSpec, render_scene
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.rig import Rig
cam = CameraModel.paper(500, 375)
rig = Rig(camera_height_m=0.25, camera_pitch_deg=3.0)
rng = np.random.default_rng(5)
spec = SceneSpec.random(rng, False, cam, rig)
image = render_scene(spec, cam, rig, 11).image
m = Measurer(cam, rig)
m.prepare_size(500, 375)
t = time.thread_time()
res = m.measure(image, spec.distance_m)
print(res.detected, (time.thread_time() - t) * 1e3)
"""
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120
    )
    detected, cpu_ms = out.stdout.split()
    assert detected == "True"
    # ~5 ms warm, ~90 ms more when the first frame builds the tables
    assert float(cpu_ms) < 40.0, out.stdout
