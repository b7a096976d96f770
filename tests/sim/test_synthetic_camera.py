"""The synthetic camera films the scenario: the obstacle where the scenario puts it."""

from __future__ import annotations

from collections import deque
from collections.abc import Iterator

import numpy as np
import pytest
from obstacle_fusion.sim.scenario import demo_scenario
from obstacle_fusion.sim.scene import render_scene
from obstacle_fusion.sim.synthetic_camera import SyntheticCamera, synthetic_camera_model
from obstacle_fusion.vision.rig import Rig

pytestmark = pytest.mark.cpu_only


def test_frames_follow_the_scene_clock_and_show_the_scenarios_obstacle() -> None:
    scenario = demo_scenario()
    cam = synthetic_camera_model(500, 375)
    now = [100.0]
    src = SyntheticCamera(
        scenario,
        cam,
        Rig(),
        fps=10.0,
        scene_time=lambda t: t - 100.0,
        realtime=False,
        clock=lambda: now[0],
    )
    frames = [src.read() for _ in range(3)]
    assert [f.t_host for f in frames if f] == pytest.approx([100.0, 100.1, 100.2])
    assert src.scene_time_of(2) == pytest.approx(0.2)
    spec = src.spec_at(5.0)
    a = scenario.obstacle_at(5.0)
    assert a is not None and spec.obstacle
    assert (spec.height_m, spec.width_m) == (a.height_m, a.width_m)
    assert spec.distance_m == pytest.approx(scenario.distance_at(5.0))
    assert not src.spec_at(13.0).obstacle  # the clear moment
    assert not src.spec_at(None).obstacle  # before the emulator's time 0 is known


def test_the_box_is_where_the_renderer_says() -> None:
    cam = synthetic_camera_model(500, 375)
    src = SyntheticCamera(demo_scenario(), cam, Rig(), realtime=False, scene_time=lambda t: 6.0)
    frame = src.read()
    assert frame is not None and frame.image.shape == (375, 500, 3)
    spec = src.spec_at(6.0)
    truth = render_scene(spec, cam, Rig(), 0, supersample=2).truth
    x0, y0, x1, y1 = (int(v) for v in truth.box_px)
    box = frame.image[y0 + 3 : y1 - 3, x0 + 3 : x1 - 3].reshape(-1, 3).mean(axis=0)
    assert np.allclose(box, spec.box_color, atol=40)


def test_sixteen_by_nine_keeps_the_papers_focal_length_per_pixel() -> None:
    wide = synthetic_camera_model(1280, 720)
    four_three = synthetic_camera_model(1280, 960)
    assert wide.fx == pytest.approx(four_three.fx, rel=0.01)
    assert (wide.width, wide.height) == (1280, 720)


def test_a_lagging_camera_shows_the_scene_of_latency_earlier() -> None:
    now = [100.0]
    src = SyntheticCamera(
        demo_scenario(),
        synthetic_camera_model(500, 375),
        Rig(),
        fps=10.0,
        scene_time=lambda t: t - 100.0,
        realtime=False,
        latency_s=0.08,
        clock=lambda: now[0],
    )
    frames = [src.read() for _ in range(3)]
    assert [f.t_host for f in frames if f] == pytest.approx([100.0, 100.1, 100.2])
    assert src.scene_time_of(2) == pytest.approx(0.2 - 0.08)  # stamped 0.2, shows 0.12
    with pytest.raises(Exception, match="latency"):
        SyntheticCamera(demo_scenario(), synthetic_camera_model(), Rig(), latency_s=-0.1)


def test_the_renderers_cold_first_frame_is_rendered_before_the_clock_runs(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A live camera renders each frame a lead before its instant, the lead twice the
    slowest of the last 15 renders. The renderer's first frame builds its state and is
    several frames slow: rendered at construction, off the clock, it sets no lead (counted,
    it made the next 15 renders start at once, beside the host's work on the frame before:
    the run's first second of frames took twice as long)."""
    from obstacle_fusion.sim import synthetic_camera

    calls: list[int] = []
    real = synthetic_camera.renderer_for

    class Counting:
        def __init__(self, inner: object) -> None:
            self.inner = inner

        def render(self, *args: object) -> object:
            calls.append(1)
            return self.inner.render(*args)  # type: ignore[attr-defined]

    monkeypatch.setattr(synthetic_camera, "renderer_for", lambda *a: Counting(real(*a)))
    now = [100.0]
    live = SyntheticCamera(
        demo_scenario(),
        synthetic_camera_model(500, 375),
        Rig(),
        clock=lambda: now[0],
        sleep=lambda s: now.__setitem__(0, now[0] + s),
    )
    assert len(calls) == 1 and not live._render_s  # rendered, not counted in the lead
    assert live.read() is not None
    assert len(calls) == 2 and len(live._render_s) == 1
    SyntheticCamera(demo_scenario(), synthetic_camera_model(500, 375), Rig(), realtime=False)
    assert len(calls) == 2  # a camera that is not live keeps no lead: no extra render


class _AppendedWhileRead(deque[tuple[int, float | None]]):
    """A frame log the capture thread appends to between two steps of a reverse read."""

    def __reversed__(self) -> Iterator[tuple[int, float | None]]:
        for item in super().__reversed__():
            self.append((99, 9.9))
            yield item


def test_a_frames_scene_time_is_found_while_frames_are_still_coming() -> None:
    src = SyntheticCamera(demo_scenario(), synthetic_camera_model(500, 375), Rig(), realtime=False)
    src.recent = _AppendedWhileRead([(1, 0.1), (2, 0.2)], maxlen=256)
    assert src.scene_time_of(1) == pytest.approx(0.1)  # no "deque mutated" error
