"""A staircase step taken for the front top edge is read on from (``top.STAIRS_CHAINED``):
the top found on a line behind a low box (a background's platform edge over its top
face), :func:`.top.front_top` takes the step under it (the top face's back edge) for the
front top edge, the real front top edge lying past the reach a top face's back edge is
sought in from the line. Sought again from the step taken, a step of the same sign under
it is the front top edge; an edge of the other sign there (the front's own darker line
or an opening's edge) is no step on.

The room is a diagnosis room (new9). Photo 3438 (hard), with the rig: a pink frame box
before a photograph whose platform's edge runs 9 rows over the box's top face; the top was
taken on the top face's back edge (172), height +17 %; read on, the front top edge (178),
+1.5 %. With the rig given only: the reach is the horizon's, which a trial with no rig
guesses.
"""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import top

from tests.vision_fixtures import (
    LOW_BOTTOM,
    LOW_DEPTH,
    LOW_H,
    LOW_LEFT,
    LOW_RIGHT,
    LOW_TOP,
    LOW_W,
    low_box_view,
    measured_room,
)

#: The drawn staircase: a line behind the box on LOW_TOP (a platform's edge, running on
#: past its sides), the box's top face from BACK to FRONT (a short one: its back edge
#: spans the face within 3 columns), the front under it. From LOW_TOP the reach is 36
#: rows (40 to the horizon's 2/3, 0.3 of the 120-row face): the back edge (32) lies in
#: it, the front top edge (39, its blur 37) past it; from the back edge the reach is 26 rows.
BACK, FRONT = LOW_TOP + 32, LOW_TOP + 39


def staircase(front: float) -> npt.NDArray[np.uint8]:
    """A dark wall over LOW_TOP, the background's band (90) under it to the floor, the
    box's top face (130) and its front ``front``; floor under LOW_BOTTOM; blurred as by
    the optics."""
    rng = np.random.default_rng(11)
    img = np.full((LOW_H, LOW_W), 50.0)
    img[LOW_TOP:] = 90.0
    img[LOW_BOTTOM:] = 60.0
    img[BACK:LOW_BOTTOM, LOW_LEFT:LOW_RIGHT] = 130.0
    img[FRONT:LOW_BOTTOM, LOW_LEFT:LOW_RIGHT] = front
    blurred = np.asarray(cv2.GaussianBlur(img, (0, 0), 0.6), np.float64)
    noisy = blurred + rng.normal(0, 1.0, img.shape)
    return np.clip(noisy, 0, 255).astype(np.uint8)


def front_row(img: npt.NDArray[np.uint8], horizon_known: bool = True) -> int:
    """The front top edge :func:`.top.front_top` finds under LOW_TOP in ``img``."""
    dy = np.empty(img.shape, np.int16)
    dx = np.empty(img.shape, np.int16)
    cv2.spatialGradient(img, dx, dy)
    noise = float(np.median(np.abs(dy[::4, ::4]))) / 0.6745 + 1.0
    row, _ = top.front_top(
        low_box_view(),
        LOW_DEPTH,
        dy,
        LOW_BOTTOM,
        LOW_LEFT,
        LOW_RIGHT,
        LOW_TOP,
        noise,
        horizon_known=horizon_known,
    )
    return row


def test_the_front_top_edge_of_the_frame_box() -> None:
    res, truth = measured_room("photo", 3438, True, True)
    assert res.detected and res.height_m is not None
    assert abs(res.height_m / truth["height_m"] - 1) < 0.05


def test_without_the_rule_the_top_face_is_measured(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(top, "STAIRS_CHAINED", False)
    res, truth = measured_room("photo", 3438, True, True)
    assert res.detected and res.height_m is not None
    assert res.height_m / truth["height_m"] - 1 > 0.15


@pytest.mark.parametrize("on", [True, False])
def test_a_staircase_is_read_on(on: bool, monkeypatch: pytest.MonkeyPatch) -> None:
    """Wall, background, top face, lighter front: three steps up; the third lies past the
    reach from the line behind and is found from the second (without the rule the
    second, the top face's back edge)."""
    monkeypatch.setattr(top, "STAIRS_CHAINED", on)
    row = front_row(staircase(170.0))
    want = FRONT if on else BACK
    assert abs(row - want) <= 1


def test_a_darker_front_is_no_step_on() -> None:
    """The front darker than the top face (a top face lit from above, a bump): the edge
    under the step taken falls where the staircase rises; the step taken stays."""
    row = front_row(staircase(100.0))
    assert abs(row - BACK) <= 1


def test_with_no_rig_the_staircase_is_not_read_on() -> None:
    """A trial's horizon is a guessed pitch's: the reach is a guess, the step taken stays
    (procedural 104 hard with no rig was read on down a text print's lines, 7 -> 20 %)."""
    assert abs(front_row(staircase(170.0), horizon_known=False) - BACK) <= 1
