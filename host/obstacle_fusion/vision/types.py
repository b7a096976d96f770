"""The vision's shared types: the answer (Measurement), the working view, the stage timer.

Every method receives a :class:`View` (the geometry built once per camera, rig and image
size) and a :class:`Timer`, and returns a :class:`Measurement`; nothing here knows any method.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from typing import Any, Protocol

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.rig import Rig

FloatArray = npt.NDArray[np.float64]


class ColourRemap(Protocol):
    """A colour block's remap (:meth:`View.use_colour_remap`): image, r0, r1, c0, c1, and
    the block's destination ``out`` (None: a new array)."""

    def __call__(
        self,
        image: npt.NDArray[Any],
        r0: int,
        r1: int,
        c0: int,
        c1: int,
        out: npt.NDArray[np.uint8] | None = None,
        /,
    ) -> npt.NDArray[np.uint8] | None: ...


Box = tuple[float, float, float, float]
Line = tuple[float, float, float, float]


@dataclass
class Measurement:
    """One frame's answer. Pixel coordinates are in the input (distorted) image."""

    detected: bool
    method: str
    range_m: float
    distance_m: float | None = None  # sonar to face, forward (the obstacle's distance)
    height_m: float | None = None
    width_m: float | None = None
    box_px: Box | None = None  # x0, y0, x1, y1 of the front face
    confidence: float | None = 0.0  # None: the method has no such notion (paper)
    timings_ms: dict[str, float] = field(default_factory=dict)
    lines: list[Line] = field(default_factory=list)  # chosen edges, x0, y0, x1, y1
    height_px: float | None = None  # in the method's working view
    width_px: float | None = None
    reason: str = ""  # why nothing was detected
    rig_source: str = "file"  # file: given; estimated: found in the image; default: assumed
    camera_height_m: float | None = None  # the estimated camera height (rig_source estimated)
    camera_pitch_deg: float | None = None  # the pitch used with it (positive: looking down)
    # image borders cutting the face (or the edges of what the working view sees)
    clipped: list[str] = field(default_factory=list)
    # what made the confidence lower than the edges alone say (fused: names and reasons in
    # obstacle_fusion.vision.fused.confidence)
    doubts: list[str] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["box_px"] = None if self.box_px is None else [round(v, 2) for v in self.box_px]
        d["lines"] = [[round(v, 2) for v in ln] for ln in self.lines]
        d["timings_ms"] = {k: round(v, 4) for k, v in self.timings_ms.items()}
        # a face cut by the image's left or right border: its width is at least this
        d["width_is_lower_bound"] = any(s in ("left", "right") for s in self.clipped)
        d["height_is_lower_bound"] = any(s in ("top", "bottom") for s in self.clipped)
        return d


class Timer:
    """Per-stage wall-clock times in ms, cheap enough for every frame."""

    def __init__(self) -> None:
        self.ms: dict[str, float] = {}
        self._t = time.perf_counter()

    def lap(self, name: str) -> None:
        now = time.perf_counter()
        self.ms[name] = self.ms.get(name, 0.0) + (now - self._t) * 1e3
        self._t = now


#: Points along a face's side checked for lying in sight of the view.
SIDE_SAMPLES = 5
#: A face side this close (view px) to what the view does not see may run on out there:
#: the methods stop a side's search a few columns short of the view's edge.
UNSEEN_MARGIN_PX = 4.0
#: The samples' places along a side (0 to 1), and the sides in the order
#: :meth:`View.unseen_sides` names them.
_SIDE_T = np.linspace(0.0, 1.0, SIDE_SAMPLES)[:, None]
_SIDE_NAMES = ("left", "right", "top", "bottom")
_SIDE_T_LIST: list[float] = _SIDE_T[:, 0].tolist()


Block = tuple[int, int, int, int]  # a view block's rows r0..r1-1, columns c0..c1-1
Uncovered = Callable[[list[Block], int, int, int, int], list[Block] | None]


def uncovered_pieces(boxes: list[Block], ra: int, rb: int, ca: int, cb: int) -> list[Block] | None:
    """None when the block (ra, rb, ca, cb) lies inside one of ``boxes`` (the blocks of a
    held frame converted before, :meth:`View.lab`); else its parts no box covers:
    rectangles (the block less each box in turn: up to four pieces around it), in order.
    (The fused method's C accelerator, ``_cmiddle.uncovered``, takes the same steps.)"""
    for a, b, c, d in reversed(boxes):
        if a <= ra and rb <= b and c <= ca and cb <= d:  # inside one block before
            return None
    pieces = [(ra, rb, ca, cb)]
    for a, b, c, d in boxes:
        rest = []
        for p0, p1, q0, q1 in pieces:
            if a >= p1 or b <= p0 or c >= q1 or d <= q0:
                rest.append((p0, p1, q0, q1))
                continue
            if p0 < a:
                rest.append((p0, a, q0, q1))
            if b < p1:
                rest.append((b, p1, q0, q1))
            m0, m1 = max(p0, a), min(p1, b)
            if q0 < c:
                rest.append((m0, m1, q0, c))
            if d < q1:
                rest.append((m0, m1, d, q1))
        pieces = rest
        if not pieces:
            break
    return pieces


class View:
    """Per-camera (and per-rig) geometry of one working view, built once.

    ``kind`` "level": undistorted AND rotated to a virtual camera with no pitch (robot
    axes), so vertical world edges are vertical image columns and a face square to the
    robot images as an exact scaled copy. "plain": undistorted only (the paper's view).
    """

    #: Rows the true horizon may lie above ``cy``: a view levelled for a guessed pitch
    #: (no rig, the pitch not read yet) may have a lens looking down more than it assumes,
    #: and then sees a box's top face above its own horizon.
    horizon_slack_px: float = 0.0

    def __init__(self, camera: CameraModel, rig: Rig, kind: str) -> None:
        self.camera = camera
        self.rig = rig
        self.kind = kind
        k = camera.camera_matrix.copy()
        k[0, 1] = 0.0
        if kind == "level":
            self.rotation = np.array(rig.camera_to_robot)  # camera -> level frame
            k[1, 2] = camera.cy - camera.fy * math.tan(rig.pitch_rad)
        else:
            self.rotation = np.eye(3)
        self.k = k
        self.fx, self.fy, self.cx, self.cy = k[0, 0], k[1, 1], k[0, 2], k[1, 2]
        self.map1, self.map2 = cv2.initUndistortRectifyMap(
            camera.camera_matrix, camera.dist_coeffs, self.rotation, k, camera.size, cv2.CV_16SC2
        )
        # input rows the first n view rows read (bilinear: the row below the lowest too),
        # so a colour frame is converted to grey only as far down as the remap looks
        lowest = np.maximum.accumulate(self.map1[:, :, 1].max(axis=1).astype(np.int64))
        self._src_rows = np.clip(lowest + 2, 1, camera.height).tolist()
        self.grey = np.empty((camera.height, camera.width), np.uint8)
        self.out = np.empty((camera.height, camera.width), np.uint8)
        # the held colour frame (:meth:`hold_colour`): its view blocks converted to CIE Lab
        # so far, in one buffer (made on the first hold), and their (r0, r1, c0, c1)
        self._held: npt.NDArray[Any] | None = None
        self._lab: npt.NDArray[np.uint8] | None = None
        self._lab_read: npt.NDArray[np.uint8] | None = None  # a read-only view of it
        self._lab_boxes: list[Block] = []
        # a method's faster remap of a colour block (:meth:`use_colour_remap`)
        self._colour_remap: ColourRemap | None = None
        # the held blocks' bookkeeping (:func:`uncovered_pieces`, or a method's faster one)
        self._uncovered: Uncovered = uncovered_pieces

    def use_colour_remap(self, remap: ColourRemap | None) -> None:
        """``remap(image, r0, r1, c0, c1)``: the view block rows r0..r1-1, columns c0..c1-1
        of the BGR ``image`` with OpenCV's bilinear remap's values (or None: OpenCV remaps
        it), for :meth:`lab`'s blocks (the fused method's table remap)."""
        self._colour_remap = remap

    def use_uncovered(self, uncovered: Uncovered | None) -> None:
        """``uncovered(boxes, r0, r1, c0, c1)``: :func:`uncovered_pieces`' answers, faster
        (the fused method's C accelerator), for :meth:`lab`'s held blocks (None: the Python
        function)."""
        self._uncovered = uncovered if uncovered is not None else uncovered_pieces

    def input_rows(self, rows: int) -> int:
        """How many of the input image's top rows the view's first ``rows`` rows read."""
        n = max(1, min(int(rows), self.out.shape[0]))
        return int(self._src_rows[n - 1])

    def warp(
        self,
        image: npt.NDArray[Any],
        rows: int | None = None,
        remap: Callable[[npt.NDArray[Any], npt.NDArray[np.uint8]], None] | None = None,
    ) -> npt.NDArray[np.uint8]:
        """Input frame (BGR or grey) to this view's grey image (a reused buffer).

        ``rows`` limits the work to the view's top rows when only they are needed.
        ``remap(grey, out)``, when given, fills ``out`` (the view's top rows) from the grey
        frame with OpenCV's values (the fused method's faster one); else OpenCV remaps.
        """
        n = self.out.shape[0] if rows is None else max(1, min(int(rows), self.out.shape[0]))
        if image.ndim == 3:
            k = self._src_rows[n - 1]
            src = cv2.cvtColor(image[:k], cv2.COLOR_BGR2GRAY, dst=self.grey[:k])
        else:
            src = image
        if remap is not None:
            remap(src, self.out[:n])
            return self.out[:n]
        cv2.remap(
            src,
            self.map1[:n],
            self.map2[:n],
            cv2.INTER_LINEAR,
            dst=self.out[:n],
            borderMode=cv2.BORDER_REPLICATE,
        )
        return self.out[:n]

    def hold_colour(self, image: npt.NDArray[Any] | None) -> None:
        """Keep the CIE Lab blocks :meth:`lab` converts from the BGR frame ``image`` until
        the next call, which forgets them (None, or a grey frame: hold none).

        The fused method's colour stages read a dozen blocks of one frame, half of them
        inside one read before (the top's rows across the image, then the top's rows
        between the sides; a side's strips, then the middle rows of those): such a block
        is taken from the one read before, not converted again. The frame must not change
        while it is held. (Held: packed 8-bit BGR frames, whose blocks are remapped and
        converted in the held buffer; others are converted block by block.)"""
        packed = (
            image is not None
            and image.ndim == 3
            and image.shape[2] == 3
            and image.dtype == np.uint8
        )
        self._held = image if packed else None
        self._lab_boxes = []
        if self._held is not None and self._lab is None:
            self._lab = np.empty((*self.out.shape, 3), np.uint8)
            # the blocks handed out are slices of a read-only view (the frame's cache: a
            # write would spoil it), made once rather than per block
            self._lab_read = self._lab.view()
            self._lab_read.flags.writeable = False

    def lab(
        self,
        image: npt.NDArray[Any],
        r0: int,
        r1: int,
        c0: int = 0,
        c1: int | None = None,
        step: int = 1,
    ) -> npt.NDArray[np.uint8]:
        """The view's rows r0..r1-1 (columns c0..c1-1, every ``step``-th; numpy's slices of
        the view) of the BGR ``image`` in CIE Lab, 8-bit: only the pixels read are
        undistorted and converted.

        Of a held frame (:meth:`hold_colour`), a block is a view of the frame's Lab pixels,
        to be read only, of which only the parts blocks before did not cover are converted
        (in place there): each pixel is the bilinear remap and the
        conversion of its own map entry, whatever block it is converted in, so the values
        are the same either way."""
        rows, cols = slice(r0, r1, step), slice(c0, c1, step)
        lab, read = self._lab, self._lab_read
        if image is not self._held or step != 1 or lab is None or read is None:
            return self._to_lab(image, rows, cols)
        h, w = self.out.shape
        ra, rb, _ = rows.indices(h)
        ca, cb, _ = cols.indices(w)
        if ra >= rb or ca >= cb:
            return self._to_lab(image, rows, cols)  # OpenCV's answer to an empty block
        pieces = self._uncovered(self._lab_boxes, ra, rb, ca, cb)
        if pieces is None:  # inside one block before
            return read[ra:rb, ca:cb]
        # each piece remapped and converted in place in the frame's Lab buffer (no block
        # of its own to copy in: the same values)
        for p0, p1, q0, q1 in pieces:
            self._lab_into(image, lab[p0:p1, q0:q1], p0, p1, q0, q1)
        if pieces:
            self._lab_boxes.append((ra, rb, ca, cb))  # whole now: a block inside it is one test
        return read[ra:rb, ca:cb]  # read only: the frame's cache, a write would spoil it

    def _lab_into(
        self,
        image: npt.NDArray[Any],
        out: npt.NDArray[np.uint8],
        r0: int,
        r1: int,
        c0: int,
        c1: int,
    ) -> None:
        """:meth:`_to_lab` of the non-empty view block r0..r1-1, c0..c1-1 into ``out`` (a
        view of its shape, rows of packed pixels): remapped into it, converted in place
        (Lab of a pixel is its own BGR's: in place or not, the same values)."""
        if self._colour_remap is None or self._colour_remap(image, r0, r1, c0, c1, out) is None:
            cv2.remap(
                image,
                self.map1[r0:r1, c0:c1],
                self.map2[r0:r1, c0:c1],
                cv2.INTER_LINEAR,
                dst=out,
                borderMode=cv2.BORDER_REPLICATE,
            )
        cv2.cvtColor(out, cv2.COLOR_BGR2LAB, dst=out)

    def _to_lab(self, image: npt.NDArray[Any], rows: slice, cols: slice) -> npt.NDArray[np.uint8]:
        """The view block (rows, cols) of the BGR ``image``, undistorted and in CIE Lab."""
        band: npt.NDArray[Any] | None = None
        if self._colour_remap is not None and rows.step in (None, 1) and cols.step in (None, 1):
            h, w = self.out.shape
            ra, rb, _ = rows.indices(h)
            ca, cb, _ = cols.indices(w)
            if ra < rb and ca < cb:
                band = self._colour_remap(image, ra, rb, ca, cb)
        if band is None:
            band = cv2.remap(
                image,
                self.map1[rows, cols],
                self.map2[rows, cols],
                cv2.INTER_LINEAR,
                borderMode=cv2.BORDER_REPLICATE,
            )
        return np.asarray(cv2.cvtColor(band, cv2.COLOR_BGR2LAB))

    def unseen_sides(self, corners: npt.ArrayLike, margin: float = UNSEEN_MARGIN_PX) -> list[str]:
        """The sides of a face (view corners bottom-left, bottom-right, top-right,
        top-left) that come within ``margin`` px of what this view does not see: past its
        own borders, or where it maps outside the input image (an undistorted, levelled
        view loses the input's corners and a few columns at its edges, so a face running
        off the image ends in the view short of the image's border). The face may run on
        out there: its size across that side is a lower bound."""
        c = np.asarray(corners, dtype=np.float64).reshape(4, 2)
        if not np.isfinite(c).all():
            return []  # no outline to place (the refinement's fits failed)
        (blx, bly), (brx, bry), (trx, try_), (tlx, tly) = c.tolist()
        map1 = self.map1
        h, w = map1.shape[:2]
        w_in, h_in = self.camera.size
        unseen = []
        # per side: its samples start + t (end - start), moved out by the margin (the same
        # float operations, point by point, as in numpy), each in sight of the view or not
        for name, (sx, sy), (ex, ey), (dx, dy) in (
            ("left", (blx, bly), (tlx, tly), (-margin, 0.0)),
            ("right", (brx, bry), (trx, try_), (margin, 0.0)),
            ("top", (tlx, tly), (trx, try_), (0.0, -margin)),
            ("bottom", (blx, bly), (brx, bry), (0.0, margin)),
        ):
            ax, ay = ex - sx, ey - sy
            for t in _SIDE_T_LIST:
                # the pixel the point lies in: a margin of exactly ``margin`` either way
                u = math.floor(sx + t * ax + dx)
                v = math.floor(sy + t * ay + dy)
                if not (0 <= u < w and 0 <= v < h):
                    break
                # the input pixel (integer part) the point reads
                x_in, y_in = map1.item(v, u, 0), map1.item(v, u, 1)
                if not (0 <= x_in < w_in and 0 <= y_in < h_in):
                    break
            else:
                continue
            unseen.append(name)
        return unseen

    def to_input(self, pts: npt.ArrayLike) -> FloatArray:
        """View pixels (N x 2) back to input-image pixels (through the lens distortion)."""
        p = np.asarray(pts, dtype=np.float64).reshape(-1, 2)
        rays = np.empty((len(p), 3))  # np.stack's columns, filled without its wrapper
        np.divide(p[:, 0] - self.cx, self.fx, out=rays[:, 0])
        np.divide(p[:, 1] - self.cy, self.fy, out=rays[:, 1])
        rays[:, 2] = 1.0
        cam = rays @ self.rotation  # R^T applied to row vectors: level -> camera frame
        return self.camera.project(cam)


class Method(Protocol):
    """What the registry in :mod:`obstacle_fusion.vision.measure` holds: one way to measure."""

    name: str

    def run(self, image: npt.NDArray[Any], range_m: float, timer: Timer) -> Measurement: ...
