"""Sonar physics: speed of sound, formulas (6) and (7), statuses, median filter."""

from __future__ import annotations

import math

import pytest
from obstacle_fusion.protocol.generated import Range, RangeStatus
from obstacle_fusion.sonar import SonarConverter, SonarStatus, speed_of_sound

pytestmark = pytest.mark.cpu_only


def _range(ticks: int, status: RangeStatus = RangeStatus.OK, m: int = 0) -> Range:
    return Range(measurement=m, sensor_id=0, trigger_us=1000, echo_ticks=ticks, status=int(status))


def test_speed_of_sound_values() -> None:
    assert speed_of_sound(0.0) == pytest.approx(331.3)
    assert speed_of_sound(20.0) == pytest.approx(343.2, abs=0.1)
    # The paper: "at T = 30 degrees, v = 349 m/s".
    assert speed_of_sound(30.0) == pytest.approx(349.0, abs=0.1)
    with pytest.raises(ValueError):
        speed_of_sound(-300.0)


def test_formula_7_far_away_and_formula_6_up_close() -> None:
    conv = SonarConverter(timer_hz=2_000_000, temperature_c=20.0, half_spacing_m=0.013)
    v = speed_of_sound(20.0)
    # 2 m: the two formulas agree to 0.002%.
    ticks = round(2 * 2.0 / v * 2_000_000)
    r = conv.convert(_range(ticks))
    assert r.status is SonarStatus.OK
    assert r.slant_m == pytest.approx(2.0, rel=1e-5)
    assert r.distance_m == pytest.approx(math.sqrt(2.0**2 - 0.013**2), rel=1e-5)
    # 5 cm slant: the geometry matters (3.4%).
    ticks = round(2 * 0.05 / v * 2_000_000)
    r = conv.convert(_range(ticks))
    assert r.distance_m == pytest.approx(math.sqrt(0.05**2 - 0.013**2), rel=1e-3)
    assert r.distance_m < 0.049
    # Formula 7 only.
    r7 = SonarConverter(half_spacing_m=0.0).convert(_range(ticks))
    assert r7.distance_m == pytest.approx(0.05, rel=1e-3)


def test_temperature_changes_the_distance() -> None:
    ticks = 11662  # about 1 m at 20 degC
    cold = SonarConverter(temperature_c=-10.0).convert(_range(ticks)).distance_m
    warm = SonarConverter(temperature_c=35.0).convert(_range(ticks)).distance_m
    assert cold is not None and warm is not None
    assert warm / cold == pytest.approx(speed_of_sound(35.0) / speed_of_sound(-10.0), rel=1e-4)


def test_timer_hz_from_hello_sets_the_tick() -> None:
    a = SonarConverter(timer_hz=2_000_000, half_spacing_m=0).convert(_range(10000)).distance_m
    b = SonarConverter(timer_hz=1_000_000, half_spacing_m=0).convert(_range(5000)).distance_m
    assert a == pytest.approx(b)


@pytest.mark.parametrize(
    ("wire", "expected"),
    [
        (RangeStatus.NO_ECHO, SonarStatus.NO_ECHO),
        (RangeStatus.TIMEOUT, SonarStatus.TIMEOUT),
        (RangeStatus.OUT_OF_RANGE, SonarStatus.OUT_OF_RANGE),
    ],
)
def test_failed_measurements_have_no_distance(wire: RangeStatus, expected: SonarStatus) -> None:
    r = SonarConverter().convert(_range(76000, wire))
    assert r.status is expected
    assert r.distance_m is None and not r.ok


def test_unknown_status_code_is_explicit() -> None:
    r = SonarConverter().convert(Range(0, 0, 0, 100, 99))
    assert r.status is SonarStatus.UNKNOWN and r.distance_m is None


def test_too_close_for_the_geometry() -> None:
    r = SonarConverter(half_spacing_m=0.013).convert(_range(100))  # 8.6 mm slant
    assert r.status is SonarStatus.TOO_CLOSE
    assert r.distance_m is None and r.slant_m == pytest.approx(0.00858, rel=1e-2)


def test_host_time_is_the_reflection_instant() -> None:
    r = SonarConverter().convert(_range(20000), t_trigger_host=100.0)
    assert r.t_host == pytest.approx(100.0 + 0.005)


def test_median_filter_rejects_a_spike_and_keeps_raw() -> None:
    conv = SonarConverter(median_window=3, half_spacing_m=0.0)
    out = []
    for i, ticks in enumerate([11662, 11670, 2000, 11680, 11690]):
        out.append(conv.convert(_range(ticks, m=i), t_trigger_host=float(i) * 0.06))
    spike = out[2]
    assert spike.raw_distance_m == pytest.approx(0.1716, rel=1e-2)
    assert spike.distance_m is not None and spike.distance_m > 0.99
    assert all(r.distance_m is not None and r.distance_m > 0.99 for r in out)


def test_median_filter_forgets_old_readings() -> None:
    conv = SonarConverter(median_window=3, median_max_age_s=0.5, half_spacing_m=0.0)
    conv.convert(_range(11662), t_trigger_host=0.0)
    conv.convert(_range(11662), t_trigger_host=0.06)
    late = conv.convert(_range(5831), t_trigger_host=5.0)
    assert late.distance_m == pytest.approx(late.raw_distance_m)


def test_bad_settings_are_refused() -> None:
    with pytest.raises(ValueError):
        SonarConverter(timer_hz=0)
    with pytest.raises(ValueError):
        SonarConverter(median_window=0)


def test_a_fast_crystal_is_corrected_by_the_clock_models_scale() -> None:
    conv = SonarConverter(half_spacing_m=0.0)
    v = speed_of_sound(20.0)
    true_echo_s = 2 * 1.0 / v
    ticks = round(true_echo_s * 2_000_000 * 1.005)  # the MCU's timer runs 5000 ppm fast
    naive = conv.convert(_range(ticks)).distance_m
    fixed = conv.convert(_range(ticks), time_scale=1 / 1.005).distance_m
    assert naive == pytest.approx(1.005, rel=1e-4)
    assert fixed == pytest.approx(1.0, rel=1e-4)


def test_each_sensor_has_its_own_median_history() -> None:
    """Two sonars facing different things, interleaved: a shared window would mix them."""
    conv = SonarConverter(median_window=3, half_spacing_m=0.0)
    near, far = 5831, 23324  # about 0.5 m and 2.0 m
    out: dict[int, list[float]] = {0: [], 1: []}
    for k in range(4):
        for sid, ticks in ((0, near), (1, far)):
            msg = Range(
                measurement=2 * k + sid, sensor_id=sid, trigger_us=0, echo_ticks=ticks, status=0
            )
            r = conv.convert(msg, t_trigger_host=0.03 * (2 * k + sid))
            assert r.distance_m is not None and r.sensor_id == sid
            out[sid].append(r.distance_m)
    assert out[0] == pytest.approx([out[0][0]] * 4)
    assert out[1] == pytest.approx([out[1][0]] * 4)
    assert out[0][0] == pytest.approx(0.5, rel=1e-2) and out[1][0] == pytest.approx(2.0, rel=1e-2)
    conv.reset()
    again = conv.convert(_range(far), t_trigger_host=1.0)
    assert again.distance_m == pytest.approx(again.raw_distance_m)  # reset forgets all


def test_the_median_of_an_even_window_is_the_mean_of_the_middle_two() -> None:
    conv = SonarConverter(median_window=4, half_spacing_m=0.0)
    vals = [conv.convert(_range(t), t_trigger_host=0.01 * i) for i, t in enumerate([10000, 12000])]
    assert vals[1].distance_m == pytest.approx(
        (vals[0].raw_distance_m + vals[1].raw_distance_m) / 2  # type: ignore[operator]
    )


def test_absolute_zero_and_below_are_refused_by_name() -> None:
    for t in (-273.15, -300.0):
        with pytest.raises(ValueError, match="absolute zero"):
            speed_of_sound(t)
    assert speed_of_sound(-273.0) > 0


def test_the_defaults_are_the_uno_timer_and_the_hc_sr04_geometry() -> None:
    conv = SonarConverter()
    ticks = 291  # 145.5 us: a slant of about 2.5 cm
    slant = speed_of_sound(20.0) * (ticks / 2e6) / 2
    r = conv.convert(_range(ticks))
    assert r.slant_m == pytest.approx(slant, rel=1e-12)
    assert r.distance_m == pytest.approx(math.sqrt(slant**2 - 0.013**2), rel=1e-12)
    assert r.time_scale == 1.0


def test_the_timer_rate_may_be_anything_positive() -> None:
    assert SonarConverter(timer_hz=1).timer_hz == 1


def test_the_too_close_boundary_and_formula_7_at_zero() -> None:
    conv = SonarConverter(half_spacing_m=0.013)
    conv.speed_mps = 2.0  # slant = echo_s exactly
    assert conv.distance(0.013) == (None, 0.013)  # the slant is the half-spacing: too close
    assert conv.distance(0.014)[0] == pytest.approx(math.sqrt(0.014**2 - 0.013**2))
    flat = SonarConverter(half_spacing_m=0.0)
    assert flat.distance(0.0) == (0.0, 0.0)


def test_the_default_median_window_forgets_after_half_a_second() -> None:
    conv = SonarConverter(median_window=3, half_spacing_m=0.0)
    conv.convert(_range(2000), t_trigger_host=0.0)
    conv.convert(_range(2000), t_trigger_host=0.25)
    late = conv.convert(_range(11662), t_trigger_host=0.625)  # the first is 0.63 s old
    assert late.distance_m == pytest.approx(
        (late.raw_distance_m + conv.distance(2000 / 2e6)[0]) / 2  # type: ignore[operator]
    )


def test_a_reading_is_ok_only_with_status_ok_and_a_distance() -> None:
    from obstacle_fusion.sonar import SonarReading

    base = dict(
        t_host=1.0,
        t_trigger_host=1.0,
        trigger_us=0,
        measurement=0,
        sensor_id=0,
        echo_ticks=0,
        echo_s=0.0,
        raw_distance_m=1.0,
        slant_m=1.0,
    )
    good = SonarReading(status=SonarStatus.OK, distance_m=1.0, **base)  # type: ignore[arg-type]
    assert good.ok and good.time_scale == 1.0  # made without a scale: no correction
    assert not SonarReading(status=SonarStatus.TIMEOUT, distance_m=1.0, **base).ok  # type: ignore[arg-type]
    assert not SonarReading(status=SonarStatus.OK, distance_m=None, **base).ok  # type: ignore[arg-type]


def test_the_median_window_is_the_middle_value_and_ages_at_its_limit() -> None:
    conv = SonarConverter(median_window=5, half_spacing_m=0.0)
    raws = []
    for i, ticks in enumerate([10000, 14000, 11000, 13000, 12000]):
        r = conv.convert(_range(ticks), t_trigger_host=0.01 * i)
        raws.append(r.raw_distance_m)
    assert r.distance_m == pytest.approx(sorted(raws)[2])  # the third of five
    # Binary-exact times (a 2^20 Hz timer): the first reading's reflection is exactly the
    # age limit older than the second's and stays in the window; a little more and it leaves.
    for t2, kept in ((0.5, True), (0.5 + 2.0**-20, False)):
        c = SonarConverter(timer_hz=1 << 20, median_window=3, half_spacing_m=0.0)
        first = c.convert(_range(1024), t_trigger_host=2.0**-11)  # reflection at 2^-10 s
        second = c.convert(_range(2048), t_trigger_host=t2)
        both = (first.raw_distance_m + second.raw_distance_m) / 2  # type: ignore[operator]
        assert second.distance_m == pytest.approx(both if kept else second.raw_distance_m)


def test_an_undated_reading_leaves_the_window_at_the_next_dated_one() -> None:
    conv = SonarConverter(median_window=3, half_spacing_m=0.0)
    conv.convert(_range(2000))  # no host time (the clock model was not ready)
    dated = conv.convert(_range(11662), t_trigger_host=0.75)
    assert dated.distance_m == pytest.approx(dated.raw_distance_m)
