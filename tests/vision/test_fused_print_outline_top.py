"""A print's top is where both sides of its outline end, closed by the background
(``method.PRINT_OUTLINE_TOP``, ``region.raise_top_by_outline``).

The rooms are tuning rooms: photo 731 (hard) is a cat's photograph printed over a box's
front face; the colour walks up its middle and just inside its sides stopped at a row of
the photograph (the cat's eyes) and the face came out 64 % too low. Procedural 2046
(hard) is a drawn pattern of coloured blocks; the edge search's settled top stopped in
the pattern (68 % too low).
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import method, region

from tests.vision_fixtures import room_size_errors


@pytest.fixture(autouse=True)
def _no_window_walk(monkeypatch: pytest.MonkeyPatch) -> None:
    """The outline rule alone: the window walk (``method.WINDOW_RESCUE_TOP``) also takes
    photo 731's print up to 12 % off where this rule is off or moved past a limit."""
    monkeypatch.setattr(method, "WINDOW_RESCUE_TOP", False)


def test_a_photo_print_is_measured_to_its_outline_top() -> None:
    eh, ew = room_size_errors("photo", 731, True)
    assert eh < 0.05 and ew < 0.1


def test_a_drawn_print_is_measured_to_its_outline_top() -> None:
    eh, ew = room_size_errors("procedural", 2046, True)
    assert eh < 0.05 and ew < 0.12


def test_without_the_outline_the_print_stops_at_its_pattern(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(method, "PRINT_OUTLINE_TOP", False)
    eh, _ = room_size_errors("photo", 731, True)
    assert eh > 0.5


def test_the_same_print_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # the photo's forehead is 13.6 (Lab) from its muzzle in median colour
    monkeypatch.setattr(region, "OUTLINE_SAME_PRINT", 12.0)
    eh, _ = room_size_errors("photo", 731, True)
    assert eh > 0.5


def test_the_cover_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # both sides stand in 0.86 of the rows up the photograph (its dark ears on the left)
    monkeypatch.setattr(region, "OUTLINE_COVER", 0.9)
    eh, _ = room_size_errors("photo", 731, True)
    assert eh > 0.5


def test_the_raise_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # the outline's top 1.75 times the found face's height above it
    monkeypatch.setattr(region, "OUTLINE_MIN_RAISE", 1.8)
    eh, _ = room_size_errors("photo", 731, True)
    assert eh > 0.5


def test_the_closing_band_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "OUTLINE_CLOSE_DISTANCE", 0.0)
    eh, _ = room_size_errors("photo", 731, True)
    assert eh > 0.5


def test_a_rail_behind_a_plain_face_is_not_a_print() -> None:
    # procedural 1124 (hard): a dark rail's posts behind a low face, in line with its
    # sides; between them the wall, the background beside the sides
    eh, ew = room_size_errors("procedural", 1124, True)
    assert eh < 0.05 and ew < 0.05


def test_the_middle_check_keeps_the_rail_out(monkeypatch: pytest.MonkeyPatch) -> None:
    # only the middle check tells the rail's frame from a print: with it at its lowest
    # (no row need differ in the middle: OUTLINE_COVER 0 lets the sides' coverage pass
    # too, the rail's 0.97 anyway) the rail is the top
    monkeypatch.setattr(region, "OUTLINE_COVER", 0.0)
    eh, _ = room_size_errors("procedural", 1124, True)
    assert eh > 0.25


def test_a_face_too_narrow_for_a_middle_is_left_alone_without_warnings() -> None:
    """A face narrower than its two inside strips has no middle between its sides to read
    (the median of no columns is a NaN and numpy's "mean of empty slice" warning, seen on
    a room of bench_rooms seed 13000): its top stays, quietly."""
    import warnings

    import cv2
    import numpy as np
    from obstacle_fusion.vision.camera import CameraModel
    from obstacle_fusion.vision.rig import Rig
    from obstacle_fusion.vision.types import View

    h, w, bottom, top = 240, 320, 200, 150
    left = 150
    right = left + 2 * (region.BESIDE_COLUMNS + region.SIDE_SKIP) - 4  # no middle columns
    lab = np.empty((h, w, 3), np.uint8)
    lab[:bottom] = (90, 150, 160)  # a dark red wall
    lab[bottom:] = (120, 128, 128)  # a grey floor
    lab[40:bottom, left : right + 1] = (200, 100, 136)  # a tall light teal post
    img = cv2.cvtColor(lab, cv2.COLOR_LAB2BGR)
    grey = cv2.cvtColor(img, cv2.COLOR_BGR2GRAY)
    ay = np.abs(cv2.Sobel(grey, cv2.CV_32F, 0, 1, ksize=3))
    k = np.array([[300.0, 0.0, w / 2], [0.0, 300.0, h / 2], [0.0, 0.0, 1.0]])
    view = View(CameraModel(k, np.zeros(5), w, h), Rig(), "level")
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        raised = region.raise_top_by_outline(img, view, ay, bottom, top, left, right, 1.0)
    assert raised == top
