"""An annotated video of the run: the frame, the obstacle's box and the fused numbers."""

from __future__ import annotations

import logging
from pathlib import Path

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.errors import UserError
from obstacle_fusion.fusion import ObstacleRecord

log = logging.getLogger(__name__)

_FOURCC = {".mp4": "mp4v", ".m4v": "mp4v", ".avi": "MJPG", ".mkv": "mp4v", ".mov": "mp4v"}


def annotate(image: npt.NDArray[np.uint8], record: ObstacleRecord) -> npt.NDArray[np.uint8]:
    """A copy of the frame with the box and the numbers drawn on it."""
    out = image.copy()
    colour = (
        (0, 0, 255) if record.alert else ((0, 200, 0) if record.status == "ok" else (0, 200, 255))
    )
    if record.box_px is not None:
        x0, y0, x1, y1 = (int(round(v)) for v in record.box_px)
        cv2.rectangle(out, (x0, y0), (x1, y1), colour, 2)
    lines = [f"{record.status}{'  STOP' if record.alert else ''}"]
    if record.distance_m is not None:
        lines.append(f"L {record.distance_m:.3f} m")
    if record.height_m is not None and record.width_m is not None:
        lines.append(f"H {record.height_m:.3f} m  W {record.width_m:.3f} m")
    scale = max(out.shape[1] / 900.0, 0.4)
    for i, text in enumerate(lines):
        y = int((i + 1) * 24 * scale) + 4
        cv2.putText(
            out, text, (6, y), cv2.FONT_HERSHEY_SIMPLEX, 0.6 * scale, (0, 0, 0), 3, cv2.LINE_AA
        )
        cv2.putText(
            out, text, (6, y), cv2.FONT_HERSHEY_SIMPLEX, 0.6 * scale, colour, 1, cv2.LINE_AA
        )
    return out


class AnnotatedVideoWriter:
    """Opens on the first frame (its size decides the video's); frames of another size are
    resized so one odd frame never ends the video."""

    def __init__(self, path: str | Path, fps: float = 15.0, *, overwrite: bool = False) -> None:
        self.path = Path(path)
        if self.path.exists() and not overwrite:
            raise UserError(
                f"video output {self.path} already exists; give another name, or --overwrite "
                "to replace it"
            )
        fourcc = _FOURCC.get(self.path.suffix.lower())
        if fourcc is None:
            raise UserError(
                f"video output {self.path}: unknown extension; use one of {', '.join(_FOURCC)}"
            )
        if not self.path.parent.exists():
            raise UserError(f"video output {self.path}: folder {self.path.parent} does not exist")
        self.fourcc = fourcc
        self.fps = fps
        self._writer: cv2.VideoWriter | None = None
        self._size: tuple[int, int] | None = None
        self.frames = 0

    def write(self, image: npt.NDArray[np.uint8], record: ObstacleRecord) -> None:
        h, w = image.shape[:2]
        if self._writer is None:
            writer = cv2.VideoWriter(
                str(self.path), cv2.VideoWriter.fourcc(*self.fourcc), self.fps, (w, h)
            )
            if not writer.isOpened():
                raise UserError(f"cannot write video {self.path} (codec {self.fourcc})")
            self._writer = writer
            self._size = (w, h)
        frame = annotate(image, record)
        if self._size != (w, h):
            frame = np.asarray(cv2.resize(frame, self._size), np.uint8)
        self._writer.write(frame)
        self.frames += 1

    def close(self) -> None:
        if self._writer is not None:
            self._writer.release()
            self._writer = None
