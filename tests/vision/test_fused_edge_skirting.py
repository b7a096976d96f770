"""The edge search's top carried past a skirting's edge behind the face
(``method.EDGE_SKIRTING_WALK``, ``region.raise_top_past_band`` with ``runs_on``).

The rooms are tuning rooms (procedural and photo, seeds 100-159, 700-759, 2000-2099):
procedural 2033 is a brick print with a teal margin before an orange skirting; the edge
search found the margin's foot and the frame-rail raise stopped at the skirting's top
(height -70 %). Photo 713 (hard) is a grey print inside a purple frame a few columns wide:
the frame's margin beside the print's sides is no band running on along the wall.
Procedural 137 is a framed face whose band walk stops at the print's top: with the lesser
of the two tops' agreements the surer colour rescue is kept.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import method, region

from tests.vision.test_fused_skirting import (
    BAND,
    BAND_TOP,
    BOTTOM,
    DEPTH,
    LEFT,
    RIGHT,
    _ay,
    _scene,
    _view,
)
from tests.vision_fixtures import room_size_errors


def test_a_top_at_a_skirtings_edge_is_carried_up() -> None:
    eh, ew = room_size_errors("procedural", 2033, False)
    assert eh < 0.1 and ew < 0.05


def test_without_the_walk_the_skirtings_edge_is_the_top(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method, "EDGE_SKIRTING_WALK", False)
    # (the outline read from the foot round the unsure short face finds it whole too)
    monkeypatch.setattr(method, "FOOT_OUTLINE", False)
    eh, _ = room_size_errors("procedural", 2033, False)
    assert eh > 0.25


def test_a_frames_margin_beside_a_print_is_no_band() -> None:
    eh, _ = room_size_errors("photo", 713, True)
    assert eh < 0.05


def test_the_band_must_run_on_as_one_colour(monkeypatch: pytest.MonkeyPatch) -> None:
    # a step this large would take the frame's margin and the floor beyond for one band
    monkeypatch.setattr(region, "BAND_RUNS_ON_STEP", 1000.0)
    eh, _ = room_size_errors("photo", 713, True)
    assert eh > 0.25


def test_the_walk_adds_no_evidence() -> None:
    # the walked top (the print's) agrees with the colours better than the first (the
    # skirting's): the lesser agreement refuses it and the colour rescue's face is kept
    eh, ew = room_size_errors("procedural", 137, False)
    assert eh < 0.05 and ew < 0.05


def _framed(margin: int) -> npt.NDArray[np.uint8]:
    """The skirting scene's face from row 120 with the wall down to the floor, the band's
    colour only in a margin ``margin`` columns wide beside each side."""
    img = _scene(120, band=False)
    img[BAND_TOP:BOTTOM, LEFT - margin : LEFT] = BAND
    img[BAND_TOP:BOTTOM, RIGHT : RIGHT + margin] = BAND
    return img


def _carried(img: npt.NDArray[np.uint8]) -> int:
    return region.raise_top_past_band(
        img, _view(), _ay(img), BOTTOM, BAND_TOP, LEFT, RIGHT, DEPTH, runs_on=True
    )


def test_a_skirting_running_on_carries_the_top() -> None:
    assert abs(_carried(_scene(120)) - 120) <= 2


@pytest.mark.parametrize("margin, carried", [(16, False), (24, True)])
def test_the_band_runs_on_band_runs_on_columns(margin: int, carried: bool) -> None:
    """The far strip lies BAND_RUNS_ON_COLUMNS (12) beyond the near one (columns 9-15 off
    the side): a margin 16 columns wide leaves it mostly on the wall, one 24 wide covers it."""
    raised = _carried(_framed(margin))
    assert abs(raised - 120) <= 2 if carried else raised == BAND_TOP


def test_a_nearer_far_strip_takes_a_margin_for_a_band(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "BAND_RUNS_ON_COLUMNS", 6)
    assert abs(_carried(_framed(16)) - 120) <= 2


def test_without_runs_on_a_margin_is_a_band() -> None:
    img = _framed(16)
    raised = region.raise_top_past_band(
        img, _view(), _ay(img), BOTTOM, BAND_TOP, LEFT, RIGHT, DEPTH
    )
    assert abs(raised - 120) <= 2
