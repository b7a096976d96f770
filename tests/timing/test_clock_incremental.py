"""The clock model's incremental hull gives the estimates the sort-and-rebuild one gave."""

from __future__ import annotations

import random

import pytest
from obstacle_fusion.timing.clock import ClockEstimate, ClockModel, WindowHull, _lower_hull

from tests.clock_fixtures import LinkSim

pytestmark = pytest.mark.cpu_only


class ReferenceModel(ClockModel):
    """The model as it was: the window sorted and its hull rebuilt at every solve."""

    def _hull_line(self) -> tuple[float, float] | None:
        return self._hull_line_sorted()

    def _best_syncs(self):  # type: ignore[no-untyped-def]
        return self._select_syncs()


def _feed_both(sim: LinkSim, use_sync: bool = True, every: int = 1) -> tuple[int, int, float]:
    """Feed both models; compare at every `every`-th RANGE (the reference is slow)."""
    new, ref = ClockModel(), ReferenceModel()
    compared = differ = 0
    worst = 0.0
    k = 0
    for arrival, kind, data in sim.events:
        if kind == "sync":
            if use_sync:
                t1, rx, tx = data
                new.add_sync(t1, arrival, rx, tx)
                ref.add_sync(t1, arrival, rx, tx)
            continue
        raw_trig, raw_end = data
        new.add_oneway(arrival, raw_end)
        ref.add_oneway(arrival, raw_end)
        k += 1
        if k % every:
            continue
        a, b = new.to_host(raw_trig), ref.to_host(raw_trig)
        ea, eb = new.estimate(), ref.estimate()
        assert (a is None) == (b is None)
        if a is None or b is None:
            continue
        assert isinstance(ea, ClockEstimate) and isinstance(eb, ClockEstimate)
        assert (ea.source, ea.n_sync, ea.n_oneway) == (eb.source, eb.n_sync, eb.n_oneway)
        compared += 1
        if (ea.slope, ea.offset_s, ea.uncertainty_s) != (eb.slope, eb.offset_s, eb.uncertainty_s):
            differ += 1
            worst = max(worst, abs(a - b))
    return compared, differ, worst


@pytest.mark.parametrize(
    "sim",
    [
        LinkSim(ppm=5000.0, seed=1),
        LinkSim(ppm=-5000.0, seed=2),
        LinkSim(ppm=0.0, seed=3, cycle_s=0.015),
        LinkSim(ppm=5000.0, seed=9, jitter_mean_s=0.004, spike_prob=0.2),
    ],
    ids=["+5000ppm", "-5000ppm", "67Hz", "heavy-jitter"],
)
def test_same_estimates_as_sorting_the_window_at_every_range(sim: LinkSim) -> None:
    """70 s (the 30 s window slides for 40 s, the hull's stacks turn over), every RANGE:
    the same slope, offset and uncertainty, bit for bit."""
    dense = sim.cycle_s < 0.02
    sim.generate(duration_s=45.0 if dense else 70.0)
    compared, differ, worst = _feed_both(sim, every=7 if dense else 1)
    assert compared > 400
    assert differ == 0, (differ, worst)


def test_same_estimates_without_time_sync() -> None:
    sim = LinkSim(ppm=5000.0, seed=4)
    sim.generate(duration_s=70.0)
    compared, differ, worst = _feed_both(sim, use_sync=False)
    assert compared > 1000 and differ == 0, worst


def test_out_of_order_stamps_fall_back_and_recover() -> None:
    """A stamp older than the newest one (out of order) uses the sorting path until it has
    left the window; the estimates stay those of the reference throughout."""
    sim = LinkSim(ppm=3000.0, seed=6)
    sim.generate(duration_s=50.0)
    ranges = [i for i, e in enumerate(sim.events) if e[1] == "range"]
    a, b = ranges[100], ranges[101]
    sim.events[a], sim.events[b] = sim.events[b], sim.events[a]  # two frames swapped
    compared, differ, worst = _feed_both(sim)
    assert compared > 500 and differ == 0, worst


def test_window_hull_matches_the_rebuilt_hull_as_points_come_and_go() -> None:
    rng = random.Random(7)
    for trial in range(40):
        hull = WindowHull()
        window: list[tuple[float, float]] = []
        x = 0.0
        for step in range(400):
            x += rng.choice([0.001, 0.01, 0.1, 1.0])
            y = 0.5 * x + (rng.expovariate(100.0) if trial % 2 else rng.uniform(-1, 1))
            hull.append((x, y))
            window.append((x, y))
            while len(window) > 3 and rng.random() < (0.6 if trial % 3 else 0.45):
                window.pop(0)
                hull.popleft()
            assert len(hull) == len(window)
            if len(window) >= 2:
                ref = _lower_hull(window)
                # Anywhere, and exactly on each vertex (the edge on its left is the one).
                for m in [rng.uniform(window[0][0], window[-1][0]), *(p[0] for p in ref)]:
                    want = next(
                        ((p, q) for p, q in zip(ref, ref[1:], strict=False) if p[0] <= m <= q[0]),
                        None,
                    )
                    assert hull.segment_at(m) == want, (trial, step, m)
