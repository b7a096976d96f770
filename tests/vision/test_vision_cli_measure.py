"""`obstacle-fusion measure`: JSON, annotation, exit codes and clear errors, no tracebacks."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest
from obstacle_fusion.cli import main
from obstacle_fusion.sim.scene import SceneSpec, render_scene
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.rig import Rig


@pytest.fixture(scope="module")
def photo(tmp_path_factory: pytest.TempPathFactory) -> Path:
    spec = SceneSpec(width_m=0.4, height_m=0.3, distance_m=1.0, floor_style="plain")
    sc = render_scene(spec, CameraModel.paper(), Rig(), 1)
    path = tmp_path_factory.mktemp("m") / "box.png"
    cv2.imwrite(str(path), sc.image)
    return path


def test_json_and_annotate(photo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "ann.png"
    rc = main(["measure", str(photo), "--range-m", "1.0", "--json", "--annotate", str(out)])
    assert rc == 0
    d = json.loads(capsys.readouterr().out)
    assert d["detected"] is True and d["method"] == "fused"
    assert d["height_m"] == pytest.approx(0.3, rel=0.03)
    assert d["width_m"] == pytest.approx(0.4, rel=0.03)
    assert d["distance_m"] == 1.0 and len(d["box_px"]) == 4 and "total" in d["timings_ms"]
    # no --rig: the floor contact was found in the image, not a guessed camera height
    assert d["rig_source"] == "estimated" and d["camera_height_m"] == pytest.approx(0.2, abs=0.01)
    assert d["clipped"] == [] and d["width_is_lower_bound"] is False
    ann = cv2.imread(str(out))
    assert ann is not None and ann.shape == (375, 500, 3)
    assert not np.array_equal(ann, cv2.imread(str(photo)))


def test_paper_method_and_rig_and_calib(
    photo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    calib = tmp_path / "cam.yaml"
    CameraModel.paper(1000, 750).save(calib)  # another resolution, same aspect: scaled
    rig = tmp_path / "rig.toml"
    Rig().save(rig)
    rc = main(
        [
            "measure",
            str(photo),
            "--range-m",
            "1.0",
            "--calib",
            str(calib),
            "--rig",
            str(rig),
            "--method",
            "paper",
            "--json",
        ]
    )
    d = json.loads(capsys.readouterr().out)
    assert d["method"] == "paper" and d["confidence"] is None and d["rig_source"] == "file"
    assert rc == (0 if d["detected"] else 1)


def test_errors_exit_2_without_traceback(
    photo: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    junk = tmp_path / "junk.png"
    junk.write_text("not an image")
    wrong = tmp_path / "wide.yaml"
    CameraModel(
        np.array([[500.0, 0, 319.5], [0, 500.0, 179.5], [0, 0, 1]]), np.zeros(5), 640, 360
    ).save(wrong)
    cases = [
        (["measure", str(junk), "--range-m", "1"], "cannot read image"),
        (["measure", str(tmp_path / "missing.png"), "--range-m", "1"], "does not exist"),
        (["measure", str(photo), "--range-m", "0.01"], "outside"),
        (["measure", str(photo), "--range-m", "9"], "outside"),
        (["measure", str(photo), "--range-m", "1", "--calib", str(wrong)], "aspect"),
        (["measure", str(photo), "--range-m", "1", "--rig", str(tmp_path / "no.toml")], "rig file"),
        (
            ["measure", str(photo), "--range-m", "1", "--annotate", str(tmp_path / "x" / "a.png")],
            "folder",
        ),
    ]
    for argv, message in cases:
        assert main(argv) == 2, argv
        err = capsys.readouterr().err
        assert message in err and "Traceback" not in err


def test_min_confidence_outside_0_1_exits_2(
    photo: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(SystemExit) as stop:
        main(["measure", str(photo), "--range-m", "1", "--min-confidence", "2"])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert "--min-confidence" in err and "within 0..1" in err and "Traceback" not in err


def test_no_obstacle_exits_1(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    spec = SceneSpec(obstacle=False, floor_style="plain")
    path = tmp_path / "empty.png"
    cv2.imwrite(str(path), render_scene(spec, CameraModel.paper(), Rig(), 2).image)
    assert main(["measure", str(path), "--range-m", "1.5", "--json"]) == 1
    assert json.loads(capsys.readouterr().out)["detected"] is False


def test_a_folder_and_a_wide_photo_without_calib_are_explained(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["measure", str(tmp_path), "--range-m", "1"]) == 2
    err = capsys.readouterr().err
    assert "is a folder, not an image" in err and "does not exist" not in err
    wide = tmp_path / "wide.png"
    cv2.imwrite(str(wide), np.full((360, 640, 3), 90, np.uint8))
    assert main(["measure", str(wide), "--range-m", "1"]) == 2
    err = capsys.readouterr().err
    assert "no --calib given" in err and "640x360" in err and "pass --calib" in err
    assert "calibration is for" not in err  # the user gave none


def test_an_unreadable_image_is_a_permission_error_not_a_format(photo: Path) -> None:
    import shutil
    import tempfile

    from tests.cli_fixtures import unreadable_run

    with tempfile.TemporaryDirectory(dir="/tmp") as folder:
        Path(folder).chmod(0o755)
        locked = Path(folder) / "locked.png"
        shutil.copy(photo, locked)
        res = unreadable_run(locked, "measure", str(locked), "--range-m", "1.0")
    assert res.returncode == 2, res.stderr
    assert "permission denied" in res.stderr and "format" not in res.stderr
