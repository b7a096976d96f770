"""Fusion: pairing frames with the range of their instant, never silently stale."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
from obstacle_fusion.fusion import (
    Fusion,
    PairingMode,
    PairKind,
    RangePairer,
    RangeTrack,
    TrackSettings,
)
from obstacle_fusion.sonar import SonarReading, SonarStatus
from obstacle_fusion.sources.frames import Frame


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
    confidence: float
    method: str = "fake"


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
