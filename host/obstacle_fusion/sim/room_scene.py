"""Textured rooms, a second scene renderer written apart from ``scene.py`` for honest figures.

``scene.py`` fills flat-shaded polygons; the fused method was tuned on its look. This renderer
maps textures onto planes by homography (floor, back wall, clutter, the box's faces), then puts
the lens distortion on with a remap, so its images differ in every way the method could have
learnt: faces with plank seams, tape, panel joints, text, posters and photos covering most of
them, gloss gradients; floors and walls of procedural materials or real photographs (the
textures scikit-image ships: brick, gravel, grass, a garage, pages of text...), clutter,
shadows, random rigs (camera 0.2-0.5 m, pitch within +-5 degrees, sonar 3 cm below).

Families (``FAMILIES``) split the textures so that some are never seen while tuning:
``procedural`` / ``procedural-holdout`` use drawn materials with disjoint parameter sets and
seeds; ``photo`` / ``photo-holdout`` use disjoint sets of photographs. A scene is fully given by
``(family, seed, hard)``; its truth (height, width, range, rig) comes with the image.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field
from functools import cache, lru_cache
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.rig import Rig

log = logging.getLogger(__name__)

Image = npt.NDArray[Any]
FloatArray = npt.NDArray[Any]  # float32 or float64 working images

#: Photographs by family. Tuning never looks at the hold-out lists.
PHOTO_TEXTURES: dict[str, dict[str, tuple[str, ...]]] = {
    "photo": {
        "floor": ("gravel", "brick"),
        "wall": ("camera", "coffee", "rocket"),
        "face": ("chelsea", "astronaut", "coins"),
        "text": ("text",),
        "brick": ("brick",),
    },
    "photo-holdout": {
        "floor": ("grass",),
        "wall": ("motorcycle_left", "hubble_deep_field", "color"),
        "face": ("motorcycle_right", "retina", "horse"),
        "text": ("page",),
        "brick": (),  # drawn bricks: the photograph is the tuning families'
    },
}
FAMILIES = ("procedural", "procedural-holdout", "photo", "photo-holdout")
FACE_KINDS = ("planks", "seams", "tape", "panels", "poster", "text", "brick", "gloss", "plain")


class TextureMissing(RuntimeError):
    """The photographs need scikit-image's data files (``pip install scikit-image``)."""


@cache
def _photo_dir() -> Path:
    import importlib.util

    spec = importlib.util.find_spec("skimage")
    if spec is None or not spec.submodule_search_locations:
        raise TextureMissing(
            "photo families need scikit-image's sample photos: pip install scikit-image"
        )
    return Path(next(iter(spec.submodule_search_locations))) / "data"


@cache
def photo(name: str) -> Image:
    """One of scikit-image's sample photographs as BGR, read straight from its file."""
    folder = _photo_dir()
    for ext in (".png", ".jpg"):
        p = folder / f"{name}{ext}"
        if p.is_file():
            img = cv2.imread(str(p), cv2.IMREAD_COLOR)
            if img is not None:
                return img
    raise TextureMissing(f"sample photo {name!r} not found in {folder}")


# ---------------------------------------------------------------- procedural materials


def _noise(gen: np.random.Generator, h: int, w: int, scale: float, amp: float) -> FloatArray:
    small = gen.normal(0.0, 1.0, (max(2, int(h / scale)), max(2, int(w / scale))))
    return cv2.resize(small, (w, h), interpolation=cv2.INTER_CUBIC) * amp


def _colour(gen: np.random.Generator, lo: float = 30, hi: float = 225) -> FloatArray:
    return gen.uniform(lo, hi, 3)


def _canvas(gen: np.random.Generator, h: int, w: int, base: FloatArray, grain: float) -> FloatArray:
    img = np.empty((h, w, 3))
    img[:] = base
    img += _noise(gen, h, w, 6.0, grain)[:, :, None]
    img += gen.normal(0, grain * 0.3, (h, w, 1))
    return img


def planks(gen: np.random.Generator, h: int, w: int, vertical: bool, n: int) -> FloatArray:
    """Boards with dark seams and a grain along them; each board a slightly other shade."""
    base = _colour(gen, 60, 200)
    img = _canvas(gen, h, w, base, 6.0)
    length = w if not vertical else h
    edges = np.linspace(0, length, n + 1).astype(int)
    for i in range(n):
        a, b = edges[i], edges[i + 1]
        k = gen.uniform(0.85, 1.15)
        sl = (slice(None), slice(a, b)) if vertical else (slice(a, b), slice(None))
        img[sl] *= k
        seam = (
            (slice(None), slice(max(0, a - 1), a + 1))
            if vertical
            else (slice(max(0, a - 1), a + 1), slice(None))
        )
        if i:
            img[seam] *= gen.uniform(0.35, 0.7)
    return img


def _face_texture(gen: np.random.Generator, kind: str, h: int, w: int, family: str) -> FloatArray:
    """A box face of the given kind, as a float BGR image (h x w)."""
    photos = PHOTO_TEXTURES.get(family)
    if kind == "planks":
        return planks(gen, h, w, vertical=True, n=int(gen.integers(3, 8)))
    base = _colour(gen, 50, 215)
    img = _canvas(gen, h, w, base, 4.0)
    if kind == "seams":
        for x in gen.uniform(0.15, 0.85, int(gen.integers(1, 4))):
            xi = int(x * w)
            img[:, max(0, xi - 1) : xi + 2] *= gen.uniform(0.4, 0.75)
    elif kind == "tape":
        ty = int(gen.uniform(0.3, 0.6) * h)
        th = max(2, int(gen.uniform(0.06, 0.14) * h))
        img[ty : ty + th] = _colour(gen, 120, 230)
        if gen.random() < 0.5:  # a vertical strip of tape too
            tx = int(gen.uniform(0.3, 0.6) * w)
            img[:, tx : tx + th] = _colour(gen, 120, 230)
    elif kind == "panels":
        for x in (w // 3, 2 * w // 3):
            img[:, x - 1 : x + 1] *= 0.55
        img[h // 2 - 1 : h // 2 + 1] *= 0.6
    elif kind in ("poster", "text", "brick"):
        choices = photos.get("face" if kind == "poster" else kind, ()) if photos else ()
        if choices:
            pic = photo(choices[int(gen.integers(len(choices)))]).astype(np.float64)
        else:
            pic = _drawn_poster(gen, 240, 320, kind)
        # covering most of the face, with a margin of the face's own shade
        m = gen.uniform(0.0, 0.12)
        y0, y1 = int(m * h), int((1 - m * gen.uniform(0.5, 1.5)) * h)
        x0, x1 = int(m * w), int((1 - m) * w)
        if y1 - y0 > 4 and x1 - x0 > 4:
            img[y0:y1, x0:x1] = cv2.resize(pic, (x1 - x0, y1 - y0), interpolation=cv2.INTER_AREA)
    elif kind == "gloss":
        yy, xx = np.mgrid[0:h, 0:w]
        cx, cy = gen.uniform(0.2, 0.8) * w, gen.uniform(0.1, 0.5) * h
        r = np.hypot(xx - cx, yy - cy) / max(h, w)
        img += (gen.uniform(40, 90) * np.exp(-(r**2) / 0.05))[:, :, None]
    return img


def _drawn_poster(gen: np.random.Generator, h: int, w: int, kind: str) -> FloatArray:
    img = _canvas(gen, h, w, _colour(gen), 3.0)
    if kind == "brick":
        bh = int(gen.integers(12, 24))
        mortar = _colour(gen, 150, 220)
        for r, y in enumerate(range(0, h, bh)):
            img[y : y + 2] = mortar
            off = bh if r % 2 else 0
            for x in range(off, w, 2 * bh):
                img[y : y + bh, x : x + 2] = mortar
        return img
    paper = np.clip(img, 0, 255).astype(np.uint8)
    for _ in range(int(gen.integers(8, 30))):
        x0, y0 = int(gen.integers(0, w - 10)), int(gen.integers(0, h - 6))
        if kind == "text":
            cv2.putText(
                paper,
                "".join(gen.choice(list("abcdefghij KLMNOP"), 8)),
                (x0, y0 + 8),
                cv2.FONT_HERSHEY_SIMPLEX,
                0.4,
                _colour(gen, 0, 90).tolist(),
                1,
            )
        else:
            x1, y1 = x0 + int(gen.integers(8, 80)), y0 + int(gen.integers(6, 60))
            cv2.rectangle(paper, (x0, y0), (x1, y1), _colour(gen).tolist(), -1)
    return paper.astype(np.float64)


def _floor_texture(gen: np.random.Generator, family: str) -> FloatArray:
    photos = PHOTO_TEXTURES.get(family)
    if photos is not None and gen.random() < 0.8:
        name = photos["floor"][int(gen.integers(len(photos["floor"])))]
        pic = photo(name).astype(np.float64)
        return np.tile(pic, (2, 2, 1))
    kind = (
        gen.choice(["planks", "tiles", "paving", "carpet"])
        if family.startswith("procedural") and family.endswith("holdout")
        else gen.choice(["planks", "tiles", "plain"])
    )
    if kind == "planks":
        return planks(gen, 512, 512, vertical=bool(gen.random() < 0.5), n=int(gen.integers(6, 16)))
    img = _canvas(gen, 512, 512, _colour(gen, 40, 200), 8.0 if kind != "carpet" else 18.0)
    if kind in ("tiles", "paving"):
        step = int(gen.integers(40, 130))
        grout = _colour(gen, 60, 220)
        for t in range(0, 512, step):
            img[t : t + 3] = grout
            img[:, t : t + 3] = grout
    return img


def _wall_texture(gen: np.random.Generator, family: str) -> FloatArray:
    photos = PHOTO_TEXTURES.get(family)
    if photos is not None and gen.random() < 0.85:
        name = photos["wall"][int(gen.integers(len(photos["wall"])))]
        return photo(name).astype(np.float64)
    img = _canvas(gen, 400, 800, _colour(gen, 60, 230), 5.0)
    # posters, shelves, a skirting board
    for _ in range(int(gen.integers(0, 5))):
        x0, y0 = int(gen.integers(0, 700)), int(gen.integers(0, 300))
        cv2.rectangle(
            img,
            (x0, y0),
            (x0 + int(gen.integers(40, 200)), y0 + int(gen.integers(40, 150))),
            _colour(gen).tolist(),
            -1,
        )
    if gen.random() < 0.5:
        for y in gen.integers(100, 380, int(gen.integers(1, 4))):
            img[y : y + 5] = _colour(gen, 40, 160)
    img[-int(gen.integers(8, 30)) :] = _colour(gen, 30, 230)
    return img


# ---------------------------------------------------------------- the scene


@dataclass
class RoomSpec:
    """Everything that fixes one textured room (drawn from a seed by :meth:`random`)."""

    family: str
    seed: int
    hard: bool
    rig: Rig
    range_m: float  # what the sonar reads: forward distance from the transducers to the face
    height_m: float
    width_m: float
    depth_m: float
    face_x_m: float  # lateral offset of the face's centre from the lens (robot x)
    yaw_deg: float
    roll_deg: float
    face_kind: str
    wall_z_m: float
    clutter: int
    shadow: bool
    light: float  # overall brightness factor
    noise: float
    blur: float
    jpeg: int | None
    clipped: tuple[str, ...] = field(default_factory=tuple)

    @classmethod
    def random(cls, family: str, seed: int, hard: bool) -> RoomSpec:
        if family not in FAMILIES:
            raise ValueError(f"unknown family {family!r}; one of {FAMILIES}")
        gen = np.random.default_rng([seed, FAMILIES.index(family), int(hard)])
        rig = Rig(
            camera_height_m=float(gen.uniform(0.2, 0.5)),
            camera_pitch_deg=float(gen.uniform(-5.0, 5.0)),
            sonar_below_m=0.03,
        )
        # one scene in ten may be cut by the image's border; the others are drawn whole
        # in view (the paper's lens sees about +-17 degrees up and down, +-28 sideways)
        whole = gen.random() >= 0.1
        low = rig.camera_height_m / 0.28 + 0.05 if whole else 0.5
        range_m = float(gen.uniform(max(0.6, low), max(0.6, low) + (2.0 if hard else 1.4)))
        height = float(gen.uniform(0.12, 0.9))
        width = float(gen.uniform(0.15, 1.0))
        if whole:
            height = min(height, rig.camera_height_m + 0.25 * range_m)
            width = min(width, 0.8 * range_m)
        face_x = float(gen.uniform(-0.25, 0.25) * width)
        kinds = FACE_KINDS if hard else ("plain", "planks", "seams", "panels", "gloss", "brick")
        return cls(
            family=family,
            seed=seed,
            hard=hard,
            rig=rig,
            range_m=range_m,
            height_m=height,
            width_m=width,
            depth_m=float(gen.uniform(0.2, 0.8)),
            face_x_m=face_x,
            yaw_deg=float(gen.uniform(-3, 3)) if hard else 0.0,
            roll_deg=float(gen.uniform(-0.8, 0.8)),
            face_kind=str(gen.choice(kinds)),
            wall_z_m=range_m + float(gen.uniform(0.6, 3.0)),
            clutter=int(gen.integers(0, 4 if hard else 2)),
            shadow=bool(gen.random() < 0.6),
            light=float(gen.uniform(0.55, 1.15) if hard else gen.uniform(0.75, 1.1)),
            noise=float(gen.uniform(1.0, 5.0 if hard else 2.5)),
            blur=float(gen.uniform(0.0, 1.2 if hard else 0.7)),
            jpeg=int(gen.integers(60, 95)) if gen.random() < 0.5 else None,
        )


class RoomRenderer:
    """Renders :class:`RoomSpec` rooms through one camera (distortion included)."""

    def __init__(self, camera: CameraModel, supersample: int = 2) -> None:
        self.camera = camera
        self.ss = supersample
        w, h = camera.size
        self.big = (w * supersample, h * supersample)
        k = camera.camera_matrix.astype(np.float64).copy()
        k[0, 1] = 0.0
        self.k_ideal = k
        ks = k.copy()
        ks[:2] *= supersample
        ks[0, 2] = (k[0, 2] + 0.5) * supersample - 0.5
        ks[1, 2] = (k[1, 2] + 0.5) * supersample - 0.5
        self.k_big = ks
        # distorted output pixel -> ideal (pinhole) pixel of the big canvas
        grid = np.stack(np.meshgrid(np.arange(w), np.arange(h)), axis=-1).reshape(-1, 1, 2)
        ideal = cv2.undistortPoints(
            grid.astype(np.float64), camera.camera_matrix, camera.dist_coeffs, P=ks
        )
        ideal = ideal.reshape(h, w, 2).astype(np.float32)
        self.map_x, self.map_y = ideal[:, :, 0].copy(), ideal[:, :, 1].copy()

    def _rotation(self, rig: Rig, roll_deg: float) -> FloatArray:
        """robot -> camera rotation (pitch about x, then roll about z)."""
        p, r = rig.pitch_rad, math.radians(roll_deg)
        rx = np.array([[1, 0, 0], [0, math.cos(p), -math.sin(p)], [0, math.sin(p), math.cos(p)]])
        rz = np.array([[math.cos(r), -math.sin(r), 0], [math.sin(r), math.cos(r), 0], [0, 0, 1]])
        return rz @ rx

    def _project(self, pts: FloatArray, rot: FloatArray) -> FloatArray:
        cam = pts @ rot.T
        return (cam @ self.k_big.T)[:, :2] / cam[:, 2:3]

    def _paste(
        self,
        canvas: FloatArray,
        tex: FloatArray,
        corners: FloatArray,
        rot: FloatArray,
        shade: float | FloatArray,
    ) -> None:
        """Texture onto the planar quad ``corners`` (robot frame: tl, tr, br, bl)."""
        if np.any((corners @ rot.T)[:, 2] < 0.05):
            return  # behind or at the lens: out of view for every rig drawn here
        dst = self._project(corners, rot).astype(np.float32)
        th, tw = tex.shape[:2]
        src = np.array([[0, 0], [tw - 1, 0], [tw - 1, th - 1], [0, th - 1]], np.float32)
        x0, y0 = np.floor(dst.min(axis=0)).astype(int)
        x1, y1 = np.ceil(dst.max(axis=0)).astype(int) + 1
        x0, y0 = max(x0, 0), max(y0, 0)
        x1, y1 = min(x1, self.big[0]), min(y1, self.big[1])
        if x1 <= x0 or y1 <= y0:
            return
        origin = np.array([x0, y0], np.float32)
        hmat = cv2.getPerspectiveTransform(src, dst - origin)
        roi = (x1 - x0, y1 - y0)
        warped = cv2.warpPerspective(
            (tex * shade).astype(np.float32),
            hmat,
            roi,
            flags=cv2.INTER_LINEAR,
            borderMode=cv2.BORDER_REPLICATE,
        )
        mask = np.zeros((roi[1], roi[0]), np.uint8)
        cv2.fillConvexPoly(
            mask,
            np.round((dst - origin) * 16).astype(np.int32),
            255,
            lineType=cv2.LINE_AA,
            shift=4,
        )
        m = (mask.astype(np.float32) / 255.0)[:, :, None]
        view = canvas[y0:y1, x0:x1]
        view *= 1.0 - m
        view += warped * m

    def render(self, spec: RoomSpec) -> tuple[Image, dict[str, Any]]:
        gen = np.random.default_rng([spec.seed, 7, FAMILIES.index(spec.family)])
        rig = spec.rig
        rot = self._rotation(rig, spec.roll_deg)
        hcam = rig.camera_height_m
        canvas = np.zeros((self.big[1], self.big[0], 3), np.float32)
        light = spec.light
        # back wall, far and wide
        wz = spec.wall_z_m
        wall_h = hcam + 3.0
        self._paste(
            canvas,
            _wall_texture(gen, spec.family),
            np.array(
                [[-4, hcam - wall_h, wz], [4, hcam - wall_h, wz], [4, hcam, wz], [-4, hcam, wz]]
            ),
            rot,
            light * gen.uniform(0.7, 1.0),
        )
        # floor, from just ahead of the lens to the wall, tiled in 1.5 m squares
        ftex = _floor_texture(gen, spec.family)
        fshade = light * gen.uniform(0.75, 1.05)
        tile = float(gen.uniform(0.8, 1.6))  # metres of floor one texture image covers
        z_near = max(0.2, 1.2 * hcam)
        nz, nx = max(1, math.ceil((wz - z_near) / tile)), 6
        floor = np.tile(cv2.resize(ftex, (256, 256), interpolation=cv2.INTER_AREA), (nz, nx, 1))
        half = nx * tile / 2
        floor = floor[: max(2, int(round(256 * (wz - z_near) / tile)))]
        self._paste(
            canvas,
            floor[::-1],
            np.array(
                [[-half, hcam, wz], [half, hcam, wz], [half, hcam, z_near], [-half, hcam, z_near]]
            ),
            rot,
            fshade,
        )
        face_z = rig.face_depth(spec.range_m)
        # shadow: a darker band on the floor at the box's foot
        if spec.shadow:
            sx = spec.face_x_m + gen.uniform(-0.2, 0.2)
            shadow = np.full((32, 32, 3), 1.0)
            self._multiply(
                canvas,
                shadow * gen.uniform(0.45, 0.8),
                np.array(
                    [
                        [sx - spec.width_m * 0.7, hcam, face_z + spec.depth_m + 0.3],
                        [sx + spec.width_m * 0.7, hcam, face_z + spec.depth_m + 0.3],
                        [sx + spec.width_m * 0.7, hcam, face_z - 0.05],
                        [sx - spec.width_m * 0.7, hcam, face_z - 0.05],
                    ]
                ),
                rot,
            )
        # clutter: other boxes and cylinders behind or beside the obstacle
        for _ in range(spec.clutter):
            cz = float(gen.uniform(face_z + 0.3, wz - 0.05))
            cx = float(gen.uniform(-1.5, 1.5))
            ch, cw = float(gen.uniform(0.1, 0.8)), float(gen.uniform(0.1, 0.6))
            if gen.random() < 0.5:  # a cylinder, as vertical strips with cosine shading
                base = _colour(gen)
                n = 12
                for i in range(n):
                    a0, a1 = math.pi * i / n, math.pi * (i + 1) / n
                    x_a, x_b = cx - cw / 2 * math.cos(a0), cx - cw / 2 * math.cos(a1)
                    z_a = cz - cw / 2 * math.sin(a0)
                    strip = np.ones((4, 4, 3)) * base * (0.5 + 0.5 * math.sin((a0 + a1) / 2))
                    self._paste(
                        canvas,
                        strip,
                        np.array(
                            [
                                [x_a, hcam - ch, z_a],
                                [x_b, hcam - ch, z_a],
                                [x_b, hcam, z_a],
                                [x_a, hcam, z_a],
                            ]
                        ),
                        rot,
                        light,
                    )
            else:  # a chair-like frame: two legs and a seat
                col = _colour(gen) * light
                for lx in (cx - cw / 2, cx + cw / 2 - 0.03):
                    self._paste(
                        canvas,
                        np.ones((4, 4, 3)) * col,
                        np.array(
                            [
                                [lx, hcam - ch, cz],
                                [lx + 0.03, hcam - ch, cz],
                                [lx + 0.03, hcam, cz],
                                [lx, hcam, cz],
                            ]
                        ),
                        rot,
                        1.0,
                    )
                self._paste(
                    canvas,
                    np.ones((4, 4, 3)) * col * 0.8,
                    np.array(
                        [
                            [cx - cw / 2, hcam - ch, cz],
                            [cx + cw / 2, hcam - ch, cz],
                            [cx + cw / 2, hcam - ch + 0.04, cz],
                            [cx - cw / 2, hcam - ch + 0.04, cz],
                        ]
                    ),
                    rot,
                    1.0,
                )
        # the obstacle: a box with its front face square to the beam (yawed a little when hard)
        face_tex = _face_texture(
            gen, spec.face_kind, 240, max(8, int(240 * spec.width_m / spec.height_m)), spec.family
        )
        face_tex = np.clip(face_tex, 0, 255)
        yaw = math.radians(spec.yaw_deg)
        hw = spec.width_m / 2
        top = hcam - spec.height_m

        def at(dx: float, y: float, dz: float) -> list[float]:
            return [
                spec.face_x_m + dx * math.cos(yaw) + dz * math.sin(yaw),
                y,
                face_z - dx * math.sin(yaw) + dz * math.cos(yaw),
            ]

        top_col = np.clip(face_tex.mean(axis=(0, 1)) * gen.uniform(1.05, 1.3), 0, 255)
        side_shade = light * gen.uniform(0.5, 0.8)
        # sides (only the one facing the camera is visible; draw both, far first)
        for sgn in (-1, 1):
            x_side = spec.face_x_m + sgn * hw
            if sgn * x_side < 0:  # this side faces the lens
                self._paste(
                    canvas,
                    face_tex[:, :8].mean(axis=1, keepdims=True).repeat(8, axis=1),
                    np.array(
                        [
                            at(sgn * hw, top, spec.depth_m),
                            at(sgn * hw, top, 0),
                            at(sgn * hw, hcam, 0),
                            at(sgn * hw, hcam, spec.depth_m),
                        ]
                    ),
                    rot,
                    side_shade,
                )
        if top > 0:  # the top face is seen only when the camera is higher than the box
            self._paste(
                canvas,
                np.ones((8, 8, 3)) * top_col,
                np.array(
                    [
                        at(-hw, top, spec.depth_m),
                        at(hw, top, spec.depth_m),
                        at(hw, top, 0),
                        at(-hw, top, 0),
                    ]
                ),
                rot,
                light,
            )
        self._paste(
            canvas,
            face_tex,
            np.array([at(-hw, top, 0), at(hw, top, 0), at(hw, hcam, 0), at(-hw, hcam, 0)]),
            rot,
            light * gen.uniform(0.85, 1.05),
        )
        # optics: blur, distortion, noise, vignetting, JPEG
        big: Any = np.clip(canvas, 0, 255).astype(np.float32)
        if spec.blur > 0.05:
            big = cv2.GaussianBlur(big, (0, 0), spec.blur * self.ss)
        big = cv2.GaussianBlur(big, (0, 0), 0.5 * self.ss)
        img = cv2.remap(
            big, self.map_x, self.map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE
        )
        h, w = img.shape[:2]
        yy, xx = np.mgrid[0:h, 0:w]
        vig = 1.0 - 0.25 * (((xx - w / 2) / w) ** 2 + ((yy - h / 2) / h) ** 2) * 2
        grain = gen.normal(0.0, spec.noise, img.shape)
        img = img * vig[:, :, None] + grain
        out = np.clip(img, 0, 255).astype(np.uint8)
        if spec.jpeg is not None:
            ok, buf = cv2.imencode(".jpg", out, [cv2.IMWRITE_JPEG_QUALITY, spec.jpeg])
            out = cv2.imdecode(buf, cv2.IMREAD_COLOR)
        clipped = self._clipped(spec, rot)
        truth = {
            "height_m": spec.height_m,
            "width_m": spec.width_m,
            "range_m": spec.range_m,
            "clipped": clipped,
            "family": spec.family,
            "seed": spec.seed,
            "hard": spec.hard,
            "face_kind": spec.face_kind,
        }
        return out, truth

    def _multiply(
        self, canvas: FloatArray, factor: FloatArray, corners: FloatArray, rot: FloatArray
    ) -> None:
        dst = self._project(corners, rot).astype(np.float32)
        src = np.array([[0, 0], [31, 0], [31, 31], [0, 31]], np.float32)
        hmat = cv2.getPerspectiveTransform(src, dst)
        f = cv2.warpPerspective(
            factor.astype(np.float32),
            hmat,
            self.big,
            borderMode=cv2.BORDER_CONSTANT,
            borderValue=(1.0, 1.0, 1.0),
        )
        f = cv2.GaussianBlur(f, (0, 0), 6.0 * self.ss)
        canvas *= f

    def _clipped(self, spec: RoomSpec, rot: FloatArray) -> list[str]:
        """Which image borders cut the front face (in the distorted output image)."""
        rig = spec.rig
        z = rig.face_depth(spec.range_m)
        top = rig.camera_height_m - spec.height_m
        xs = np.linspace(spec.face_x_m - spec.width_m / 2, spec.face_x_m + spec.width_m / 2, 9)
        ys = np.linspace(top, rig.camera_height_m, 9)
        pts = np.array([[x, y, z] for x in xs for y in ys])
        cam = pts @ rot.T
        px = self.camera.project(cam)
        w, h = self.camera.size
        out = []
        if px[:, 0].min() < 0:
            out.append("left")
        if px[:, 0].max() > w - 1:
            out.append("right")
        if px[:, 1].min() < 0:
            out.append("top")
        if px[:, 1].max() > h - 1:
            out.append("bottom")
        return out


def render_room(
    family: str, seed: int, hard: bool, camera: CameraModel | None = None
) -> tuple[Image, dict[str, Any], RoomSpec]:
    camera = camera or CameraModel.paper(500, 375)
    spec = RoomSpec.random(family, seed, hard)
    image, truth = _renderer(camera).render(spec)
    return image, truth, spec


@lru_cache(maxsize=4)
def _renderer(camera: CameraModel) -> RoomRenderer:
    return RoomRenderer(camera)
