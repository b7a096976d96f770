"""With no rig and the pitch unread, a lens looking down more than guessed sees a box's top
face above the guessed horizon. The face measured allowing for it is taken where it lowers
the guessed face's top to the front edge, however sure, and not where it raises it
(``measure.UNREAD_TOP_FACE_LOWERS``, ``measure._top_moved``).

The rooms are tuning rooms, measured with no rig. Procedural 147 (hard): panels, the lens
2.6 degrees down; the level guess reads the top face's back edge (+15 %), the allowance the
front edge at a lower confidence (+1 %). Procedural 752 (hard): the allowance raises the
top five rows onto a line above the face (+22 %), the guessed face is within 5 %.

The raised-top half of the counterfactual guards the rule with
``confidence.TOP_FACE_PAST_REACH`` off, a setting that does not ship: with it on (session
44) 752's raised top is read as a top face's back edge and moved back down by itself
(+2.2 % without the rule). No room replaces it: over the own and fresh sets (procedural
and photo, both kinds, no rig, 1,280 rooms; session 44, helper G) the rule turned away a
raised top in 9 rooms, and without it only procedural 111 h (+0.8 -> +2.9 %) and 718 h
(-1.2 -> +3.6 %, confidence 0.07 -> 0.33) moved, neither past 5 %. With the band read past
its reach, the rule's raised half is a guard no room is known to need.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.fused import confidence as conf_mod
from obstacle_fusion.vision.measure import _top_moved

from tests.vision_fixtures import room_size_errors

BOX = (100.0, 50.0, 200.0, 120.0)


def test_a_lowered_top_face_front_is_taken() -> None:
    eh, ew = room_size_errors("procedural", 147, True, with_rig=False)
    assert eh < 0.03 and ew < 0.03


def test_a_raised_top_is_not_taken() -> None:
    eh, ew = room_size_errors("procedural", 752, True, with_rig=False)
    assert eh < 0.06 and ew < 0.03


def test_without_the_rule_the_back_edge_and_the_raised_top_stand(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(measure, "UNREAD_TOP_FACE_LOWERS", False)
    eh, _ = room_size_errors("procedural", 147, True, with_rig=False)
    assert eh > 0.10
    # 752's raised top stands only with the top face's band read no further than its
    # reach: read one row past it (confidence.TOP_FACE_PAST_REACH, session 44) the band
    # under the raised top is found and the top moved back down (+2.2 %)
    monkeypatch.setattr(conf_mod, "TOP_FACE_PAST_REACH", False)
    eh, _ = room_size_errors("procedural", 752, True, with_rig=False)
    assert eh > 0.15


@pytest.mark.parametrize(
    ("again", "moved"),
    [
        ((100.0, 51.5, 200.0, 120.0), None),  # a top a pixel and a half off: the same top
        ((100.0, 51.6, 200.0, 120.0), -1.6),  # lowered just past the limit
        ((100.0, 48.4, 200.0, 120.0), 1.6),  # raised just past it
        ((103.0, 55.0, 197.0, 120.0), -5.0),  # sides 3 columns in: one face
        ((103.1, 55.0, 200.0, 120.0), None),  # a side past them: another face
        ((100.0, 55.0, 203.1, 120.0), None),
        ((100.0, 55.0, 200.0, 122.0), -5.0),  # feet ROW_JITTER_PX apart: one foot
        ((100.0, 55.0, 200.0, 122.1), None),  # farther: another foot
    ],
)
def test_top_moved_limits(again: tuple[float, float, float, float], moved: float | None) -> None:
    assert measure.TOP_FACE_MOVE_PX == 1.5 and measure.TOP_FACE_SIDES_PX == 3.0
    assert measure.ROW_JITTER_PX == 2
    got = _top_moved(BOX, again)
    assert got == (None if moved is None else pytest.approx(moved))


def test_top_moved_needs_both_boxes() -> None:
    assert _top_moved(None, BOX) is None
    assert _top_moved(BOX, None) is None
