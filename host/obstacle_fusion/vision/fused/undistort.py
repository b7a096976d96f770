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
try:  # the optional C accelerator (setup.py)
    from obstacle_fusion.vision.fused._cmiddle import remap_table as _c_remap_table
except ImportError:  # pragma: no cover - only where the extension did not build
    _c_remap_table = None

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
