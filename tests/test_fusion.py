"""Fusion: pairing frames with the range of their instant, never silently stale."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
from obstacle_fusion.fusion import Fusion, PairKind, RangePairer
from obstacle_fusion.sonar import SonarReading, SonarStatus
from obstacle_fusion.sources.frames import Frame


def _reading(
    t: float, d: float | None, status: SonarStatus = SonarStatus.OK, m: int = 0
) -> SonarReading:
    return SonarReading(
        t_host=t,
        t_trigger_host=t - 0.003,
        trigger_us=int(t * 1e6) & 0xFFFFFFFF,
        measurement=m,
        sensor_id=0,
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
    f.add_frame(_frame(1.01))
    rec = f.add_reading(_reading(1.06, None, SonarStatus.NO_ECHO))[0]
    assert rec.status == "clear" and rec.distance_m is None and not rec.alert
    assert meas.ranges == []


def test_timeout_is_a_sonar_error() -> None:
    clock = Clock()
    f = Fusion(measurer=FakeMeasurer(), clock=clock)
    f.add_reading(_reading(1.00, None, SonarStatus.TIMEOUT))
    f.add_frame(_frame(1.01))
    rec = f.add_reading(_reading(1.06, None, SonarStatus.TIMEOUT))[0]
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
    f = Fusion(measurer=FakeMeasurer(), clock=clock)
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
