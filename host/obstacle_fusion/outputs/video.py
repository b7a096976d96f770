"""An annotated video of the run: the frame, the obstacle's box and the fused numbers.

``.mp4`` (and ``.m4v``, ``.mov``, ``.mkv``) is H.264 (libx264 through PyAV, whose wheels
bundle FFmpeg with it; the ``video`` extra), yuv420p, ``+faststart``: what browsers and
Foxglove play. A frame of odd width or height gets one replicated column/row (H.264 in
4:2:0 needs even sides). ``.avi`` stays Motion-JPEG through OpenCV.

The overlay is drawn for a 500x375 frame at least: Hershey simplex with capitals about
17 px high, a 2 px stroke and a clear column between glyphs, on a dark band (scaled up
with bigger frames).
"""

from __future__ import annotations

import logging
import queue
import threading
from fractions import Fraction
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.errors import UserError
from obstacle_fusion.fusion import ObstacleRecord

log = logging.getLogger(__name__)

H264_SUFFIXES = (".mp4", ".m4v", ".mov", ".mkv")
MJPEG_SUFFIXES = (".avi",)

#: Overlay font at a 500x375 frame; the glyph height the test holds it to is >= 14 px.
FONT = cv2.FONT_HERSHEY_SIMPLEX
FONT_SCALE = 0.8
FONT_THICKNESS = 2
LINE_STEP_PX = 26
BASE_SIZE = (500, 375)


def _colour(record: ObstacleRecord) -> tuple[int, int, int]:
    if record.alert:
        return (0, 0, 255)
    return (0, 200, 0) if record.status == "ok" else (0, 200, 255)


def overlay_lines(record: ObstacleRecord) -> list[str]:
    lines = [f"{record.status}{'  STOP' if record.alert else ''}"]
    if record.distance_m is not None:
        lines.append(f"L {record.distance_m:.3f} m")
    if record.height_m is not None and record.width_m is not None:
        lines.append(f"H {record.height_m:.3f} m  W {record.width_m:.3f} m")
    return lines


def annotate(image: npt.NDArray[np.uint8], record: ObstacleRecord) -> npt.NDArray[np.uint8]:
    """A copy of the frame with the box, the chosen edges and the numbers drawn on it."""
    out = image.copy()
    colour = _colour(record)
    if record.box_px is not None:
        x0, y0, x1, y1 = (int(round(v)) for v in record.box_px)
        cv2.rectangle(out, (x0, y0), (x1, y1), colour, 2)
    for ax, ay, bx, by in record.edges_px:
        p0 = (int(round(ax * 16)), int(round(ay * 16)))
        p1 = (int(round(bx * 16)), int(round(by * 16)))
        cv2.line(out, p0, p1, (0, 255, 255), 1, cv2.LINE_AA, 4)
    lines = overlay_lines(record)
    k = max(1.0, min(out.shape[1] / BASE_SIZE[0], out.shape[0] / BASE_SIZE[1]))
    scale, thick, step = FONT_SCALE * k, max(1, round(FONT_THICKNESS * k)), LINE_STEP_PX * k
    width = max(cv2.getTextSize(t, FONT, scale, thick)[0][0] for t in lines)
    band = out[0 : int(step * len(lines) + 8 * k), 0 : int(width + 16 * k)]
    band[:] = (band * 0.35).astype(np.uint8)  # darken behind the text: readable on any scene
    for i, text in enumerate(lines):
        org = (int(8 * k), int(step * (i + 1)))
        cv2.putText(out, text, org, FONT, scale, colour, thick, cv2.LINE_AA)
    return out


def check_video_path(path: Path) -> None:
    """Refuse an output the writer cannot make, before the run starts."""
    suffix = path.suffix.lower()
    if suffix not in H264_SUFFIXES + MJPEG_SUFFIXES:
        raise UserError(
            f"video output {path}: unknown extension; use one of "
            f"{', '.join(H264_SUFFIXES + MJPEG_SUFFIXES)}"
        )
    if not path.parent.exists():
        raise UserError(f"video output {path}: folder {path.parent} does not exist")
    if suffix in H264_SUFFIXES:
        _require_av()


def _require_av() -> Any:
    try:
        import av
    except ImportError:
        raise UserError(
            "--video with H.264 needs PyAV: pip install 'obstacle-fusion[video]' (make setup "
            "installs it), or write an .avi (Motion-JPEG through OpenCV)"
        ) from None
    return av


class _H264Writer:
    def __init__(self, path: Path, fps: float, size: tuple[int, int]) -> None:
        av = _require_av()
        self.size = size
        try:
            self.container = av.open(
                str(path), mode="w", container_options={"movflags": "+faststart"}
            )
            rate = Fraction(fps).limit_denominator(1001)
            self.stream = self.container.add_stream("libx264", rate=rate)
        except Exception as exc:  # PyAV/FFmpeg errors: no encoder, cannot open the file
            raise UserError(f"cannot write video {path} (H.264): {exc}") from None
        self.stream.width, self.stream.height = size
        self.stream.pix_fmt = "yuv420p"
        self.stream.codec_context.time_base = Fraction(1, 1) / rate
        # zerolatency: no lookahead, so no frame ever waits (and no stall) inside the encoder
        self.stream.options = {"crf": "23", "preset": "veryfast", "tune": "zerolatency"}
        self._av = av
        self._pts = 0

    def write(self, bgr: npt.NDArray[np.uint8]) -> None:
        frame = self._av.VideoFrame.from_ndarray(np.ascontiguousarray(bgr), format="bgr24")
        frame.pts = self._pts
        self._pts += 1
        for packet in self.stream.encode(frame):
            self.container.mux(packet)

    def close(self) -> None:
        try:
            for packet in self.stream.encode():
                self.container.mux(packet)
        finally:
            self.container.close()


class AnnotatedVideoWriter:
    """Opens on the first frame (its size decides the video's); frames of another size are
    resized so one odd frame never ends the video.

    Drawing and encoding run on a thread of their own (``threaded``, the default), so the
    encoder's start-up and its occasional slow frame never hold up the live loop; a bounded
    queue (``queue_frames``) makes a writer that falls far behind slow the loop down rather
    than lose frames. An encoder error is raised by the next write() or by close()."""

    def __init__(
        self,
        path: str | Path,
        fps: float = 15.0,
        *,
        overwrite: bool = False,
        threaded: bool = True,
        queue_frames: int = 64,
    ) -> None:
        self.path = Path(path)
        if self.path.exists() and not overwrite:
            raise UserError(
                f"video output {self.path} already exists; give another name, or --overwrite "
                "to replace it"
            )
        check_video_path(self.path)
        self.codec = "h264" if self.path.suffix.lower() in H264_SUFFIXES else "mjpeg"
        self.fps = fps
        self._writer: Any = None
        self._size: tuple[int, int] | None = None  # the input frames' (w, h)
        self.frames = 0
        self._error: BaseException | None = None
        self._closed = False
        self._queue: queue.Queue[tuple[npt.NDArray[np.uint8], ObstacleRecord] | None] | None = None
        self._thread: threading.Thread | None = None
        if threaded:
            self._queue = queue.Queue(maxsize=queue_frames)
            self._thread = threading.Thread(target=self._work, name="video-writer", daemon=True)
            self._thread.start()

    def _open(self, w: int, h: int) -> None:
        if self.codec == "h264":
            self._writer = _H264Writer(self.path, self.fps, (w + w % 2, h + h % 2))
        else:
            writer = cv2.VideoWriter(
                str(self.path), cv2.VideoWriter.fourcc(*"MJPG"), self.fps, (w, h)
            )
            if not writer.isOpened():
                raise UserError(f"cannot write video {self.path} (codec MJPG)")
            self._writer = writer
        self._size = (w, h)

    def _work(self) -> None:
        assert self._queue is not None
        while True:
            item = self._queue.get()
            if item is None:
                return
            if self._error is not None:
                continue  # drain: the error is reported once, by write() or close()
            try:
                self._encode(*item)
            except BaseException as exc:
                self._error = exc

    def _raise_error(self) -> None:
        if self._error is not None:
            exc, self._error = self._error, None
            if isinstance(exc, UserError):
                raise exc
            raise UserError(f"writing video {self.path} failed: {exc}") from exc

    def write(self, image: npt.NDArray[np.uint8], record: ObstacleRecord) -> None:
        self._raise_error()
        if self._closed:
            return
        if self._queue is None:
            self._encode(image, record)
        else:
            self._queue.put((image, record))

    def _encode(self, image: npt.NDArray[np.uint8], record: ObstacleRecord) -> None:
        h, w = image.shape[:2]
        if self._writer is None:
            self._open(w, h)
        assert self._size is not None
        frame = annotate(image, record)
        if self._size != (w, h):
            frame = np.asarray(cv2.resize(frame, self._size), np.uint8)
        if self.codec == "h264":
            pw, ph = self._size[0] % 2, self._size[1] % 2
            if pw or ph:
                frame = np.asarray(
                    cv2.copyMakeBorder(frame, 0, ph, 0, pw, cv2.BORDER_REPLICATE), np.uint8
                )
        self._writer.write(frame)
        self.frames += 1

    def close(self) -> None:
        """Write what is queued, finish the file; raise a pending encoder error."""
        self._closed = True
        if self._thread is not None and self._queue is not None:
            self._queue.put(None)
            self._thread.join()
            self._thread = None
        try:
            if self._writer is not None:
                writer, self._writer = self._writer, None
                if isinstance(writer, _H264Writer):
                    writer.close()
                else:
                    writer.release()
        finally:
            self._raise_error()
