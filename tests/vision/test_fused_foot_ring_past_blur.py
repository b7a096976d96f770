"""A print's lower margin is read past the print's blurred edge
(``region.FOOT_RING_PAST_BLUR``, in ``region.enclose_from_foot``).

Photo 2059 (a tuning room, ordinary, with its rig) is a brick print in a dark purple
frame before a photographed cup: the texture stage finds the print, its foot a row short
of the print's lower edge, on the blur between print and margin. The margin's colour read
on the two rows under that foot was the blur's, half print, so its run down to the floor
broke at once and no frame was found: height -16 %, width -15 %.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import region

from tests.vision_fixtures import room_size_errors


def test_the_frame_round_a_brick_print_is_found_from_its_foot() -> None:
    eh, ew = room_size_errors("photo", 2059, False)
    assert eh < 0.02 and ew < 0.02


def test_without_reading_past_the_blur_the_print_is_taken_for_the_face(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(region, "FOOT_RING_PAST_BLUR", False)
    eh, ew = room_size_errors("photo", 2059, False)
    assert eh > 0.1 and ew > 0.1


def test_the_margin_colour_is_sought_within_the_blur_rows(monkeypatch: pytest.MonkeyPatch) -> None:
    # the margin's core lies three rows under the found foot here: two rows read are the
    # print's blur only
    monkeypatch.setattr(region, "RING_BLUR", 2)
    eh, _ = room_size_errors("photo", 2059, False)
    assert eh > 0.1
