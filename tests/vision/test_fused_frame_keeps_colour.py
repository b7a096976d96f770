"""A frame round a print raises the top only where the colour runs on past the print's top
(``method.FRAME_KEEPS_COLOUR``, ``region.ends_in_colour``).

The rooms are tuning rooms (procedural and photo, seeds 100-159 and 700-759): photo 739
is a blue face before a photographed rocket and a lit gantry in line with its sides; the
frame search took their edges for a frame's and raised the top 58 % too high (confidence
0.13). Procedural 143 (hard) is a small face whose frame is right and raises its top by
three rows only.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import method

from tests.vision_fixtures import room_size_errors


def test_sides_running_on_into_the_background_raise_no_frame() -> None:
    eh, ew = room_size_errors("photo", 739, False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_colour_check_the_background_is_taken_for_the_frame(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(method, "FRAME_KEEPS_COLOUR", False)
    # the face's surface under the top (method.SURFACE_UP_TO_TOP) brings it down too: off
    monkeypatch.setattr(method, "SURFACE_UP_TO_TOP", False)
    # ... and so does the whole way's judgment (method.WHOLE_RAISE_JUDGED): off
    monkeypatch.setattr(method, "WHOLE_RAISE_JUDGED", False)
    eh, _ = room_size_errors("photo", 739, False)
    assert eh > 0.25


def test_a_short_raise_is_not_judged_by_colour() -> None:
    # the frame's top three rows above the print's: within the top edge's blur
    eh, ew = room_size_errors("procedural", 143, True)
    assert eh < 0.05 and ew < 0.05


def test_the_short_raise_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method, "FRAME_CHECKED_RAISE", 0.0)
    eh, _ = room_size_errors("procedural", 143, True)
    assert eh > 0.08
