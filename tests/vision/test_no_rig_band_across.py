"""With no rig, a face reported that is a band running across a nearer, taller face (a
wall's band seen on both sides of the box in front of it, read as a face across the box's
own surface) gives way to that nearer face on the beam's axis (``measure._band_across``,
``measure.NEARER_ACROSS_BAND``, in ``Measurer._nearer_on_axis``)."""

from __future__ import annotations

import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.measure import Measurer, _band_across

from tests.vision.test_rig_source_and_clipping import CAM

BAND = (100.0, 100.0, 300.0, 130.0)  # 200 px wide, 30 px tall


@pytest.mark.parametrize(
    "face",
    [
        (150.0, 70.0, 250.0, 160.0),  # 90 px tall: 3 times the band
        (150.0, 99.0, 250.0, 159.0),  # 60 px: twice (ACROSS_TALLER), at the limit
        (100.0, 70.0, 300.0, 160.0),  # as wide as the band
    ],
)
def test_a_band_across_a_taller_face_in_front(face: tuple[float, float, float, float]) -> None:
    assert _band_across(BAND, face)


@pytest.mark.parametrize(
    "face",
    [
        (150.0, 99.5, 250.0, 158.5),  # 59 px: under twice the band
        (90.0, 70.0, 250.0, 160.0),  # the face reaches past the band's left side
        (150.0, 70.0, 310.0, 160.0),  # ... past its right side
        (150.0, 100.0, 250.0, 190.0),  # no higher than the band's top: under it
        (150.0, 40.0, 250.0, 130.0),  # no lower than the band's foot: behind or on it
    ],
)
def test_no_band_across_another_face(face: tuple[float, float, float, float]) -> None:
    assert not _band_across(BAND, face)


def test_the_limit_is_the_constant(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "ACROSS_TALLER", 2.1)
    assert not _band_across(BAND, (150.0, 99.0, 250.0, 159.0))


def test_with_no_rig_photo_718_hard_is_the_box_not_the_band_behind_it(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """photo 718 hard: a dark print box before a wall whose orange band runs behind it; a
    row on the band's foot stood a face across the box (h -78 %, w +140 %), while the box
    itself, unsure, stood on its own foot on a lower row. With the rule the box is
    measured; with the rule off the band is back."""
    image, truth, _ = render_room("photo", 718, True, CAM)
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected and res.height_m is not None and res.width_m is not None, res.reason
    assert res.height_m == pytest.approx(truth["height_m"], rel=0.05)
    assert res.width_m == pytest.approx(truth["width_m"], rel=0.05)
    monkeypatch.setattr(measure, "NEARER_ACROSS_BAND", False)
    off = Measurer(CAM, None).measure(image, truth["range_m"])
    assert off.detected and off.width_m is not None
    assert off.width_m > 2.0 * truth["width_m"]
