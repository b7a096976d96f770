"""The annotated video: H.264 in MP4 decoded back with PyAV, and an overlay whose glyphs are
tall enough and apart enough to read at 500x375."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import av
import cv2
import numpy as np
import pytest
from obstacle_fusion.errors import UserError
from obstacle_fusion.fusion import ObstacleRecord
from obstacle_fusion.outputs.video import AnnotatedVideoWriter, annotate

pytestmark = pytest.mark.cpu_only


def _record(**kw: Any) -> ObstacleRecord:
    base: dict[str, Any] = {
        "t_host": 1.0,
        "distance_m": 1.234,
        "height_m": 0.4,
        "width_m": 0.5,
        "confidence": 0.9,
        "status": "ok",
        "alert": False,
        "frame_index": 1,
        "source": "t",
        "pairing": "nearest",
        "pair_dt_s": 0.0,
        "sonar_status": "ok",
        "measurements": (1,),
        "trigger_us": (1,),
        "box_px": (300.0, 220.0, 420.0, 340.0),
    }
    base.update(kw)
    return ObstacleRecord(**base)


def _text_lines(image: np.ndarray) -> list[list[tuple[int, int, int, int]]]:
    """Glyph boxes (x, y, w, h) of the green overlay text, grouped by text line."""
    b, g, r = (image[:, :, i].astype(int) for i in range(3))
    mask = ((g > 100) & (r < 90) & (b < 90)).astype(np.uint8)
    mask[200:, :] = 0  # the text sits at the top; the box is below
    rows = np.flatnonzero(mask.any(axis=1))
    bands: list[tuple[int, int]] = []
    for y in rows:
        if bands and y == bands[-1][1] + 1:
            bands[-1] = (bands[-1][0], y)
        else:
            bands.append((y, y))
    n, _, stats, _ = cv2.connectedComponentsWithStats(mask, connectivity=8)
    glyphs = [tuple(int(v) for v in stats[i][:4]) for i in range(1, n)]
    return [
        sorted((gl for gl in glyphs if y0 <= gl[1] <= y1), key=lambda gl: gl[0])  # type: ignore[misc]
        for y0, y1 in bands
    ]


def test_overlay_glyphs_are_at_least_14_px_high_and_apart_at_500x375() -> None:
    frame = np.full((375, 500, 3), 128, np.uint8)
    out = annotate(frame, _record())
    lines = _text_lines(out)
    assert len(lines) == 3  # "ok", "L 1.234 m", "H 0.400 m  W 0.500 m"
    # one connected component per glyph: none run together
    assert [len(line) for line in lines] == [2, 7, 14]
    capitals = [lines[1][0], lines[2][0], lines[2][7]]  # L, H, W
    heights = [h for _, _, _, h in capitals]
    assert min(heights) >= 14, heights
    gaps = [b[0] - (a[0] + a[2]) for a, b in zip(lines[1], lines[1][1:], strict=False)]
    assert min(gaps) >= 1, gaps  # a clear column between neighbouring glyphs


def test_h264_mp4_decodes_back_with_every_frame(tmp_path: Path) -> None:
    path = tmp_path / "run.mp4"
    writer = AnnotatedVideoWriter(path, fps=15.0)
    for i in range(12):
        img = np.full((375, 500, 3), 60 + 10 * i, np.uint8)
        writer.write(img, _record(alert=i == 11))
    writer.close()
    assert writer.codec == "h264" and writer.frames == 12
    with av.open(str(path)) as container:
        stream = container.streams.video[0]
        assert stream.codec_context.name == "h264"
        assert (stream.width, stream.height) == (500, 376)  # odd height padded for 4:2:0
        assert stream.codec_context.pix_fmt == "yuv420p"
        assert float(stream.average_rate) == pytest.approx(15.0)
        frames = [f.to_ndarray(format="bgr24") for f in container.decode(video=0)]
    assert len(frames) == 12
    assert abs(int(frames[5][300, 50, 1]) - (60 + 50)) < 12  # the picture survives coding
    data = path.read_bytes()
    assert data.find(b"moov") < data.find(b"mdat")  # faststart: a browser plays it at once


def test_missing_pyav_names_the_extra(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "av", None)
    with pytest.raises(UserError, match=r"obstacle-fusion\[video\]"):
        AnnotatedVideoWriter(tmp_path / "x.mp4")
    AnnotatedVideoWriter(tmp_path / "x.avi").close()  # Motion-JPEG needs only OpenCV


def test_an_encoder_failure_on_the_writer_thread_is_reported(tmp_path: Path) -> None:
    folder = tmp_path / "gone"
    folder.mkdir()
    writer = AnnotatedVideoWriter(folder / "run.mp4")
    folder.rmdir()  # the file cannot be created any more when the first frame comes
    writer.write(np.full((375, 500, 3), 90, np.uint8), _record())
    with pytest.raises(UserError, match=r"video .*gone/run\.mp4"):
        writer.close()
    assert writer.frames == 0


def test_unthreaded_writer_writes_in_the_callers_thread(tmp_path: Path) -> None:
    writer = AnnotatedVideoWriter(tmp_path / "run.mp4", threaded=False)
    writer.write(np.full((375, 500, 3), 90, np.uint8), _record())
    assert writer.frames == 1  # done before write() returned
    writer.close()
    with av.open(str(tmp_path / "run.mp4")) as container:
        assert sum(1 for _ in container.decode(video=0)) == 1
