"""The camera's latency from the face's image height against the sonar's range."""

from __future__ import annotations

import numpy as np
import pytest
from obstacle_fusion.timing.latency import CameraLatencyEstimator

pytestmark = pytest.mark.cpu_only

FY, H = 459.0, 0.4  # paper lens at 500x375, a 0.4 m tall face


def _feed(
    est: CameraLatencyEstimator, keys_t: list[float], keys_d: list[float], latency: float,
    seed: int, noise_px: float = 0.3, outliers: float = 0.1,
) -> None:  # fmt: skip
    rng = np.random.default_rng(seed)
    end = keys_t[-1]
    for t in np.arange(0.0, end, 1 / 20) + rng.uniform(0.0, 0.01):  # sonar at 20 Hz
        est.add_range(t, float(np.interp(t, keys_t, keys_d)) + rng.normal(0.0, 0.002))
    for t in np.arange(0.3, end, 1 / 15):  # frames at 15 fps, stamped late by `latency`
        h = FY * H / float(np.interp(t - latency, keys_t, keys_d)) + rng.normal(0.0, noise_px)
        if rng.random() < outliers:  # a wrong top edge now and then
            h *= rng.uniform(0.6, 1.4)
        est.add_frame(t, h)


def _stop_and_go(speed: float) -> tuple[list[float], list[float]]:
    """Approach 2.5 -> 0.8 m, stop 0.7 s, back off to 2.0 m: a robot meeting a box."""
    t1 = (2.5 - 0.8) / speed
    return [0.0, t1, t1 + 0.7, t1 + 0.7 + 1.2 / speed], [2.5, 0.8, 0.8, 2.0]


@pytest.mark.parametrize("speed", [0.3, 0.6, 1.0])
@pytest.mark.parametrize("seed", [0, 1])
def test_recovers_80_ms_within_5_ms(speed: float, seed: int) -> None:
    est = CameraLatencyEstimator()
    _feed(est, *_stop_and_go(speed), latency=0.080, seed=seed)
    got = est.estimate()
    assert got is not None
    latency, confidence = got[:2]
    assert abs(latency - 0.080) < 0.005
    assert confidence > 0.8


def test_a_camera_without_latency_reads_near_zero() -> None:
    est = CameraLatencyEstimator()
    _feed(est, *_stop_and_go(0.5), latency=0.0, seed=3)
    got = est.estimate()
    assert got is not None and got.latency_s < 0.005


def test_steady_approach_is_weaker_and_says_so() -> None:
    """At constant speed a delay looks like a depth offset; only the 1/D curvature tells
    them apart, so the error bar is wider than with a stop."""
    steady, stop = CameraLatencyEstimator(), CameraLatencyEstimator()
    _feed(steady, [0.0, 3.0], [2.5, 0.7], latency=0.08, seed=4)
    _feed(stop, *_stop_and_go(0.6), latency=0.08, seed=4)
    a, b = steady.estimate(), stop.estimate()
    assert a is not None and b is not None
    assert abs(a.latency_s - 0.08) < 0.015
    assert a.std_error_s > 2 * b.std_error_s


def test_no_motion_means_no_confidence() -> None:
    est = CameraLatencyEstimator()
    _feed(est, [0.0, 5.0], [1.0, 1.0], latency=0.08, seed=5, outliers=0.0)
    got = est.estimate()
    assert got is None or got.confidence < 0.2


def test_two_obstacles_are_two_segments() -> None:
    """A pause between detections starts a new constant: a second box twice as tall."""
    est = CameraLatencyEstimator()
    rng = np.random.default_rng(6)
    keys_t, keys_d = _stop_and_go(0.6)
    end = keys_t[-1]
    for t in np.arange(0.0, 2 * end + 1.0, 1 / 20):
        tt = t if t < end else t - end - 1.0
        est.add_range(t, float(np.interp(tt, keys_t, keys_d)) + rng.normal(0.0, 0.002))
    for t in np.arange(0.3, 2 * end + 1.0, 1 / 15):
        if end - 0.2 < t < end + 1.3:
            continue  # nothing seen between the boxes
        second = t >= end
        tt = (t if not second else t - end - 1.0) - 0.08
        height = H * (2.0 if second else 1.0)
        est.add_frame(t, FY * height / float(np.interp(tt, keys_t, keys_d)))
    got = est.estimate()
    assert got is not None and abs(got.latency_s - 0.08) < 0.003


def test_too_few_frames() -> None:
    est = CameraLatencyEstimator(min_frames=20)
    _feed(est, [0.0, 1.2], [2.0, 1.5], latency=0.08, seed=7)
    assert est.estimate() is None and "needed" in est.why_not
