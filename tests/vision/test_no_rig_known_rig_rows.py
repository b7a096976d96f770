"""With no rig, when the search gives no face (a miss or a refusal), each floor-contact row
and weaker step, lowest first, is measured as with a rig at a few guessed pitches, and the
first row whose readings agree on one face on one foot gives it, with its low confidence
(``measure.KNOWN_RIG_ROWS``, ``measure.Measurer._known_rig_rows``).

The rooms are tuning rooms, measured with no rig. Photo 700 (ordinary): the face's foot is
the last of the band's weak steps (row 229); the no-rig trials there find no face, the
rig's stages do, alike at all four pitches (within 3 %). Procedural 144 (hard): the search
refused a band of the face; its foot row read as with a rig gives the face at three of the
four pitches (within 4 %), while the step under it (row 265) agrees only twice, its width a
quarter short: at KNOWN_RIG_AGREE 2 that row is taken, at 4 no row agrees. Photo 2085
(hard): readings agreeing on a face 59 % too tall carry the search's refusal's doubts
(second top edge, top running on, skewed edges, small): refused as the search refuses.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused.confidence import PITCH_UNREAD
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.types import Measurement

from tests.vision_fixtures import room_size_errors


def _measured(family: str, seed: int, hard: bool) -> Measurement:
    cam = CameraModel.paper(500, 375)
    image, truth, _ = render_room(family, seed, hard, cam)
    return Measurer(cam, None).measure(image, truth["range_m"])


def test_a_foot_on_a_weak_step_is_read_as_with_a_rig() -> None:
    eh, ew = room_size_errors("photo", 700, False, with_rig=False)
    assert eh < 0.05 and ew < 0.05


def test_the_face_is_reported_unsure() -> None:
    found = _measured("photo", 700, False)
    assert found.detected and (found.confidence or 0.0) < 0.5
    assert PITCH_UNREAD in found.doubts


def test_without_the_rule_the_face_is_missed(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "KNOWN_RIG_ROWS", False)
    assert not _measured("photo", 700, False).detected
    assert not _measured("procedural", 144, True).detected


def test_three_pitches_agree_on_the_face() -> None:
    eh, ew = room_size_errors("procedural", 144, True, with_rig=False)
    assert eh < 0.05 and ew < 0.05


def test_two_agreeing_readings_take_the_row_below(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "KNOWN_RIG_AGREE", 2)
    _, ew = room_size_errors("procedural", 144, True, with_rig=False)
    assert ew > 0.2


def test_four_agreeing_readings_are_too_many(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "KNOWN_RIG_AGREE", 4)
    monkeypatch.setattr(measure, "SIDE_BAND_ROWS", False)  # (a side band's row agrees 4 times)
    monkeypatch.setattr(measure, "REFINED_ROWS", False)  # (so does a row by its foot: 3 %)
    assert not _measured("procedural", 144, True).detected


def test_a_face_doubted_on_every_count_stays_refused() -> None:
    assert not _measured("photo", 2085, True).detected


def test_a_stream_rests_after_a_frame_it_found_nothing_on(monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[int] = []
    read = Measurer._known_rig_rows

    def counting(self: Measurer, *args: Any) -> Measurement | None:
        calls.append(1)
        return read(self, *args)

    monkeypatch.setattr(Measurer, "_known_rig_rows", counting)
    cam = CameraModel.paper(500, 375)
    measurer = Measurer(cam, None)
    blank = np.full((375, 500, 3), 128, np.uint8)
    for _ in range(measure.SWEEP_REST_FRAMES + 2):
        assert not measurer.measure(blank, 2.0).detected
    assert len(calls) == 2  # the first frame and the one after the rest


# Side bands (``measure.SIDE_BAND_ROWS``): photo 702 (hard) has a grey stripe down the face
# on the beam's axis, of the floor's shade: the axis band shows no step at the face's foot
# (row 201), the bands a width either side do. That row is so near the horizon that pitches
# -2 and 0 put the lens under the floor's minimum; read at 6 and 8 degrees instead, the four
# readings agree on the face. Photo 723 (ordinary): the foot row (237) is a side band's step
# only. Photo 747 (ordinary): a side band's step (row 197) stands a pole 23 px wide that does
# not span that band: not taken.


def test_a_foot_shown_beside_the_axis_is_read() -> None:
    eh, ew = room_size_errors("photo", 702, True, with_rig=False)
    assert eh < 0.05 and ew < 0.05
    eh, ew = room_size_errors("photo", 723, False, with_rig=False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_side_bands_those_faces_are_missed(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "SIDE_BAND_ROWS", False)
    monkeypatch.setattr(measure, "REFINED_ROWS", False)  # (723 o's row 237 is a step's neighbour)
    assert not _measured("photo", 702, True).detected
    assert not _measured("photo", 723, False).detected


@pytest.mark.parametrize(("step", "found"), [(4.0, True), (4.5, False)])
def test_a_row_near_the_horizon_is_read_at_steeper_pitches(
    monkeypatch: pytest.MonkeyPatch, step: float, found: bool
) -> None:
    # 4 + 4 = 8 degrees is the steepest pitch the search allows (MAX_ESTIMATED_PITCH_DEG):
    # a step over 4 leaves row 201 two readings, under KNOWN_RIG_AGREE
    monkeypatch.setattr(measure, "SIDE_BAND_PITCH_STEP_DEG", step)
    assert _measured("photo", 702, True).detected is found


def test_a_face_not_spanning_the_side_band_is_not_taken() -> None:
    assert not _measured("photo", 747, False).detected


@pytest.mark.parametrize("range_m", [0.02, 0.05])
def test_a_band_beside_the_axis_past_the_image_is_not_read(range_m: float) -> None:
    # so near, the bands one band width either side of the axis lie outside the view: a
    # miss with its reason, not an error from an empty band (cv2.remap's empty map)
    blank = np.full((375, 500, 3), 128, np.uint8)
    result = Measurer(CameraModel.paper(500, 375), None).measure(blank, range_m)
    assert not result.detected and "floor contact" in result.reason


def test_a_face_spans_a_band_within_the_slack() -> None:
    # the band's columns mapped to the input image: a box reaching them within
    # BAND_SPAN_SLACK_PX spans it, a box a tenth of a pixel short of that does not
    slack = measure.BAND_SPAN_SLACK_PX
    box = (100.0, 50.0, 200.0, 120.0)
    assert measure._spans_band(box, [100.0 - slack, 200.0 + slack])
    assert not measure._spans_band(box, [100.0 - slack - 0.1, 150.0])
    assert not measure._spans_band(box, [150.0, 200.0 + slack + 0.1])
    assert not measure._spans_band(None, [150.0, 160.0])
