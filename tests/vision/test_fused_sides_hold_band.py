"""The sides' walk crossing a band where the sides lose their step but the strips inside
them keep the face's colour (``method.SIDES_HOLD_BAND``, ``region.raise_top_by_sides``
with ``held_band_share``, ``region._cross_held_bands``).

The room is a tuning room (procedural, seeds 700-759): procedural 757 hard is a mauve
frame round a yellow brick print before an olive wall with a pink skirting band of nearly
the frame's colour (8-11 Lab beside its sides). With the rig the edge search took the
print's lower edge for the top, and the sides' walk stopped where the skirting hid the
sides' step: the height was 80 % short. The strips inside both sides keep the frame's
colour through the band and the sides step again above it, up to the frame's top. The
drawn faces below try each limit of the crossing.
"""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import method, region
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import View

from tests.vision_fixtures import room_size_errors


def test_a_frame_before_a_skirting_of_its_colour_is_read_whole() -> None:
    eh, ew = room_size_errors("procedural", 757, True)
    assert eh < 0.05 and ew < 0.05


def test_without_the_held_band_the_top_stays_on_the_print(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(method, "SIDES_HOLD_BAND", False)
    # (the frame closing over the print, method.FRAME_CLOSES_TOP, finds this top too)
    monkeypatch.setattr(method, "FRAME_CLOSES_TOP", False)
    eh, _ = room_size_errors("procedural", 757, True)
    assert eh > 0.25


# A drawn face (rows FACE_TOP..BOTTOM, columns LEFT..RIGHT) before a wall far from its
# colour, with a band of nearly its colour beside it over rows BAND (BAND_ROWS rows), just
# above the top the walk starts from (START, a line inside the face).
H, W = 240, 320
FACE_TOP, BOTTOM, LEFT, RIGHT = 20, 200, 60, 260
BAND = (110, 150)
BAND_ROWS = BAND[1] - BAND[0]
START = 150
DEPTH = 1.0
FACE_LAB = (100.0, 150.0, 120.0)
WALL_LAB = (140.0, 115.0, 160.0)
BAND_LAB = (104.0, 145.0, 126.0)  # 9 Lab from the face: under MIN_BESIDE_STEP
FLOOR_LAB = (160.0, 128.0, 128.0)
TAPE_LAB = (200.0, 128.0, 128.0)


def level_view() -> View:
    """A distortion-free camera with no pitch (the horizon at row H / 2)."""
    k = np.array([[300.0, 0.0, W / 2], [0.0, 300.0, H / 2], [0.0, 0.0, 1.0]])
    return View(CameraModel(k, np.zeros(5), W, H), Rig(), "level")


def band_scene(face_top: int = FACE_TOP, tape_rows: int = 0) -> npt.NDArray[np.uint8]:
    """The face before the wall and the band; ``face_top``: its top row; ``tape_rows``: a
    light tape across the face over that many rows from the band's foot up."""
    lab = np.empty((H, W, 3), np.float64)
    lab[:] = WALL_LAB
    lab[BAND[0] : BAND[1]] = BAND_LAB
    lab[BOTTOM:] = FLOOR_LAB
    lab[face_top:BOTTOM, LEFT:RIGHT] = FACE_LAB
    if tape_rows:
        lab[BAND[1] - tape_rows : BAND[1], LEFT:RIGHT] = TAPE_LAB
    lab += np.random.default_rng(5).normal(0, 1.5, lab.shape)
    return cv2.cvtColor(np.clip(lab, 0, 255).astype(np.uint8), cv2.COLOR_LAB2BGR)


def walk(img: npt.NDArray[np.uint8], share: float = method.SIDES_HOLD_BAND_SHARE) -> int:
    grey = img.mean(axis=2)
    ay = np.zeros(grey.shape, np.float32)
    ay[1:-1] = np.abs(grey[2:] - grey[:-2])
    return region.raise_top_by_sides(
        img, level_view(), ay, BOTTOM, START, LEFT, RIGHT, DEPTH, held_band_share=share
    )


def test_the_band_is_crossed_up_to_the_faces_top() -> None:
    assert abs(walk(band_scene()) - FACE_TOP) <= 2


def test_with_no_held_band_the_walk_stops_under_the_band() -> None:
    # the band is taller than the tape the plain walk crosses
    assert walk(band_scene(), share=0.0) >= BAND[1] - 2


def test_the_band_share_decides() -> None:
    # the face found is BOTTOM - START = 50 rows: 0.9 of it reaches over the band's 40
    # rows (and its edges' blur), 0.7 does not
    height = BOTTOM - START
    assert 0.7 * height < BAND_ROWS < 0.9 * height
    assert walk(band_scene(), share=0.7) >= BAND[1] - 2
    assert abs(walk(band_scene(), share=0.9) - FACE_TOP) <= 2


def test_a_face_ending_in_the_band_is_not_raised_past_it() -> None:
    # above the band the wall: nothing steps at the sides for the face's return
    assert walk(band_scene(face_top=BAND[0] + 10)) >= BAND[0] + 8


def test_a_tape_across_the_band_stops_the_crossing() -> None:
    # the strips take the tape's colour over half the band's rows
    assert walk(band_scene(tape_rows=BAND_ROWS // 2)) >= BAND[1] - 2


def test_the_held_rows_share_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # a tape over 3 of the band's 40 rows (and its blur) leaves the strips held in over
    # 0.9 of them and under 0.95: crossed at 0.9, not at 0.95
    monkeypatch.setattr(region, "HELD_BAND_ROWS_SHARE", 0.9)
    assert abs(walk(band_scene(tape_rows=3)) - FACE_TOP) <= 2
    monkeypatch.setattr(region, "HELD_BAND_ROWS_SHARE", 0.95)
    assert walk(band_scene(tape_rows=3)) >= BAND[1] - 2


def test_a_refused_crossing_keeps_the_plain_walks_top(monkeypatch: pytest.MonkeyPatch) -> None:
    """Where the held band's crossing reaches a top the face check refuses, the plain
    walk's top is still tried (procedural 711 hard: the sides' walk raises its top from
    row 183 to 92). Here the crossing is forced 20 rows above the plain walk and refused:
    the answer must be the one with the crossing switched off."""
    monkeypatch.setattr(method, "SIDES_HOLD_BAND", False)
    plain = room_size_errors("procedural", 711, True)
    monkeypatch.setattr(method, "SIDES_HOLD_BAND", True)
    walk, check = method.raise_top_by_sides, method.face_under_raised_top
    forced: set[int] = set()

    def crossing(*args: object, **kwargs: object) -> int:
        top = walk(*args, **kwargs)  # type: ignore[arg-type]
        if kwargs.get("held_band_share") is None:
            return top
        forced.add(max(0, top - 20))
        return max(0, top - 20)

    def refuse(*args: object, **kwargs: object) -> bool:
        return args[4] not in forced and check(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(method, "raise_top_by_sides", crossing)
    monkeypatch.setattr(method, "face_under_raised_top", refuse)
    assert room_size_errors("procedural", 711, True) == plain
    assert forced  # the crossing ran
