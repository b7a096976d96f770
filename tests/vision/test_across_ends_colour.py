"""The face's top line across the search's pair (``extent.top_line_across``) is its top
only where the face's colour ends on that row (``method.ACROSS_ENDS_COLOUR``,
``method._across_ends_colour``, ``ACROSS_COLOUR_STEP``): a face's top edge parts the
face from what is above it, a panel joint across the face has the face's own colour on
both sides of it.

The rooms are diagnosis rooms, measured with the rig. Procedural 3307 (ordinary): a tan
face of three panels, a horizontal joint across it 38 % of the way up; the search found
the right top between two vertical joints (243-268, top 192), the joint's line across
then ran on past both joints to the face's sides and was taken for the top (colour step
2.6 Lab), -48 %; with the rule +0.9 %. Photo 3249 (ordinary, new5), the room the top
line across was made for (its line steps >= 12 Lab), keeps its answer. Procedural 2002
(ordinary), a joint across a face in line with a band behind (see
test_fused_lines_end_together.py), steps 4.2 Lab on the joint's row: the rule refuses
it by itself too (the run-on check ``extent.ACROSS_ABOVE_SHARE`` refuses it first). The
limit lies between the two rooms' steps: over 4.2 (2002's joint) and at most 12 (3249's
line; top_agreement's reading is capped at ``TOP_STEP_FULL``, so a limit over it
refuses every line).
"""

from __future__ import annotations

import numpy as np
import pytest
from obstacle_fusion.vision.fused import extent, method
from obstacle_fusion.vision.fused.method import _across_ends_colour
from obstacle_fusion.vision.fused.region import TOP_STEP_FULL

from tests.vision_fixtures import room_size_errors


def test_the_joint_across_the_panels_is_no_top() -> None:
    eh, ew = room_size_errors("procedural", 3307, False)
    assert eh < 0.03 and ew < 0.03


def test_without_the_rule_the_joint_is_taken(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method, "ACROSS_ENDS_COLOUR", False)
    eh, ew = room_size_errors("procedural", 3307, False)
    assert eh > 0.4 and ew < 0.03


def test_the_top_line_the_rule_was_made_for_stays() -> None:
    eh, ew = room_size_errors("photo", 3249, False)
    assert eh < 0.03 and ew < 0.05


def test_the_rule_by_itself_refuses_the_joint_in_line_with_a_band(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # procedural/2002: the run-on check off, the joint's row steps 4.2 Lab only
    monkeypatch.setattr(extent, "ACROSS_ABOVE_SHARE", 1.0)
    eh, ew = room_size_errors("procedural", 2002, False)
    assert eh < 0.05 and ew < 0.05


def test_a_limit_under_that_joints_step_takes_it(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(extent, "ACROSS_ABOVE_SHARE", 1.0)
    monkeypatch.setattr(method, "ACROSS_COLOUR_STEP", 4.0)  # under 2002's 4.2
    eh, _ = room_size_errors("procedural", 2002, False)
    assert eh > 0.25


def test_a_limit_over_a_full_step_refuses_the_faces_own_top(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # photo/3249's line steps >= 12, read capped at TOP_STEP_FULL: no line is taken
    monkeypatch.setattr(method, "ACROSS_COLOUR_STEP", TOP_STEP_FULL + 0.5)
    eh, _ = room_size_errors("photo", 3249, False)
    assert eh > 0.25


@pytest.mark.parametrize(
    ("step", "taken"),
    [
        (method.ACROSS_COLOUR_STEP, True),  # a step of ACROSS_COLOUR_STEP ends the colour
        (method.ACROSS_COLOUR_STEP - 0.01, False),  # a hair under it: a joint
        (TOP_STEP_FULL, True),
        (0.0, False),
    ],
)
def test_the_limits(monkeypatch: pytest.MonkeyPatch, step: float, taken: bool) -> None:
    seen = np.zeros((40, 40, 3), np.uint8)
    read: list[tuple[int, int, int]] = []

    def agreement(image: object, view: object, top: int, left: int, right: int) -> float:
        read.append((top, left, right))
        return min(1.0, step / TOP_STEP_FULL)

    monkeypatch.setattr(method, "top_agreement", agreement)
    assert _across_ends_colour(seen, None, (20, 5, 35)) is taken  # type: ignore[arg-type]
    assert read == [(20, 5, 35)]  # the line's own row, between the sides it ends at


def test_the_constant_is_half_a_full_step() -> None:
    # a face's own top reaches TOP_STEP_FULL; a joint's rows differ by grain only
    assert method.ACROSS_COLOUR_STEP == 6.0 == TOP_STEP_FULL / 2


def test_with_the_switch_off_every_line_passes(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method, "ACROSS_ENDS_COLOUR", False)
    monkeypatch.setattr(method, "top_agreement", lambda *a: 0.0)
    seen = np.zeros((40, 40, 3), np.uint8)
    assert _across_ends_colour(seen, None, (20, 5, 35))  # type: ignore[arg-type]
