"""Frame sources: timestamps on the host clock, bad images skipped and counted, clean errors."""

from __future__ import annotations

import logging
from pathlib import Path

import cv2
import numpy as np
import pytest
from obstacle_fusion.errors import UserError
from obstacle_fusion.sources.frames import Frame, FrameSource, SourceError
from obstacle_fusion.sources.opencv_sources import (
    CameraSource,
    ImageFolderSource,
    VideoFileSource,
    open_source,
)

pytestmark = pytest.mark.cpu_only

W, H = 160, 120


def _numbered(k: int) -> np.ndarray:
    """A frame whose number k can be read back after lossy compression."""
    img = np.zeros((H, W, 3), np.uint8)
    img[:, :] = (10 * k % 250, 40, 200 - 10 * k % 200)
    cv2.rectangle(img, (8 * k, 20), (8 * k + 15, 60), (255, 255, 255), -1)
    return img


def _number_of(img: np.ndarray) -> int:
    """Recovers k from the white bar's left edge."""
    row = img[40, :, :].min(axis=1)
    return int(np.argmax(row > 200)) // 8


class FakeClock:
    def __init__(self, t: float = 1000.0) -> None:
        self.t = t
        self.sleeps: list[float] = []

    def __call__(self) -> float:
        return self.t

    def sleep(self, dt: float) -> None:
        self.sleeps.append(dt)
        self.t += dt


@pytest.fixture
def video(tmp_path: Path) -> Path:
    path = tmp_path / "clip.avi"
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter.fourcc(*"MJPG"), 20.0, (W, H))
    assert writer.isOpened()
    for k in range(12):
        writer.write(_numbered(k))
    writer.release()
    return path


def test_video_frames_are_stamped_from_the_file_rate(video: Path) -> None:
    clock = FakeClock(500.0)
    with VideoFileSource(video, clock=clock, sleep=clock.sleep) as src:
        assert src.nominal_fps == pytest.approx(20.0)
        frames = list(src)
    assert [f.index for f in frames] == list(range(12))
    assert [_number_of(f.image) for f in frames] == list(range(12))
    np.testing.assert_allclose([f.t_host for f in frames], 500.0 + np.arange(12) / 20.0)
    assert all(f.image.shape == (H, W, 3) and f.image.dtype == np.uint8 for f in frames)
    assert frames[0].source == "video:clip.avi"
    assert clock.sleeps == []  # not paced unless asked
    assert src.stats.delivered == 12 and src.stats.skipped == 0
    assert src.closed


def test_video_realtime_paces_delivery(video: Path) -> None:
    clock = FakeClock(10.0)
    with VideoFileSource(video, realtime=True, clock=clock, sleep=clock.sleep) as src:
        for frame in src:
            # Delivered no earlier than its stamp: the file plays like a live camera.
            assert clock() >= frame.t_host - 1e-9
    assert sum(clock.sleeps) == pytest.approx(11 / 20.0)


def test_video_fps_override_and_start_time(video: Path) -> None:
    with VideoFileSource(video, fps=5.0, start_time=2.0) as src:
        first, second = src.read(), src.read()
    assert first is not None and second is not None
    assert (first.t_host, second.t_host) == (2.0, 2.2)


def test_video_errors(tmp_path: Path, video: Path) -> None:
    with pytest.raises(SourceError, match=r"missing\.avi does not exist"):
        VideoFileSource(tmp_path / "missing.avi")
    junk = tmp_path / "junk.mp4"
    junk.write_bytes(b"\x00\x01 definitely not a video" * 10)
    with pytest.raises(SourceError, match=r"cannot open video .*junk\.mp4"):
        VideoFileSource(junk)
    with pytest.raises(SourceError, match="positive"):
        VideoFileSource(video, fps=0)
    with pytest.raises(SourceError, match="folder"):
        VideoFileSource(tmp_path)


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    d = tmp_path / "frames"
    d.mkdir()
    for k in (1, 2, 10, 3, 5):  # natural order: 1 2 3 4(corrupt) 5 10
        cv2.imwrite(str(d / f"img{k}.png"), _numbered(k))
    (d / "img4.jpg").write_bytes(b"\xff\xd8\xff\xe0 broken jpeg")
    (d / "notes.txt").write_text("not an image, ignored")
    cv2.imwrite(str(d / "img20.png"), cv2.cvtColor(_numbered(6), cv2.COLOR_BGR2GRAY))
    return d


def test_folder_in_natural_order_skips_corrupt_file(
    folder: Path, caplog: pytest.LogCaptureFixture
) -> None:
    clock = FakeClock(100.0)
    with caplog.at_level(logging.WARNING):
        with ImageFolderSource(folder, fps=4.0, clock=clock, sleep=clock.sleep) as src:
            frames = list(src)
    names = [p.name for p in src.paths]
    assert names == [
        "img1.png",
        "img2.png",
        "img3.png",
        "img4.jpg",
        "img5.png",
        "img10.png",
        "img20.png",
    ]
    assert [_number_of(f.image) for f in frames[:5]] == [1, 2, 3, 5, 10]
    # Stamps follow the folder position, so the skipped file leaves a gap, no shift.
    assert [f.index for f in frames] == [0, 1, 2, 4, 5, 6]
    np.testing.assert_allclose([f.t_host for f in frames], 100.0 + np.array([0, 1, 2, 4, 5, 6]) / 4)
    assert frames[-1].image.shape == (H, W, 3)  # grey file delivered as BGR
    assert src.stats.skipped == 1 and src.stats.skipped_names == ["img4.jpg"]
    assert src.stats.delivered == 6
    assert "img4.jpg" in caplog.text


def test_folder_errors(tmp_path: Path) -> None:
    with pytest.raises(SourceError, match="does not exist"):
        ImageFolderSource(tmp_path / "nowhere")
    (tmp_path / "empty").mkdir()
    with pytest.raises(SourceError, match="no images in"):
        ImageFolderSource(tmp_path / "empty")
    (tmp_path / "a.png").write_bytes(b"")
    with pytest.raises(SourceError, match="not a folder"):
        ImageFolderSource(tmp_path / "a.png")
    with pytest.raises(SourceError, match="positive"):
        ImageFolderSource(tmp_path, fps=-1)


def test_folder_of_only_corrupt_images_ends_cleanly(tmp_path: Path) -> None:
    for k in range(3):
        (tmp_path / f"{k}.png").write_bytes(b"nope")
    with ImageFolderSource(tmp_path) as src:
        assert src.read() is None
        assert src.read() is None
    assert src.stats.skipped == 3 and src.stats.delivered == 0


def test_missing_camera_is_a_clear_error() -> None:
    with pytest.raises(SourceError, match=r"cannot open camera 97.*/dev/video") as info:
        CameraSource(97)
    assert isinstance(info.value, UserError)
    with pytest.raises(SourceError, match=r"/dev/video-none does not exist"):
        CameraSource("/dev/video-none")
    with pytest.raises(SourceError, match="latency"):
        CameraSource(0, latency_s=-0.1)


def test_open_source_dispatches(folder: Path, video: Path) -> None:
    with open_source(str(folder), fps=2.0) as src:
        assert isinstance(src, ImageFolderSource) and src.nominal_fps == 2.0
    with open_source(str(video)) as src:
        assert isinstance(src, VideoFileSource)
    with pytest.raises(SourceError, match="cannot open camera 98"):
        open_source("98")
    with pytest.raises(SourceError, match=r"no_such_thing\.mp4 does not exist.*not a camera index"):
        open_source("no_such_thing.mp4")
    with pytest.raises(SourceError, match="not a camera index") as info:
        open_source("webcam")
    assert "does not exist" not in str(info.value)


def test_a_single_image_is_not_taken_for_a_video(folder: Path) -> None:
    """OpenCV opens one PNG as a one-frame "video"; a corrupt one gives none, silently."""
    with pytest.raises(SourceError, match=r"single image.*folder.*measure"):
        open_source(str(folder / "img1.png"))
    with pytest.raises(SourceError, match="single image"):
        open_source(str(folder / "img4.jpg"))


def test_video_that_opens_but_never_decodes_says_so(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    broken = tmp_path / "frame.png"  # OpenCV opens it as an image sequence, then cannot read
    broken.write_bytes(b"\x89PNG\r\n\x1a\nBROKEN")
    with caplog.at_level(logging.ERROR):
        with VideoFileSource(broken, fps=10.0) as src:
            assert src.read() is None
    assert src.end_reason is not None and "could be decoded" in src.end_reason
    assert "could be decoded" in caplog.text


def test_missing_camera_device_message_reads_once() -> None:
    with pytest.raises(SourceError) as info:
        CameraSource("/dev/video-none")
    text = str(info.value)
    assert text.startswith("camera device /dev/video-none does not exist. Try:")
    assert "cannot open camera" not in text


def test_closed_source_refuses_reads(folder: Path) -> None:
    src = ImageFolderSource(folder)
    assert src.read() is not None
    src.close()
    src.close()  # idempotent
    with pytest.raises(SourceError, match="closed"):
        src.read()


class CountingSource(FrameSource):
    """What a subclass (the synthetic camera) has to write: _capture and _release."""

    def __init__(self, n: int) -> None:
        super().__init__("count")
        self.n = n
        self.released = 0

    def _capture(self) -> Frame | None:
        if self.stats.delivered >= self.n:
            return None
        grey = np.full((4, 5), self.stats.delivered, np.uint8)
        return self._frame(grey, 7.0 + self.stats.delivered)

    def _release(self) -> None:
        self.released += 1


def test_subclassing_the_base_is_small() -> None:
    with CountingSource(3) as src:
        frames = list(src)
        assert src.read() is None and src.end_reason == "end of stream"
    assert [(f.index, f.t_host, int(f.image[0, 0, 2])) for f in frames] == [
        (0, 7.0, 0),
        (1, 8.0, 1),
        (2, 9.0, 2),
    ]
    assert frames[0].image.shape == (4, 5, 3) and (frames[0].width, frames[0].height) == (5, 4)
    assert src.released == 1
    with pytest.raises(SourceError, match="8-bit"):
        CountingSource(1)._frame(np.zeros((2, 2), np.float32), 0.0)


def test_camera_stamps_grab_time_minus_latency_and_ends_when_frames_stop(video: Path) -> None:
    """A file opened through the camera path exercises grab/stamp/retrieve without hardware."""
    clock = FakeClock(50.0)
    with CameraSource(str(video), latency_s=0.08, clock=clock, sleep=clock.sleep) as src:
        assert src.size == (W, H)
        first = src.read()
        assert first is not None
        assert first.t_host == pytest.approx(50.0 - 0.08)
        assert first.source == f"camera:{video}"
        rest = list(src)
    assert len(rest) == 11 and [f.index for f in rest] == list(range(1, 12))
    # At the end of the clip the "camera" stops giving frames: a clear reason, no exception.
    assert src.stats.read_failures == CameraSource.MAX_CONSECUTIVE_FAILURES
    assert src.end_reason is not None and "gave no frame" in src.end_reason
    assert len(clock.sleeps) == CameraSource.MAX_CONSECUTIVE_FAILURES - 1
