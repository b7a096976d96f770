"""Raw echo ticks to metres, on the host, where the physics can be changed and replayed.

Speed of sound at the configured air temperature, v = 331.3 sqrt(1 + T/273.15) m/s. The
paper's formula (7), H = v t / 2, assumes the transmitter and receiver coincide; formula (6)
keeps their spacing: the sound travels S = v t / 2 to the obstacle and back along a slant, so
the perpendicular distance is H = sqrt(S^2 - L^2) with L the half-spacing of the two
transducers (about 13 mm on an HC-SR04). The difference is 0.1% at 30 cm and 2% at 7 cm,
which is why a setting of 0 (formula 7) is offered but not the default.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field
from enum import StrEnum

from obstacle_fusion.protocol.generated import Range, RangeStatus

HC_SR04_HALF_SPACING_M = 0.013
DEFAULT_TEMPERATURE_C = 20.0


def speed_of_sound(temperature_c: float) -> float:
    """Metres per second in dry air (the linearised ideal-gas law around 0 degC)."""
    if temperature_c <= -273.15:
        raise ValueError(f"temperature {temperature_c} degC is below absolute zero")
    return 331.3 * math.sqrt(1.0 + temperature_c / 273.15)


class SonarStatus(StrEnum):
    """Every reading says what it is; a missing distance is never a zero."""

    OK = "ok"
    NO_ECHO = "no_echo"
    TIMEOUT = "timeout"
    OUT_OF_RANGE = "out_of_range"
    TOO_CLOSE = "too_close"  # the slant path is shorter than the transducers' half-spacing
    UNKNOWN = "unknown"  # a status code this host does not know

    @classmethod
    def from_wire(cls, code: int) -> SonarStatus:
        try:
            return cls(RangeStatus(code).name.lower())
        except ValueError:
            return cls.UNKNOWN


@dataclass(frozen=True, slots=True)
class SonarReading:
    """One measurement: raw values kept next to the converted ones and their host time."""

    t_host: float | None  # host monotonic s of the reflection (trigger + half the flight)
    t_trigger_host: float | None  # host monotonic s of the TRIG edge
    trigger_us: int  # raw MCU microseconds (wraps at 2^32)
    measurement: int
    sensor_id: int
    echo_ticks: int
    echo_s: float
    status: SonarStatus
    distance_m: float | None  # perpendicular distance (filtered if a median filter is set)
    raw_distance_m: float | None  # before the median filter
    slant_m: float | None  # formula (7): v t / 2
    t_receipt: float | None = None  # host monotonic s when the frame was read
    time_scale: float = 1.0  # true seconds per MCU second used (the crystal's error removed)

    @property
    def ok(self) -> bool:
        return self.status is SonarStatus.OK and self.distance_m is not None


@dataclass
class SonarConverter:
    """Ticks to metres for one board; timer_hz comes from its HELLO."""

    timer_hz: int = 2_000_000
    temperature_c: float = DEFAULT_TEMPERATURE_C
    half_spacing_m: float = HC_SR04_HALF_SPACING_M
    median_window: int = 1  # 1 = no filter; 3 or 5 reject single spikes
    median_max_age_s: float = 0.5  # older readings leave the filter window
    _history: dict[int, deque[tuple[float, float]]] = field(default_factory=dict, repr=False)

    def __post_init__(self) -> None:
        if self.timer_hz <= 0:
            raise ValueError(f"timer_hz must be positive, got {self.timer_hz}")
        if self.median_window < 1:
            raise ValueError(f"median window must be at least 1, got {self.median_window}")
        self.speed_mps = speed_of_sound(self.temperature_c)

    def set_temperature(self, temperature_c: float) -> None:
        self.temperature_c = temperature_c
        self.speed_mps = speed_of_sound(temperature_c)

    def distance(self, echo_s: float) -> tuple[float | None, float]:
        """(perpendicular distance or None if too close, slant distance) for an echo width."""
        slant = self.speed_mps * echo_s / 2.0
        half = self.half_spacing_m
        if half <= 0.0:
            return slant, slant
        if slant <= half:
            return None, slant
        return math.sqrt(slant * slant - half * half), slant

    def convert(
        self,
        msg: Range,
        t_trigger_host: float | None = None,
        t_receipt: float | None = None,
        time_scale: float = 1.0,
    ) -> SonarReading:
        """``time_scale`` is the clock model's host seconds per MCU second: a crystal 0.5%
        fast counts 0.5% too many ticks, and the distance would be 0.5% long without it."""
        echo_s = msg.echo_ticks / self.timer_hz * time_scale
        status = SonarStatus.from_wire(msg.status)
        distance: float | None = None
        raw: float | None = None
        slant: float | None = None
        if status is SonarStatus.OK:
            raw, slant = self.distance(echo_s)
            if raw is None:
                status = SonarStatus.TOO_CLOSE
        t_host = None if t_trigger_host is None else t_trigger_host + echo_s / 2.0
        if raw is not None:
            distance = self._filter(msg.sensor_id, t_host, raw)
        return SonarReading(
            t_host=t_host,
            t_trigger_host=t_trigger_host,
            trigger_us=msg.trigger_us,
            measurement=msg.measurement,
            sensor_id=msg.sensor_id,
            echo_ticks=msg.echo_ticks,
            echo_s=echo_s,
            status=status,
            distance_m=distance,
            raw_distance_m=raw,
            slant_m=slant,
            t_receipt=t_receipt,
            time_scale=time_scale,
        )

    def reset(self) -> None:
        self._history.clear()

    def _filter(self, sensor_id: int, t: float | None, value: float) -> float:
        if self.median_window == 1:
            return value
        hist = self._history.setdefault(sensor_id, deque(maxlen=self.median_window))
        # A reading without a host time is the oldest there is: the next dated one ages it out.
        hist.append((t if t is not None else -math.inf, value))
        if t is not None:
            while hist and hist[0][0] < t - self.median_max_age_s:
                hist.popleft()
        values = sorted(v for _, v in hist)
        n = len(values)
        mid = n // 2
        return values[mid] if n % 2 else (values[mid - 1] + values[mid]) / 2.0
