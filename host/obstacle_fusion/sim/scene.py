"""Synthetic scenes with a known answer: a box of known size at a known distance.

The tests, the benchmark and the host's live synthetic camera all draw from here, so the
renderer is built for speed: projected 3-D quads filled with OpenCV (no ray tracing),
supersampled for sub-pixel accurate edges, then pushed through the camera's real lens
distortion by one cached remap. World = the rig's robot frame (x right, y down, z forward,
origin at the lens, floor at y = camera height); see :mod:`obstacle_fusion.vision.rig`.

Fill rule: OpenCV fills every pixel whose centre lies within half a pixel of the polygon
(measured per scan line), so each polygon is shrunk by that half pixel before filling; a
supersampled edge then lands where the geometry says to within ~1/(2 S) pixel.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace
from functools import lru_cache
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.rig import Rig

FloatArray = npt.NDArray[np.float64]
Color = tuple[float, float, float]

_NEAR_Z = 0.02  # metres: polygons are clipped to z_cam >= this
_SHIFT = 4  # fractional bits for cv2.fillPoly

FLOOR_STYLES = ("tiles", "planks", "plain")
HARD_TRAITS = ("contrast", "lines", "busy", "low", "yaw", "far", "label", "rough")


# ---------------------------------------------------------------------- the scene description
@dataclass(frozen=True)
class SceneSpec:
    """What is in front of the robot. Lengths in metres, colours BGR 0..255."""

    width_m: float = 0.40
    height_m: float = 0.30
    length_m: float = 0.30  # the box's extent along z (its depth)
    distance_m: float = 1.0  # true sonar range to the front face (at the face centre)
    lateral_m: float = 0.0  # face centre x relative to the sonar axis
    yaw_deg: float = 0.0  # box turned about the vertical through the face centre
    obstacle: bool = True  # False: an empty room (for "no obstacle" checks)
    box_color: Color = (60.0, 90.0, 170.0)
    floor_style: str = "tiles"
    floor_color: Color = (150.0, 160.0, 165.0)
    seam_color: Color = (110.0, 115.0, 120.0)
    tile_m: float = 0.30
    wall_color: Color = (200.0, 205.0, 210.0)
    wall_gap_m: float = 1.2  # back wall distance behind the box's back face
    skirting_m: float = 0.08  # skirting-board height on the back wall; 0 = none
    skirting_color: Color = (90.0, 90.0, 95.0)
    shelves: int = 0  # horizontal shelf boards on the back wall, with books
    clutter: int = 0  # posters/frames on the back wall
    extra_boxes: int = 0  # other boxes farther back on the floor
    label: bool = False  # a contrasting horizontal stripe across the box's front face
    light_gain: float = 1.0
    light_gradient: float = 0.0  # relative brightness change across the image
    noise_sigma: float = 2.0  # grey levels
    blur_sigma: float = 0.5  # pixels (lens/motion softness)
    shadow: float = 0.35  # darkness of the soft contact shadow under the box, 0..1
    light_x: float = 0.2  # light direction (x, 1 = downwards, z) shading the box faces
    light_z: float = 0.6
    hard: bool = False  # a label for statistics only
    traits: tuple[str, ...] = ()  # which hard-case traits SceneSpec.random mixed in

    def __post_init__(self) -> None:
        for name in ("width_m", "height_m", "length_m", "distance_m", "tile_m"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"SceneSpec.{name} must be positive, got {value}")
        if self.floor_style not in FLOOR_STYLES:
            raise ValueError(f"floor_style must be one of {FLOOR_STYLES}, got {self.floor_style}")

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> SceneSpec:
        clean = dict(data)
        for key in ("box_color", "floor_color", "seam_color", "wall_color", "skirting_color"):
            if key in clean:
                clean[key] = tuple(float(c) for c in clean[key])
        if "traits" in clean:
            clean["traits"] = tuple(str(t) for t in clean["traits"])
        return cls(**clean)

    @classmethod
    def random(
        cls,
        rng: np.random.Generator | int | None = None,
        hard: bool = False,
        camera: CameraModel | None = None,
        rig: Rig | None = None,
        traits: tuple[str, ...] | None = None,
    ) -> SceneSpec:
        """A varied scene whose obstacle's front face lies wholly inside the image.

        Ordinary scenes: a clearly contrasting box at 0.4-3 m, face at least ~30 px.
        Hard scenes mix one to three (or exactly ``traits``) of HARD_TRAITS: "contrast"
        (low contrast), "lines" (skirting, shelves, strong seams), "busy" (cluttered wall,
        other boxes), "low" (a low box whose top shows), "yaw" (2-6 degrees), "far"
        (small boxes at 2.5-4.8 m), "label" (a stripe across the face), "rough" (heavy
        noise, blur, light gradient).
        """
        if traits is not None:
            unknown = set(traits) - set(HARD_TRAITS)
            if unknown:
                raise ValueError(f"unknown traits {sorted(unknown)}; known: {HARD_TRAITS}")
            hard = hard or bool(traits)
        gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
        cam = camera if camera is not None else CameraModel.paper()
        the_rig = rig if rig is not None else Rig()
        for _ in range(200):
            spec = _draw(gen, hard, the_rig, traits)
            if _fits(spec, cam, the_rig, min_px=15.0 if hard else 30.0):
                return spec
        raise RuntimeError(
            "could not place an obstacle in view; is the camera pointed at the floor?"
        )


def front_shade(light_x: float, light_z: float) -> float:
    """Brightness factor of the box's front face under the spec's light (as rendered)."""
    return 0.55 + 0.45 * light_z / math.sqrt(light_x**2 + 1.0 + light_z**2)


def _grey(c: Color) -> float:
    return 0.114 * c[0] + 0.587 * c[1] + 0.299 * c[2]


def _color(gen: np.random.Generator, lo: float = 20.0, hi: float = 235.0) -> Color:
    base = gen.uniform(lo, hi)
    tint = gen.normal(0.0, 25.0, 3)
    b, g, r = (float(np.clip(base + t, 0, 255)) for t in tint)
    return (b, g, r)


def _contrasting(gen: np.random.Generator, others: list[Color], min_diff: float) -> Color:
    for _ in range(100):
        c = _color(gen)
        if all(abs(_grey(c) - _grey(o)) >= min_diff for o in others):
            return c
    return (20.0, 20.0, 20.0) if all(_grey(o) > 128 for o in others) else (235.0, 235.0, 235.0)


def _scaled(ref: Color, grey: float) -> Color:
    """``ref``'s hue at the given grey level (clipped to 8 bit)."""
    k = grey / max(_grey(ref), 1.0)
    return tuple(float(np.clip(c * k, 0, 255)) for c in ref)  # type: ignore[return-value]


def _draw(
    gen: np.random.Generator, hard: bool, rig: Rig, chosen: tuple[str, ...] | None
) -> SceneSpec:
    floor = _color(gen, 60, 200)
    wall = _color(gen, 80, 235)
    seam_delta = gen.uniform(15, 40) * gen.choice([-1.0, 1.0])
    seam = tuple(float(np.clip(c + seam_delta, 0, 255)) for c in floor)
    style = str(gen.choice(FLOOR_STYLES))
    kw: dict[str, Any] = dict(
        floor_color=floor,
        wall_color=wall,
        seam_color=seam,
        floor_style=style,
        tile_m=float(gen.uniform(0.2, 0.6)),
        wall_gap_m=float(gen.uniform(0.4, 2.5)),
        skirting_m=float(gen.choice([0.0, gen.uniform(0.04, 0.12)])),
        skirting_color=_color(gen),
        clutter=int(gen.integers(0, 4)),
        light_gain=float(gen.uniform(0.8, 1.2)),
        light_gradient=float(gen.uniform(-0.15, 0.15)),
        noise_sigma=float(gen.uniform(1.0, 3.0)),
        blur_sigma=float(gen.uniform(0.3, 0.8)),
        shadow=float(gen.uniform(0.1, 0.5)),
        distance_m=float(gen.uniform(0.4, 3.0)),
        width_m=float(gen.uniform(0.15, 0.8)),
        height_m=float(gen.uniform(0.10, 0.6)),
        length_m=float(gen.uniform(0.15, 0.6)),
    )
    kw["light_x"] = float(gen.uniform(-0.5, 0.5))
    kw["light_z"] = float(gen.uniform(0.2, 1.0))
    shade = front_shade(kw["light_x"], kw["light_z"])
    for _ in range(100):  # ordinary: the lit front face contrasts with floor and wall
        box = _color(gen)
        lit = _grey(box) * shade
        if abs(lit - _grey(floor)) >= 35 and abs(lit - _grey(wall)) >= 35:
            break
    kw["box_color"] = box
    half_beam = kw["distance_m"] * math.tan(rig.beam_half_rad)
    kw["lateral_m"] = float(gen.uniform(-0.5, 0.5) * half_beam)
    if hard:
        if chosen is None:
            picked = gen.choice(HARD_TRAITS, size=int(gen.integers(1, 4)), replace=False)
            traits = tuple(str(t) for t in picked)
        else:
            traits = tuple(chosen)
        kw["hard"] = True
        kw["traits"] = tuple(sorted(traits))
        if "contrast" in traits:
            # low, not zero: the lit front face 10-20 grey levels from the floor and
            # 12-25 from the wall, in the floor's hue
            fg = _grey(floor)
            lit = fg + (1.0 if fg < 128 else -1.0) * float(gen.uniform(10, 20))
            kw["box_color"] = _scaled(floor, lit / shade)
            wall_lit = lit + float(gen.choice([-1.0, 1.0])) * float(gen.uniform(12, 25))
            if not 5.0 <= wall_lit <= 250.0:
                wall_lit = lit - (wall_lit - lit)
            kw["wall_color"] = _scaled(_color(gen, 60, 200), wall_lit)
        if "lines" in traits:
            kw["skirting_m"] = float(gen.uniform(0.05, 0.15))
            kw["shelves"] = int(gen.integers(1, 4))
            kw["floor_style"] = str(gen.choice(["tiles", "planks"]))
            kw["seam_color"] = tuple(float(np.clip(c - 60, 0, 255)) for c in floor)
        if "busy" in traits:
            kw["clutter"] = int(gen.integers(6, 20))
            kw["extra_boxes"] = int(gen.integers(1, 4))
            kw["shelves"] = max(kw.get("shelves", 0), int(gen.integers(0, 3)))
        if "low" in traits:
            kw["height_m"] = float(gen.uniform(0.04, 0.6 * rig.camera_height_m + 0.02))
            kw["length_m"] = float(gen.uniform(0.3, 0.8))
            kw["distance_m"] = float(gen.uniform(0.35, 1.5))
        if "yaw" in traits:
            kw["yaw_deg"] = float(gen.uniform(2.0, 6.0) * gen.choice([-1.0, 1.0]))
        if "far" in traits:
            kw["distance_m"] = float(gen.uniform(2.5, 4.8))
            kw["width_m"] = float(gen.uniform(0.1, 0.4))
            kw["height_m"] = float(gen.uniform(0.08, 0.35))
        if "label" in traits:
            kw["label"] = True
        if "rough" in traits:
            kw["noise_sigma"] = float(gen.uniform(4.0, 8.0))
            kw["blur_sigma"] = float(gen.uniform(0.8, 1.5))
            kw["light_gradient"] = float(gen.uniform(-0.35, 0.35))
            kw["light_gain"] = float(gen.uniform(0.6, 1.4))
        half_beam = kw["distance_m"] * math.tan(rig.beam_half_rad)
        kw["lateral_m"] = float(gen.uniform(-0.7, 0.7) * half_beam)
    return SceneSpec(**kw)


def _fits(
    spec: SceneSpec, camera: CameraModel, rig: Rig, min_px: float, margin: float = 8.0
) -> bool:
    corners = _box_corners(spec, rig)
    pix, z = _project_points(corners, camera, rig)
    if np.any(z < 0.1):
        return False
    x0, y0 = pix.min(axis=0)
    x1, y1 = pix.max(axis=0)
    inside = (
        x0 >= margin
        and y0 >= margin
        and x1 <= camera.width - 1 - margin
        and y1 <= camera.height - 1 - margin
    )
    front = pix[:4]
    size_ok = bool(np.ptp(front[:, 0]) >= min_px and np.ptp(front[:, 1]) >= min_px)
    return bool(inside and size_ok)


# ---------------------------------------------------------------------- the answer
@dataclass(frozen=True)
class SceneTruth:
    """The ground truth of one rendered scene."""

    present: bool
    height_m: float
    width_m: float
    length_m: float
    distance_m: float  # true sonar range (forward, sonar to face centre)
    depth_m: float  # face-centre depth from the lens
    box_px: tuple[float, float, float, float]  # front face bounds in the rendered image
    hard: bool

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["box_px"] = list(self.box_px)
        return d


@dataclass
class RenderedScene:
    image: npt.NDArray[np.uint8]  # BGR
    truth: SceneTruth
    spec: SceneSpec = field(repr=False)


# ---------------------------------------------------------------------- geometry helpers
def _box_corners(spec: SceneSpec, rig: Rig) -> FloatArray:
    """8 corners: front face (bl, br, tr, tl) then back face, robot frame."""
    depth = rig.face_depth(spec.distance_m)
    cx = rig.sonar_right_m + spec.lateral_m
    floor_y = rig.camera_height_m
    w2 = spec.width_m / 2.0
    yaw = math.radians(spec.yaw_deg)
    c, s = math.cos(yaw), math.sin(yaw)
    local = []
    for dz in (0.0, spec.length_m):
        for lx, top in ((-w2, False), (w2, False), (w2, True), (-w2, True)):
            local.append((lx, floor_y - (spec.height_m if top else 0.0), dz))
    pts = np.array(local)
    x = pts[:, 0] * c + pts[:, 2] * s
    z = -pts[:, 0] * s + pts[:, 2] * c
    return np.stack([x + cx, pts[:, 1], z + depth], axis=1)


def _project_points(
    points: FloatArray, camera: CameraModel, rig: Rig
) -> tuple[FloatArray, FloatArray]:
    """Robot-frame points to distorted pixels; also returns camera z."""
    cam_pts = points @ rig.camera_to_robot  # row-vector form of R^T p
    z = cam_pts[:, 2]
    safe = cam_pts.copy()
    safe[:, 2] = np.maximum(z, 1e-6)
    return camera.project(safe), z


def _clip_near(poly: FloatArray) -> FloatArray:
    """Sutherland-Hodgman against z >= _NEAR_Z (camera frame)."""
    out = []
    n = len(poly)
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        ina, inb = a[2] >= _NEAR_Z, b[2] >= _NEAR_Z
        if ina:
            out.append(a)
        if ina != inb:
            t = (_NEAR_Z - a[2]) / (b[2] - a[2])
            out.append(a + t * (b - a))
    return np.array(out) if out else np.zeros((0, 3))


def _shrink(poly: FloatArray) -> FloatArray | None:
    """Inset a convex polygon by half a pixel (per-axis), undoing OpenCV's fill dilation."""
    n = len(poly)
    if n < 3:
        return None
    area2 = float(
        np.sum(poly[:, 0] * np.roll(poly[:, 1], -1) - np.roll(poly[:, 0], -1) * poly[:, 1])
    )
    if abs(area2) < 1e-9:
        return None
    orient = 1.0 if area2 > 0 else -1.0
    pts = []
    lines = []
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        d = b - a
        length = math.hypot(d[0], d[1])
        if length < 1e-9:
            continue
        nx, ny = orient * d[1] / length, -orient * d[0] / length  # outward normal
        h = 0.5 * (abs(nx) + abs(ny))
        lines.append((nx, ny, nx * a[0] + ny * a[1] - h))
    m = len(lines)
    if m < 3:
        return None
    for i in range(m):
        n1x, n1y, c1 = lines[i - 1]
        n2x, n2y, c2 = lines[i]
        det = n1x * n2y - n1y * n2x
        if abs(det) < 1e-9:
            continue
        pts.append(((c1 * n2y - c2 * n1y) / det, (n1x * c2 - n2x * c1) / det))
    out = np.array(pts)
    if len(out) < 3:
        return None
    area2b = float(np.sum(out[:, 0] * np.roll(out[:, 1], -1) - np.roll(out[:, 0], -1) * out[:, 1]))
    if area2b * area2 <= 0:
        return None  # thinner than a pixel: vanished
    return out


def _shrink_quads(pix: FloatArray) -> tuple[FloatArray, npt.NDArray[np.bool_]]:
    """_shrink for N convex quads at once; also which survived (thicker than a pixel)."""
    a = pix
    b = np.roll(pix, -1, axis=1)
    area2 = np.sum(a[:, :, 0] * b[:, :, 1] - b[:, :, 0] * a[:, :, 1], axis=1)
    orient = np.where(area2 > 0, 1.0, -1.0)[:, None]
    d = b - a
    length = np.maximum(np.hypot(d[:, :, 0], d[:, :, 1]), 1e-9)
    nx = orient * d[:, :, 1] / length
    ny = -orient * d[:, :, 0] / length
    c = nx * a[:, :, 0] + ny * a[:, :, 1] - 0.5 * (np.abs(nx) + np.abs(ny))
    n1x, n1y, c1 = np.roll(nx, 1, axis=1), np.roll(ny, 1, axis=1), np.roll(c, 1, axis=1)
    det = n1x * ny - n1y * nx
    safe = np.where(np.abs(det) < 1e-9, 1e-9, det)
    out = np.stack([(c1 * ny - c * n1y) / safe, (n1x * c - nx * c1) / safe], axis=2)
    b2 = np.roll(out, -1, axis=1)
    area2b = np.sum(out[:, :, 0] * b2[:, :, 1] - b2[:, :, 0] * out[:, :, 1], axis=1)
    good = (np.abs(area2) > 1e-9) & (area2b * area2 > 0) & np.all(np.abs(det) >= 1e-9, axis=1)
    return out, good


def _face_bounds(
    corners: FloatArray, camera: CameraModel, rig: Rig
) -> tuple[float, float, float, float]:
    """Bounds of the front face in the distorted image (edges sampled: distortion bends them)."""
    front = corners[:4]
    t = np.linspace(0.0, 1.0, 17)[:, None]
    samples = np.concatenate([front[i] + t * (front[(i + 1) % 4] - front[i]) for i in range(4)])
    pix, _ = _project_points(samples, camera, rig)
    return (
        float(pix[:, 0].min()),
        float(pix[:, 1].min()),
        float(pix[:, 0].max()),
        float(pix[:, 1].max()),
    )


# ---------------------------------------------------------------------- the renderer
class SceneRenderer:
    """Per-camera state (distortion map, canvases) built once; ``render`` per frame."""

    def __init__(self, camera: CameraModel, rig: Rig, supersample: int = 4) -> None:
        if supersample < 1:
            raise ValueError("supersample must be >= 1")
        self.camera = camera
        self.rig = rig
        self.ss = int(supersample)
        w, h = camera.width, camera.height
        # Where each distorted output pixel comes from in the ideal pinhole image.
        grid = np.mgrid[0:h, 0:w][::-1].reshape(2, -1).T.astype(np.float64)
        rays = camera.unproject(grid)
        ideal_u = rays[:, 0] * camera.fx + camera.camera_matrix[0, 1] * rays[:, 1] + camera.cx
        ideal_v = rays[:, 1] * camera.fy + camera.cy
        pad_x = int(math.ceil(max(0.0, -ideal_u.min(), ideal_u.max() - (w - 1)))) + 3
        pad_y = int(math.ceil(max(0.0, -ideal_v.min(), ideal_v.max() - (h - 1)))) + 3
        self.pad = (pad_x, pad_y)
        self.ideal_size = (w + 2 * pad_x, h + 2 * pad_y)
        self.map_x = (ideal_u + pad_x).reshape(h, w).astype(np.float32)
        self.map_y = (ideal_v + pad_y).reshape(h, w).astype(np.float32)
        self.map1, self.map2 = cv2.convertMaps(self.map_x, self.map_y, cv2.CV_16SC2)
        iw, ih = self.ideal_size
        self._canvas = np.zeros((ih * self.ss, iw * self.ss, 3), np.uint8)
        self._ideal = np.zeros((ih, iw, 3), np.uint8)
        yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
        self._xx = (xx / max(w - 1, 1) - 0.5).astype(np.float32)
        self._yy = (yy / max(h - 1, 1) - 0.5).astype(np.float32)
        self._r_world_to_cam = np.ascontiguousarray(rig.camera_to_robot)  # p_c = p_r @ R
        self._noise: npt.NDArray[np.float32] | None = None
        self._float: tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]] | None = None

    # -- projection onto the supersampled ideal canvas
    def _to_canvas(self, cam_pts: FloatArray) -> FloatArray:
        cam = self.camera
        u = (
            cam.fx * cam_pts[:, 0] / cam_pts[:, 2]
            + cam.camera_matrix[0, 1] * cam_pts[:, 1] / cam_pts[:, 2]
            + cam.cx
        )
        v = cam.fy * cam_pts[:, 1] / cam_pts[:, 2] + cam.cy
        s = self.ss
        return np.stack(
            [(u + self.pad[0] + 0.5) * s - 0.5, (v + self.pad[1] + 0.5) * s - 0.5], axis=1
        )

    def _fill(self, quad_world: FloatArray, color: Color) -> None:
        cam_pts = quad_world @ self._r_world_to_cam
        if np.all(cam_pts[:, 2] < _NEAR_Z):
            return
        if np.any(cam_pts[:, 2] < _NEAR_Z):
            cam_pts = _clip_near(cam_pts)
            if len(cam_pts) < 3:
                return
        pix = self._to_canvas(cam_pts)
        h, w = self._canvas.shape[:2]
        if (
            pix[:, 0].max() < -1
            or pix[:, 1].max() < -1
            or pix[:, 0].min() > w
            or pix[:, 1].min() > h
        ):
            return
        pix = np.clip(pix, -4 * w, 4 * w)
        shrunk = _shrink(pix)
        if shrunk is None:
            return
        pts = np.round(shrunk * (1 << _SHIFT)).astype(np.int32)
        cv2.fillConvexPoly(self._canvas, pts, color, cv2.LINE_8, _SHIFT)

    # -- scene parts
    def _wall(self, spec: SceneSpec, gen: np.random.Generator, wall_z: float, light: float) -> None:
        floor_y = self.rig.camera_height_m
        big = 30.0
        self._fill(
            _quad_z(-big, big, floor_y - 3.0, floor_y, wall_z), _shade(spec.wall_color, light)
        )
        for _ in range(spec.clutter):
            w, hgt = gen.uniform(0.1, 0.9), gen.uniform(0.1, 0.8)
            x = gen.uniform(-3.0, 3.0)
            y1 = floor_y - gen.uniform(0.15, 1.2)
            self._fill(_quad_z(x, x + w, y1 - hgt, y1, wall_z - 0.002), _shade(_color(gen), light))
        for _ in range(spec.shelves):
            y = floor_y - gen.uniform(0.12, 1.0)
            x = gen.uniform(-3.0, 1.0)
            w = gen.uniform(1.0, 4.0)
            board = _color(gen)
            xb = x
            while xb < x + w - 0.05:  # books standing on the shelf
                bw = gen.uniform(0.02, 0.08)
                bh = gen.uniform(0.12, 0.3)
                self._fill(
                    _quad_z(xb, xb + bw, y - bh, y, wall_z - 0.15), _shade(_color(gen), light)
                )
                xb += bw + gen.uniform(0.0, 0.02)
            self._fill(_quad_z(x, x + w, y, y + 0.025, wall_z - 0.3), _shade(board, light))
        if spec.skirting_m > 0:
            self._fill(
                _quad_z(-big, big, floor_y - spec.skirting_m, floor_y, wall_z - 0.01),
                _shade(spec.skirting_color, light),
            )

    def _floor(
        self, spec: SceneSpec, gen: np.random.Generator, wall_z: float, light: float
    ) -> None:
        y = self.rig.camera_height_m
        z_near = 0.03
        half = 6.0
        base = spec.seam_color if spec.floor_style != "plain" else spec.floor_color
        self._fill(_quad_y(-half, half, z_near, wall_z, y), _shade(base, light))
        if spec.floor_style == "plain":
            return
        t = spec.tile_m
        gap = 0.004 + 0.004 * gen.random()
        fc = np.array(spec.floor_color)
        rects: list[tuple[float, float, float, float]] = []  # x0, x1, z0, z1
        tiles: FloatArray | None = None
        if spec.floor_style == "tiles":
            xs = np.arange(-half, half, t) + gen.uniform(0, t)
            zs = np.arange(z_near - gen.uniform(0, t), wall_z, t)
            # every (z0, x0) tile, z-major: the same values a loop over zs then xs gives
            tiles = np.empty((zs.size, xs.size, 4))
            tiles[:, :, 0] = xs + gap
            tiles[:, :, 1] = xs + t - gap
            tiles[:, :, 2] = np.maximum(zs + gap, z_near)[:, None]
            tiles[:, :, 3] = np.minimum(zs + t - gap, wall_z)[:, None]
            jitter = 4.0
        else:  # planks run forward, staggered ends
            pw = t / 3.0
            for x0 in np.arange(-half, half, pw):
                z0 = z_near - gen.uniform(0, 1.2)
                while z0 < wall_z:
                    ln = gen.uniform(0.8, 1.5)
                    rects.append(
                        (x0 + gap, x0 + pw - gap, max(z0 + gap, z_near), min(z0 + ln - gap, wall_z))
                    )
                    z0 += ln
            jitter = 8.0
        r = tiles.reshape(-1, 4) if tiles is not None else np.array(rects)
        r = r[r[:, 3] > r[:, 2]]
        colors = np.clip(fc + gen.normal(0, jitter, (len(r), 3)), 0, 255) * light
        quads = np.empty((len(r), 4, 3))
        quads[:, :, 1] = y
        quads[:, 0, 0] = quads[:, 3, 0] = r[:, 0]
        quads[:, 1, 0] = quads[:, 2, 0] = r[:, 1]
        quads[:, 0, 2] = quads[:, 1, 2] = r[:, 2]
        quads[:, 2, 2] = quads[:, 3, 2] = r[:, 3]
        self._fill_many(quads, colors)

    def _fill_many(self, quads: FloatArray, colors: FloatArray) -> None:
        """Many convex quads at once: projection, culling and the half-pixel inset vectorised."""
        cam = quads @ self._r_world_to_cam
        ok = cam[:, :, 2] >= _NEAR_Z
        for i in np.nonzero(ok.any(axis=1) & ~ok.all(axis=1))[0]:  # cross the near plane
            self._fill(quads[i], tuple(colors[i]))  # type: ignore[arg-type]
        keep = ok.all(axis=1)
        cam, colors = cam[keep], colors[keep]
        if len(cam) == 0:
            return
        pix = self._to_canvas(cam.reshape(-1, 3)).reshape(-1, 4, 2)
        h, w = self._canvas.shape[:2]
        lo, hi = pix.min(axis=1), pix.max(axis=1)
        vis = (hi[:, 0] >= -1) & (hi[:, 1] >= -1) & (lo[:, 0] <= w) & (lo[:, 1] <= h)
        pix, colors = np.clip(pix[vis], -4 * w, 4 * w), colors[vis]
        if len(pix) == 0:
            return
        shrunk, good = _shrink_quads(pix)
        pts = np.round(shrunk * (1 << _SHIFT)).astype(np.int32)
        for i in np.nonzero(good)[0]:
            cv2.fillConvexPoly(self._canvas, pts[i], tuple(colors[i]), cv2.LINE_8, _SHIFT)

    def _box(
        self, corners: FloatArray, color: Color, light_dir: FloatArray, label: Color | None
    ) -> None:
        faces = {
            "front": (0, 1, 2, 3),
            "back": (5, 4, 7, 6),
            "left": (4, 0, 3, 7),
            "right": (1, 5, 6, 2),
            "top": (3, 2, 6, 7),
        }
        drawn = []
        for name, idx in faces.items():
            q = corners[list(idx)]
            centre = q.mean(axis=0)
            centre_box = corners.mean(axis=0)
            normal = np.cross(q[1] - q[0], q[3] - q[0])
            normal /= np.linalg.norm(normal)
            if np.dot(normal, centre - centre_box) < 0:
                normal = -normal
            if np.dot(normal, centre) >= 0:  # facing away from the lens (at the origin)
                continue
            shade = 0.55 + 0.45 * max(0.0, float(-np.dot(normal, light_dir)))
            drawn.append((float(np.linalg.norm(centre)), name, q, shade))
        for _, name, q, shade in sorted(drawn, key=lambda d: -d[0]):
            self._fill(q, _shade(color, shade))
            if name == "front" and label is not None:
                bl, br, tr, tl = q
                a0, a1 = 0.45, 0.62
                stripe = np.array(
                    [
                        bl + a0 * (tl - bl),
                        br + a0 * (tr - br),
                        br + a1 * (tr - br),
                        bl + a1 * (tl - bl),
                    ]
                )
                self._fill(stripe, _shade(label, shade))

    # -- one frame
    def render(
        self, spec: SceneSpec, rng: np.random.Generator | int | None = None
    ) -> RenderedScene:
        gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
        rig = self.rig
        self._canvas[:] = 0
        light = 1.0
        depth = rig.face_depth(spec.distance_m)
        wall_z = depth + spec.length_m + spec.wall_gap_m
        self._wall(spec, gen, wall_z, light)
        self._floor(spec, gen, wall_z, light)
        corners = _box_corners(spec, rig)
        light_dir = np.array([spec.light_x, 1.0, spec.light_z])
        light_dir /= np.linalg.norm(light_dir)
        for _ in range(spec.extra_boxes):
            ez = (
                gen.uniform(depth + spec.length_m + 0.3, wall_z - 0.2)
                if wall_z - depth - spec.length_m > 0.6
                else wall_z - 0.25
            )
            other = SceneSpec(
                width_m=float(gen.uniform(0.2, 0.8)),
                height_m=float(gen.uniform(0.1, 0.8)),
                length_m=0.2,
                distance_m=float(max(rig.range_from_depth(ez), 0.1)),
                lateral_m=float(gen.uniform(-2.0, 2.0)),
                yaw_deg=float(gen.uniform(-20, 20)),
            )
            self._box(_box_corners(other, rig), _color(gen), light_dir, None)
        if spec.obstacle:
            if spec.shadow > 0:
                # Soft contact shadow: a little wider than the box and behind it, never in
                # front of the face (overhead light), so the floor-contact edge stays true.
                wide = _box_corners(
                    replace(spec, width_m=spec.width_m * 1.04, length_m=spec.length_m * 1.2), rig
                )
                grown = np.array([wide[0], wide[1], wide[5], wide[4]])
                dark = _shade(spec.floor_color, 1.0 - 0.6 * spec.shadow)
                self._fill(grown, dark)
            label = None
            if spec.label:
                label = _contrasting(gen, [spec.box_color], 50.0)
            self._box(corners, spec.box_color, light_dir, label)
        img = self._finish(spec, gen)
        if spec.obstacle:
            box = _face_bounds(corners, self.camera, rig)
        else:
            box = (math.nan,) * 4  # type: ignore[assignment]
        truth = SceneTruth(
            present=spec.obstacle,
            height_m=spec.height_m,
            width_m=spec.width_m,
            length_m=spec.length_m,
            distance_m=spec.distance_m,
            depth_m=depth,
            box_px=box,
            hard=spec.hard,
        )
        return RenderedScene(img, truth, spec)

    def _finish(self, spec: SceneSpec, gen: np.random.Generator) -> npt.NDArray[np.uint8]:
        iw, ih = self.ideal_size
        cv2.resize(self._canvas, (iw, ih), dst=self._ideal, interpolation=cv2.INTER_AREA)
        img = cv2.remap(self._ideal, self.map1, self.map2, cv2.INTER_LINEAR)
        if spec.blur_sigma > 0.05:
            img = cv2.GaussianBlur(img, (0, 0), spec.blur_sigma)
        angle = gen.uniform(0, 2 * math.pi)
        # frame-sized float buffers reused: fresh ones cost more in page faults than the
        # arithmetic (the live synthetic camera renders every frame)
        f, tmp = self._float_buffers(img.shape)
        np.copyto(f, img)  # exact: uint8 to float32
        if spec.light_gain != 1.0 or spec.light_gradient != 0.0:  # else a gain of exactly 1
            gain = np.float32(spec.light_gain) * (
                1.0
                + np.float32(spec.light_gradient)
                * (np.float32(math.cos(angle)) * self._xx + np.float32(math.sin(angle)) * self._yy)
            )
            f *= gain[:, :, None]
        if spec.noise_sigma > 0:
            # unit Gaussian noise drawn once per renderer; each frame takes a random window
            h, w = img.shape[:2]
            if self._noise is None:
                self._noise = np.random.default_rng(12345).standard_normal(
                    (2 * h, 2 * w, 3), dtype=np.float32
                )
            oy, ox = int(gen.integers(0, h)), int(gen.integers(0, w))
            window = self._noise[oy : oy + h, ox : ox + w]
            np.multiply(window, np.float32(spec.noise_sigma), out=tmp)
            f += tmp
        np.clip(f, 0, 255, out=f)
        return f.astype(np.uint8)

    def _float_buffers(
        self, shape: tuple[int, ...]
    ) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]:
        if self._float is None or self._float[0].shape != shape:
            self._float = (np.empty(shape, np.float32), np.empty(shape, np.float32))
        return self._float


def _shade(color: Color | tuple[Any, ...], k: float) -> Color:
    return tuple(float(min(255.0, max(0.0, c * k))) for c in color)  # type: ignore[return-value]


def _quad_z(x0: float, x1: float, y0: float, y1: float, z: float) -> FloatArray:
    return np.array([[x0, y1, z], [x1, y1, z], [x1, y0, z], [x0, y0, z]])


def _quad_y(x0: float, x1: float, z0: float, z1: float, y: float) -> FloatArray:
    return np.array([[x0, y, z0], [x1, y, z0], [x1, y, z1], [x0, y, z1]])


@lru_cache(maxsize=8)
def renderer_for(camera: CameraModel, rig: Rig, supersample: int = 4) -> SceneRenderer:
    """One renderer per (camera, rig): its distortion map is the expensive part."""
    return SceneRenderer(camera, rig, supersample)


def render_scene(
    spec: SceneSpec,
    camera: CameraModel,
    rig: Rig,
    rng_or_seed: np.random.Generator | int | None = None,
    supersample: int = 4,
) -> RenderedScene:
    """Render ``spec`` through ``camera`` mounted as ``rig``; deterministic for a given seed."""
    return renderer_for(camera, rig, supersample).render(spec, rng_or_seed)


def with_range(spec: SceneSpec, distance_m: float) -> SceneSpec:
    """The same scene with the obstacle moved to another range (for live playback)."""
    return replace(spec, distance_m=float(distance_m))
