"""Frame sources backed by OpenCV: a camera, a video file, a folder of images.

Each is a :class:`~obstacle_fusion.sources.frames.FrameSource` stamping frames on the host's
monotonic clock; :func:`open_source` picks one from a user's ``--camera`` argument.
"""

from __future__ import annotations

import logging
import math
import re
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from obstacle_fusion.sources.frames import Clock, Frame, FrameSource, Sleep, SourceError

log = logging.getLogger(__name__)

IMAGE_EXTENSIONS = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".webp", ".ppm", ".pgm")


# ---------------------------------------------------------------------------- camera


class _QuietOpenCV:
    """Silence OpenCV's own log lines while probing a device or decoding a file; we report
    our own, clearer error (a corrupt PNG otherwise prints OpenCV's ERROR line first)."""

    def __enter__(self) -> None:
        self._level = cv2.utils.logging.getLogLevel()
        cv2.utils.logging.setLogLevel(cv2.utils.logging.LOG_LEVEL_SILENT)

    def __exit__(self, *exc: object) -> None:
        cv2.utils.logging.setLogLevel(self._level)


def _camera_help(device: int | str, problem: str | None = None) -> str:
    lead = problem or f"cannot open camera {device!r}"
    return (
        f"{lead}. Try: `ls /dev/video*` or `v4l2-ctl --list-devices` "
        "to see which cameras exist; another index (0 is usually the built-in one); close "
        "other programs using the camera; on Linux, check you may read it (the 'video' group)"
    )


class CameraSource(FrameSource):
    """A live camera through cv2.VideoCapture.

    ``latency_s`` is the time from exposure to the frame being readable (USB webcams:
    typically 30-100 ms); it is subtracted from the read time. ``width``/``height``/``fps``
    are requests; the camera may choose otherwise (logged; ``size``/``nominal_fps`` tell).
    """

    #: Consecutive failed reads, or seconds of them, after which the camera is taken as gone.
    MAX_CONSECUTIVE_FAILURES = 30
    MAX_FAILING_S = 5.0

    def __init__(
        self,
        device: int | str = 0,
        *,
        width: int | None = None,
        height: int | None = None,
        fps: float | None = None,
        latency_s: float = 0.0,
        fourcc: str | None = None,
        api_preference: int = cv2.CAP_ANY,
        clock: Clock = time.monotonic,
        sleep: Sleep = time.sleep,
    ) -> None:
        if isinstance(device, str) and device.strip().isdigit():
            device = int(device.strip())
        super().__init__(f"camera:{device}", clock=clock)
        if not math.isfinite(latency_s) or latency_s < 0:
            raise SourceError(f"camera latency must be >= 0 s, got {latency_s}")
        if isinstance(device, int) and device < 0:
            raise SourceError(f"camera index must be >= 0, got {device}")
        if isinstance(device, str) and device.startswith("/dev/") and not Path(device).exists():
            raise SourceError(_camera_help(device, f"camera device {device} does not exist"))
        self.device = device
        self.latency_s = float(latency_s)
        self._consecutive_failures = 0
        self._failing_since = 0.0
        self._sleep = sleep
        with _QuietOpenCV():
            try:
                cap = cv2.VideoCapture(device, api_preference)
            except cv2.error as exc:
                raise SourceError(_camera_help(device) + f" (OpenCV: {exc})") from None
            if not cap.isOpened():
                cap.release()
                raise SourceError(_camera_help(device))
        self._cap = cap
        if fourcc is not None:
            if len(fourcc) != 4:
                cap.release()
                raise SourceError(f"fourcc must be 4 characters such as MJPG, got {fourcc!r}")
            cap.set(cv2.CAP_PROP_FOURCC, cv2.VideoWriter.fourcc(*fourcc))
        if width is not None:
            cap.set(cv2.CAP_PROP_FRAME_WIDTH, width)
        if height is not None:
            cap.set(cv2.CAP_PROP_FRAME_HEIGHT, height)
        if fps is not None:
            cap.set(cv2.CAP_PROP_FPS, fps)
        # A deep driver queue would hand us old frames stamped as new: keep it short.
        cap.set(cv2.CAP_PROP_BUFFERSIZE, 1)
        got = self.size
        if (width is not None and got[0] != width) or (height is not None and got[1] != height):
            log.warning("%s: asked for %sx%s, camera gives %dx%d", self.name, width, height, *got)
        if fps is not None and self.nominal_fps and abs(self.nominal_fps - fps) > 0.5:
            log.warning("%s: asked for %g fps, camera gives %g", self.name, fps, self.nominal_fps)

    @property
    def size(self) -> tuple[int, int]:
        return (
            int(self._cap.get(cv2.CAP_PROP_FRAME_WIDTH)),
            int(self._cap.get(cv2.CAP_PROP_FRAME_HEIGHT)),
        )

    @property
    def nominal_fps(self) -> float | None:
        fps = float(self._cap.get(cv2.CAP_PROP_FPS))
        return fps if math.isfinite(fps) and fps > 0 else None

    def _capture(self) -> Frame | None:
        while True:
            # grab() returns once a frame is in hand: stamp then, decode after.
            ok = self._cap.grab()
            t_read = self.clock()
            image = None
            if ok:
                ok, image = self._cap.retrieve()
            if ok and image is not None:
                self._consecutive_failures = 0
                return self._frame(image, t_read - self.latency_s)
            self.stats.read_failures += 1
            self._consecutive_failures += 1
            if self._consecutive_failures == 1:
                self._failing_since = t_read
            if (
                self._consecutive_failures >= self.MAX_CONSECUTIVE_FAILURES
                or t_read - self._failing_since > self.MAX_FAILING_S
            ):
                self.end_reason = (
                    f"camera {self.device!r} gave no frame in {self._consecutive_failures} "
                    "tries in a row (unplugged or taken by another program?)"
                )
                log.error("%s: %s", self.name, self.end_reason)
                return None
            self._sleep(0.01)  # a USB hiccup gets a moment to recover

    def _release(self) -> None:
        self._cap.release()


# ---------------------------------------------------------------------------- files


class _Timeline:
    """Frame k of a recording is stamped start + k / fps; optionally paced to real time."""

    def __init__(
        self, fps: float, start: float | None, realtime: bool, clock: Clock, sleep: Sleep
    ) -> None:
        self.fps = fps
        self.start = clock() if start is None else float(start)
        self.realtime = realtime
        self.clock = clock
        self.sleep = sleep

    def stamp(self, position: int) -> float:
        t = self.start + position / self.fps
        if self.realtime:
            wait = t - self.clock()
            if wait > 0:
                self.sleep(wait)
        return t


def _check_fps(fps: float | None, what: str) -> float | None:
    if fps is None:
        return None
    if not math.isfinite(fps) or fps <= 0:
        raise SourceError(f"{what}: frame rate must be a positive number, got {fps}")
    return float(fps)


class VideoFileSource(FrameSource):
    """A video file; frame k is stamped ``start_time + k / fps`` on the host clock.

    ``start_time`` defaults to the moment of opening. ``realtime=True`` also waits until
    each frame's stamp before delivering it, so the file plays like a live camera.
    ``fps`` overrides the rate the file declares (needed when it declares none).
    """

    #: Unreadable frames in a row after which the rest of the file is taken as lost.
    MAX_CONSECUTIVE_BAD = 10

    def __init__(
        self,
        path: str | Path,
        *,
        fps: float | None = None,
        realtime: bool = False,
        start_time: float | None = None,
        clock: Clock = time.monotonic,
        sleep: Sleep = time.sleep,
    ) -> None:
        p = Path(path)
        super().__init__(f"video:{p.name}", clock=clock)
        if not p.exists():
            raise SourceError(f"video file {p} does not exist")
        if p.is_dir():
            raise SourceError(f"{p} is a folder; for a folder of images use an image source")
        fps = _check_fps(fps, str(p))
        with _QuietOpenCV():
            cap = cv2.VideoCapture(str(p))
        if not cap.isOpened():
            cap.release()
            raise SourceError(
                f"cannot open video {p}: not a video OpenCV can decode (corrupt, empty or "
                "an unsupported codec); try re-encoding it, e.g. `ffmpeg -i IN -c:v mjpeg OUT.avi`"
            )
        self.path = p
        self._cap = cap
        declared = float(cap.get(cv2.CAP_PROP_FPS))
        if fps is None:
            if not (math.isfinite(declared) and 0 < declared < 10000):
                cap.release()
                raise SourceError(f"video {p} declares no frame rate; give one (fps=...)")
            fps = declared
        self._fps = fps
        count = int(cap.get(cv2.CAP_PROP_FRAME_COUNT))
        self.frame_count: int | None = count if count > 0 else None
        self._timeline = _Timeline(fps, start_time, realtime, clock, sleep)
        self._position = 0

    @property
    def nominal_fps(self) -> float:
        return self._fps

    @property
    def start_time(self) -> float:
        return self._timeline.start

    def _capture(self) -> Frame | None:
        bad = 0
        while True:
            ok, image = self._cap.read()
            position = self._position
            self._position += 1
            if ok and image is not None:
                return self._frame(image, self._timeline.stamp(position), position)
            more = self.frame_count is not None and position < self.frame_count - 1
            if not more:
                if self.stats.delivered == 0:
                    # Opened but nothing decodes (a lone image, a broken file): say so.
                    self.end_reason = f"no frame of {self.path} could be decoded"
                    log.error("%s: %s", self.name, self.end_reason)
                return None
            bad += 1
            self._skip(f"frame {position}", "could not be decoded")
            if bad >= self.MAX_CONSECUTIVE_BAD:
                self.end_reason = f"{bad} unreadable frames in a row at frame {position}"
                log.error("%s: %s; stopping", self.name, self.end_reason)
                return None

    def _release(self) -> None:
        self._cap.release()


def _natural_key(path: Path) -> list[Any]:
    """frame2 before frame10, as a person numbers files."""
    return [int(part) if part.isdigit() else part.lower() for part in re.split(r"(\d+)", path.name)]


class ImageFolderSource(FrameSource):
    """The images of a folder in natural order, at a fixed frame rate.

    Image k (by position in the folder, skipped ones included) is stamped
    ``start_time + k / fps``, so skipping a corrupt file never shifts the others in time.
    """

    def __init__(
        self,
        folder: str | Path,
        *,
        fps: float = 10.0,
        realtime: bool = False,
        start_time: float | None = None,
        extensions: Sequence[str] = IMAGE_EXTENSIONS,
        clock: Clock = time.monotonic,
        sleep: Sleep = time.sleep,
    ) -> None:
        p = Path(folder)
        super().__init__(f"folder:{p.name}", clock=clock)
        if not p.exists():
            raise SourceError(f"image folder {p} does not exist")
        if not p.is_dir():
            raise SourceError(f"{p} is not a folder; for a video file use a video source")
        checked = _check_fps(fps, str(p))
        assert checked is not None
        exts = {e.lower() if e.startswith(".") else "." + e.lower() for e in extensions}
        self.paths = sorted(
            (f for f in p.iterdir() if f.is_file() and f.suffix.lower() in exts), key=_natural_key
        )
        if not self.paths:
            raise SourceError(f"no images in {p} (looked for {', '.join(sorted(exts))})")
        self.folder = p
        self._fps = checked
        self._timeline = _Timeline(checked, start_time, realtime, clock, sleep)
        self._position = 0

    @property
    def nominal_fps(self) -> float:
        return self._fps

    @property
    def start_time(self) -> float:
        return self._timeline.start

    def _capture(self) -> Frame | None:
        while self._position < len(self.paths):
            position = self._position
            path = self.paths[position]
            self._position += 1
            try:
                data = np.fromfile(path, dtype=np.uint8)
            except OSError as exc:
                self._skip(path.name, f"cannot read it ({exc.strerror or exc})")
                continue
            with _QuietOpenCV():
                image = cv2.imdecode(data, cv2.IMREAD_COLOR) if data.size else None
            if image is None:
                self._skip(path.name, "not a readable image (empty, corrupt or unknown format)")
                continue
            return self._frame(image, self._timeline.stamp(position), position)
        return None


# ---------------------------------------------------------------------------- factory


def open_source(
    spec: str | int,
    *,
    width: int | None = None,
    height: int | None = None,
    fps: float | None = None,
    latency_s: float = 0.0,
    realtime: bool = False,
    clock: Clock = time.monotonic,
) -> FrameSource:
    """A source from a command-line value: a camera index or /dev path, a video, a folder."""
    if isinstance(spec, int) or str(spec).strip().isdigit():
        return CameraSource(
            int(spec), width=width, height=height, fps=fps, latency_s=latency_s, clock=clock
        )
    text = str(spec)
    path = Path(text)
    if text.startswith("/dev/") or "://" in text:  # a device, or a network stream
        return CameraSource(
            text, width=width, height=height, fps=fps, latency_s=latency_s, clock=clock
        )
    if path.is_dir():
        return ImageFolderSource(path, fps=fps or 10.0, realtime=realtime, clock=clock)
    if path.is_file():
        if path.suffix.lower() in IMAGE_EXTENSIONS:
            raise SourceError(
                f"{path} is a single image, not a stream: put the images in a folder and "
                "give the folder (they play in name order), or measure one photo with "
                "`obstacle-fusion measure`"
            )
        return VideoFileSource(path, fps=fps, realtime=realtime, clock=clock)
    missing = f"{text} does not exist; " if (path.suffix or "/" in text) else ""
    raise SourceError(
        f"{missing}{text!r} is not a camera index, a /dev/video device, a video file or an "
        "image folder"
    )
