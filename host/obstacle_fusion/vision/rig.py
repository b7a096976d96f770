"""Where the camera and the sonar sit on the robot, and what the sonar's range means to the image.

Axes (the *robot frame*): origin at the camera's optical centre, x to the right, y down,
z forward, level with the floor; the floor is the plane y = camera_height_m. The camera is
pitched down by ``camera_pitch_deg`` about x. The paper mounts both sensors on one vertical
axis (its Fig. 2), which is the default here: the sonar 5 cm below the lens, no pitch.

The sonar reports the forward distance from its transducers to the obstacle's face; the
measurement formulas need the depth of that face from the camera, which is the range plus
how far the sonar sits ahead of the lens (``face_depth``).
"""

from __future__ import annotations

import math
import os
import tomllib
from dataclasses import asdict, dataclass, fields
from functools import cached_property
from pathlib import Path

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
class Rig:
    """The mounting: lens height and pitch, sonar position relative to the lens, beam width."""

    camera_height_m: float = 0.20
    camera_pitch_deg: float = 0.0  # positive: looking down
    sonar_right_m: float = 0.0
    sonar_below_m: float = 0.05
    sonar_ahead_m: float = 0.0
    beam_width_deg: float = 15.0  # full cone angle of the HC-SR04's useful beam

    def __post_init__(self) -> None:
        for f in fields(self):
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
        data = data.get("rig", data)  # accept a [rig] table or top-level keys
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
        lines += [f"{k} = {v!r}" for k, v in asdict(self).items()]
        Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")


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
