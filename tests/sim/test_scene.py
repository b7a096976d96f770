"""The synthetic scene renderer: deterministic, and its ground truth is where the pixels are."""

from __future__ import annotations

import numpy as np
import pytest
from obstacle_fusion.sim.scene import SceneSpec, render_scene
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.rig import Rig

pytestmark = pytest.mark.cpu_only

CAM = CameraModel.paper()


def fresh_seed() -> int:
    return int(np.random.SeedSequence().entropy % (1 << 31))


def test_same_seed_same_image_and_other_seed_differs() -> None:
    spec = SceneSpec.random(7, hard=True)
    a = render_scene(spec, CAM, Rig(), 11)
    b = render_scene(spec, CAM, Rig(), 11)
    c = render_scene(spec, CAM, Rig(), 12)
    assert np.array_equal(a.image, b.image)
    assert not np.array_equal(a.image, c.image)
    assert a.image.shape == (375, 500, 3) and a.image.dtype == np.uint8


def test_truth_box_matches_rendered_edges() -> None:
    """A dark box on a bright, featureless room: its edges sit on the truth box to < 0.3 px.

    Level camera, so each edge's extreme (barrel distortion bows it outwards) is mid-edge.
    """
    rig = Rig(camera_height_m=0.25)
    spec = SceneSpec(
        width_m=0.5,
        height_m=0.4,
        distance_m=1.2,
        box_color=(20.0, 20.0, 20.0),
        floor_style="plain",
        floor_color=(220.0, 220.0, 220.0),
        wall_color=(220.0, 220.0, 220.0),
        skirting_m=0.0,
        shadow=0.0,
        noise_sigma=0.0,
        blur_sigma=0.0,
        light_gradient=0.0,
    )
    sc = render_scene(spec, CAM, rig, 1)
    grey = sc.image[:, :, 1].astype(np.float64)
    x0, y0, x1, y1 = sc.truth.box_px
    row = int(round((y0 + y1) / 2))
    col = int(round((x0 + x1) / 2))

    def crossing(profile: np.ndarray, start: int) -> float:
        # sub-pixel position where the profile crosses half way between its two plateaus
        lo, hi = profile.min(), profile.max()
        half = (lo + hi) / 2
        i = int(np.nonzero(np.diff(np.sign(profile - half)))[0][0])
        return start + i + (half - profile[i]) / (profile[i + 1] - profile[i])

    left = crossing(grey[row, int(x0) - 4 : int(x0) + 5], int(x0) - 4)
    right = crossing(grey[row, int(x1) - 4 : int(x1) + 5], int(x1) - 4)
    top = crossing(grey[int(y0) - 4 : int(y0) + 5, col], int(y0) - 4)
    # edge at continuous coordinate e: pixel k covers [k-0.5, k+0.5], so the half-way
    # crossing of pixel values sits at e - 0.5 + 0.5 = e along the sample axis
    assert left == pytest.approx(x0, abs=0.3)
    assert right == pytest.approx(x1, abs=0.3)
    assert top == pytest.approx(y0, abs=0.3)


@pytest.mark.parametrize("hard", [False, True])
def test_random_scenes_keep_the_face_in_view(hard: bool) -> None:
    seed = fresh_seed()
    rng = np.random.default_rng(seed)
    for _ in range(6):
        rig = Rig(
            camera_height_m=float(rng.uniform(0.12, 0.4)),
            camera_pitch_deg=float(rng.uniform(0, 10)),
        )
        spec = SceneSpec.random(rng, hard, CAM, rig)
        sc = render_scene(spec, CAM, rig, rng)
        x0, y0, x1, y1 = sc.truth.box_px
        assert 0 <= x0 < x1 <= 499 and 0 <= y0 < y1 <= 374, f"seed {seed}"
        assert sc.truth.hard is hard
        assert 0.02 <= sc.truth.distance_m <= 5.0


def test_empty_room_and_dict_round_trip() -> None:
    spec = SceneSpec(obstacle=False)
    sc = render_scene(spec, CAM, Rig(), 3)
    assert not sc.truth.present
    assert SceneSpec.from_dict(spec.to_dict()) == spec
    with pytest.raises(ValueError):
        SceneSpec(width_m=-1.0)
