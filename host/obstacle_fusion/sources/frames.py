"""The frame record and the source base class, free of OpenCV.

Fusion pairs each frame with the echo of the same instant, so a frame carries the time it
was *captured* (time.monotonic() at read minus the camera's latency), never the time some
later stage happened to look at it. Bad images are skipped and counted, never fatal.

To add a source, subclass :class:`FrameSource` and implement ``_capture`` (and ``_release``
if it holds a resource); build each frame with ``self._frame(image, t_host)``.
"""

from __future__ import annotations

import logging
import time
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from types import TracebackType
from typing import Any, Self

import numpy as np
import numpy.typing as npt

from obstacle_fusion.errors import UserError

log = logging.getLogger(__name__)

Clock = Callable[[], float]
Sleep = Callable[[float], None]


class SourceError(UserError):
    """A frame source that cannot be opened or used as asked."""


@dataclass(frozen=True)
class Frame:
    """One image and the host-monotonic instant it was captured."""

    image: npt.NDArray[np.uint8]  # H x W x 3, BGR
    t_host: float  # time.monotonic() seconds at the capture instant
    index: int  # position in the source (camera: frames grabbed; file: frame number)
    source: str  # the source's name, e.g. "camera:0", "video:run.mp4"

    @property
    def width(self) -> int:
        return int(self.image.shape[1])

    @property
    def height(self) -> int:
        return int(self.image.shape[0])


@dataclass
class SourceStats:
    """Counters a live view shows: what was delivered and what was lost."""

    delivered: int = 0
    skipped: int = 0  # unreadable images or frames, passed over with a warning
    read_failures: int = 0  # failed camera reads (retried)
    skipped_names: list[str] = field(default_factory=list)


def as_bgr(image: npt.NDArray[Any]) -> npt.NDArray[np.uint8]:
    """Any 8-bit grey/BGR/BGRA image as 3-channel BGR uint8 (a view when already so)."""
    if image.dtype != np.uint8:
        raise SourceError(f"frames must be 8-bit images, got dtype {image.dtype}")
    if image.ndim == 2:
        return np.repeat(image[:, :, None], 3, axis=2)
    if image.ndim == 3 and image.shape[2] == 3:
        return image
    if image.ndim == 3 and image.shape[2] == 4:
        return np.ascontiguousarray(image[:, :, :3])
    if image.ndim == 3 and image.shape[2] == 1:
        return np.repeat(image, 3, axis=2)
    raise SourceError(f"unsupported image layout {image.shape}")


class FrameSource(ABC):
    """A stream of :class:`Frame` records; iterate it, or call :meth:`read` until None.

    Use it as a context manager (or call :meth:`close`) so devices and files are released.
    """

    def __init__(self, name: str, *, clock: Clock = time.monotonic) -> None:
        self.name = name
        self.clock = clock
        self.stats = SourceStats()
        self.end_reason: str | None = None  # why the stream ended, once it has
        self._closed = False

    # -- for subclasses ------------------------------------------------------------
    @abstractmethod
    def _capture(self) -> Frame | None:
        """The next frame, or None at the end of the stream (set ``end_reason``)."""

    def _release(self) -> None:
        """Free the device or file; called once by :meth:`close`."""
        return None

    def _frame(self, image: npt.NDArray[Any], t_host: float, index: int | None = None) -> Frame:
        """A Frame from an image of this source (converted to BGR uint8 if needed)."""
        return Frame(
            as_bgr(image),
            float(t_host),
            self.stats.delivered if index is None else int(index),
            self.name,
        )

    def _skip(self, what: str, reason: str) -> None:
        self.stats.skipped += 1
        self.stats.skipped_names.append(what)
        log.warning("%s: skipping %s: %s", self.name, what, reason)

    # -- for users -----------------------------------------------------------------
    @property
    def nominal_fps(self) -> float | None:
        """Frame rate the source claims, when it claims one."""
        return None

    @property
    def closed(self) -> bool:
        return self._closed

    def read(self) -> Frame | None:
        """The next frame, or None when the stream has ended."""
        if self._closed:
            raise SourceError(f"{self.name} is closed")
        if self.end_reason is not None:
            return None
        frame = self._capture()
        if frame is None:
            if self.end_reason is None:
                self.end_reason = "end of stream"
            return None
        self.stats.delivered += 1
        return frame

    def __iter__(self) -> Iterator[Frame]:
        while (frame := self.read()) is not None:
            yield frame

    def close(self) -> None:
        if not self._closed:
            self._closed = True
            try:
                self._release()
            finally:
                log.debug("%s closed: %s", self.name, self.stats)

    def __enter__(self) -> Self:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()
