"""A side standing on the contact row still comes in to the face's widest foot where the
columns between show no step from the floor (``region.NO_FOOT_BESIDE``,
``NO_FOOT_BESIDE_SHARE``, in ``region.trim_to_foot``).

The rooms (new10 photo 3497 ordinary, new7 photo 3319 hard, 3341 ordinary): a narrow post
before a band along the wall's foot; the search took the band's end or a frame's leg for
the far side, which stands on the gravel's texture at the contact row. The floor's chroma
is the face's (a dim photograph), so ``FLOOR_BETWEEN`` cannot see the floor between; the
walk from the step nearest the pair's middle started on a glare's blip. Here: a grey face
60 columns wide (0.2 m at 1 m) on a grey floor, a dark pole standing down to the contact
row 80 columns right of it, a blue wall between.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import region

from tests.vision.test_fused_region import BOTTOM, FLOOR, LEFT, POLE, TOP, trim

FACE_RIGHT = LEFT + 60
POLE_AT = FACE_RIGHT + 80
WALL_BLUE = (160, 90, 60)  # BGR


def post_and_pole(blips: int = 0, gap_foot: int = 0) -> npt.NDArray[np.uint8]:
    """The grey post LEFT..FACE_RIGHT, light in the floor's chroma, on the grey floor; the
    blue wall above the floor elsewhere; a dark pole at POLE_AT standing on the contact row.
    ``blips``: a 3-column glare at the foot that many columns right of the post (no face);
    ``gap_foot``: that many columns, 30 right of the post, given a foot step (a light
    strip just above the contact row: a band's broken foot)."""
    rng = np.random.default_rng(3)
    img = np.empty((240, 320, 3), np.float64)
    img[:BOTTOM] = WALL_BLUE
    img[BOTTOM - 12 : BOTTOM] = FLOOR  # the floor seen up to the wall's foot
    img[BOTTOM:] = FLOOR
    img[TOP:BOTTOM, LEFT:FACE_RIGHT] = (190, 190, 190)
    img[TOP - 20 : BOTTOM, POLE_AT : POLE_AT + 6] = POLE
    if blips:
        img[BOTTOM - 8 : BOTTOM, FACE_RIGHT + blips : FACE_RIGHT + blips + 3] = (230, 230, 230)
    if gap_foot:
        img[BOTTOM - 8 : BOTTOM, FACE_RIGHT + 30 : FACE_RIGHT + 30 + gap_foot] = (190, 190, 190)
    img += rng.normal(0, 8.0, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def test_the_pole_beyond_the_foot_comes_in() -> None:
    left, right = trim(post_and_pole(), LEFT, POLE_AT)
    assert left == LEFT and abs(right - FACE_RIGHT) <= 3


def test_a_glare_near_the_middle_does_not_start_the_walk() -> None:
    # a 3-column step 40 columns right of the post, nearer the pair's middle than the post
    left, right = trim(post_and_pole(blips=40), LEFT, POLE_AT)
    assert left == LEFT and abs(right - FACE_RIGHT) <= 3


def test_without_the_rule_the_pole_stays(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "NO_FOOT_BESIDE", False)
    assert trim(post_and_pole(), LEFT, POLE_AT) == (LEFT, POLE_AT)
    assert trim(post_and_pole(blips=40), LEFT, POLE_AT) == (LEFT, POLE_AT)


@pytest.mark.parametrize(("limit", "cut"), [(0.75, True), (0.8, False)])
def test_the_share_without_a_foot_decides(
    monkeypatch: pytest.MonkeyPatch, limit: float, cut: bool
) -> None:
    # a 12-column strip of foot 30 columns right of the post (its step blurred over 18 of
    # the 79 columns between the post and the pole): 0.77 of them without a foot, over
    # 0.75 and under 0.8; a 14-column one (0.75) is not cut at the default
    monkeypatch.setattr(region, "NO_FOOT_BESIDE_SHARE", limit)
    left, right = trim(post_and_pole(gap_foot=12), LEFT, POLE_AT)
    assert left == LEFT
    assert (abs(right - FACE_RIGHT) <= 3) if cut else right == POLE_AT


def test_a_wider_broken_foot_keeps_the_pole() -> None:
    assert trim(post_and_pole(gap_foot=14), LEFT, POLE_AT) == (LEFT, POLE_AT)
