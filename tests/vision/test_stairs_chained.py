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
    LOW_H,
    LOW_LEFT,
    LOW_RIGHT,
    LOW_TOP,
    LOW_W,
    low_box_front_row,
    measured_room,
)

#: The drawn staircase: a line behind the box on LOW_TOP (a platform's edge, running on
#: past its sides), the box's top face from BACK to FRONT (a short one: its back edge
#: spans the face within 3 columns), the front under it. From LOW_TOP the reach is 36
#: rows (40 to the horizon's 2/3, 0.3 of the 120-row face): the back edge (32) lies in
#: it, the front top edge (39, its blur 37) past it; from the back edge the reach is 26 rows.
BACK, FRONT = LOW_TOP + 32, LOW_TOP + 39


def staircase(
    front: float, band: float = 90.0, face: float = 130.0, rows: tuple[int, int] = (BACK, FRONT)
) -> npt.NDArray[np.uint8]:
    """A dark wall (50) over LOW_TOP, the background's ``band`` under it to the floor, the
    box's top ``face`` from ``rows[0]`` and its front ``front`` from ``rows[1]``; floor
    under LOW_BOTTOM; blurred as by the optics."""
    img = np.full((LOW_H, LOW_W), 50.0)
    img[LOW_TOP:] = band
    img[LOW_BOTTOM:] = 60.0
    img[rows[0] : LOW_BOTTOM, LOW_LEFT:LOW_RIGHT] = face
    img[rows[1] : LOW_BOTTOM, LOW_LEFT:LOW_RIGHT] = front
    return optics(img)


def optics(img: npt.NDArray[np.float64]) -> npt.NDArray[np.uint8]:
    """``img`` blurred as by the optics, with the sensor's noise (one fixed draw), in
    8 bits."""
    rng = np.random.default_rng(11)
    blurred = np.asarray(cv2.GaussianBlur(img, (0, 0), 0.6), np.float64)
    noisy = blurred + rng.normal(0, 1.0, img.shape)
    return np.clip(noisy, 0, 255).astype(np.uint8)


def front_row(img: npt.NDArray[np.uint8], horizon_known: bool = True) -> int:
    """The front top edge :func:`.top.front_top` finds under LOW_TOP in ``img`` (the
    horizon known unless told: as with the rig given)."""
    return low_box_front_row(img, horizon_known)


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


def test_a_staircase_down_under_a_rising_top_is_not_read_on() -> None:
    """The top edge rising (wall 50, band 150), the step taken falling (a top face of 110,
    a bump's fall, see ``top._front_step``) and the front falling again (70): two steps
    alike but not of the top edge's sign, no staircase up from the wall; the step taken
    stays."""
    img = staircase(70.0, band=150.0, face=110.0)
    assert abs(front_row(img, horizon_known=False) - BACK) <= 1
    assert abs(front_row(img) - BACK) <= 1


def test_a_dark_front_under_a_thin_top_face_is_no_step_on() -> None:
    """A thin top face (two rows, LOW_TOP + 35 and 36) at the end of the 36-row reach from
    the line behind, over a dark front (20): the step taken is the face's back edge (34,
    its blur), and the front's fall under it, stronger, is the top edge the second search
    reads its steps' sign from; that search takes the fall (37), which steps the other way
    from the step taken (no staircase): the step taken stays."""
    rows = (LOW_TOP + 35, LOW_TOP + 37)
    img = staircase(20.0, rows=rows)
    assert front_row(img, horizon_known=False) == LOW_TOP + 34
    assert front_row(img) == LOW_TOP + 34


def test_a_falling_step_under_a_rising_top_is_no_staircase() -> None:
    """The top rising (wall 50, band 90 from row 26, six rows under the horizon: a reach
    of 4 rows), a darker face falling (40) three rows under it and its front falling
    again (10) four rows further, past the reach: the top edge's peak, read two rows
    either side of the top, is the fall's (stronger), so the step taken has the peak's
    sign but not the top row's. No staircase up from the wall: the step taken stays
    (new6 photo/3287 hard with the rig, read on down the step's own tail, 1.0 -> 6.2 %)."""
    t = 26
    img = np.full((LOW_H, LOW_W), 50.0)
    img[t:] = 90.0
    img[LOW_BOTTOM:] = 60.0
    img[t + 3 : LOW_BOTTOM, LOW_LEFT:LOW_RIGHT] = 40.0
    img[t + 7 : LOW_BOTTOM, LOW_LEFT:LOW_RIGHT] = 10.0
    drawn = optics(img)
    assert low_box_front_row(drawn, False, t) == t + 3
    assert low_box_front_row(drawn, True, t) == t + 3


def test_a_staircase_down_under_a_bright_band_is_not_read_on() -> None:
    """The top row falling (wall 90, a dark line of 70 two rows high), the band under it
    rising strongly (150: the top edge's peak, read two rows either side of the top), the
    top face falling (110, a bump's fall) and the front falling again (70): two falls
    alike, of the top row's sign but not of the peak's; the step taken stays."""
    img = np.full((LOW_H, LOW_W), 90.0)
    img[LOW_TOP:] = 70.0
    img[LOW_TOP + 2 :] = 150.0
    img[LOW_BOTTOM:] = 60.0
    img[BACK:LOW_BOTTOM, LOW_LEFT:LOW_RIGHT] = 110.0
    img[FRONT:LOW_BOTTOM, LOW_LEFT:LOW_RIGHT] = 70.0
    drawn = optics(img)
    assert front_row(drawn, horizon_known=False) == BACK
    assert front_row(drawn) == BACK


def test_with_no_rig_the_staircase_is_not_read_on() -> None:
    """A trial's horizon is a guessed pitch's: the reach is a guess, the step taken stays
    (procedural 104 hard with no rig was read on down a text print's lines, 7 -> 20 %)."""
    assert abs(front_row(staircase(170.0), horizon_known=False) - BACK) <= 1
