"""With no rig, a reading that encloses the found face (``measure._encloses_print``) is the
face a print lies on only where it is one surface up to its top
(``measure.AGAIN_ENCLOSE_ONE_SURFACE``): a print's face has the print's margin, its own
colour, above the print as below it, so a reading whose top band looks like the
background above it rather than like its face (TOP_BAND_UNLIKE_FACE, the found face
carrying no such doubt) took in what stands behind in line with it.

Procedural 3244 (hard, the new5 rooms), measured with no rig: a pink gloss box before a
stool's dark blue frame and a green pole; the search found the box whole (-7 %, 0.25),
read again with its estimated rig the box, frame and pole as one face round it, its top
on the frame's rail (+118 % high, +66 % wide, doubting its top band).
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.fused.confidence import TOP_BAND_UNLIKE_FACE
from obstacle_fusion.vision.measure import Measurement

from tests.vision_fixtures import room_size_errors


def test_the_box_found_whole_stays() -> None:
    eh, ew = room_size_errors("procedural", 3244, True, with_rig=False)
    assert eh < 0.08 and ew < 0.03


def test_without_the_rule_the_frame_behind_is_taken_in(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "AGAIN_ENCLOSE_ONE_SURFACE", False)
    eh, ew = room_size_errors("procedural", 3244, True, with_rig=False)
    assert eh > 1.0 and ew > 0.5


def _face(box: tuple[float, float, float, float], doubts: list[str] | None = None) -> Measurement:
    x0, y0, x1, y1 = box
    return Measurement(
        detected=True, method="fused", range_m=2.0, box_px=box, confidence=0.3,
        height_px=y1 - y0, width_px=x1 - x0, height_m=0.4, width_m=0.5,
        doubts=doubts or [],
    )  # fmt: skip


FOUND = (100.0, 150.0, 200.0, 190.0)
AROUND = (95.0, 100.0, 205.0, 195.0)


def test_a_top_band_unlike_the_face_is_no_margin() -> None:
    assert measure._encloses_print(_face(FOUND), _face(AROUND))
    assert not measure._encloses_print(_face(FOUND), _face(AROUND, [TOP_BAND_UNLIKE_FACE]))
    # the doubt is the reading's anew only: a found face doubting its top band as well
    doubted = _face(FOUND, [TOP_BAND_UNLIKE_FACE])
    assert measure._encloses_print(doubted, _face(AROUND, [TOP_BAND_UNLIKE_FACE]))
    # ... and a found face's doubt alone does not refuse the reading
    assert measure._encloses_print(doubted, _face(AROUND))


def test_the_switch_off_takes_the_reading_again(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "AGAIN_ENCLOSE_ONE_SURFACE", False)
    assert measure._encloses_print(_face(FOUND), _face(AROUND, [TOP_BAND_UNLIKE_FACE]))
