"""With no rig, an unsure answer found surer than SURER_TOP_RAISES allows (its raw
confidence under FAR_TOP_MAX_FOUND_CONFIDENCE) gives way to the rows' face read as with a
rig on the same foot and columns, when that face is far the surer (at least FAR_TOP_SURE
and FAR_TOP_RATIO times the answer) and its top higher by at least FAR_TOP_SHARE of the
answer's height, the rows it adds of the face's colour (``measure.FAR_TOP_RAISES``,
``measure._top_moves_far_up``, ``floor_contact.face_runs_above``).

The room is a diagnosis room (new10), measured with no rig. Photo 3465 (hard): a plain
blue box before a photo; the level trials stood its top 33 rows low (0.40 as found),
-14 % high; the rows as with a rig read the same foot and sides up to the top (0.81).
With the rule: 0.5 %.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.measure import _top_moves_far_up
from obstacle_fusion.vision.types import Measurement

from tests.vision_fixtures import room_size_errors

FOUND = (100.0, 100.0, 200.0, 200.0)  # 100 rows high: FAR_TOP_SHARE 0.1 is 10 rows
GROWN = (100.0, 80.0, 200.0, 200.0)


def _face(
    box: tuple[float, float, float, float], conf: float, lens: float | None = 0.4
) -> Measurement:
    return Measurement(True, "fused", 2.0, box_px=box, confidence=conf, camera_height_m=lens)


def test_the_plain_box_is_read_up_to_its_top() -> None:
    eh, ew = room_size_errors("photo", 3465, True, with_rig=False)
    assert eh < 0.03 and ew < 0.03


def test_without_the_rule_the_top_stays_low(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "FAR_TOP_RAISES", False)
    eh, _ = room_size_errors("photo", 3465, True, with_rig=False)
    assert eh > 0.1


def test_the_rows_it_adds_must_be_the_faces(monkeypatch: pytest.MonkeyPatch) -> None:
    # face_runs_above at the call: the rows' face taken only when the rows it adds have
    # the face's colour (here read as never so)
    monkeypatch.setattr(measure, "face_runs_above", lambda *_: False)
    eh, _ = room_size_errors("photo", 3465, True, with_rig=False)
    assert eh > 0.1


@pytest.mark.parametrize(
    ("grown", "conf", "lens", "raises"),
    [
        (GROWN, 0.8, 0.4, True),
        ((100.0, 80.0, 200.0, 202.0), 0.8, 0.4, True),  # foot ROW_JITTER_PX lower
        ((100.0, 80.0, 200.0, 202.1), 0.8, 0.4, False),  # another foot
        ((100.0, 80.0, 200.0, 197.9), 0.8, 0.4, False),  # ... higher
        ((100.0, 90.0, 200.0, 200.0), 0.8, 0.4, True),  # top FAR_TOP_SHARE higher
        ((100.0, 90.1, 200.0, 200.0), 0.8, 0.4, False),  # a few rows up: no far move
        ((100.0, 80.0, 180.0, 200.0), 0.8, 0.4, True),  # overlap 0.8 of the wider
        ((100.0, 80.0, 179.9, 200.0), 0.8, 0.4, False),  # LOWER_FOOT_SIDES_SHARE
        (GROWN, 0.6, 0.4, True),  # FAR_TOP_SURE (over 1.5 x 0.39)
        (GROWN, 0.599, 0.4, False),
        (GROWN, 0.8, 0.6, True),  # UNDER_MAX_CAMERA_HEIGHT_M
        (GROWN, 0.8, 0.61, False),
        (GROWN, 0.8, None, False),  # no lens read
    ],
)
def test_the_limits(
    grown: tuple[float, float, float, float], conf: float, lens: float | None, raises: bool
) -> None:
    assert _top_moves_far_up(_face(FOUND, 0.39), _face(grown, conf, lens)) is raises


@pytest.mark.parametrize(("found", "raises"), [(0.499, True), (0.5, False)])
def test_only_an_answer_under_the_limit(found: float, raises: bool) -> None:
    # FAR_TOP_MAX_FOUND_CONFIDENCE 0.5 on the raw confidence (the rows' face at 0.9 is
    # over FAR_TOP_RATIO times either)
    assert _top_moves_far_up(_face(FOUND, found), _face(GROWN, 0.9)) is raises


@pytest.mark.parametrize(("grown", "raises"), [(0.75, True), (0.749, False)])
def test_far_the_surer(grown: float, raises: bool, monkeypatch: pytest.MonkeyPatch) -> None:
    # FAR_TOP_RATIO 1.5: over an answer at 0.5 (the limit moved up for the check) the
    # rows' face at 0.75 at least, over FAR_TOP_SURE both
    monkeypatch.setattr(measure, "FAR_TOP_MAX_FOUND_CONFIDENCE", 0.6)
    assert _top_moves_far_up(_face(FOUND, 0.5), _face(GROWN, grown)) is raises


@pytest.mark.parametrize(("top", "raises"), [(183.0, False), (182.9, True)])
def test_a_small_faces_top_moves_past_the_jitter(top: float, raises: bool) -> None:
    # a face 15 rows high: FAR_TOP_SHARE of it is 1.5 rows, under ROW_JITTER_PX 2: a top
    # 2 rows up is the same top read again, 2.1 rows up a move
    found = _face((100.0, 185.0, 200.0, 200.0), 0.39)
    assert _top_moves_far_up(found, _face((100.0, top, 200.0, 200.0), 0.8)) is raises


def test_a_lower_top_never_raises_it() -> None:
    assert not _top_moves_far_up(_face(GROWN, 0.1), _face(FOUND, 0.9))
