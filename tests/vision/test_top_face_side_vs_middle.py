"""A top face's band is refused for a margin running down the face's sides only where the
side strips read like the band and unlike the face's own middle over the same rows
(``confidence.TOP_FACE_SIDE_VS_MIDDLE`` in ``_band_ends_at_sides``): a stripe or a tape
across the face lies in the side strips as in the middle, and is the face, not a margin.

Found on new11 photo 3506 hard with the rig: a magenta tape box, a cyan tape across its
middle rows; the side strips' median (tape and magenta mixed) lay 12.69 from the top
face's band and 12.73 from the face read under it, the band was refused, and the top face's
back edge was measured for the top: +12.4 % at 0.61; with the rule -0.1 %.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import confidence as conf_mod
from obstacle_fusion.vision.fused.confidence import TOP_FACE_STEP, top_face_band

from tests.vision.test_fused_confidence import GREY_FACE, LINES, _lid_image

#: a stripe across the face's middle rows (130-170 of the face's 100-200), of another
#: hue, nearer the lid's colour (GREY_FACE + 10) than the face's
STRIPE = np.array([125.0, 95.0, 125.0])


def _striped(margin: bool = False) -> npt.NDArray[np.uint8]:
    """A grey face (rows 100-200, columns 150-350) under a green wall, its top face rows
    101-105 10 levels lighter, a stripe across rows 135-165; ``margin``: instead of the
    stripe, a print over the middle with a 12-column margin of the lid's colour down each
    side (a print's margin, no top face)."""
    img = _lid_image(GREY_FACE + 10.0)
    if margin:
        img[101:200, 150:162] = np.round(GREY_FACE + 10.0)
        img[101:200, 338:350] = np.round(GREY_FACE + 10.0)
        img[110:195, 162:338] = np.round(STRIPE)
    else:
        img[135:165, 150:350] = np.round(STRIPE)
    return img


def test_a_stripe_across_the_face_is_no_margin() -> None:
    assert conf_mod.TOP_FACE_SIDE_VS_MIDDLE
    band = top_face_band(_striped(), LINES)
    assert band is not None and band[0] >= TOP_FACE_STEP
    assert band[1] == pytest.approx(104.5, abs=0.6)


def test_without_the_rule_the_stripe_reads_as_a_margin(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(conf_mod, "TOP_FACE_SIDE_VS_MIDDLE", False)
    band = top_face_band(_striped(), LINES)
    assert band is None or band[0] < TOP_FACE_STEP


def test_a_margin_down_the_sides_is_still_refused() -> None:
    """The margin's strips are the band's colour, the face's middle the print's: refused."""
    band = top_face_band(_striped(margin=True), LINES)
    assert band is None or band[0] < TOP_FACE_STEP


def test_photo_3506_hard_is_measured_on_its_front_top() -> None:
    """The room itself (new11, with the rig): the top face's band is read, the top moved to
    its end, the front top edge (without the rule +12.4 %: see the synthetic tests)."""
    from obstacle_fusion.sim.room_scene import render_room
    from obstacle_fusion.vision.camera import CameraModel
    from obstacle_fusion.vision.measure import Measurer

    cam = CameraModel.paper(500, 375)
    image, truth, spec = render_room("photo", 3506, True, cam)

    def error() -> float:
        res = Measurer(cam, spec.rig).measure(image, truth["range_m"])
        assert res.detected and res.height_m is not None
        return float(res.height_m / truth["height_m"] - 1)

    assert abs(error()) < 0.02


#: the side strips' colour over the middle rows: 7 from the lid's (GREY_FACE + 10, over
#: TOP_FACE_SIDE_AGREE of its 17.3 step: no one column refuses), 22 from the face's
SIDES = np.array([110.0, 117.0, 110.0])


def _sides_and_middle(off: float) -> npt.NDArray[np.uint8]:
    """The lid image, its middle rows (130-170) in SIDES from each side to the inner
    columns (150-190, 310-350) and ``off`` levels (blue) from SIDES between them."""
    img = _lid_image(GREY_FACE + 10.0)
    img[130:170, 150:190] = np.round(SIDES)
    img[130:170, 310:350] = np.round(SIDES)
    img[130:170, 190:310] = np.round(SIDES + np.array([off, 0.0, 0.0]))
    return img


@pytest.mark.parametrize(("off", "margin"), [(6.0, False), (8.0, True)])
def test_the_strip_is_weighed_against_the_middle_and_the_band_alike(
    off: float, margin: bool
) -> None:
    """The strips lie 7 from the band: a middle 6 from them is the face the strips read
    (a stripe across it), a middle 8 from them a print between margins of the band's
    colour, shaded (the strips' median refuses it; no one column does)."""
    band = top_face_band(_sides_and_middle(off), LINES)
    assert band is not None
    assert (band[0] < TOP_FACE_STEP) is margin
