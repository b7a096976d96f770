"""With no rig, a frame of one colour found round a print whose foot lies in the last
rows of the tried row's view is measured once more with the view read down past that foot
(``method.FRAME_FOOT_READ``, ``method.FRAME_FOOT_ROWS``): the face is the frame standing on
the floor, the print's lower edge only passed for the contact.

The room is a diagnosis room (new4), measured with no rig. Photo 3198 (hard): a poster
print in a green frame before a teal skirting; the rows tried stand the print (-19 / -19
%); the frame found round it on a pitched trial has its foot 2 rows from the view's end,
so it was dropped. Read down to it, the frame is the face (+2.2 / +1.2 %). Photo 3180
(hard, a text print in a thin blue frame on gravel) goes the same way (-13 -> +2.4 %).
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import method

from tests.vision_fixtures import room_size_errors


def test_the_rows_read_are_at_least_the_limit() -> None:
    # FRAME_FOOT_ROWS 4: the frame's foot then lies 4 rows over the view's end, past the
    # last 3 rows where a foot is not measured (the least that reads it; the room below)
    assert method.FRAME_FOOT_ROWS >= 4


def test_without_the_rule_the_print_stands(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method, "FRAME_FOOT_READ", False)
    eh, ew = room_size_errors("photo", 3198, True, with_rig=False)
    assert eh > 0.15 and ew > 0.15


@pytest.mark.parametrize(("rows", "read"), [(3, False), (4, True)])
def test_the_rows_read_under_the_foot(
    monkeypatch: pytest.MonkeyPatch, rows: int, read: bool
) -> None:
    # 3 rows under the foot leave it in the last 3 rows again: the frame is dropped;
    # 4 read it (the frame is the face)
    monkeypatch.setattr(method, "FRAME_FOOT_ROWS", rows)
    eh, ew = room_size_errors("photo", 3198, True, with_rig=False)
    assert (max(eh, ew) < 0.05) is read
