"""A print whose margin beside it is too thin to read, its foot taken from a tried row
(``floor_contact.MARGIN_ABOVE_PRINT``, with no rig).

Procedural 742 (hard, a tuning room) is an orange box with a teal text print over most of
its front: the orange margin is 2-3 px beside the print (blurred into the wall behind it),
11 rows above it and 14 below. With no rig, the print's own lower edge (row 236) is the
surest row; the face found on the box's foot row (249) covers it, the strip between the
two feet orange, but the columns 2-6 px beside the print read the wall: the margin did
not match and the print was answered (-18 % in both sizes). The margin above the print,
up to the lower face's top, has the strip's colour: one surface round the print."""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import floor_contact, method

from tests.vision_fixtures import room_size_errors


def test_a_print_in_a_thin_margin_gives_way_to_the_box() -> None:
    eh, ew = room_size_errors("procedural", 742, True, with_rig=False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_rule_the_print_is_answered(monkeypatch: pytest.MonkeyPatch) -> None:
    # (session 41: method.MARGIN_UNDER_TRIED_ROW encloses this print by its frame too, in
    # the trial on the print's own row; off here, so this rule alone is read)
    monkeypatch.setattr(floor_contact, "MARGIN_ABOVE_PRINT", False)
    monkeypatch.setattr(method, "MARGIN_UNDER_TRIED_ROW", False)
    eh, ew = room_size_errors("procedural", 742, True, with_rig=False)
    assert eh > 0.15 and ew > 0.15


@pytest.mark.parametrize("rows, right", [(10, True), (12, False)])
def test_the_margin_above_must_be_tall_enough(
    monkeypatch: pytest.MonkeyPatch, rows: int, right: bool
) -> None:
    """The box's top stands 10.9 px above the print's here."""
    monkeypatch.setattr(floor_contact, "MIN_ABOVE_PX", rows)
    eh, ew = room_size_errors("procedural", 742, True, with_rig=False)
    assert (eh < 0.05 and ew < 0.05) is right
