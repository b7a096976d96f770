"""`run` and `replay` refuse bad options up front, with the same rules, and never a traceback."""

from __future__ import annotations

import json
import logging
from pathlib import Path

import numpy as np
import pytest
from obstacle_fusion.app import App, RunSettings
from obstacle_fusion.cli import build_parser, main
from obstacle_fusion.cli.run import _LazyMeasurer
from obstacle_fusion.errors import UserError
from obstacle_fusion.link.connection import Link
from obstacle_fusion.outputs.mcap_file import McapRecorder, read_recording
from obstacle_fusion.protocol.generated import Range
from obstacle_fusion.sonar import SonarConverter
from obstacle_fusion.sources.frames import Frame
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.rig import Rig

pytestmark = pytest.mark.cpu_only


def _refused(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    with pytest.raises(SystemExit) as exc:
        build_parser().parse_args(argv)
    assert exc.value.code == 2, argv
    return capsys.readouterr().err


@pytest.mark.parametrize(
    "option, value",
    [
        ("--exit-on-alert", "0"),
        ("--exit-on-alert", "256"),
        ("--exit-on-alert", "126"),
        ("--baud", "0"),
        ("--baud", "-9600"),
        ("--width", "-1"),
        ("--height", "0"),
        ("--width", "100000"),
        ("--camera-latency-ms", "nan"),
        ("--camera-latency-ms", "-5"),
        ("--camera-latency-ms", "2500"),
        ("--temperature", "nan"),
        ("--temperature", "1000"),
        ("--temperature", "-60"),
        ("--pair-tolerance-ms", "1e9"),
        ("--pair-tolerance-ms", "nan"),
        ("--stop-distance", "-1"),
        ("--stop-distance", "inf"),
        ("--median", "0"),
        ("--fps", "nan"),
    ],
)
def test_run_refuses_out_of_range_options(
    option: str, value: str, capsys: pytest.CaptureFixture[str]
) -> None:
    err = _refused(["run", f"{option}={value}"], capsys)
    assert option in err


@pytest.mark.parametrize(
    "option, value",
    [
        ("--temperature", "nan"),
        ("--temperature", "500"),
        ("--stop-distance", "-1"),
        ("--pair-tolerance-ms", "nan"),
        ("--pair-tolerance-ms", "-1"),
        ("--pair-tolerance-ms", "5000"),
        ("--median", "0"),
    ],
)
def test_replay_shares_runs_validators(
    option: str, value: str, capsys: pytest.CaptureFixture[str]
) -> None:
    err = _refused(["replay", "x.mcap", f"{option}={value}"], capsys)
    assert option in err


def test_the_edges_of_each_span_are_accepted() -> None:
    a = build_parser().parse_args(
        ["run", "--exit-on-alert", "125", "--stop-distance", "0.5", "--temperature", "-50"]
        + ["--pair-tolerance-ms", "1000", "--width", "16", "--height", "8192"]
        + ["--camera-latency-ms", "2000", "--baud", "9600"]
    )
    assert (a.exit_on_alert, a.temperature, a.pair_tolerance_ms) == (125, -50.0, 1000.0)
    assert (a.width, a.height, a.camera_latency_ms, a.baud) == (16, 8192, 2000.0, 9600)
    a = build_parser().parse_args(["run", "--exit-on-alert", "1", "--pair-tolerance-ms", "0"])
    assert a.exit_on_alert == 1 and a.temperature is None  # None: 20 C, or the scenario's
    r = build_parser().parse_args(["replay", "x.mcap", "--temperature", "80"])
    assert r.temperature == 80.0 and r.pair_tolerance_ms == 50.0


def test_run_never_overwrites_a_recording_or_video_unless_asked(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    for option, name in (("--record", "rec.mcap"), ("--video", "out.mp4")):
        path = tmp_path / name
        path.write_bytes(b"an earlier run" * 1000)
        assert main(["run", option, str(path)]) == 2  # refused before the emulator starts
        err = capsys.readouterr().err
        assert str(path) in err and "already exists" in err and "--overwrite" in err
        assert path.read_bytes() == b"an earlier run" * 1000


def test_width_and_height_for_a_folder_are_warned_about(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, capsys: pytest.CaptureFixture[str]
) -> None:
    existing = tmp_path / "rec.mcap"
    existing.write_bytes(b"x")
    with caplog.at_level(logging.WARNING):
        # The existing recording stops the run right after the option checks.
        argv = ["run", "--port", "/dev/null", "--camera", str(tmp_path), "--width", "640"]
        assert main([*argv, "--record", str(existing)]) == 2
    assert any("plays at its own size" in r.getMessage() for r in caplog.records)


def test_without_calib_a_wide_camera_is_refused_and_a_calib_must_fit() -> None:
    wide = np.zeros((360, 640, 3), np.uint8)
    with pytest.raises(UserError, match=r"no --calib given.*640x360.*pass --calib"):
        _LazyMeasurer(None, Rig(), "fused").prepare(wide)
    calib = Path("cam43.yaml")
    with pytest.raises(UserError, match=r"--calib cam43\.yaml: .*640x360"):
        _LazyMeasurer(CameraModel.paper(), Rig(), "fused", calib).prepare(wide)
    _LazyMeasurer(None, Rig(), "fused").prepare(np.zeros((375, 500, 3), np.uint8))


class _NoSource:
    name = "none"


def test_the_run_stops_at_the_first_frame_a_calibration_cannot_measure(tmp_path: Path) -> None:
    recorder = McapRecorder(tmp_path / "r.mcap")
    app = App(
        RunSettings(),
        Link("/dev/null"),
        _NoSource(),  # type: ignore[arg-type]
        _LazyMeasurer(CameraModel.paper(), Rig(), "fused", Path("cam43.yaml")),
        recorder=recorder,
    )
    with pytest.raises(UserError, match="cam43.yaml"):
        app._on_frame(Frame(np.zeros((360, 640, 3), np.uint8), 1.0, 0, "cam"))
    recorder.close()
    assert recorder.counts["/camera/image"] == 0  # nothing claimed for that camera


# ----------------------------------------------------------------------------- replay


def _recording(path: Path, rig: str | None, size: tuple[int, int] = (500, 375)) -> Path:
    conv = SonarConverter()
    meta: dict[str, str] = {"mode": "robot", "method": "fused", "temperature_c": "20"}
    if rig is not None:
        meta["rig"] = rig
    with McapRecorder(path, metadata={"run": meta}) as rec:
        for i in range(4):
            t = 10.0 + i * 0.06
            reading = conv.convert(Range(i, 0, 1000 * i, 11662, 0), t_trigger_host=t)
            rec.write_range(reading, 2_000_000, 1, log_t=t + 0.01)
        w, h = size
        image = np.full((h, w, 3), 90, np.uint8)
        rec.write_frame(Frame(image, 10.09, 0, "cam"), log_t=10.1)
    return path


def test_replay_skips_unknown_rig_keys_and_refuses_a_malformed_rig(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], caplog: pytest.LogCaptureFixture
) -> None:
    newer = json.dumps({"camera_height_m": 0.3, "lens_tilt_deg": 2.0})
    path = _recording(tmp_path / "newer.mcap", newer)
    assert read_recording(path).complete
    with caplog.at_level(logging.WARNING):
        assert main(["replay", str(path)]) == 0
    out = capsys.readouterr().out
    assert len(out.splitlines()) == 1
    assert any("lens_tilt_deg" in r.getMessage() for r in caplog.records)
    for bad, words in (("{not json", "not valid JSON"), ('{"camera_height_m": -1}', "unusable")):
        path = _recording(tmp_path / "bad.mcap", bad)
        assert main(["replay", str(path)]) == 2
        err = capsys.readouterr().err
        assert words in err and "--rig" in err and "Traceback" not in err
        path.unlink()


def test_replay_refuses_a_calibration_of_another_aspect_up_front(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _recording(tmp_path / "r.mcap", None)
    calib = tmp_path / "wide.yaml"
    CameraModel(
        np.array([[500.0, 0, 319.5], [0, 500.0, 179.5], [0, 0, 1]]), np.zeros(5), 640, 360
    ).save(calib)
    assert main(["replay", str(path), "--calib", str(calib)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and "wide.yaml" in err and "500x375" in err
