"""With the rig, a front top row predicted from a top face's back edge (``top.front_from_back``,
taken from the prediction alone: no edge of its own near it) is moved down to where the
top face's band of the face's colour ends (``method.TOP_FACE_PAST_PREDICTED``,
``PREDICTED_TOP_GAP``): the prediction scales the back edge's row by the share of the
face's width its ends span, and those ends are read where the edge fades at the blurred
corners; the band shows where the top face ends.

The room is a diagnosis room (new5), measured with the rig. Photo 3212 (ordinary): a
purple plank box 0.16 m tall at 1.69 m, its top face two rows of the face's colour 1.26
times lighter; the back edge's ends gave a scale of 0.948 and a front top row 1.9 rows
above the band's end: +5.3 % high at 0.94; with the rule +1.1 % (confidence unchanged).

Also the band's reading window one row past its reach (``confidence.TOP_FACE_PAST_REACH``):
photo 3217 ordinary, whose top face ends on the reach's last row.
"""

from __future__ import annotations

import numpy as np
import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import confidence as conf_mod
from obstacle_fusion.vision.fused import method as method_mod
from obstacle_fusion.vision.fused.confidence import (
    TOP_FACE_UNDER_TOP,
    top_face_band,
    top_face_doubts,
)
from obstacle_fusion.vision.measure import Measurer

from tests.vision.test_fused_confidence import GREY_FACE, LINES, _lid_image

CAM = CameraModel.paper(500, 375)


def _measured(with_rig: bool = True) -> tuple[float, float, float, list[str]]:
    """Photo 3212 ordinary: (height error, width error, confidence, doubts)."""
    image, truth, spec = render_room("photo", 3212, False, CAM)
    res = Measurer(CAM, spec.rig if with_rig else None).measure(image, truth["range_m"])
    assert res.detected and res.height_m is not None and res.width_m is not None
    assert res.confidence is not None
    return (
        res.height_m / truth["height_m"] - 1,
        res.width_m / truth["width_m"] - 1,
        res.confidence,
        res.doubts,
    )


def test_the_predicted_top_moves_to_the_band_s_end() -> None:
    eh, ew, conf, doubts = _measured()
    assert abs(eh) < 0.02 and abs(ew) < 0.02
    assert conf > 0.9 and TOP_FACE_UNDER_TOP not in doubts


def test_without_the_rule_the_top_face_is_measured_sure(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method_mod, "TOP_FACE_PAST_PREDICTED", False)
    eh, _, conf, _ = _measured()
    assert eh > 0.05 and conf > 0.9


def test_the_band_is_read_from_half_a_row_under_the_predicted_top(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The predicted row lies inside the band (its rows 186-188 of the input); read from
    1.5 rows under it (TOP_FACE_GAP, an edge's blur) the band's rows are passed over."""
    assert method_mod.PREDICTED_TOP_GAP == 0.5
    monkeypatch.setattr(method_mod, "PREDICTED_TOP_GAP", 1.5)
    eh, _, _, _ = _measured()
    assert eh > 0.05


def test_the_move_keeps_the_least_move(monkeypatch: pytest.MonkeyPatch) -> None:
    """The band ends 1.9 rows under the predicted top: a least move
    (TOP_FACE_MIN_MOVE_PX) of 1.8 rows moves it, 2.0 not."""
    monkeypatch.setattr(method_mod, "TOP_FACE_MIN_MOVE_PX", 1.8)
    assert abs(_measured()[0]) < 0.02
    monkeypatch.setattr(method_mod, "TOP_FACE_MIN_MOVE_PX", 2.0)
    assert _measured()[0] > 0.05


def test_with_no_rig_the_answer_is_its_own() -> None:
    # no rig: the rule stands aside (the horizon a guessed pitch's); this room's answer
    # with none is right and unsure (pitch_unread) either way
    eh, _, conf, _ = _measured(with_rig=False)
    assert abs(eh) < 0.02 and conf < 0.5


@pytest.mark.parametrize(("gap", "found"), [(0.5, True), (1.5, False)])
def test_a_band_under_a_row_inside_it(gap: float, found: bool) -> None:
    """A drawn lid on rows 100-102 of a grey face (its top line at 100), the top taken
    at 101.4, inside the lid: from 0.5 rows under it the lid's last row (102) is read and
    its step to the face at 103; from 1.5 rows under (row 103 on) no band is left."""
    img = _lid_image(GREY_FACE + 6.0, rows=(100, 103))
    lines = [LINES[0], (150.0, 101.4, 350.0, 101.4), (150.0, 200.0, 150.0, 101.4)]
    lines.append((350.0, 200.0, 350.0, 101.4))
    band = top_face_band(img, lines, gap=gap)
    assert band is not None
    assert (band[0] >= 5.0) is found
    if found:
        assert band[1] == pytest.approx(102.5)
    assert np.isfinite(band[1])


# --- TOP_FACE_PAST_REACH (confidence.py): the band read one row past the reach ---------


def _room(family: str, seed: int, hard: bool) -> float:
    image, truth, spec = render_room(family, seed, hard, CAM)
    res = Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    assert res.detected and res.height_m is not None
    return float(res.height_m / truth["height_m"] - 1)


def test_a_top_face_ending_on_the_reach_s_last_row_is_read() -> None:
    """Photo 3217 ordinary, rig: a plain blue box 0.18 m tall at 2.33 m, 0.13 m under the
    lens; its top face (rows 226-231, 4.3-4.7 levels lighter, the face's colour scaled)
    ends between rows 231 and 232, the reach (15 % of 42 rows) on row 231: read one row
    past it, the step shows and the face is measured from its front top edge (+19.6 % at
    0.68 -> +2.7 %)."""
    assert abs(_room("photo", 3217, False)) < 0.04


def test_without_reading_past_the_reach_the_top_face_stays(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(conf_mod, "TOP_FACE_PAST_REACH", False)
    assert _room("photo", 3217, False) > 0.15


@pytest.mark.parametrize("past", [True, False])
def test_a_drawn_band_ending_on_the_reach_s_row(
    monkeypatch: pytest.MonkeyPatch, past: bool
) -> None:
    """A drawn lid on rows 101-115 of a 100-row face (its top line at 100, the reach 15
    rows: row 115), the face's grey from row 116: read to 116 the step shows; read to
    115 (without the switch) the band runs on to the last row read, no step."""
    monkeypatch.setattr(conf_mod, "TOP_FACE_PAST_REACH", past)
    doubts = top_face_doubts(_lid_image(GREY_FACE + 6.0, rows=(101, 116)), LINES, True)
    assert (doubts == [TOP_FACE_UNDER_TOP]) is past
