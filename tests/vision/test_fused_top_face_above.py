"""A frame's top margin under a low box's top face is the front top edge
(region.top_face_above, wired in fused/method.py after enclose_by_margin)."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import region
from obstacle_fusion.vision.fused.region import top_face_above

from tests.vision.test_fused_region import BOTTOM, FLOOR, LEFT, RIGHT, TOP, high_view, level_view

H, W = 240, 320
MARGIN = (220, 200, 150)  # BGR light blue: the frame's margin
TOP_FACE = (165, 155, 140)  # the same material lit from above: darker, greyer
WAY = 14  # rows of top face above the front top edge TOP
CY = 20.0  # the horizon of high_view: the top face recedes towards (W / 2, CY)


def framed_box(top_face: str = "converging") -> npt.NDArray[np.uint8]:
    """A light frame (margin 10) round a print of the floor's grey, TOP to BOTTOM, over a
    grey floor that also shows behind the box; above TOP, ``top_face``: "converging" (a
    top face whose sides run towards the vanishing point), "band" (another colour the
    face's full width: a band behind it), "margin" (the frame's colour the full width)
    or "none"."""
    rng = np.random.default_rng(5)
    img = np.empty((H, W, 3), np.float64)
    img[:] = FLOOR
    img[TOP:BOTTOM, LEFT:RIGHT] = MARGIN
    img[TOP + 10 : BOTTOM - 10, LEFT + 10 : RIGHT - 10] = FLOOR
    for r in range(TOP - WAY, TOP):
        if top_face == "converging":
            t = (TOP - r) / (TOP - CY)
            a = int(round(LEFT + (W / 2 - LEFT) * t))
            b = int(round(RIGHT - (RIGHT - W / 2) * t))
            img[r, a:b] = TOP_FACE
        elif top_face == "band":
            img[r, LEFT:RIGHT] = TOP_FACE
        elif top_face == "margin":
            img[r, LEFT:RIGHT] = MARGIN
    img += rng.normal(0, 3.0, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


ARGS = (BOTTOM, TOP, TOP - WAY, LEFT, RIGHT)


def test_a_top_face_seen_from_above_is_no_face() -> None:
    assert top_face_above(framed_box(), high_view(CY), *ARGS)


def test_the_face_colour_running_on_is_the_face() -> None:
    assert not top_face_above(framed_box("margin"), high_view(CY), *ARGS)


def test_a_band_the_full_width_behind_the_face_is_no_top_face() -> None:
    # its sides do not recede: the strips inside the front's sides show it too
    assert not top_face_above(framed_box("band"), high_view(CY), *ARGS)


def test_above_the_horizon_there_is_no_top_face() -> None:
    # level_view's horizon is row H / 2, under the face's top: the lens looks up at it
    assert not top_face_above(framed_box(), level_view(), *ARGS)


def test_a_long_way_up_is_not_judged() -> None:
    assert not top_face_above(framed_box(), high_view(CY), BOTTOM, TOP, TOP - 70, LEFT, RIGHT)


def test_the_colour_step_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "MIN_BESIDE_STEP", 500.0)
    assert not top_face_above(framed_box(), high_view(CY), *ARGS)
