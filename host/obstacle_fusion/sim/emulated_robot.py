"""The robot with no hardware: the emulator playing a scenario, kept alive, and the mapping
from host time to scenario time that the synthetic camera needs to film the same world.

The emulator's simulated clock is locked to wall-clock time, and the scenario's time 0 is its
power-up, so scenario time = host time - (host instant of simulated time 0). That instant is
measured through the control channel (host time around a `time` query, minus the answer)
and refreshed every few seconds. If the emulator process dies it is started again (a board
reset, as far as the host can tell); the link reconnects to the new pty on its own.
"""

from __future__ import annotations

import logging
import statistics
import tempfile
import time
from collections import deque
from dataclasses import dataclass, field
from pathlib import Path

from obstacle_fusion.sim.emulator import Emulator, EmulatorConfig, EmulatorError
from obstacle_fusion.sim.scenario import Scenario

log = logging.getLogger(__name__)


@dataclass
class EmulatedRobot:
    scenario: Scenario
    clock_ppm: float = 0.0
    sensors: int = 1  # virtual HC-SR04s (at least the scenario's sonars)
    restart: bool = True
    workdir: Path | None = None
    extra: dict[str, object] = field(default_factory=dict)  # more EmulatorConfig fields
    emulator: Emulator | None = None
    generation: int = 0
    restarts: int = 0
    events: list[str] = field(default_factory=list)
    _t0_samples: deque[float] = field(default_factory=lambda: deque(maxlen=7))
    _t0: float | None = None
    _next_t0_probe: float = 0.0

    def start(self) -> EmulatedRobot:
        if self.workdir is None:
            self.workdir = Path(tempfile.mkdtemp(prefix="ofrun-"))
        scene = self.scenario.write_keyframes(self.workdir / "scene.txt")
        config = EmulatorConfig(
            scene=scene,
            sensors=max(self.sensors, self.scenario.sensor_count),
            sensor_scenes=self.scenario.write_sensor_keyframes(self.workdir),
            temperature_c=self.scenario.temperature_c,
            clock_ppm=self.clock_ppm,
            wait_client=True,
            **self.extra,  # type: ignore[arg-type]
        )
        self.emulator = Emulator(config=config).start()
        self.generation += 1
        self._t0 = None
        self._t0_samples.clear()
        self._next_t0_probe = 0.0
        return self

    @property
    def pid(self) -> int | None:
        return self.emulator.pid if self.emulator else None

    def port(self) -> str | None:
        """The current pty (the link's port provider), None while there is no emulator."""
        emu = self.emulator
        if emu is None or not emu.running():
            return None
        return emu.pty_path

    def check(self) -> str | None:
        """Restart a dead emulator; return what happened (for the log and the recording)."""
        emu = self.emulator
        if emu is None or emu.running():
            return None
        code = emu.returncode()
        why = f"the emulator (pid {emu.pid}) stopped unexpectedly (exit status {code})"
        emu.cleanup()
        self.emulator = None
        self._t0 = None
        if not self.restart:
            raise EmulatorError(why)
        self.restarts += 1
        self.start()
        event = f"{why}; restarted it as pid {self.pid} on {self.port()}"
        self.events.append(event)
        log.warning(event)
        return event

    def probe_t0(self, now: float | None = None, force: bool = False) -> float | None:
        """Refresh the host instant of simulated time 0 (call once the pty is open)."""
        now = time.monotonic() if now is None else now
        emu = self.emulator
        if emu is None or not emu.running() or (now < self._next_t0_probe and not force):
            return self._t0
        self._next_t0_probe = now + 2.0
        try:
            t_a = time.monotonic()
            sim = emu.control.sim_time()
            t_b = time.monotonic()
        except (EmulatorError, OSError) as exc:
            log.debug("sim time query failed: %s", exc)
            return self._t0
        if sim <= 0.0 or t_b - t_a > 0.05:
            return self._t0  # not running yet (held until the port opens) or a slow answer
        # `time` answers in MCU seconds (cycles / nominal clock); the scene runs on true
        # time, which a crystal N ppm fast makes shorter.
        true_s = sim / (1.0 + self.clock_ppm * 1e-6)
        self._t0_samples.append((t_a + t_b) / 2.0 - true_s)
        self._t0 = statistics.median(self._t0_samples)
        return self._t0

    def scene_time(self, t_host: float) -> float | None:
        """Scenario time at a host instant, None while the emulator's time 0 is unknown."""
        return None if self._t0 is None else t_host - self._t0

    def stop(self) -> None:
        if self.emulator is not None:
            self.emulator.cleanup()
            self.emulator = None
