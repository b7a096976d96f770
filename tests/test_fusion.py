"""Fusion: pairing frames with the range of their instant, never silently stale."""

from __future__ import annotations

import dataclasses
import logging
import math
from dataclasses import dataclass

import numpy as np
import pytest
from obstacle_fusion.fusion import (
    Fusion,
    FusionStats,
    PairingMode,
    PairKind,
    RangePairer,
    RangeTrack,
    TrackSettings,
)
from obstacle_fusion.sonar import SonarReading, SonarStatus
from obstacle_fusion.sources.frames import Frame

pytestmark = pytest.mark.cpu_only


def _reading(
    t: float, d: float | None, status: SonarStatus = SonarStatus.OK, m: int = 0, sensor: int = 0
) -> SonarReading:
    return SonarReading(
        t_host=t,
        t_trigger_host=t - 0.003,
        trigger_us=int(t * 1e6) & 0xFFFFFFFF,
        measurement=m,
        sensor_id=sensor,
        echo_ticks=0,
        echo_s=0.0,
        status=status,
        distance_m=d,
        raw_distance_m=d,
        slant_m=d,
    )


def _frame(t: float, i: int = 0) -> Frame:
    return Frame(np.zeros((4, 4, 3), np.uint8), t, i, "test")


@dataclass
class _M:
    detected: bool
    height_m: float | None
    width_m: float | None
    distance_m: float | None
    box_px: tuple[float, float, float, float] | None
    confidence: float | None
    method: str = "fake"
    reason: str = ""


class FakeMeasurer:
    def __init__(self, detect: bool = True) -> None:
        self.ranges: list[float] = []
        self.detect = detect

    def measure(self, image: np.ndarray, range_m: float) -> _M:
        self.ranges.append(range_m)
        if not self.detect:
            return _M(False, None, None, None, None, 0.0)
        return _M(True, 0.3, 0.5, range_m, (1.0, 2.0, 3.0, 4.0), 0.9)


class Clock:
    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t


def test_interpolates_between_the_two_readings_around_the_frame() -> None:
    p = RangePairer()
    p.add(_reading(1.00, 2.0, m=1))
    p.add(_reading(1.06, 1.94, m=2))
    pair = p.pair(1.045)
    assert pair.kind is PairKind.INTERPOLATED
    assert pair.distance_m == pytest.approx(1.955)
    assert [r.measurement for r in pair.readings] == [1, 2]


def test_nearest_within_tolerance_when_no_reading_after() -> None:
    p = RangePairer(tolerance_s=0.05)
    p.add(_reading(1.00, 2.0))
    assert p.pair(1.03).kind is PairKind.NEAREST
    assert p.pair(1.03).distance_m == 2.0
    stale = p.pair(1.2)
    assert stale.kind is PairKind.NONE and stale.distance_m is None
    assert stale.reason is not None and "200 ms away" in stale.reason


def test_a_gap_between_readings_is_not_interpolated_across() -> None:
    p = RangePairer(tolerance_s=0.05, max_gap_s=0.2)
    p.add(_reading(1.0, 2.0))
    p.add(_reading(2.0, 1.0))  # one second later: a sonar dropout in between
    assert p.pair(1.5).kind is PairKind.NONE
    near = p.pair(1.98)
    assert near.kind is PairKind.NEAREST and near.distance_m == 1.0


def test_a_failed_reading_next_door_is_not_interpolated() -> None:
    p = RangePairer()
    p.add(_reading(1.00, 2.0))
    p.add(_reading(1.06, None, SonarStatus.NO_ECHO))
    pair = p.pair(1.05)
    assert pair.kind is PairKind.NEAREST and pair.sonar_status is SonarStatus.NO_ECHO
    assert pair.distance_m is None


def test_unmapped_readings_are_counted_not_used() -> None:
    p = RangePairer()
    r = _reading(1.0, 2.0)
    p.add(SonarReading(**{**{f: getattr(r, f) for f in r.__dataclass_fields__}, "t_host": None}))
    assert len(p) == 0 and p.dropped_unmapped == 1


def test_frame_waits_for_the_reading_after_it_then_is_measured_at_its_range() -> None:
    clock = Clock()
    meas = FakeMeasurer()
    f = Fusion(measurer=meas, stop_distance_m=1.0, clock=clock)
    assert f.add_reading(_reading(1.00, 1.2)) == []
    clock.t = 1.05
    assert f.add_frame(_frame(1.03)) == []  # the next reading is still in flight
    clock.t = 1.07
    out = f.add_reading(_reading(1.06, 0.9))
    assert len(out) == 1
    rec = out[0]
    assert rec.status == "ok" and rec.pairing == "interpolated"
    assert rec.distance_m == pytest.approx(1.05)
    assert meas.ranges == [pytest.approx(1.05)]
    assert rec.height_m == 0.3 and rec.width_m == 0.5 and rec.box_px == (1.0, 2.0, 3.0, 4.0)
    assert rec.alert is False
    assert rec.latency_s == pytest.approx(1.07 - 1.03)
    assert f.stats.interpolated == 1 and f.stats.paired_fraction == 1.0


def test_alert_at_the_stop_distance() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), stop_distance_m=1.0, clock=clock)
    f.add_reading(_reading(1.00, 0.95))
    f.add_frame(_frame(1.01))
    rec = f.add_reading(_reading(1.06, 0.93))[0]
    assert rec.alert and f.stats.alerts == 1


def test_wait_expires_and_the_frame_is_unpaired_not_stale() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock, max_wait_s=0.25)
    f.add_reading(_reading(1.00, 1.0))
    clock.t = 1.5
    assert f.add_frame(_frame(1.5)) == []
    clock.t = 1.8
    out = f.poll()
    assert len(out) == 1 and out[0].status == "unpaired" and out[0].distance_m is None
    assert f.stats.unpaired == 1 and f.stats.forced == 1


def test_no_echo_is_published_as_clear_without_measuring() -> None:
    clock = Clock()
    meas = FakeMeasurer()
    f = Fusion(measurer=meas, clock=clock, stop_distance_m=5.0)
    f.add_reading(_reading(1.00, None, SonarStatus.NO_ECHO))
    out = f.add_frame(_frame(1.01))  # a failed newest reading is published at once
    out += f.add_reading(_reading(1.06, None, SonarStatus.NO_ECHO))
    assert len(out) == 1
    rec = out[0]
    assert rec.status == "clear" and rec.distance_m is None and not rec.alert
    assert meas.ranges == []


def test_timeout_is_a_sonar_error() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock)
    f.add_reading(_reading(1.00, None, SonarStatus.TIMEOUT))
    out = f.add_frame(_frame(1.01))
    out += f.add_reading(_reading(1.06, None, SonarStatus.TIMEOUT))
    rec = out[0]
    assert rec.status == "sonar_error" and "timeout" in (rec.reason or "")


def test_not_detected_keeps_the_distance() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(detect=False), clock=clock)
    f.add_reading(_reading(1.00, 1.5))
    f.add_frame(_frame(1.01))
    rec = f.add_reading(_reading(1.06, 1.5))[0]
    assert rec.status == "not_detected" and rec.distance_m == 1.5 and rec.height_m is None


def test_records_come_out_in_frame_order_and_flush_decides_the_rest() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock, pairing=PairingMode.INTERPOLATED)
    for k in range(10):
        f.add_reading(_reading(k * 0.06, 2.0 - k * 0.01, m=k))
    out = []
    for i, t in enumerate([0.07, 0.2, 0.33, 0.5, 0.56]):
        out += f.add_frame(_frame(t, i))
    assert [r.frame_index for r in out] == [0, 1, 2, 3]
    out += f.flush()
    assert [r.frame_index for r in out] == [0, 1, 2, 3, 4]
    assert out[-1].pairing == "nearest"
    assert f.stats.published == 5 and f.stats.paired == 5


def test_to_dict_is_json_ready() -> None:
    import json

    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock)
    f.add_reading(_reading(1.00, 1.0, m=7))
    f.add_frame(_frame(1.02))
    rec = f.add_reading(_reading(1.06, 1.0, m=8))[0]
    d = json.loads(json.dumps(rec.to_dict()))
    assert d["measurements"] == [7, 8] and d["status"] == "ok" and "latency_s" in d


def test_a_vision_refusal_or_crash_is_a_record_not_an_exception() -> None:
    from obstacle_fusion.errors import UserError

    class Refuses:
        def measure(self, image: np.ndarray, range_m: float) -> _M:
            raise UserError("range 0.01 m is outside 0.02..5 m")

    class Crashes:
        def measure(self, image: np.ndarray, range_m: float) -> _M:
            raise RuntimeError("boom")

    for meas, text in ((Refuses(), "outside"), (Crashes(), "boom")):
        clock = Clock()
        f = Fusion(measurer=meas, clock=clock)
        f.add_reading(_reading(1.00, 1.0))
        f.add_frame(_frame(1.01))
        rec = f.add_reading(_reading(1.06, 1.0))[0]
        # Not "not_detected": a robot would read that as "nothing there" and drive on.
        assert rec.status == "vision_error" and text in (rec.reason or "")
        assert rec.distance_m == pytest.approx(1.0) and rec.height_m is None
        assert f.stats.vision_errors == 1 and f.stats.not_detected == 0


# ---------------------------------------------------------------- the defaults' limits
def test_the_default_nearest_tolerance_is_50_ms() -> None:
    p = RangePairer()
    p.add(_reading(1.00, 2.0))
    assert p.pair(1.045).kind is PairKind.NEAREST
    assert p.pair(0.955).kind is PairKind.NEAREST
    far = p.pair(1.06)
    assert far.kind is PairKind.NONE and "60 ms away" in (far.reason or "")
    assert p.pair(0.94).kind is PairKind.NONE


def test_the_default_interpolation_gap_limit_is_200_ms() -> None:
    p = RangePairer()
    p.add(_reading(1.00, 2.0))
    p.add(_reading(1.19, 1.81))
    inside = p.pair(1.10)
    assert inside.kind is PairKind.INTERPOLATED and inside.distance_m == pytest.approx(1.90)
    q = RangePairer()
    q.add(_reading(1.00, 2.0))
    q.add(_reading(1.21, 1.79))
    assert q.pair(1.04).kind is PairKind.NEAREST  # 40 ms from the first: nearest, no line
    assert q.pair(1.10).kind is PairKind.NONE  # 100 ms from both


def test_out_of_range_is_clear_and_too_close_a_sonar_error() -> None:
    for status, expected in (
        (SonarStatus.OUT_OF_RANGE, "clear"),
        (SonarStatus.NO_ECHO, "clear"),
        (SonarStatus.TOO_CLOSE, "sonar_error"),
        (SonarStatus.UNKNOWN, "sonar_error"),
    ):
        clock = Clock()
        f = Fusion(measurer=FakeMeasurer(), clock=clock)
        f.add_reading(_reading(1.00, None, status))
        out = f.add_frame(_frame(1.01))
        out += f.add_reading(_reading(1.06, None, status))
        rec = out[0]
        assert rec.status == expected, status
        assert (f.stats.clear, f.stats.sonar_errors) == ((1, 0) if expected == "clear" else (0, 1))


# ---------------------------------------------------------------- predicted pairing
def _approach(f: Fusion, t0: float = 1.0, n: int = 4, speed: float = -1.0) -> float:
    """Readings every 60 ms of an obstacle coming closer at `speed` m/s from 2 m."""
    t = t0
    for k in range(n):
        t = t0 + 0.06 * k
        f.add_reading(_reading(t, 2.0 + speed * (t - t0), m=k))
    return t


def test_predicted_is_the_default_and_published_at_once() -> None:
    clock = Clock()
    meas = FakeMeasurer()
    f = Fusion(measurer=meas, clock=clock)
    assert f.pairing is PairingMode.PREDICTED
    last = _approach(f)
    clock.t = last + 0.05
    out = f.add_frame(_frame(last + 0.04))
    assert len(out) == 1, "a predicted frame does not wait for the next echo"
    rec = out[0]
    truth = 2.0 - (last + 0.04 - 1.0)
    assert rec.pairing == "predicted" and rec.status == "ok"
    assert rec.distance_m == pytest.approx(truth, abs=2e-4)
    assert meas.ranges == [pytest.approx(truth, abs=2e-4)]
    assert rec.range_sigma_m is not None and 0.0005 < rec.range_sigma_m < 0.01
    assert rec.pair_dt_s == pytest.approx(0.04)
    assert rec.measurements == (3,)
    assert rec.latency_s == pytest.approx(0.01)
    assert f.stats.predicted == 1 and f.stats.paired == 1 and f.stats.forced == 0
    d = rec.to_dict()
    assert d["pairing"] == "predicted" and d["range_sigma_m"] == rec.range_sigma_m
    assert d["ranges"] == {"0": rec.distance_m}


def test_the_prediction_is_uncertain_in_proportion_to_its_reach() -> None:
    track = RangeTrack()
    for k in range(5):
        track.add(_reading(1.0 + 0.06 * k, 2.0 - 0.06 * k))
    near, _ = track.predict(1.25)
    far, _ = track.predict(1.40)
    assert near is not None and far is not None
    assert far.sigma_m > near.sigma_m
    assert near.speed_mps == pytest.approx(-1.0, abs=1e-3)


def test_never_extrapolates_past_the_gap_limit() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock, max_wait_s=0.25)
    last = _approach(f)
    clock.t = last + 0.195
    inside = f.add_frame(_frame(last + 0.19, 0))
    assert [r.pairing for r in inside] == ["predicted"]  # 190 ms: within the 200 ms limit
    assert f.track.max_extrapolation_s == 0.2
    clock.t = last + 0.215
    assert f.add_frame(_frame(last + 0.21, 1)) == [], "210 ms past the last reading: waits"
    clock.t = last + 0.215 + 0.25
    late = f.poll()
    assert len(late) == 1 and late[0].pairing == "none" and late[0].distance_m is None
    assert "extrapolation limit 200 ms" in (late[0].reason or "")
    assert f.stats.forced == 1 and f.stats.unpaired == 1


def test_a_single_reading_does_not_predict_the_frame_waits_and_interpolates() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock)
    f.add_reading(_reading(1.00, 2.0))
    clock.t = 1.05
    assert f.add_frame(_frame(1.03)) == []
    out = f.add_reading(_reading(1.06, 1.94))
    assert [r.pairing for r in out] == ["interpolated"]
    assert out[0].distance_m == pytest.approx(1.97)


def test_a_frame_before_the_newest_reading_is_interpolated_not_predicted() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock)
    last = _approach(f)
    clock.t = last + 0.01
    rec = f.add_frame(_frame(last - 0.03))[0]
    assert rec.pairing == "interpolated" and rec.range_sigma_m is None


def test_a_failed_reading_stops_predictions_and_is_published_at_once() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock)
    last = _approach(f)
    f.add_reading(_reading(last + 0.06, None, SonarStatus.NO_ECHO))
    clock.t = last + 0.09
    rec = f.add_frame(_frame(last + 0.08))[0]
    assert rec.pairing == "nearest" and rec.status == "clear" and rec.distance_m is None
    # A good reading again: the track goes on (its last good reading is 120 ms old).
    f.add_reading(_reading(last + 0.12, 2.0 - (last + 0.12 - 1.0)))
    clock.t = last + 0.16
    rec = f.add_frame(_frame(last + 0.15, 1))[0]
    assert rec.pairing == "predicted"
    assert rec.distance_m == pytest.approx(2.0 - (last + 0.15 - 1.0), abs=1e-3)


def test_another_obstacle_stepping_in_restarts_the_filter() -> None:
    track = RangeTrack()
    for k in range(4):
        track.add(_reading(1.0 + 0.06 * k, 2.0))
    track.add(_reading(1.24, 0.8))  # 1.2 m nearer in 60 ms: not motion
    pred, why = track.predict(1.26)
    assert pred is None and "fewer than two" in why and track.restarts == 1
    track.add(_reading(1.30, 0.8))
    pred, _ = track.predict(1.32)
    assert pred is not None and pred.distance_m == pytest.approx(0.8, abs=1e-3)
    # Within the gate (5 cm off a still obstacle): filtered, not restarted.
    track.add(_reading(1.36, 0.85))
    assert track.restarts == 1


def test_a_gap_in_the_readings_restarts_the_filter() -> None:
    track = RangeTrack(TrackSettings(max_gap_s=0.2))
    track.add(_reading(1.0, 2.0))
    track.add(_reading(1.06, 1.94))
    track.add(_reading(1.27, 1.73))  # 210 ms later
    pred, why = track.predict(1.28)
    assert pred is None and track.restarts == 1 and "fewer than two" in why


def test_interpolated_mode_still_waits() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock, pairing=PairingMode.INTERPOLATED)
    last = _approach(f)
    clock.t = last + 0.05
    assert f.add_frame(_frame(last + 0.04)) == []
    out = f.add_reading(_reading(last + 0.06, 2.0 - (last + 0.06 - 1.0)))
    assert [r.pairing for r in out] == ["interpolated"]


# ---------------------------------------------------------------- several sonars
class Beams:
    def __init__(self, answer: int | None) -> None:
        self.answer = answer
        self.asked: list[list[int]] = []

    def in_view(self, sensors: list[int]) -> list[int]:
        return list(sensors)

    def choose(
        self, box_px: tuple[float, float, float, float], depth_m: float, sensors: list[int]
    ) -> int | None:
        self.asked.append(list(sensors))
        return self.answer


def _two_sonars(f: Fusion) -> float:
    for k in range(4):
        t = 1.0 + 0.06 * k
        f.add_reading(_reading(t, 2.0, m=2 * k, sensor=0))
        f.add_reading(_reading(t + 0.03, 0.7, m=2 * k + 1, sensor=1))
    return 1.0 + 0.06 * 3 + 0.03


def test_every_sonars_range_is_recorded_and_the_nearest_valid_is_used() -> None:
    clock = Clock()
    meas = FakeMeasurer()
    f = Fusion(measurer=meas, clock=clock)
    last = _two_sonars(f)
    clock.t = last + 0.02
    rec = f.add_frame(_frame(last + 0.01))[0]
    assert rec.sensor_id == 1 and rec.distance_m == pytest.approx(0.7)
    assert dict(rec.ranges) == {0: pytest.approx(2.0), 1: pytest.approx(0.7)}
    assert rec.to_dict()["ranges"] == {"0": pytest.approx(2.0), "1": pytest.approx(0.7)}
    assert meas.ranges == [pytest.approx(0.7)]


def test_the_sonar_whose_beam_covers_the_box_gives_the_distance() -> None:
    clock = Clock()
    meas = FakeMeasurer()
    beams = Beams(0)
    f = Fusion(measurer=meas, clock=clock, beams=beams)
    last = _two_sonars(f)
    clock.t = last + 0.02
    rec = f.add_frame(_frame(last + 0.01))[0]
    assert beams.asked == [[1, 0], [1, 0]]  # nearest first, then the covering one confirms
    assert rec.sensor_id == 0 and rec.distance_m == pytest.approx(2.0)
    assert meas.ranges == [pytest.approx(0.7), pytest.approx(2.0)]  # measured again
    assert rec.depth_m == pytest.approx(2.0)
    none_cover = Fusion(measurer=FakeMeasurer(), clock=clock, beams=Beams(None))
    _two_sonars(none_cover)
    assert none_cover.add_frame(_frame(last + 0.01))[0].sensor_id == 1


def test_a_silent_sonar_does_not_hold_frames_back() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock, pairing=PairingMode.INTERPOLATED)
    f.add_reading(_reading(0.5, 1.0, sensor=1))  # sensor 1 spoke once, long ago
    for k in range(4):
        f.add_reading(_reading(2.0 + 0.06 * k, 2.0, m=k))
    assert f.sensors() == [0]
    clock.t = 2.2
    rec = f.add_frame(_frame(2.1))[0]
    assert rec.pairing == "interpolated" and dict(rec.ranges) == {0: pytest.approx(2.0)}


def test_when_the_nearest_sonars_range_finds_no_box_the_next_one_is_tried() -> None:
    class Picky(FakeMeasurer):
        def measure(self, image: np.ndarray, range_m: float) -> _M:
            self.ranges.append(range_m)
            if abs(range_m - 2.0) > 1e-6:
                return _M(False, None, None, None, None, 0.0)
            return _M(True, 0.3, 0.5, range_m, (1.0, 2.0, 3.0, 4.0), 0.9)

    clock = Clock()
    meas = Picky()
    f = Fusion(measurer=meas, clock=clock, beams=Beams(0), stop_distance_m=1.0)
    last = _two_sonars(f)
    clock.t = last + 0.02
    rec = f.add_frame(_frame(last + 0.01))[0]
    assert meas.ranges == [pytest.approx(0.7), pytest.approx(2.0)]
    assert rec.status == "ok" and rec.sensor_id == 0 and rec.distance_m == pytest.approx(2.0)
    assert rec.alert  # sonar 1 sees something at 0.7 m: the robot must stop all the same


# ---------------------------------------------------------------- the filter's numbers
def _reference_kalman(
    readings: list[tuple[float, float]],
    t_pred: float,
    sigma: float = 0.003,
    psd: float = 0.5,
    v0: float = 2.0,
) -> tuple[float, float, float]:
    """The textbook constant-velocity Kalman filter, in matrices, as an independent check:
    x = (r, v), F = [[1, dt], [0, 1]], Q = q [[dt^3/3, dt^2/2], [dt^2/2, dt]], H = [1, 0],
    with the documented model: 3 mm reading noise, q = 0.5 m^2/s^3, 2 m/s speed prior."""
    t0, z0 = readings[0]
    x = np.array([z0, 0.0])
    p = np.diag([sigma**2, v0**2])
    t_prev = t0
    h = np.array([[1.0, 0.0]])
    r = np.array([[sigma**2]])

    def step(dt: float) -> tuple[np.ndarray, np.ndarray]:
        f = np.array([[1.0, dt], [0.0, 1.0]])
        a = abs(dt)
        q = psd * np.array([[a**3 / 3, dt * a / 2], [dt * a / 2, a]])
        return f @ x, f @ p @ f.T + q

    for t, z in readings[1:]:
        x, p = step(t - t_prev)
        y = z - (h @ x)[0]
        s_mat = h @ p @ h.T + r
        k = p @ h.T @ np.linalg.inv(s_mat)
        x = x + (k * y).ravel()
        p = (np.eye(2) - k @ h) @ p
        t_prev = t
    xp, pp = step(t_pred - t_prev)
    return float(xp[0]), float(xp[1]), float(np.sqrt(pp[0, 0]))


def test_the_filter_is_the_textbook_constant_velocity_kalman_filter() -> None:
    rng = np.random.default_rng(7)
    t = 5.0
    readings = []
    for _ in range(12):
        t += 0.055 + 0.01 * rng.random()
        readings.append((t, 2.0 - 0.7 * (t - 5.0) + 0.003 * rng.standard_normal()))
    track = RangeTrack()
    for k, (tk, z) in enumerate(readings):
        track.add(_reading(tk, z, m=k))
    for reach in (0.0, 0.03, 0.15):
        pred, why = track.predict(t + reach)
        assert pred is not None, why
        r, v, sigma = _reference_kalman(readings, t + reach)
        assert pred.distance_m == pytest.approx(r, abs=1e-12)
        assert pred.speed_mps == pytest.approx(v, abs=1e-9)
        assert pred.sigma_m == pytest.approx(sigma, rel=1e-9)
    assert track.updates == 12 and track.restarts == 0


def test_the_filter_ignores_readings_without_a_time_repeated_or_out_of_order() -> None:
    track = RangeTrack()
    track.add(_reading(1.0, 2.0))
    track.add(_reading(1.06, 1.94))
    state = (track.r, track.v, track.p00, track.p01, track.p11, track.updates)
    for bad in (
        _reading(1.06, 1.5),  # the same instant again
        _reading(1.03, 1.5),  # older
        dataclasses.replace(_reading(1.2, 1.5), t_host=None),
        dataclasses.replace(_reading(1.2, 1.5), t_host=float("nan")),
    ):
        track.add(bad)
        assert (track.r, track.v, track.p00, track.p01, track.p11, track.updates) == state


def test_the_filter_restarts_after_a_gap_over_its_limit_not_at_it() -> None:
    s = TrackSettings(max_gap_s=0.25)
    at = RangeTrack(s)
    for t in (1.0, 1.25, 1.5):  # exactly the limit apart (binary-exact times)
        at.add(_reading(t, 2.0 - (t - 1.0)))
    assert at.restarts == 0 and at.updates == 3
    over = RangeTrack(s)
    for t in (1.0, 1.25, 1.5078125):
        over.add(_reading(t, 2.0 - (t - 1.0)))
    assert over.restarts == 1 and over.updates == 1


def test_the_gate_is_at_least_10_cm_and_otherwise_5_sigma() -> None:
    def steady(settings: TrackSettings) -> RangeTrack:
        track = RangeTrack(settings)
        for k in range(6):
            track.add(_reading(1.0 + 0.0625 * k, 2.0))
        return track

    t_next = 1.0 + 0.0625 * 6
    near = steady(TrackSettings())
    near.add(_reading(t_next, 2.095))  # 9.5 cm off: within the 10 cm floor
    assert near.restarts == 0
    far = steady(TrackSettings())
    far.add(_reading(t_next, 2.105))
    assert far.restarts == 1
    # A noisy sensor (5 cm): 5 sigma of the innovation is the wider bound.
    noisy = TrackSettings(measurement_sigma_m=0.05)
    probe = steady(noisy)
    _, _, p00, _, _ = probe._propagate(0.0625)
    sigma = math.sqrt(p00 + 0.05**2)
    assert 5 * sigma > 0.12
    inside = steady(noisy)
    inside.add(_reading(t_next, 2.0 + 4.8 * sigma))
    assert inside.restarts == 0
    outside = steady(noisy)
    outside.add(_reading(t_next, 2.0 + 5.2 * sigma))
    assert outside.restarts == 1


def test_the_default_filter_restarts_after_a_gap_over_200_ms() -> None:
    track = RangeTrack()
    for t in (1.0, 1.0625, 1.28125):  # 218.75 ms after the second
        track.add(_reading(t, 2.0))
    assert track.restarts == 1 and track.updates == 1
    kept = RangeTrack()
    for t in (1.0, 1.0625, 1.25):  # 187.5 ms
        kept.add(_reading(t, 2.0))
    assert kept.restarts == 0 and kept.updates == 3


def test_a_prediction_reaches_to_the_limit_and_no_further() -> None:
    s = TrackSettings(max_extrapolation_s=0.25)
    track = RangeTrack(s)
    track.add(_reading(0.875, 2.0))
    track.add(_reading(1.0, 2.0))
    at, _ = track.predict(1.25)  # exactly the limit (binary-exact times)
    assert at is not None
    beyond, why = track.predict(1.2578125)
    assert beyond is None and "258 ms old (extrapolation limit 250 ms)" in why


def test_a_prediction_through_zero_is_refused() -> None:
    track = RangeTrack()
    track.add(_reading(1.0, 0.2))
    track.add(_reading(1.0625, 0.1))  # 1.6 m/s closer: through zero 62 ms later
    pred, why = track.predict(1.19)
    assert pred is None and "not positive" in why
    assert track.predict(1.08)[0] is not None


# ---------------------------------------------------------------- boundaries and bookkeeping
def test_a_history_longer_than_10_s_is_forgotten() -> None:
    p = RangePairer()
    p.add(_reading(0.0, 2.0))
    p.add(_reading(9.9375, 2.0))
    assert len(p) == 2
    p.add(_reading(10.0625, 2.0))  # the first is now 10.06 s older than the newest
    assert len(p) == 2 and p.pair(0.0).kind is PairKind.NONE


def test_interpolation_at_the_gap_limit_and_the_nearest_readings_offset() -> None:
    p = RangePairer()
    p.add(_reading(0.0, 2.0))
    p.add(_reading(0.2, 1.8))  # exactly 200 ms apart: still interpolated
    assert p.pair(0.1).kind is PairKind.INTERPOLATED
    q = RangePairer()
    q.add(_reading(1.0, 2.0))
    q.add(_reading(1.0625, 1.9375))
    mid = q.pair(1.03125)  # exactly half way: dated against the reading before
    assert mid.dt_s == pytest.approx(0.03125) and mid.distance_m == pytest.approx(1.96875)
    late = q.pair(1.046875)  # three quarters: against the reading after
    assert late.dt_s == pytest.approx(-0.015625)


def test_the_nearest_tolerance_boundary_is_inclusive() -> None:
    p = RangePairer(tolerance_s=0.0625)
    p.add(_reading(1.0, 2.0))
    assert p.pair(1.0625).kind is PairKind.NEAREST
    assert p.pair(0.9375).kind is PairKind.NEAREST
    assert p.pair(1.0703125).kind is PairKind.NONE
    edge = RangePairer(tolerance_s=0.0625)
    edge.add(_reading(1.0, None, SonarStatus.NO_ECHO))
    edge.add(_reading(1.25, 1.0))
    assert edge.pair(1.0625).sonar_status is SonarStatus.NO_ECHO  # the nearer one


def test_a_reading_at_the_frames_instant_is_not_the_one_after_it() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock, pairing=PairingMode.INTERPOLATED)
    f.add_reading(_reading(1.0, 2.0))
    f.add_reading(_reading(1.0625, 1.9375))
    clock.t = 1.07
    assert f.add_frame(_frame(1.0625)) == []  # waits for the reading after 1.0625
    out = f.add_reading(_reading(1.125, 1.875))
    assert [r.pairing for r in out] == ["interpolated"]


def test_an_unpaired_frame_says_exactly_why() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock, pairing=PairingMode.INTERPOLATED)
    f.add_reading(_reading(1.0, 2.0))
    clock.t = 1.5
    f.add_frame(_frame(1.5))
    clock.t = 1.75
    (rec,) = f.poll()
    assert rec.reason == "nearest sonar reading is 500 ms away (tolerance 50 ms)"
    assert rec.sensor_id is None and rec.confidence == 0.0


def test_the_default_wait_is_250_ms_and_32_frames() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock)
    f.add_reading(_reading(1.0, 2.0))
    clock.t = 1.0
    f.add_frame(_frame(1.0078125, 0))
    clock.t = 1.2421875
    assert f.poll() == []
    clock.t = 1.25  # exactly 250 ms after it arrived
    assert [r.frame_index for r in f.poll()] == [0]
    g = Fusion(measurer=FakeMeasurer(), clock=clock)
    g.add_reading(_reading(1.0, 2.0))
    out = []
    for k in range(32):
        out += g.add_frame(_frame(1.0078125 + k * 1e-4, k))
    assert out == [] and g.pending == 32
    out = g.add_frame(_frame(1.02, 32))
    assert [r.frame_index for r in out] == [0] and g.pending == 32


def test_no_reading_at_all_waits_then_is_unpaired() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock)
    assert not f.ready_for_frames() and f.newest_t is None and f.sensors() == []
    assert f.add_frame(_frame(1.0)) == []
    clock.t = 0.3
    (rec,) = f.poll()
    assert rec.status == "unpaired" and rec.reason == "no sonar reading yet"
    assert rec.to_dict()["ranges"] == {"0": None}
    assert f.stats.forced == 1 and f.stats.unpaired == 1


def test_ready_for_frames_needs_a_predicting_filter() -> None:
    f = Fusion()
    f.add_reading(_reading(1.0, 2.0))
    assert not f.ready_for_frames()
    f.add_reading(_reading(1.06, 2.0))
    assert f.ready_for_frames()
    g = Fusion(pairing=PairingMode.INTERPOLATED)
    g.add_reading(_reading(1.0, 2.0))
    assert g.ready_for_frames()


def test_sonars_speaking_within_a_second_of_the_newest_count() -> None:
    f = Fusion()
    f.add_reading(_reading(2.0, 1.0, sensor=1))  # only sensor 1 so far
    assert f.newest_t == 2.0 and f.sensors() == [1]
    f.add_reading(_reading(3.0, 1.0, sensor=0))  # exactly 1 s later
    assert f.sensors() == [0, 1]
    f.add_reading(_reading(3.0078125, 1.0, sensor=0))
    assert f.sensors() == [0]


def test_every_counter_counts_once() -> None:
    clock = Clock()

    class Mixed(FakeMeasurer):
        def measure(self, image: np.ndarray, range_m: float) -> _M:
            self.ranges.append(range_m)
            if range_m > 1.9:
                raise RuntimeError("boom")
            if range_m > 1.4:
                return _M(False, None, None, None, None, 0.0, reason="")
            return _M(True, 0.3, 0.5, range_m, (1.0, 2.0, 3.0, 4.0), None)

    f = Fusion(measurer=Mixed(), clock=clock, pairing=PairingMode.INTERPOLATED)
    recs = []
    plan = [(2.0, "vision_error"), (1.5, "not_detected"), (1.0, "ok")]
    t = 1.0
    for d, _ in plan:
        f.add_reading(_reading(t, d))
        recs += f.add_frame(_frame(t + 0.01))
        recs += f.add_reading(_reading(t + 0.02, d))
        t += 0.5
    f.add_reading(_reading(t, None, SonarStatus.NO_ECHO))
    recs += f.add_frame(_frame(t + 0.01))
    recs += f.add_reading(_reading(t + 0.02, None, SonarStatus.TIMEOUT))
    clock.t = 9.0
    recs += f.add_frame(_frame(9.0))
    clock.t = 9.5
    recs += f.poll()
    assert [r.status for r in recs] == [
        "vision_error",
        "not_detected",
        "ok",
        "clear",
        "unpaired",
    ]
    assert recs[1].reason == "no obstacle found in the image"
    assert recs[2].confidence == 0.0 and recs[2].method == "fake"  # confidence None: 0
    assert recs[3].confidence == 0.0 and recs[3].method is None
    d = f.stats.as_dict()
    assert d == {
        "frames": 5,
        "published": 5,
        "paired": 4,
        "predicted": 0,
        "interpolated": 3,
        "nearest": 1,
        "unpaired": 1,
        "detected": 1,
        "not_detected": 1,
        "clear": 1,
        "sonar_errors": 0,
        "vision_errors": 1,
        "alerts": 0,
        "forced": 1,
        "readings": 8,
        "paired_fraction": 0.8,
    }
    assert f.vision_errors == 1
    assert FusionStats().paired_fraction == 0.0


def test_vision_crashes_are_logged_three_times_then_counted_quietly(
    caplog: pytest.LogCaptureFixture,
) -> None:
    class Crashes:
        def measure(self, image: np.ndarray, range_m: float) -> _M:
            raise RuntimeError("boom")

    clock = Clock()
    f = Fusion(measurer=Crashes(), clock=clock, pairing=PairingMode.INTERPOLATED)
    with caplog.at_level(logging.ERROR, logger="obstacle_fusion.fusion"):
        for k in range(5):
            t = 1.0 + k * 0.0625
            f.add_reading(_reading(t, 1.0))
            f.add_frame(_frame(t + 0.01, k))
        f.add_reading(_reading(2.0, 1.0))
    assert f.vision_errors == 5
    assert len([r for r in caplog.records if "vision failed" in r.getMessage()]) == 3


def test_the_vision_time_is_measured_in_milliseconds(monkeypatch: pytest.MonkeyPatch) -> None:
    import obstacle_fusion.fusion as fusion_module

    ticks = iter([10.0, 10.025, 20.0, 20.0125])
    monkeypatch.setattr(fusion_module.time, "perf_counter", lambda: next(ticks))
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock, pairing=PairingMode.INTERPOLATED)
    f.add_reading(_reading(1.0, 1.0))
    f.add_frame(_frame(1.01))
    (rec,) = f.add_reading(_reading(1.06, 1.0))
    assert rec.vision_ms == pytest.approx(25.0)


def test_without_a_measurer_the_nearest_sonar_of_all_is_used() -> None:
    class OnlyZeroInView(Beams):
        def in_view(self, sensors: list[int]) -> list[int]:
            return [s for s in sensors if s == 0]

    clock = Clock()
    f = Fusion(measurer=None, clock=clock, beams=OnlyZeroInView(0))
    last = _two_sonars(f)
    clock.t = last + 0.02
    rec = f.add_frame(_frame(last + 0.01))[0]
    assert rec.sensor_id == 1 and rec.status == "not_detected"
    assert rec.reason == "no measurer configured" and f.stats.not_detected == 1
    g = Fusion(measurer=FakeMeasurer(), clock=clock, beams=OnlyZeroInView(0))
    _two_sonars(g)
    rec = g.add_frame(_frame(last + 0.01))[0]
    assert rec.sensor_id == 0  # the image can only show what sonar 0 sees


def _three_sonars(f: Fusion) -> float:
    for k in range(4):
        t = 1.0 + 0.06 * k
        for sid, d in ((0, 2.0), (1, 0.7), (2, 1.2)):
            f.add_reading(_reading(t + 0.01 * sid, d, m=3 * k + sid, sensor=sid))
    return 1.0 + 0.06 * 3 + 0.02


class ByRange:
    """A chooser that says which sonar covers the box found at each range."""

    def __init__(self, answers: dict[float, int | None]) -> None:
        self.answers = answers
        self.boxes: list[tuple[float, ...]] = []

    def in_view(self, sensors: list[int]) -> list[int]:
        return list(sensors)

    def choose(
        self, box_px: tuple[float, float, float, float], depth_m: float, sensors: list[int]
    ) -> int | None:
        self.boxes.append((*box_px, depth_m))
        return self.answers[round(depth_m, 3)]


def test_the_covering_sonar_is_measured_next_not_the_next_nearest() -> None:
    clock = Clock()
    meas = FakeMeasurer()
    beams = ByRange({0.7: 0, 2.0: 0})
    f = Fusion(measurer=meas, clock=clock, beams=beams)
    last = _three_sonars(f)
    clock.t = last + 0.02
    rec = f.add_frame(_frame(last + 0.01))[0]
    assert meas.ranges == [pytest.approx(0.7), pytest.approx(2.0)]  # not 1.2 in between
    assert rec.sensor_id == 0
    assert beams.boxes[0] == (1.0, 2.0, 3.0, 4.0, pytest.approx(0.7))


def test_two_sonars_pointing_at_each_other_end_with_a_detection() -> None:
    clock = Clock()
    meas = FakeMeasurer()
    f = Fusion(measurer=meas, clock=clock, beams=ByRange({0.7: 0, 2.0: 1}))
    last = _two_sonars(f)
    clock.t = last + 0.02
    rec = f.add_frame(_frame(last + 0.01))[0]
    assert meas.ranges == [pytest.approx(0.7), pytest.approx(2.0)]
    assert rec.sensor_id == 1 and rec.status == "ok"  # the first detection is kept

    class FirstBlind(FakeMeasurer):
        def measure(self, image: np.ndarray, range_m: float) -> _M:
            self.ranges.append(range_m)
            if range_m < 1.0:
                return _M(False, None, None, None, None, 0.0)
            return _M(True, 0.3, 0.5, range_m, (1.0, 2.0, 3.0, 4.0), 0.9)

    g = Fusion(measurer=FirstBlind(), clock=clock, beams=ByRange({2.0: 1}))
    _two_sonars(g)
    rec = g.add_frame(_frame(last + 0.01))[0]
    assert rec.sensor_id == 0 and rec.status == "ok"  # 1 found nothing: 0's box is kept


def test_no_covering_sonar_keeps_the_nearest_in_view() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock, beams=ByRange({0.7: None}))
    last = _two_sonars(f)
    clock.t = last + 0.02
    rec = f.add_frame(_frame(last + 0.01))[0]
    assert rec.sensor_id == 1 and rec.box_px == (1.0, 2.0, 3.0, 4.0)


def test_the_gate_boundary_keeps_the_track() -> None:
    track = RangeTrack(TrackSettings(gate_min_m=0.125))
    for k in range(6):
        track.add(_reading(1.0 + 0.0625 * k, 2.0))
    assert track.r == 2.0 and track.v == 0.0  # exact: every innovation was 0
    track.add(_reading(1.375, 2.125))  # exactly at the 12.5 cm gate: still motion
    assert track.restarts == 0


def test_an_obstacle_exactly_at_the_stop_distance_alerts() -> None:
    clock = Clock()
    f = Fusion(
        measurer=FakeMeasurer(), clock=clock, stop_distance_m=1.0, pairing=PairingMode.INTERPOLATED
    )
    f.add_reading(_reading(1.0, 1.0))
    f.add_frame(_frame(1.01))
    (rec,) = f.add_reading(_reading(1.06, 1.0))
    assert rec.distance_m == 1.0 and rec.alert


def test_a_paired_failure_is_preferred_to_an_unpaired_sonar() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock, pairing=PairingMode.INTERPOLATED)
    f.add_reading(_reading(0.5, 2.0, sensor=0))  # sensor 0: 510 ms before the frame
    f.add_reading(_reading(1.0, None, SonarStatus.NO_ECHO, sensor=1))
    f.add_frame(_frame(1.01))
    clock.t = 1.3
    (rec,) = f.poll()
    assert rec.sensor_id == 1 and rec.status == "clear"
    assert rec.to_dict()["ranges"] == {"0": None, "1": None}


def test_a_sonar_out_of_view_is_never_measured() -> None:
    class OnlyZeroInView(Beams):
        def in_view(self, sensors: list[int]) -> list[int]:
            return [s for s in sensors if s == 0]

    clock = Clock()
    meas = FakeMeasurer()
    beams = OnlyZeroInView(1)  # it would say the box is in sonar 1's beam
    f = Fusion(measurer=meas, clock=clock, beams=beams)
    last = _two_sonars(f)
    clock.t = last + 0.02
    rec = f.add_frame(_frame(last + 0.01))[0]
    assert rec.sensor_id == 0 and meas.ranges == [pytest.approx(2.0)] and beams.asked == []


def test_a_failed_or_boxless_measurement_moves_on_to_the_next_sonar() -> None:
    for first in ("crash", "no_detection_with_a_box"):

        class Odd(FakeMeasurer):
            def measure(self, image: np.ndarray, range_m: float, first: str = first) -> _M:
                self.ranges.append(range_m)
                if range_m < 1.0:
                    if first == "crash":
                        raise RuntimeError("boom")
                    return _M(False, None, None, None, (1.0, 2.0, 3.0, 4.0), 0.0)
                return _M(True, 0.3, 0.5, range_m, (1.0, 2.0, 3.0, 4.0), 0.9)

        clock = Clock()
        meas = Odd()
        f = Fusion(measurer=meas, clock=clock, beams=ByRange({2.0: 0}))
        last = _two_sonars(f)
        clock.t = last + 0.02
        rec = f.add_frame(_frame(last + 0.01))[0]
        assert rec.sensor_id == 0 and rec.status == "ok", first
        assert meas.ranges == [pytest.approx(0.7), pytest.approx(2.0)]


def test_the_observer_sees_each_measurement_and_not_a_failed_one() -> None:
    seen: list[tuple[int, float]] = []

    def observe(frame: Frame, range_m: float, m: object) -> None:
        seen.append((frame.index, range_m))

    clock = Clock()
    f = Fusion(
        measurer=FakeMeasurer(), clock=clock, pairing=PairingMode.INTERPOLATED, observer=observe
    )
    f.add_reading(_reading(1.0, 1.5))
    f.add_frame(_frame(1.01, 7))
    f.add_reading(_reading(1.06, 1.5))
    assert seen == [(7, pytest.approx(1.5))]

    class Crashes:
        def measure(self, image: np.ndarray, range_m: float) -> _M:
            raise RuntimeError("boom")

    g = Fusion(measurer=Crashes(), clock=clock, pairing=PairingMode.INTERPOLATED, observer=observe)
    g.add_reading(_reading(1.0, 1.5))
    g.add_frame(_frame(1.01, 8))
    g.add_reading(_reading(1.06, 1.5))
    assert seen == [(7, pytest.approx(1.5))]


def test_sonar_only_records_say_what_the_sonar_heard() -> None:
    f = Fusion(stop_distance_m=1.0)
    cases = [
        (_reading(1.0, 1.0), "range", 1.0, True),
        (_reading(1.1, None, SonarStatus.NO_ECHO), "clear", None, False),
        (_reading(1.2, None, SonarStatus.OUT_OF_RANGE), "clear", None, False),
        (_reading(1.3, None, SonarStatus.TIMEOUT), "sonar_error", None, False),
        # A distance with a failed status is not a range.
        (
            dataclasses.replace(_reading(1.4, 0.5), status=SonarStatus.TIMEOUT),
            "sonar_error",
            None,
            False,
        ),
    ]
    for reading, status, distance, alert in cases:
        rec = f.range_record(reading)
        assert (rec.status, rec.distance_m, rec.alert) == (status, distance, alert), reading
        assert rec.t_host == reading.t_host and rec.frame_index == -1
        assert rec.confidence == (1.0 if distance is not None else 0.0)
    clock = Clock()
    clock.t = 9.0
    g = Fusion(clock=clock)
    undated = g.range_record(dataclasses.replace(_reading(1.0, 2.0), t_host=None))
    assert undated.t_host == 9.0 and not undated.alert  # no stop distance: never an alert
    # the next reading, dated by the clock model now ready, happened before that receipt:
    # the records still come out in time order
    assert g.range_record(_reading(8.99, 2.0)).t_host == 9.0
    assert g.range_record(_reading(9.5, 2.0)).t_host == 9.5
    s = f.stats
    assert (s.readings, s.clear, s.sonar_errors, s.alerts, s.published) == (5, 2, 2, 1, 5)
