"""The sides' walk judged against the horizon by the edge it snaps to
(``region.WALK_EDGE_HORIZON``, in ``region.raise_top_by_sides``).

The room is new11's photo 3546 hard with the rig: a teal face with a light tape across it,
its top 1 cm over the camera's height. The edge search took the tape for the top; the
sides' walk went on up past it (both sides still part the face from the night sky beside
it) and its step faded one row under the horizon, two rows under the face's top edge, so
the horizon guard (kept for top faces seen from above) refused it: -38 % high. The edge
the walk snaps to lies over the horizon, where no top face's back edge can be.
"""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import region
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import View

from tests.vision_fixtures import room_size_errors


def test_a_taped_face_with_its_top_at_the_cameras_height_is_read_whole() -> None:
    eh, ew = room_size_errors("photo", 3546, True)
    assert eh < 0.05 and ew < 0.05


def test_without_the_rule_the_top_stays_on_the_tape(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "WALK_EDGE_HORIZON", False)
    eh, _ = room_size_errors("photo", 3546, True)
    assert eh > 0.25


# A drawn face (rows FACE_TOP..BOTTOM, columns LEFT..RIGHT) before a dark wall, a light
# tape across it at rows TAPE; the walk starts under the tape. The image is blurred as a
# lens does: the walk's step fades at row FACE_TOP + 1, the edge it snaps to is FACE_TOP.
H, W = 240, 320
FACE_TOP, BOTTOM, LEFT, RIGHT = 100, 200, 60, 260
TAPE = (140, 143)
DEPTH = 1.0


def view(horizon: float) -> View:
    """A distortion-free camera with no pitch whose horizon lies at row ``horizon``."""
    k = np.array([[300.0, 0.0, W / 2], [0.0, 300.0, horizon], [0.0, 0.0, 1.0]])
    return View(CameraModel(k, np.zeros(5), W, H), Rig(), "level")


def taped_face() -> npt.NDArray[np.uint8]:
    lab = np.empty((H, W, 3), np.float64)
    lab[:] = (60.0, 128.0, 128.0)
    lab[BOTTOM:] = (160.0, 128.0, 128.0)
    lab[FACE_TOP:BOTTOM, LEFT:RIGHT] = (120.0, 100.0, 120.0)
    lab[TAPE[0] : TAPE[1], LEFT:RIGHT] = (200.0, 100.0, 120.0)
    lab += np.random.default_rng(5).normal(0, 1.5, lab.shape)
    img = cv2.cvtColor(np.clip(lab, 0, 255).astype(np.uint8), cv2.COLOR_LAB2BGR)
    return cv2.GaussianBlur(img, (0, 0), 1.0)


def walk(horizon: float) -> int:
    img = taped_face()
    grey = img.mean(axis=2)
    ay = np.zeros(grey.shape, np.float32)
    ay[1:-1] = np.abs(grey[2:] - grey[:-2])
    return region.raise_top_by_sides(img, view(horizon), ay, BOTTOM, TAPE[1], LEFT, RIGHT, DEPTH)


def test_a_walk_ending_under_the_horizon_at_an_edge_over_it_is_taken() -> None:
    # the step fades at row 101, under the horizon at 100.5; the edge (100) is over it
    assert walk(100.5) == FACE_TOP


def test_with_the_switch_off_the_faded_step_refuses_it(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "WALK_EDGE_HORIZON", False)
    assert walk(100.5) == TAPE[1]
    # (with the horizon over the step's end the walk was taken before the rule too)
    assert walk(101.5) == FACE_TOP


def test_an_edge_under_the_horizon_stays_refused() -> None:
    # one row lower the horizon lies over the edge: a top face's back edge may be there
    assert walk(99.5) == TAPE[1]


def test_an_edge_on_the_horizon_row_is_not_over_it() -> None:
    # the edge (100) on the horizon itself is not over it: refused as before the rule
    assert walk(100.0) == TAPE[1]


def test_the_edge_must_lie_over_a_guessed_pitchs_slack_too() -> None:
    """A no-rig trial's guessed pitch may put the true horizon ``horizon_slack_px`` rows
    over ``cy`` (a top face's back edge with it): the edge must lie over that row too."""
    img = taped_face()
    grey = img.mean(axis=2)
    ay = np.zeros(grey.shape, np.float32)
    ay[1:-1] = np.abs(grey[2:] - grey[:-2])
    v = view(100.5)
    v.horizon_slack_px = 1.0  # the true horizon may lie at 99.5: over the edge (100)
    assert region.raise_top_by_sides(img, v, ay, BOTTOM, TAPE[1], LEFT, RIGHT, DEPTH) == TAPE[1]
    v.horizon_slack_px = 0.25  # ... at 100.25 at most: under the edge
    assert region.raise_top_by_sides(img, v, ay, BOTTOM, TAPE[1], LEFT, RIGHT, DEPTH) == FACE_TOP
