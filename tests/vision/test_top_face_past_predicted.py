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

from collections.abc import Sequence

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import confidence as conf_mod
from obstacle_fusion.vision.fused import method as method_mod
from obstacle_fusion.vision.fused.confidence import (
    TOP_FACE_STEP,
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


def test_with_no_rig_the_predicted_branch_is_not_taken(monkeypatch: pytest.MonkeyPatch) -> None:
    """The rule needs the rig (``self._rig_given``): photo 3018 ordinary reads the band from
    a predicted top with the rig (PREDICTED_TOP_GAP), and with no rig (the horizon a
    guessed pitch's) never; without the guard its no-rig trials read it too (a band 20
    levels clear on one of them), though the answer kept is the same."""
    gaps: list[float] = []
    real = method_mod.top_face_band

    def spy(
        image: npt.NDArray[np.uint8],
        lines: Sequence[tuple[float, float, float, float]],
        gap: float = conf_mod.TOP_FACE_GAP,
    ) -> tuple[float, float] | None:
        gaps.append(gap)
        return real(image, lines, gap=gap)

    monkeypatch.setattr(method_mod, "top_face_band", spy)
    image, truth, spec = render_room("photo", 3018, False, CAM)
    Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    assert method_mod.PREDICTED_TOP_GAP in gaps
    gaps.clear()
    Measurer(CAM, None).measure(image, truth["range_m"])
    assert method_mod.PREDICTED_TOP_GAP not in gaps


def test_the_band_must_be_a_step_clear(monkeypatch: pytest.MonkeyPatch) -> None:
    """Photo 3212's band is 22.0 levels clear (``band[0]``): the predicted top moves with
    a least step (TOP_FACE_STEP in the branch) of 22.0, not with one a tenth over."""
    monkeypatch.setattr(method_mod, "TOP_FACE_STEP", 22.0)
    assert abs(_measured()[0]) < 0.02
    monkeypatch.setattr(method_mod, "TOP_FACE_STEP", 22.1)
    assert _measured()[0] > 0.05


@pytest.mark.parametrize(("gap", "found"), [(0.5, True), (1.5, False)])
def test_a_band_under_a_row_inside_it(gap: float, found: bool) -> None:
    """A drawn lid on rows 100-102 of a grey face (its top line at 100), the top taken
    at 101.4, inside the lid: from 0.5 rows under it the lid's last row (102) is read and
    its step to the face at 103; from 1.5 rows under (row 103 on) no band is left: no row
    read is lighter than the face, and the end given is under the last row read (101 +
    15 rows' reach + 1 past it, TOP_FACE_PAST_REACH)."""
    img = _lid_image(GREY_FACE + 6.0, rows=(100, 103))
    band = top_face_band(img, _top_at(101.4), gap=gap)
    assert band is not None
    assert (band[0] >= TOP_FACE_STEP) is found
    if found:
        assert band[1] == pytest.approx(102.5)
    else:
        assert band == (0.0, pytest.approx(117.5))


def _top_at(vt: float) -> list[tuple[float, float, float, float]]:
    """LINES (a face on rows 100-200, columns 150-350) with its top line at row ``vt``."""
    return [LINES[0], (150.0, vt, 350.0, vt), (150.0, 200.0, 150.0, vt), (350.0, 200.0, 350.0, vt)]


@pytest.mark.parametrize(("vt", "found"), [(101.4, True), (108.4, False), (109.4, False)])
def test_a_top_predicted_deep_inside_the_band_is_not_read(vt: float, found: bool) -> None:
    """The limit (README, PREDICTED_TOP_GAP): the colour above the top is read 3 to 6 rows
    above the row given (FOOT_BAND_GAP, FOOT_BAND_MIN_ROWS); a predicted row more than 3
    rows under the band's first row reads the band itself there, the band's rows differ
    from no mix of "above" and the face, and no band is found (the top stays where
    predicted). A drawn lid on rows 100-109: from 101.4 it ends at 109.5; from 108.4 or
    109.4 nothing."""
    img = _lid_image(GREY_FACE + 6.0, rows=(100, 110))
    band = top_face_band(img, _top_at(vt), gap=0.5)
    assert band is not None
    assert (band[0] >= TOP_FACE_STEP) is found
    if found:
        assert band[1] == pytest.approx(109.5)


SMALL = [(150.0, 112.0, 350.0, 112.0), (150.0, 100.0, 350.0, 100.0)] + [
    (150.0, 112.0, 150.0, 100.0),
    (350.0, 112.0, 350.0, 100.0),
]


@pytest.mark.parametrize("past", [True, False])
@pytest.mark.parametrize(("end", "read"), [(104, True), (105, False)])
def test_a_small_face_reads_no_row_past_its_floor(
    monkeypatch: pytest.MonkeyPatch, past: bool, end: int, read: bool
) -> None:
    """TOP_FACE_PAST_REACH adds its row to the reach term only: a 12-row face (top line at
    100) reaches round(0.15 * 12) + 1 = 3 rows (to 103), its floor TOP_FACE_MIN_ROWS from
    row 102 (to 104) is the larger and is left as it was. A lid ending on row 103 shows
    its step on row 104; one ending on 104, the last row read, shows none, with the switch
    or without."""
    assert conf_mod.TOP_FACE_MIN_ROWS == 3
    monkeypatch.setattr(conf_mod, "TOP_FACE_PAST_REACH", past)
    img = _lid_image(GREY_FACE + 6.0, rows=(101, end))
    assert (top_face_doubts(img, SMALL, True) == [TOP_FACE_UNDER_TOP]) is read


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
