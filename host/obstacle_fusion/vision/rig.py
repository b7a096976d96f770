"""Where the camera and the sonar sit on the robot, and what the sonar's range means to the image.

Axes (the *robot frame*): origin at the camera's optical centre, x to the right, y down,
z forward, level with the floor; the floor is the plane y = camera_height_m. The camera is
pitched down by ``camera_pitch_deg`` about x. The paper mounts both sensors on one vertical
axis (its Fig. 2), which is the default here: the sonar 5 cm below the lens, no pitch.

The sonar reports the forward distance from its transducers to the obstacle's face; the
measurement formulas need the depth of that face from the camera, which is the range plus
how far the sonar sits ahead of the lens (``face_depth``).

Several sonars: ``[[sonar]]`` tables list each one's id (the firmware's sensor id, 0..3), its
position (right_m, below_m, ahead_m), its direction (yaw_deg, positive to the right) and its
beam width. Without them the rig has one sonar, sensor 0, at the top-level sonar_* values
(the single-sonar files of before read unchanged). The vision measures with sensor 0's
mounting; the others tell the fusion whose beam covers the obstacle the image shows.
"""

from __future__ import annotations

import math
import os
import tomllib
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, fields
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from obstacle_fusion.errors import UserError

FloatArray = npt.NDArray[np.float64]

#: The ranges the measurement accepts (the HC-SR04's useful span, and the paper's 5 m).
MIN_RANGE_M = 0.02
MAX_RANGE_M = 5.0


class RigError(UserError):
    """A rig file or value that cannot describe a real mounting."""


@dataclass(frozen=True)
class SonarMount:
    """One sonar on the robot: where it sits relative to the lens and where it looks."""

    id: int = 0
    right_m: float = 0.0
    below_m: float = 0.05
    ahead_m: float = 0.0
    yaw_deg: float = 0.0  # direction of its axis, positive to the right
    beam_width_deg: float = 15.0

    def __post_init__(self) -> None:
        if isinstance(self.id, bool) or not isinstance(self.id, int) or not 0 <= self.id <= 3:
            raise RigError(f"sonar id must be an integer 0..3 (the sensor id), got {self.id!r}")
        for f in fields(self)[1:]:
            value = getattr(self, f.name)
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise RigError(f"sonar {self.id}: {f.name} must be a number, got {value!r}")
            if not math.isfinite(value):
                raise RigError(f"sonar {self.id}: {f.name} must be finite, got {value}")
            object.__setattr__(self, f.name, float(value))
        if max(abs(self.right_m), abs(self.below_m), abs(self.ahead_m)) > 1.0:
            raise RigError(f"sonar {self.id}: offsets above 1 m are not a robot rig (metres)")
        if not -180.0 <= self.yaw_deg <= 180.0:
            raise RigError(f"sonar {self.id}: yaw_deg must be in [-180, 180], got {self.yaw_deg}")
        if not 1.0 <= self.beam_width_deg <= 90.0:
            raise RigError(
                f"sonar {self.id}: beam_width_deg must be in [1, 90], got {self.beam_width_deg}"
            )

    def off_axis_rad(self, x_m: float, z_m: float) -> float:
        """Angle between this sonar's axis and the direction to robot-frame point (x, z)."""
        bearing = math.atan2(x_m - self.right_m, z_m - self.ahead_m)
        off = bearing - math.radians(self.yaw_deg)
        return abs(math.atan2(math.sin(off), math.cos(off)))

    def covers(self, x_m: float, z_m: float) -> bool:
        return self.off_axis_rad(x_m, z_m) <= math.radians(self.beam_width_deg) / 2.0


@dataclass(frozen=True)
class Rig:
    """The mounting: lens height and pitch, sonar position relative to the lens, beam width."""

    camera_height_m: float = 0.20
    camera_pitch_deg: float = 0.0  # positive: looking down
    sonar_right_m: float = 0.0
    sonar_below_m: float = 0.05
    sonar_ahead_m: float = 0.0
    beam_width_deg: float = 15.0  # full cone angle of the HC-SR04's useful beam
    sonars: tuple[SonarMount, ...] = ()  # several sonars; () = one, sensor 0, as above

    def __post_init__(self) -> None:
        self._check_sonars()
        for f in fields(self):
            if f.name == "sonars":
                continue
            value = getattr(self, f.name)
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise RigError(f"rig value {f.name} must be a number, got {value!r}")
            if not math.isfinite(value):
                raise RigError(f"rig value {f.name} must be finite, got {value}")
            object.__setattr__(self, f.name, float(value))
        if not 0.0 < self.camera_height_m < 5.0:
            raise RigError(
                f"camera_height_m must be in (0, 5) m above the floor, got {self.camera_height_m}"
            )
        if not -60.0 < self.camera_pitch_deg < 60.0:
            raise RigError(f"camera_pitch_deg must be in (-60, 60), got {self.camera_pitch_deg}")
        if not 1.0 <= self.beam_width_deg <= 90.0:
            raise RigError(f"beam_width_deg must be in [1, 90], got {self.beam_width_deg}")
        if abs(self.sonar_ahead_m) > 1.0 or abs(self.sonar_right_m) > 1.0:
            raise RigError("sonar offsets above 1 m are not a robot rig; check the units (metres)")

    def _check_sonars(self) -> None:
        raw = self.sonars
        if isinstance(raw, (str, bytes, dict)) or not isinstance(raw, (list, tuple)):
            raise RigError(f"sonars must be a list of [[sonar]] tables, got {raw!r}")
        mounts: list[SonarMount] = []
        for item in raw:
            if isinstance(item, SonarMount):
                mounts.append(item)
            elif isinstance(item, dict):
                known = {f.name for f in fields(SonarMount)}
                unknown = sorted(set(item) - known)
                if unknown:
                    raise RigError(
                        f"[[sonar]]: unknown keys {unknown}; known keys: {sorted(known)}"
                    )
                mounts.append(SonarMount(**item))
            else:
                raise RigError(f"a [[sonar]] entry must be a table, got {item!r}")
        ids = [m.id for m in mounts]
        if len(set(ids)) != len(ids):
            raise RigError(f"[[sonar]] ids must differ, got {ids}")
        if mounts and 0 not in ids:
            raise RigError("[[sonar]] tables must include sensor 0 (the one the vision uses)")
        object.__setattr__(self, "sonars", tuple(sorted(mounts, key=lambda m: m.id)))
        for m in mounts:
            if m.id == 0:  # the vision's sonar: the top-level values follow its table
                object.__setattr__(self, "sonar_right_m", m.right_m)
                object.__setattr__(self, "sonar_below_m", m.below_m)
                object.__setattr__(self, "sonar_ahead_m", m.ahead_m)
                object.__setattr__(self, "beam_width_deg", m.beam_width_deg)

    # ------------------------------------------------------------------ sonars
    def sonar_mounts(self) -> tuple[SonarMount, ...]:
        """Every sonar (one, sensor 0, unless the file lists several)."""
        if self.sonars:
            return self.sonars
        return (
            SonarMount(
                0,
                self.sonar_right_m,
                self.sonar_below_m,
                self.sonar_ahead_m,
                0.0,
                self.beam_width_deg,
            ),
        )

    def sensor_count_wanted(self) -> int | None:
        """How many sonars to range: 1 + the highest id listed, when it lists several."""
        if len(self.sonars) <= 1:
            return None
        return max(m.id for m in self.sonars) + 1

    def sonar_covering(self, x_m: float, z_m: float, sensors: Sequence[int]) -> int | None:
        """Of ``sensors``, the one whose beam covers robot-frame point (x, z), nearest its
        axis; None when none does."""
        best: tuple[float, int] | None = None
        for m in self.sonar_mounts():
            if m.id in sensors and m.covers(x_m, z_m):
                off = m.off_axis_rad(x_m, z_m)
                if best is None or off < best[0]:
                    best = (off, m.id)
        return None if best is None else best[1]

    # ------------------------------------------------------------------ geometry
    @property
    def pitch_rad(self) -> float:
        return math.radians(self.camera_pitch_deg)

    @property
    def beam_half_rad(self) -> float:
        return math.radians(self.beam_width_deg) / 2.0

    @cached_property
    def camera_to_robot(self) -> FloatArray:
        """Rotation whose columns are the camera's axes in the robot frame (p_r = R p_c)."""
        c, s = math.cos(self.pitch_rad), math.sin(self.pitch_rad)
        r = np.array([[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]])
        r.setflags(write=False)
        return r

    def face_depth(self, range_m: float) -> float:
        """Depth (robot z from the lens) of the face the sonar sees at ``range_m``."""
        return float(range_m) + self.sonar_ahead_m

    def range_from_depth(self, depth_m: float) -> float:
        return float(depth_m) - self.sonar_ahead_m

    def beam_x_bounds(self, range_m: float) -> tuple[float, float]:
        """Robot-frame x interval the beam covers at the face (the face must reach into it)."""
        half = float(range_m) * math.tan(self.beam_half_rad)
        return (self.sonar_right_m - half, self.sonar_right_m + half)

    # ------------------------------------------------------------------ files
    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> Rig:
        """Read a TOML rig file; keys are the field names, missing keys keep the defaults."""
        p = Path(path)
        if not p.is_file():
            raise RigError(f"rig file {p} does not exist (write one with Rig().save or by hand)")
        try:
            data = tomllib.loads(p.read_text(encoding="utf-8"))
        except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
            raise RigError(f"rig file {p} is not valid TOML: {exc}") from None
        table = dict(data.get("rig", data))  # accept a [rig] table or top-level keys
        if "rig" in data and "sonar" in data:
            table["sonar"] = data["sonar"]
        data = table
        if "sonar" in data:
            data["sonars"] = data.pop("sonar")
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(data) - known)
        if unknown:
            raise RigError(f"rig file {p}: unknown keys {unknown}; known keys: {sorted(known)}")
        try:
            return cls(**data)
        except RigError as exc:
            raise RigError(f"rig file {p}: {exc}") from None

    def save(self, path: str | os.PathLike[str]) -> None:
        lines = [
            "# obstacle-fusion rig: robot frame x right, y down, z forward, origin at the lens"
        ]
        values = asdict(self)
        sonars = values.pop("sonars")
        lines += [f"{k} = {v!r}" for k, v in values.items()]
        for m in sonars:
            lines += ["", "[[sonar]]"] + [f"{k} = {v!r}" for k, v in m.items()]
        Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")


class BeamSelector:
    """Which sonar's beam covers the obstacle an image box shows (the fusion's BeamChooser).

    The box's horizontal centre and the measured depth place the obstacle in the robot
    frame through the camera matrix (distortion ignored: a beam is 15 degrees wide); the
    sonar whose beam holds that point, nearest its axis, is chosen."""

    def __init__(self, rig: Rig, camera: Callable[[], Any]) -> None:
        self.rig = rig
        self.camera = camera  # () -> a CameraModel at the frames' size, or None

    def in_view(self, sensors: Sequence[int]) -> list[int]:
        """Those of ``sensors`` whose beam overlaps the camera's horizontal field of view
        (a sonar looking aside or behind measures what the image cannot show)."""
        cam = self.camera()
        if cam is None:
            return list(sensors)
        k = cam.camera_matrix
        fx, cx = float(k[0][0]), float(k[0][2])
        left = math.atan2(-cx - 0.5, fx)
        right = math.atan2(cam.width - 0.5 - cx, fx)
        mounts = {m.id: m for m in self.rig.sonar_mounts()}
        out = []
        for sid in sensors:
            m = mounts.get(sid)
            if m is None:
                continue
            half = math.radians(m.beam_width_deg) / 2.0
            yaw = math.radians(m.yaw_deg)
            if yaw + half >= left and yaw - half <= right:
                out.append(sid)
        return out

    def choose(
        self, box_px: tuple[float, float, float, float], depth_m: float, sensors: Sequence[int]
    ) -> int | None:
        cam = self.camera()
        if cam is None or not math.isfinite(depth_m) or depth_m <= 0.0:
            return None
        k = cam.camera_matrix
        u = (box_px[0] + box_px[2]) / 2.0
        x = depth_m * (u - float(k[0][2])) / float(k[0][0])
        return self.rig.sonar_covering(x, depth_m, sensors)


def check_range(range_m: float) -> float:
    """The sonar range as a float, or a UserError naming the accepted span."""
    try:
        value = float(range_m)
    except (TypeError, ValueError):
        raise UserError(f"range must be a number of metres, got {range_m!r}") from None
    if not math.isfinite(value) or not MIN_RANGE_M <= value <= MAX_RANGE_M:
        raise UserError(
            f"range {range_m} m is outside {MIN_RANGE_M}..{MAX_RANGE_M} m, the span the sonar "
            "and the measurement support; pass the sonar's range in metres"
        )
    return value
