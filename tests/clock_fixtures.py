"""A simulated MCU and serial link with a drifting crystal and jittery delivery, for clock tests."""

from __future__ import annotations

import random
from dataclasses import dataclass, field

from obstacle_fusion.timing.clock import ClockModel


@dataclass
class LinkSim:
    ppm: float = 5000.0  # MCU crystal fast by this much
    seed: int = 1
    host0: float = 1000.0  # host monotonic time at the MCU counter's start value
    mcu0_us: int = (1 << 32) - 3_000_000  # wraps 3 s into the run
    cycle_s: float = 0.060
    sync_period_s: float = 0.2
    jitter_mean_s: float = 0.001
    spike_prob: float = 0.05
    spike_max_s: float = 0.020
    burst_s: float = 0.00045
    wire_byte_s: float = 10 / 115200
    events: list[tuple[float, str, tuple]] = field(default_factory=list)  # type: ignore[type-arg]
    truth: list[tuple[int, float]] = field(default_factory=list)  # (trigger_us raw, host time)

    def mcu_us(self, host: float) -> int:
        return int(round(self.mcu0_us + (host - self.host0) * (1 + self.ppm * 1e-6) * 1e6))

    def host_of_mcu(self, us: float) -> float:
        return self.host0 + (us - self.mcu0_us) / ((1 + self.ppm * 1e-6) * 1e6)

    def jitter(self, rng: random.Random) -> float:
        j = 0.0002 + rng.expovariate(1 / self.jitter_mean_s)
        if rng.random() < self.spike_prob:
            j += rng.uniform(0, self.spike_max_s)
        return j

    def generate(self, duration_s: float) -> None:
        rng = random.Random(self.seed)
        # RANGE frames, cycle on the MCU clock.
        k = 0
        while True:
            trig_us = self.mcu0_us + k * self.cycle_s * 1e6 * 1.0 + 1234
            host_trig = self.host_of_mcu(trig_us)
            if host_trig > self.host0 + duration_s:
                break
            width_us = 2 * rng.uniform(0.2, 3.0) / 343.0 * 1e6
            end_us = trig_us + self.burst_s * 1e6 + width_us
            send_host = self.host_of_mcu(end_us + 80)
            arrival = send_host + 20 * self.wire_byte_s + self.jitter(rng)
            raw_trig = int(trig_us) & 0xFFFFFFFF
            raw_end = int(end_us) & 0xFFFFFFFF
            self.events.append((arrival, "range", (raw_trig, raw_end)))
            self.truth.append((raw_trig, host_trig))
            k += 1
        # TIME_SYNC round trips.
        t = self.host0 + 0.01
        while t < self.host0 + duration_s:
            t1 = t
            arrive_mcu = t1 + 10 * self.wire_byte_s + self.jitter(rng) * 0.5
            rx_us = self.mcu_us(arrive_mcu)
            tx_us = rx_us + rng.randint(40, 300)
            t4 = self.host_of_mcu(tx_us) + 18 * self.wire_byte_s + self.jitter(rng) * 0.5
            self.events.append((t4, "sync", (t1, rx_us & 0xFFFFFFFF, tx_us & 0xFFFFFFFF)))
            t += self.sync_period_s
        self.events.sort(key=lambda e: e[0])

    def run(self, model: ClockModel, use_sync: bool = True, after_s: float = 10.0) -> list[float]:
        """Feed the model in arrival order; return |mapped - true| trigger errors after after_s."""
        errors: list[float] = []
        truth = dict(self.truth)
        for arrival, kind, data in self.events:
            if kind == "sync":
                if use_sync:
                    t1, rx, tx = data
                    model.add_sync(t1, arrival, rx, tx)
                continue
            raw_trig, raw_end = data
            model.add_oneway(arrival, raw_end)
            mapped = model.to_host(raw_trig)
            if arrival - self.host0 >= after_s and mapped is not None:
                errors.append(abs(mapped - truth[raw_trig]))
        return errors


def percentile(values: list[float], q: float) -> float:
    s = sorted(values)
    return s[min(len(s) - 1, int(q * len(s)))]
