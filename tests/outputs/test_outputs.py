"""Outputs: MCAP (Foxglove schemas, crash and reconnect safety), JSON lines, console, video."""

from __future__ import annotations

import base64
import io
import json
import shutil
import time
from pathlib import Path

import cv2
import numpy as np
import pytest
from mcap.reader import make_reader
from obstacle_fusion.errors import UserError
from obstacle_fusion.fusion import ObstacleRecord
from obstacle_fusion.link.connection import Link
from obstacle_fusion.outputs.console import ConsoleView, RateMeter, Status, status_line
from obstacle_fusion.outputs.foxglove_schemas import FoxgloveTopics, recording_unix_offset_ns
from obstacle_fusion.outputs.jsonl import JsonLinesWriter
from obstacle_fusion.outputs.mcap_file import (
    TOPIC_EVENT,
    TOPIC_IMAGE,
    TOPIC_OBSTACLE,
    TOPIC_RANGE,
    McapRecorder,
    decode_image,
    event_of_log,
    read_recording,
)
from obstacle_fusion.outputs.video import AnnotatedVideoWriter
from obstacle_fusion.protocol.generated import Range
from obstacle_fusion.sonar import SonarConverter, SonarStatus
from obstacle_fusion.sources.frames import Frame

from tests.link_fixtures import FakeBoard

pytestmark = pytest.mark.cpu_only


def _record(t: float = 1.5, alert: bool = False, distance: float | None = 1.2) -> ObstacleRecord:
    return ObstacleRecord(
        t_host=t,
        distance_m=distance,
        height_m=0.4,
        width_m=0.5,
        confidence=0.9,
        status="ok",
        alert=alert,
        frame_index=3,
        source="test",
        pairing="interpolated",
        pair_dt_s=0.01,
        sonar_status="ok",
        measurements=(4, 5),
        trigger_us=(100, 200),
        box_px=(10.0, 20.0, 60.0, 70.0),
        t_published=t + 0.05,
    )


def _frame(t: float, i: int) -> Frame:
    img = np.full((120, 160, 3), 40, np.uint8)
    cv2.rectangle(img, (40 + i, 30), (100 + i, 90), (30, 90, 200), -1)
    return Frame(img, t, i, "test")


def test_mcap_is_a_valid_foxglove_file_with_acquisition_publish_times(tmp_path: Path) -> None:
    path = tmp_path / "run.mcap"
    conv = SonarConverter()
    unix = 1_700_000_000_000_000_000  # the run's host-monotonic -> Unix offset, ns
    topics = FoxgloveTopics(unix_offset_ns=unix)
    with McapRecorder(path, metadata={"camera": {"fx": "400"}}, topics=topics) as rec:
        for i in range(5):
            rec.write_frame(_frame(10.0 + i * 0.1, i), log_t=10.02 + i * 0.1)
            reading = conv.convert(Range(i, 0, 1000 * i, 11662, 0), t_trigger_host=10.0 + i * 0.06)
            rec.write_range(reading, 2_000_000, 1, log_t=10.03 + i * 0.06)
        rec.write_obstacle(_record())
    with open(path, "rb") as fh:
        reader = make_reader(fh)
        summary = reader.get_summary()
        assert summary is not None
        schemas = {s.name: s for s in summary.schemas.values()}
        assert schemas["foxglove.CompressedImage"].encoding == "jsonschema"
        schema = json.loads(schemas["foxglove.CompressedImage"].data)
        assert schema["properties"]["data"]["contentEncoding"] == "base64"
        msgs = list(reader.iter_messages())
    images = [(c, m) for _, c, m in msgs if c.topic == TOPIC_IMAGE]
    assert len(images) == 5 and images[0][0].message_encoding == "json"
    first = json.loads(images[0][1].data)
    assert first["format"] == "jpeg" and first["timestamp"] == {"sec": 1_700_000_010, "nsec": 0}
    assert first["frame_id"] == "camera"
    assert images[0][1].publish_time == unix + 10_000_000_000  # Unix-epoch ns
    assert images[0][1].log_time == unix + 10_020_000_000
    jpeg = base64.b64decode(first["data"])
    assert jpeg[:2] == b"\xff\xd8"
    ranges = [json.loads(m.data) for _, c, m in msgs if c.topic == TOPIC_RANGE]
    assert ranges[1]["echo_ticks"] == 11662 and ranges[1]["timer_hz"] == 2_000_000
    assert ranges[1]["status"] == "ok" and ranges[1]["distance_m"] == pytest.approx(1.0, abs=0.01)
    obst = [(m, json.loads(m.data)) for _, c, m in msgs if c.topic == TOPIC_OBSTACLE]
    assert obst[0][1]["height_m"] == 0.4 and obst[0][0].publish_time == unix + 1_500_000_000
    assert obst[0][1]["t_host"] == 1.5  # the monotonic instant stays in the record
    back = read_recording(path)
    assert back.complete and back.metadata["camera"] == {"fx": "400"}
    assert back.metadata["obstacle_fusion"]["unix_offset_ns"] == str(unix)
    assert recording_unix_offset_ns(back.metadata) == unix
    img = decode_image(next(m.data for m in back.messages if m.topic == TOPIC_IMAGE))
    assert img is not None and img.shape == (120, 160, 3)


def test_a_crashed_recording_keeps_everything_flushed(tmp_path: Path) -> None:
    path = tmp_path / "crash.mcap"
    rec = McapRecorder(path, flush_interval_s=0.0)  # every message closes a chunk
    for i in range(6):
        rec.write_frame(_frame(1.0 + i * 0.1, i))
    # The process dies here: no close(), no footer. Copy the file as it is on disk.
    cut = tmp_path / "cut.mcap"
    shutil.copy(path, cut)
    back = read_recording(cut)
    assert not back.complete and back.problem
    assert len([m for m in back.messages if m.topic == TOPIC_IMAGE]) == 6
    # A copy cut in the middle of a record: what precedes it is still read.
    data = cut.read_bytes()
    half = tmp_path / "half.mcap"
    half.write_bytes(data[: len(data) - 500])
    back = read_recording(half)
    assert not back.complete and 1 <= len([m for m in back.messages if m.topic == TOPIC_IMAGE]) < 6
    rec.close()
    assert read_recording(path).complete


def test_a_non_mcap_file_is_refused_clearly(tmp_path: Path) -> None:
    bogus = tmp_path / "notes.mcap"
    bogus.write_text("hello, I am a text file\n")
    with pytest.raises(UserError, match="not an MCAP file"):
        read_recording(bogus)
    with pytest.raises(UserError, match="does not exist"):
        read_recording(tmp_path / "missing.mcap")


@pytest.mark.realtime  # the fake board's link, paced in real time
def test_a_recording_across_a_reconnect_holds_both_sides(tmp_path: Path) -> None:
    path = tmp_path / "reconnect.mcap"
    conv = SonarConverter()
    with FakeBoard() as board, McapRecorder(path) as rec:
        link = Link(
            board.port, handshake_timeout_s=1.5, get_info_after_s=0.05, retry_interval_s=0.05
        )
        link.start()
        try:

            def pump(seconds: float) -> None:
                end = time.monotonic() + seconds
                while time.monotonic() < end:
                    item = link.get(timeout=0.02)
                    if item is not None and isinstance(item.msg, Range):
                        r = conv.convert(item.msg, item.t_host - 0.01, item.t_host)
                        rec.write_range(r, 2_000_000, item.session, log_t=item.t_host)

            pump(0.4)
            board.unplug()
            pump(0.3)
            lost_port = board.path  # plugging in again may open another pty
            rec.write_event("disconnected", {"port": lost_port})
            board.plug()
            pump(0.8)
        finally:
            link.close()
    back = read_recording(path)
    assert back.complete
    sessions = {m.data["session"] for m in back.messages if m.topic == TOPIC_RANGE}
    assert sessions == {1, 2}
    events = [event_of_log(m.data) for m in back.messages if m.topic == TOPIC_EVENT]
    assert ("disconnected", {"port": lost_port}) in events


def test_json_lines_one_object_per_line_and_no_nan() -> None:
    buf = io.StringIO()
    w = JsonLinesWriter(buf)
    w.write(_record(), extra={"scene_t_s": 1.0})
    w.write(_record(distance=None))
    lines = buf.getvalue().splitlines()
    assert len(lines) == 2
    first = json.loads(lines[0])
    assert first["distance_m"] == 1.2 and first["scene_t_s"] == 1.0 and first["alert"] is False
    assert json.loads(lines[1])["distance_m"] is None


def test_json_lines_survive_a_closed_pipe() -> None:
    class Closed(io.StringIO):
        def write(self, s: str) -> int:
            raise BrokenPipeError

    w = JsonLinesWriter(Closed())
    w.write(_record())
    assert w.broken and w.lines == 0


def test_console_plain_mode_without_a_terminal() -> None:
    buf = io.StringIO()
    view = ConsoleView(buf, plain_interval_s=0.0)
    assert view.plain
    status = Status(
        mode="emulator", latest=_record(alert=True), link={"connected": True, "frames": 10}
    )
    view.update(status)
    text = buf.getvalue()
    assert "ALERT" in text and "d=1.200 m" in text and "link up" in text
    assert status_line(Status()).startswith("[] no frame yet")


def test_console_rich_mode_renders_a_table() -> None:
    buf = io.StringIO()
    view = ConsoleView(buf, live=True, refresh_hz=1000)
    assert not view.plain
    view.update(
        Status(mode="robot", latest=_record(), link={"connected": False, "port": "/dev/x"}),
        force=True,
    )
    view.close()
    out = buf.getvalue()
    assert "DOWN" in out and "0.400" in out


def test_rate_meter() -> None:
    m = RateMeter(window_s=2.0)
    for i in range(11):
        m.tick(100.0 + i * 0.1)
    assert m.rate(now=101.0) == pytest.approx(10.0)
    assert m.rate(now=110.0) == 0.0


def test_annotated_video_is_written(tmp_path: Path) -> None:
    path = tmp_path / "out.avi"
    w = AnnotatedVideoWriter(path, fps=10)
    for i in range(5):
        w.write(_frame(i * 0.1, i).image, _record(alert=i == 4))
    w.close()
    cap = cv2.VideoCapture(str(path))
    n = 0
    while cap.read()[0]:
        n += 1
    cap.release()
    assert n == 5
    with pytest.raises(UserError, match="unknown extension"):
        AnnotatedVideoWriter(tmp_path / "out.gif")


def test_status_values_are_strings() -> None:
    assert str(SonarStatus.NO_ECHO) == "no_echo"


def test_console_degrades_to_plain_lines_without_rich(monkeypatch: pytest.MonkeyPatch) -> None:
    import sys

    monkeypatch.setitem(sys.modules, "rich.live", None)  # as if rich were not installed
    buf = io.StringIO()
    view = ConsoleView(buf, live=True, plain_interval_s=0.0)
    assert view.plain
    view.update(Status(mode="robot", latest=_record()))
    assert "d=1.200 m" in buf.getvalue()


def test_an_existing_recording_or_video_is_not_overwritten_unless_asked(tmp_path: Path) -> None:
    mcap = tmp_path / "rec.mcap"
    with McapRecorder(mcap) as rec:
        rec.write_frame(_frame(1.0, 0), log_t=1.0)
    before = mcap.read_bytes()
    with pytest.raises(UserError, match=r"rec\.mcap already exists.*--overwrite"):
        McapRecorder(mcap)
    assert mcap.read_bytes() == before  # not truncated by the refusal
    McapRecorder(mcap, overwrite=True).close()
    assert mcap.read_bytes() != before
    video = tmp_path / "out.avi"
    video.write_bytes(b"earlier video")
    with pytest.raises(UserError, match=r"out\.avi already exists.*--overwrite"):
        AnnotatedVideoWriter(video)
    assert video.read_bytes() == b"earlier video"
    AnnotatedVideoWriter(video, overwrite=True).close()


def test_console_says_emulated_and_ends_the_table_with_a_newline() -> None:
    buf = io.StringIO()
    view = ConsoleView(buf, live=True, refresh_hz=1000)
    view.update(Status(mode="emulator", latest=_record()), force=True)
    view.close()
    out = buf.getvalue()
    assert "EMULATED" in out
    assert out.endswith("┘\n")  # a summary printed next starts on its own line
    plain = io.StringIO()
    ConsoleView(plain, plain_interval_s=0.0).update(Status(mode="emulator"), force=True)
    assert plain.getvalue().startswith("[EMULATED")
