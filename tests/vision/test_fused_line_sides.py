"""A thin line on one shade (a seam, a panel joint up the face) is no side of its own:
when a side's ranked places are all such lines, the strongest other columns are its
candidates too."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import region, search
from obstacle_fusion.vision.fused.search import line_columns
from obstacle_fusion.vision.measure import Measurer

W, ROWS = 80, 10


def strip(profile: npt.NDArray[np.float64]) -> npt.NDArray[np.uint8]:
    img = np.repeat(profile[None], ROWS, axis=0)
    img = img + np.random.default_rng(3).normal(0, 1.5, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def test_a_dark_seam_on_one_shade_is_a_line() -> None:
    prof = np.full(W, 150.0)
    prof[39:42] = 90.0  # a seam three columns wide; its edges at 38/39 and 41/42
    assert line_columns(strip(prof), [39, 41]) == {39, 41}


def test_a_step_between_two_shades_is_no_line() -> None:
    prof = np.where(np.arange(W) < 40, 150.0, 90.0)
    assert line_columns(strip(prof), [40]) == set()


def test_a_seam_at_a_face_side_is_no_line() -> None:
    # a dark joint just inside a face's side: the shades beside it differ
    prof = np.where(np.arange(W) < 40, 60.0, 150.0)
    prof[41:43] = 90.0
    assert line_columns(strip(prof), [40, 42]) == set()


def _error(fam: str, seed: int) -> float:
    cam = CameraModel.paper(500, 375)
    image, truth, spec = render_room(fam, seed, False, cam)
    res = Measurer(cam, spec.rig).measure(image, truth["range_m"])
    if not res.detected or res.height_m is None or res.width_m is None:
        return 9.0
    return max(abs(res.height_m / truth["height_m"] - 1), abs(res.width_m / truth["width_m"] - 1))


# two seams up a face took every place of both sides: the seam pair was measured, its top
# far up the background (photo/1106, +56 % high), or no face was found (procedural/1172)
SCENES = [("photo", 1106), ("procedural", 1172)]


@pytest.mark.parametrize(("fam", "seed"), SCENES)
def test_a_face_with_seams_is_measured_by_its_sides(fam: str, seed: int) -> None:
    assert _error(fam, seed) < 0.05


@pytest.mark.parametrize(("fam", "seed"), SCENES)
def test_without_the_rule_the_seams_are_the_sides(
    monkeypatch: pytest.MonkeyPatch, fam: str, seed: int
) -> None:
    monkeypatch.setattr(search, "LINE_SIDES", False)
    # a strip rising as the face's keeps its side (session 39, region.TRIM_KEEPS_RISING):
    # with it on, procedural/1172 is measured within 5.1 % even with this rule off
    monkeypatch.setattr(region, "TRIM_KEEPS_RISING", False)
    # the sides' walk judged by the edge it snaps to (session 50, region.WALK_EDGE_HORIZON)
    # measures procedural/1172 within 1.1 % with both of those off
    monkeypatch.setattr(region, "WALK_EDGE_HORIZON", False)
    assert _error(fam, seed) > 0.25


def _line_columns_reference(strip: np.ndarray, cols: list[int]) -> set[int]:
    """line_columns as first written, one column at a time (numpy scalars)."""
    if strip.shape[0] == 0 or not cols:
        return set()
    prof = strip.astype(np.float32).mean(axis=0)
    d = search.LINE_BESIDE
    out: set[int] = set()
    for c in cols:
        if c - d - 2 < 0 or c + d + 3 > prof.size:
            continue
        left = float(np.median(prof[c - d - 2 : c - d + 1]))
        right = float(np.median(prof[c + d : c + d + 3]))
        mid = 0.5 * (left + right)
        contrast = float(np.max(np.abs(prof[c - d + 2 : c + d - 1] - mid)))
        if contrast >= search.LINE_CONTRAST and abs(left - right) <= min(
            search.LINE_SAME * contrast, search.LINE_SAME_MAX
        ):
            out.add(c)
    return out


def test_line_columns_matches_its_column_by_column_reference() -> None:
    rng = np.random.default_rng(27)
    found = 0
    for _ in range(300):
        w = int(rng.integers(1, 80))
        rows = int(rng.integers(0, 9))
        base = rng.integers(0, 256, w)
        # thin lines on one shade and steps, with noise, so both answers occur
        for c in rng.integers(0, w, 3):
            base[c : c + 3] = rng.integers(0, 256)
        strip = np.clip(base + rng.integers(-6, 7, (rows, w)), 0, 255).astype(np.uint8)
        cols = rng.integers(-3, w + 3, int(rng.integers(0, 12))).tolist()
        got = line_columns(strip, cols)
        assert got == _line_columns_reference(strip, cols)
        found += len(got)
    assert found > 20  # the random strips do hold lines
