"""A camera that films the emulator's world: the scenario rendered at each frame's instant.

The emulator plays the scenario's distances to the firmware on its simulated clock; this
source renders the same obstacle at the same distance for the host instant of each frame,
so a run with no hardware is consistent end to end and its answers can be checked against
the scenario. ``scene_time`` maps a host monotonic instant to scenario time (for the
emulator: host time minus the host instant of its simulated time 0).
"""

from __future__ import annotations

import logging
import math
import time
from collections import deque
from collections.abc import Callable
from dataclasses import replace

import numpy as np

from obstacle_fusion.sim.scenario import Scenario
from obstacle_fusion.sim.scene import SceneSpec, renderer_for
from obstacle_fusion.sources.frames import Clock, Frame, FrameSource, Sleep, SourceError
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.rig import Rig

log = logging.getLogger(__name__)

# The paper's camera: 2592x1944 with fx 2378, fy 2374 and its lens distortion.
_PAPER_FX_PER_WIDTH = 2378.0 / 2592.0
_PAPER_DIST = (-0.1356, 0.14432, -0.001021, 0.006401)


def synthetic_camera_model(width: int = 500, height: int = 375) -> CameraModel:
    """The paper's lens at any resolution: its 4:3 calibration scaled, or, for another
    aspect ratio, the same focal length per pixel of width with the centre in the middle
    (a sensor crop, as webcams do for 16:9)."""
    if width * 3 == height * 4:
        return CameraModel.paper(width, height)
    f = _PAPER_FX_PER_WIDTH * width
    k = np.array([[f, 0.0, (width - 1) / 2.0], [0.0, f, (height - 1) / 2.0], [0.0, 0.0, 1.0]])
    return CameraModel(k, np.array(_PAPER_DIST), width, height)


class SyntheticCamera(FrameSource):
    """Frames at ``fps`` on the host clock, each the scenario's scene at that instant
    (``latency_s`` earlier: a camera that lags, for the latency estimate to find)."""

    def __init__(
        self,
        scenario: Scenario,
        camera: CameraModel,
        rig: Rig,
        *,
        fps: float = 15.0,
        scene_time: Callable[[float], float | None] | None = None,
        base_spec: SceneSpec | None = None,
        seed: int = 0,
        realtime: bool = True,
        max_frames: int | None = None,
        supersample: int = 2,
        latency_s: float = 0.0,
        clock: Clock = time.monotonic,
        sleep: Sleep = time.sleep,
    ) -> None:
        super().__init__(f"synthetic:{scenario.name}", clock=clock)
        if not (math.isfinite(fps) and fps > 0):
            raise SourceError(f"frame rate must be positive, got {fps}")
        self.scenario = scenario
        self.camera = camera
        self.rig = rig
        self.fps = float(fps)
        self.realtime = realtime
        if not (math.isfinite(latency_s) and 0.0 <= latency_s <= 2.0):
            raise SourceError(f"camera latency must be within 0..2 s, got {latency_s}")
        #: as a USB camera: the frame stamped t shows the scene at t - latency_s
        self.latency_s = float(latency_s)
        self.max_frames = max_frames
        self.sleep = sleep
        start = clock()
        self.scene_time: Callable[[float], float | None] = scene_time or (lambda t: t - start)
        self.base_spec = base_spec or SceneSpec(noise_sigma=1.5, blur_sigma=0.5)
        self._renderer = renderer_for(camera, rig, supersample)
        self._rng = np.random.default_rng(seed)
        self._next = start
        self._k = 0
        self.recent: deque[tuple[int, float | None]] = deque(maxlen=256)  # (index, scene time)
        self._render_s: deque[float] = deque(maxlen=15)  # recent render durations
        if realtime:
            # the renderer's first frame builds its per-scene state and costs several
            # frames' time: rendered here, off the clock, it would otherwise set the lead
            # (twice the slowest recent render) for the next 15 frames, whose renders then
            # start at once and run beside the host's work on the frame before
            self._renderer.render(self.spec_at(self.scene_time(start)), np.random.default_rng(seed))

    @property
    def nominal_fps(self) -> float:
        return self.fps

    @property
    def frame_size(self) -> tuple[int, int]:
        """(width, height) of every frame, known before the first."""
        return self.camera.width, self.camera.height

    def spec_at(self, scene_t: float | None) -> SceneSpec:
        """What the camera sees at scenario time ``scene_t`` (None: before the world exists)."""
        obstacle = self.scenario.obstacle_at(scene_t) if scene_t is not None else None
        distance = self.scenario.distance_at(scene_t) if scene_t is not None else None
        if obstacle is None or distance is None:
            return replace(self.base_spec, obstacle=False, distance_m=2.0)
        return replace(
            self.base_spec,
            obstacle=True,
            width_m=obstacle.width_m,
            height_m=obstacle.height_m,
            length_m=obstacle.depth_m,
            box_color=tuple(float(c) for c in obstacle.color_bgr),  # type: ignore[arg-type]
            distance_m=distance,
        )

    def scene_time_of(self, index: int) -> float | None:
        # a snapshot (one C-level copy): the capture thread appends while the publisher
        # looks a frame up, and a deque iterated across an append raises
        for i, t in reversed(tuple(self.recent)):
            if i == index:
                return t
        return None

    def _capture(self) -> Frame | None:
        if self.max_frames is not None and self._k >= self.max_frames:
            self.end_reason = f"{self.max_frames} frames rendered"
            return None
        now = self.clock()
        if self.realtime and now - self._next > 1.0 / self.fps:
            self._next = now  # fell behind (a slow render): skip, don't burst
        t = self._next
        self._next += 1.0 / self.fps
        # The world is known ahead, so the frame of instant t is rendered before t and
        # handed over at t: like a camera whose exposure ends as the frame is delivered, the
        # host sees it at its capture instant (rendering is this simulator's cost, not the
        # host's latency). The render starts a margin before t (twice the slowest recent
        # render), not right after the previous frame, so it does not compete with the
        # host's work on that frame.
        if self.realtime:
            lead = 2.0 * max(self._render_s, default=0.02) + 0.005
            now = self.clock()
            if t - lead > now:
                self.sleep(t - lead - now)
        scene_t = self.scene_time(t - self.latency_s)  # a late camera shows an older scene
        r0 = time.perf_counter()
        rendered = self._renderer.render(self.spec_at(scene_t), self._rng)
        self._render_s.append(time.perf_counter() - r0)
        if self.realtime:
            now = self.clock()
            if t > now:
                self.sleep(t - now)
        index = self._k
        self._k += 1
        self.recent.append((index, scene_t))
        return self._frame(rendered.image, t, index)
