"""The online rig: camera height and pitch from floor-contact rows at sonar depths."""

from __future__ import annotations

import math

import numpy as np
import pytest
from obstacle_fusion.vision.rig_estimator import OnlineRigEstimator, floor_row

FY, CY = 459.0, 187.0  # the paper's lens at 500x375


def _observe(
    est: OnlineRigEstimator, h: float, p: float, rng: np.random.Generator, n: int = 100,
    outliers: float = 0.2, noise_px: float = 0.5, depths: tuple[float, float] = (0.6, 2.5),
) -> None:  # fmt: skip
    for _ in range(n):
        d = rng.uniform(*depths)
        v = floor_row(FY, CY, h, p, d) + rng.normal(0.0, noise_px)
        if rng.random() < outliers:  # a wrong bottom edge: a seam, a shadow, a shelf
            v += rng.choice([-1.0, 1.0]) * rng.uniform(4.0, 40.0)
        est.add(v, d)


def test_floor_row_is_the_pinhole_projection_of_the_floor_point() -> None:
    h, p, d = 0.3, 8.0, 1.4
    c, s = math.cos(math.radians(p)), math.sin(math.radians(p))
    y_c, z_c = h * c - d * s, h * s + d * c  # the floor point in the pitched camera's frame
    assert floor_row(FY, CY, h, p, d) == pytest.approx(CY + FY * y_c / z_c, abs=1e-9)
    assert floor_row(FY, CY, h, 0.0, d) == pytest.approx(CY + FY * h / d, abs=1e-9)


@pytest.mark.parametrize("seed", range(8))
def test_recovers_height_and_pitch_with_noise_and_20_percent_outliers(seed: int) -> None:
    rng = np.random.default_rng(seed)
    h, p = rng.uniform(0.12, 0.5), rng.uniform(-5.0, 15.0)
    est = OnlineRigEstimator(FY, CY)
    _observe(est, h, p, rng)
    got = est.estimate()
    assert got is not None
    height, pitch, n_used, residual = got  # also a plain tuple
    assert abs(height - h) < 0.01
    assert abs(pitch - p) < 0.5
    assert 70 <= n_used <= 90  # the 20 % outliers are left out (a few fall within the band)
    assert residual < 1.0


def test_one_depth_cannot_tell_height_from_pitch() -> None:
    est = OnlineRigEstimator(FY, CY)
    _observe(est, 0.25, 3.0, np.random.default_rng(1), depths=(1.0, 1.2), outliers=0.0)
    assert est.estimate() is None
    assert "too alike" in est.why_not


def test_too_few_detections_give_nothing_yet() -> None:
    est = OnlineRigEstimator(FY, CY, min_points=15)
    _observe(est, 0.25, 3.0, np.random.default_rng(2), n=14, outliers=0.0)
    assert est.estimate() is None and "14 of the 15" in est.why_not
    _observe(est, 0.25, 3.0, np.random.default_rng(3), n=1, outliers=0.0)
    assert est.estimate() is not None


def test_mostly_garbage_is_refused() -> None:
    est = OnlineRigEstimator(FY, CY)
    rng = np.random.default_rng(4)
    for _ in range(60):
        est.add(rng.uniform(190.0, 370.0), rng.uniform(0.6, 2.5))
    assert est.estimate() is None
    assert "agree" in est.why_not
