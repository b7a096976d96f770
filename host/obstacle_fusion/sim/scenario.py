"""The demo world: which obstacle stands how far in front of the robot, over time.

One description feeds both halves of an emulated run: it is written out as the emulator's
keyframe file (so the virtual HC-SR04 echoes these distances) and read by the synthetic
camera (so the frames show the same obstacle at the same distance). Scenario time 0 is the
emulator's simulated time 0 (the firmware's power-up).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from obstacle_fusion.errors import UserError

STEP_S = 0.001  # how long a keyframe step takes in the emulator's scene
TEMPERATURE_C = (-50.0, 80.0)  # the span `run --temperature` accepts too


@dataclass(frozen=True, slots=True)
class Obstacle:
    """A box-like obstacle: the face toward the robot is width x height."""

    name: str
    height_m: float
    width_m: float
    depth_m: float = 0.3
    color_bgr: tuple[int, int, int] = (60, 90, 170)


@dataclass(frozen=True, slots=True)
class Segment:
    """From t0 to t1 the obstacle moves linearly from d0 to d1 (None: nothing in front)."""

    t0: float
    t1: float
    obstacle: Obstacle | None
    d0: float
    d1: float

    def distance(self, t: float) -> float:
        if self.t1 <= self.t0:
            return self.d1
        f = min(max((t - self.t0) / (self.t1 - self.t0), 0.0), 1.0)
        return self.d0 + f * (self.d1 - self.d0)


Keyframes = tuple[tuple[float, float | None], ...]  # (time s, distance m or None), linear


@dataclass(frozen=True)
class Scenario:
    """``segments`` are what sensor 0 and the camera face; ``sonar_keyframes`` give other
    sonars their own distances over time (a sonar without its own plays sensor 0's)."""

    segments: tuple[Segment, ...]
    temperature_c: float = 20.0
    name: str = "scenario"
    sonar_keyframes: tuple[tuple[int, Keyframes], ...] = ()

    def __post_init__(self) -> None:
        if not self.segments:
            raise ValueError("a scenario needs at least one segment")
        for a, b in zip(self.segments, self.segments[1:], strict=False):
            if b.t0 < a.t1:
                raise ValueError(f"segments overlap at t={b.t0}")

    @property
    def duration_s(self) -> float:
        return self.segments[-1].t1

    @property
    def sensor_count(self) -> int:
        """1 + the highest sonar id that has its own distances (1 with none)."""
        return 1 + max((sid for sid, _ in self.sonar_keyframes), default=0)

    def sensor_distance_at(self, sensor_id: int, t: float) -> float | None:
        """What sonar ``sensor_id`` faces at scenario time t (None: nothing)."""
        for sid, frames in self.sonar_keyframes:
            if sid == sensor_id:
                return keyframe_distance(list(frames), t)
        return self.distance_at(t)

    def write_sensor_keyframes(self, folder: str | Path) -> tuple[tuple[int, Path], ...]:
        """One emulator keyframe file per sonar with its own distances: (id, path)."""
        out = []
        for sid, frames in self.sonar_keyframes:
            p = Path(folder) / f"sensor{sid}.txt"
            lines = [f"# obstacle-fusion scenario '{self.name}', sensor {sid}"]
            lines += [f"{t:.6f} {'none' if d is None else f'{d:.6f}'}" for t, d in frames]
            p.write_text("\n".join(lines) + "\n", encoding="ascii")
            out.append((sid, p))
        return tuple(out)

    def segment_at(self, t: float) -> Segment | None:
        """The segment covering t; before the first, the first; after the last, the last.
        In a gap between segments: None (nothing in front)."""
        if t < self.segments[0].t0:
            return self.segments[0]
        for seg in self.segments:
            if seg.t0 <= t < seg.t1:
                return seg
        last = self.segments[-1]
        if t >= last.t1:
            return last
        return None

    def obstacle_at(self, t: float) -> Obstacle | None:
        seg = self.segment_at(t)
        return None if seg is None else seg.obstacle

    def distance_at(self, t: float) -> float | None:
        seg = self.segment_at(t)
        if seg is None or seg.obstacle is None:
            return None
        return seg.distance(t)

    def keyframes(self) -> list[tuple[float, float | None]]:
        """The emulator's keyframes: linear within a segment, steps between segments.

        The format holds the earlier value until the next keyframe when either end of a
        pair is `none`, and interpolates between numbers, so a step from one obstacle to
        another (or to nothing) starts STEP_S after the old segment's last keyframe.
        """
        out: list[tuple[float, float | None]] = []

        def add(t: float, d: float | None) -> None:
            if out and t <= out[-1][0]:
                t = out[-1][0] + STEP_S
            out.append((t, d))

        prev_end: float | None = None
        for seg in self.segments:
            if prev_end is not None and seg.t0 > prev_end:
                add(prev_end, None)
            if seg.obstacle is None:
                add(seg.t0, None)
            else:
                add(seg.t0, seg.d0)
                if seg.t1 > out[-1][0]:
                    add(seg.t1, seg.d1)
            prev_end = seg.t1
        return out

    def keyframe_text(self) -> str:
        lines = [
            f"# obstacle-fusion scenario '{self.name}': <time_s> <distance_m>|none",
            f"temperature {self.temperature_c:g}",
        ]
        for t, d in self.keyframes():
            lines.append(f"{t:.6f} {'none' if d is None else f'{d:.6f}'}")
        return "\n".join(lines) + "\n"

    def write_keyframes(self, path: str | Path) -> Path:
        p = Path(path)
        p.write_text(self.keyframe_text(), encoding="ascii")
        return p


def parse_keyframes(text: str) -> tuple[list[tuple[float, float | None]], float | None]:
    """Read a keyframe file back (for checks and for replaying an emulator scene)."""
    frames: list[tuple[float, float | None]] = []
    temperature: float | None = None
    for n, raw in enumerate(text.splitlines(), 1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        parts = line.split()
        if parts[0] == "temperature" and len(parts) == 2:
            temperature = float(parts[1])
            continue
        if len(parts) != 2:
            raise ValueError(f"line {n}: expected '<time_s> <distance_m>|none', got {raw!r}")
        t = float(parts[0])
        d = None if parts[1] == "none" else float(parts[1])
        if d is not None and not (math.isfinite(d) and d >= 0):
            raise ValueError(f"line {n}: bad distance {parts[1]!r}")
        frames.append((t, d))
    return frames, temperature


def keyframe_distance(frames: list[tuple[float, float | None]], t: float) -> float | None:
    """The keyframe format's own rule: linear between numbers, steps at `none`."""
    if not frames:
        return None
    if t <= frames[0][0]:
        return frames[0][1]
    for (t0, d0), (t1, d1) in zip(frames, frames[1:], strict=False):
        if t0 <= t < t1:
            if d0 is None or d1 is None or t1 <= t0:
                return d0
            return d0 + (t - t0) / (t1 - t0) * (d1 - d0)
    return frames[-1][1]


def load_scenario(path: str | Path) -> Scenario:
    """A scenario from a TOML file, for runs on scenes other than the demo::

    name = "corridor"
    temperature_c = 22.0
    [[segment]]            # a 0.4 m x 0.5 m box approaching from 2 m to 1 m
    t0 = 0.0
    t1 = 8.0
    d0 = 2.0
    d1 = 1.0
    height_m = 0.4
    width_m = 0.5
    [[segment]]            # nothing in front (no height/width)
    t0 = 8.0
    t1 = 10.0
    """
    p = Path(path)
    try:
        data = tomllib.loads(p.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise UserError(f"scenario file {p} does not exist") from None
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise UserError(f"scenario file {p} is not readable TOML: {exc}") from None
    raw = data.get("segment")
    if not isinstance(raw, list) or not raw:
        raise UserError(f"scenario file {p} has no [[segment]] tables")
    segments = []
    for i, seg in enumerate(raw, 1):
        segments.append(_segment(seg, i, p))
    temperature = data.get("temperature_c", 20.0)
    lo, hi = TEMPERATURE_C
    if (
        isinstance(temperature, bool)
        or not isinstance(temperature, int | float)
        or not math.isfinite(temperature)
        or not lo <= temperature <= hi
    ):
        raise UserError(
            f"scenario file {p}: temperature_c must be a number of degrees celsius within "
            f"{lo:g}..{hi:g}, got {temperature!r}"
        )
    sonars = _sonar_keyframes(data.get("sonar", []), p)
    try:
        return Scenario(
            tuple(segments),
            temperature_c=float(temperature),
            name=str(data.get("name", p.stem)),
            sonar_keyframes=sonars,
        )
    except ValueError as exc:
        raise UserError(f"scenario file {p}: {exc}") from None


def _sonar_keyframes(raw: Any, p: Path) -> tuple[tuple[int, Keyframes], ...]:
    if not isinstance(raw, list):
        raise UserError(f"scenario file {p}: [[sonar]] must be a list of tables")
    out: dict[int, Keyframes] = {}

    def dist(value: Any, where: str) -> float | None:
        if value == "none":
            return None
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not math.isfinite(value)
            or not 0.02 <= value <= 4.0
        ):
            raise UserError(
                f'scenario file {p}, {where}: a distance is metres within 0.02..4 or "none", '
                f"got {value!r}"
            )
        return float(value)

    for i, entry in enumerate(raw, 1):
        if not isinstance(entry, dict):
            raise UserError(f"scenario file {p}: [[sonar]] {i} is not a table")
        sid = entry.get("id")
        if isinstance(sid, bool) or not isinstance(sid, int) or not 1 <= sid <= 3:
            raise UserError(
                f"scenario file {p}, [[sonar]] {i}: id must be 1..3 (sensor 0 plays the "
                f"segments), got {sid!r}"
            )
        if sid in out:
            raise UserError(f"scenario file {p}: sonar {sid} is listed twice")
        unknown = sorted(set(entry) - {"id", "keyframes", "distance"})
        if unknown or ("keyframes" in entry) == ("distance" in entry):
            raise UserError(
                f"scenario file {p}, sonar {sid}: give either keyframes = [[t, d], ...] or "
                f"distance = d" + (f" (unknown keys {unknown})" if unknown else "")
            )
        where = f"sonar {sid}"
        if "distance" in entry:
            out[sid] = ((0.0, dist(entry["distance"], where)),)
            continue
        frames = entry["keyframes"]
        if not isinstance(frames, list) or not frames:
            raise UserError(f"scenario file {p}, {where}: keyframes must be a non-empty list")
        kf: list[tuple[float, float | None]] = []
        for pair in frames:
            if not isinstance(pair, list) or len(pair) != 2:
                raise UserError(
                    f"scenario file {p}, {where}: each keyframe is [t, d], got {pair!r}"
                )
            t = pair[0]
            if isinstance(t, bool) or not isinstance(t, int | float) or not math.isfinite(t):
                raise UserError(f"scenario file {p}, {where}: time {t!r} is not a number")
            if kf and t <= kf[-1][0]:
                raise UserError(f"scenario file {p}, {where}: keyframe times must increase")
            kf.append((float(t), dist(pair[1], where)))
        out[sid] = tuple(kf)
    return tuple(sorted(out.items()))


def _segment(seg: Any, i: int, p: Path) -> Segment:
    def num(key: str, default: float | None = None) -> float:
        value = seg.get(key, default)
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not math.isfinite(value)
        ):
            raise UserError(
                f"scenario file {p}, segment {i}: {key} must be a number, got {value!r}"
            )
        return float(value)

    if not isinstance(seg, dict):
        raise UserError(f"scenario file {p}, segment {i} is not a table")
    t0, t1 = num("t0"), num("t1")
    if t1 < t0:
        raise UserError(f"scenario file {p}, segment {i}: t1 {t1} is before t0 {t0}")
    if "height_m" not in seg and "width_m" not in seg:
        return Segment(t0, t1, None, 0.0, 0.0)
    height, width = num("height_m"), num("width_m")
    d0 = num("d0")
    d1 = num("d1", d0)
    if min(height, width) <= 0 or not 0.02 <= min(d0, d1) <= max(d0, d1) <= 4.0:
        raise UserError(
            f"scenario file {p}, segment {i}: sizes must be positive and distances within "
            "0.02..4 m (the HC-SR04's range)"
        )
    color = seg.get("color_bgr", (60, 90, 170))
    obstacle = Obstacle(
        str(seg.get("name", f"obstacle-{i}")),
        height_m=height,
        width_m=width,
        depth_m=num("depth_m", 0.3),
        color_bgr=(int(color[0]), int(color[1]), int(color[2])),
    )
    return Segment(t0, t1, obstacle, d0, d1)


BOX_A = Obstacle("box-a", height_m=0.40, width_m=0.50, color_bgr=(50, 80, 160))
BOX_B = Obstacle("box-b", height_m=0.50, width_m=0.30, color_bgr=(140, 90, 40))


def demo_scenario() -> Scenario:
    """An obstacle approaching from 2.5 m to 0.8 m, a clear moment, then a taller,
    narrower one approaching from 3.0 m to 1.2 m (both stay wholly in view of a 20 cm high
    camera with the paper's field of view, at 4:3 and at 16:9)."""
    return Scenario(
        segments=(
            Segment(0.0, 12.0, BOX_A, 2.5, 0.8),
            Segment(12.0, 14.0, None, 0.0, 0.0),
            Segment(14.0, 28.0, BOX_B, 3.0, 1.2),
        ),
        temperature_c=20.0,
        name="demo",
    )
