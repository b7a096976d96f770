"""The levelled grey view's remap, from a table made once per view (in C where built).

Receives the view (its OpenCV maps) and a grey frame; fills the view's top rows exactly as
``cv2.remap(src, map1, map2, INTER_LINEAR, borderMode=BORDER_REPLICATE)`` does. OpenCV's
bilinear remap costs ~39 instructions a pixel here and was the largest single cost of a
frame (~5 M of ~35 M); from a table of per-pixel source offsets and weights (the maps
decoded once, border pixels folded in) the optional C accelerator takes ~19, with the same
integers. Without the accelerator, or for a frame it cannot take (another size, pixels not
packed, rows cut short above what the view reads), OpenCV remaps as before.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.types import View

_c_remap_table: Callable[[Any, int, Any, Any, Any, Any], None] | None
_c_remap_table3: Callable[[Any, Any, Any, Any, int, int, Any], None] | None
try:  # the optional C accelerator (setup.py)
    from obstacle_fusion.vision.fused._cmiddle import remap_table as _c_remap_table
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_remap_table = None
try:  # (apart: an accelerator built before the colour remap still remaps the grey view)
    from obstacle_fusion.vision.fused._cmiddle import remap_table3 as _c_remap_table3
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_remap_table3 = None

#: Weights of OpenCV's fixed-point maps: 32nds of a pixel (INTER_BITS = 5).
TAB_BITS = 5

#: The largest byte offset a table holds (int32).
MAX_TABLE_OFFSET = int(np.iinfo(np.int32).max)

Table = tuple[npt.NDArray[np.int32], npt.NDArray[np.int16], npt.NDArray[np.int16]]


def _axis(at: npt.NDArray[Any], frac: npt.NDArray[Any], n: int) -> tuple[Any, Any]:
    """One axis of the table: the first of the two pixels read (inside 0..n-2) and the
    weight of the second, in 32nds. Where OpenCV's replicated border makes both pixels the
    same (the pair starts past an edge), all the weight goes on that one pixel: weight 0 on
    the second with the first at the edge, or 32 with the first one pixel in."""
    first = np.clip(at, 0, n - 1)
    same = first == np.clip(at + 1, 0, n - 1)
    last = same & (first > n - 2)
    weight = np.where(same, np.where(last, 1 << TAB_BITS, 0), frac)
    return np.where(last, n - 2, first), weight


def remap_table(view: View, stride: int) -> Table:
    """Per view pixel: the byte offset of its top-left source pixel in a frame of the
    camera's size whose rows are ``stride`` bytes apart, and its x and y weights."""
    w, h = view.camera.size
    x = view.map1[..., 0].astype(np.int32)
    y = view.map1[..., 1].astype(np.int32)
    f = view.map2.astype(np.int32) & ((1 << 2 * TAB_BITS) - 1)
    x0, fx = _axis(x, f & ((1 << TAB_BITS) - 1), w)
    y0, fy = _axis(y, f >> TAB_BITS, h)
    offsets = np.ascontiguousarray(y0 * stride + x0, np.int32)
    return offsets, np.ascontiguousarray(fx, np.int16), np.ascontiguousarray(fy, np.int16)


def pair_weights(table: Table) -> tuple[npt.NDArray[np.int32], npt.NDArray[np.int32]]:
    """The table's bilinear weights as products per source pixel pair, two 16-bit halves
    of an int32 each (the C colour remap's): (32 - fx)(32 - fy) | fx (32 - fy) << 16 for
    the top row's pixels, (32 - fx) fy | fx fy << 16 for the bottom row's."""
    fx, fy = table[1].astype(np.int32), table[2].astype(np.int32)
    hx, hy = (1 << TAB_BITS) - fx, (1 << TAB_BITS) - fy
    top = np.ascontiguousarray(hx * hy | (fx * hy) << 16, np.int32)
    bottom = np.ascontiguousarray(hx * fy | (fx * fy) << 16, np.int32)
    return top, bottom


class TableRemap:
    """:meth:`View.warp`'s remap for one view: by the view's table in C (one table per row
    stride of the frames seen), else by OpenCV. ``eager``: the table for packed frames of
    the camera's width is made now, with the rest of the per-size state, not on the first
    frame's clock; otherwise a stride's table is made when a second frame of it comes (a
    table costs ~11 ms of numpy: a view levelled for a pitch tried once, with no rig, is
    remapped by OpenCV and never pays it)."""

    def __init__(self, view: View, eager: bool = True) -> None:
        self.view = view
        self._tables: dict[int, Table] = {}
        self._seen: set[int] = set()  # strides remapped once by OpenCV, no table yet
        # the camera width's table's weights as the colour remap takes them (pair_weights)
        self._weights3: tuple[npt.NDArray[np.int32], npt.NDArray[np.int32]] | None = None
        # the last frame colour_block remapped (it is a packed BGR frame of the camera's
        # size: the next block of it skips the checks) and its table's offsets
        self._packed: npt.NDArray[Any] | None = None
        self._offsets3: npt.NDArray[np.int32] | None = None
        if _c_remap_table is not None and eager:
            self._tables[view.camera.width] = remap_table(view, view.camera.width)

    def _table(self, stride: int) -> Table | None:
        """The table for frames whose rows are ``stride`` bytes apart, or None: not made
        yet (its first frame), or a stride no table can serve."""
        table = self._tables.get(stride)
        if table is not None:
            return table
        w, h = self.view.camera.size
        if stride < w or (h - 2) * stride + w - 2 > MAX_TABLE_OFFSET:
            return None  # rows reversed or overlapping, or offsets past int32
        if stride not in self._seen:
            self._seen.add(stride)
            return None
        table = self._tables[stride] = remap_table(self.view, stride)
        return table

    def colour_block(
        self,
        src: npt.NDArray[Any],
        r0: int,
        r1: int,
        c0: int,
        c1: int,
        out: npt.NDArray[np.uint8] | None = None,
    ) -> npt.NDArray[np.uint8] | None:
        """The view block rows r0..r1-1, columns c0..c1-1 of the packed BGR frame ``src``,
        remapped as OpenCV's bilinear remap does it (the same integers, channel by
        channel), by the table of the camera's width, into ``out`` (rows x columns x 3
        uint8, packed pixels; None: a new array); None where the C accelerator, that
        table or such a frame is missing (the caller remaps with OpenCV)."""
        if src is self._packed and self._weights3 is not None and _c_remap_table3 is not None:
            # the frame checked at the last call (the colour stages' dozens of blocks of
            # one held frame): straight to the C remap
            dst = np.empty((r1 - r0, c1 - c0, 3), np.uint8) if out is None else out
            try:
                _c_remap_table3(src, self._offsets3, *self._weights3, r0, c0, dst)
            except ValueError:  # pragma: no cover - a table not of this frame's view
                return None
            return dst
        w, h = self.view.camera.size
        table = self._tables.get(w)
        if (
            _c_remap_table3 is None
            or table is None
            or src.ndim != 3
            or src.shape[:2] != (h, w)
            or src.shape[2] != 3
            or src.dtype != np.uint8
            or src.strides != (3 * w, 3, 1)
        ):
            return None
        if self._weights3 is None:
            self._weights3 = pair_weights(table)
        dst = np.empty((r1 - r0, c1 - c0, 3), np.uint8) if out is None else out
        try:
            _c_remap_table3(src, table[0], *self._weights3, r0, c0, dst)
        except ValueError:  # pragma: no cover - a table not of this frame's view
            return None
        self._packed, self._offsets3 = src, table[0]
        return dst

    def __call__(self, src: npt.NDArray[Any], dst: npt.NDArray[np.uint8]) -> None:
        """The view's first ``len(dst)`` rows of the grey ``src`` into ``dst``."""
        v = self.view
        n = dst.shape[0]
        w, h = v.camera.size
        if (
            _c_remap_table is not None
            and src.ndim == 2
            and src.dtype == np.uint8
            and src.shape[1] == w
            and 2 <= src.shape[0] <= h
            and src.strides[1] == 1
            and dst.strides[1] == 1
            and n <= v.map1.shape[0]
        ):
            table = self._table(src.strides[0])
            if table is not None:
                off, fx, fy = table
                try:
                    _c_remap_table(src, src.strides[0], off[:n], fx[:n], fy[:n], dst)
                    return
                except ValueError:  # a frame cut short above a row the view reads
                    pass
        cv2.remap(
            src,
            v.map1[:n],
            v.map2[:n],
            cv2.INTER_LINEAR,
            dst=dst,
            borderMode=cv2.BORDER_REPLICATE,
        )
