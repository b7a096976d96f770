"""The fused method prefers, of two faces at the sonar's depth, the one on the beam's axis."""

from __future__ import annotations

import pytest
from obstacle_fusion.sim.room_scene import TextureMissing, render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import method
from obstacle_fusion.vision.measure import Measurer


@pytest.mark.parametrize(
    "family, seed, hard",
    [
        # a box with a poster, a plain can beside it at the same depth, off the axis
        ("procedural", 357, True),
        # a gloss box, a planked cylinder beside it at the same depth (photo 320 ordinary,
        # a box of the floor's colour beside a brighter thing, no longer needs the axis
        # since the parts of a face are no rivals of it: confidence.same_face)
        ("photo", 333, True),
    ],
)
def test_of_two_faces_at_the_sonars_depth_the_one_on_the_axis_is_measured(
    family: str, seed: int, hard: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Tuning-family rooms (fresh seeds): with the off-axis face's score kept whole
    (OFF_AXIS_SHARE 1) the method measures the wrong one, over 10 % off (photo/320: a
    candidate reaching past the face, 14 %; 78 % before its top stopped where the face's
    colour ends, ``region.stops_at_colour_top``)."""
    try:
        image, truth, spec = render_room(family, seed, hard)
    except TextureMissing as exc:
        pytest.skip(str(exc))
    cam = CameraModel.paper(500, 375)

    def errors() -> float:
        res = Measurer(cam, spec.rig).measure(image, truth["range_m"])
        assert res.detected and res.height_m is not None and res.width_m is not None
        return max(
            abs(res.height_m / truth["height_m"] - 1), abs(res.width_m / truth["width_m"] - 1)
        )

    assert errors() <= 0.07
    monkeypatch.setattr(method, "OFF_AXIS_SHARE", 1.0)
    monkeypatch.setattr(method, "FAR_OFF_AXIS", False)  # the far share alone finds it too
    assert errors() > 0.10


def test_with_no_rig_the_axis_is_not_preferred(monkeypatch: pytest.MonkeyPatch) -> None:
    """While a floor-contact row is only tried (no rig), the preference is off: it would
    lift a face on the axis at a wrong row over the real one (room procedural/111, hard:
    a poster's strip, 74 % short, over the face at 19 %)."""
    image, truth, _ = render_room("procedural", 111, True)
    cam = CameraModel.paper(500, 375)
    before = Measurer(cam, None).measure(image, truth["range_m"])
    monkeypatch.setattr(method, "OFF_AXIS_SHARE", 0.01)
    after = Measurer(cam, None).measure(image, truth["range_m"])
    assert (before.height_m, before.width_m, before.confidence) == (
        after.height_m,
        after.width_m,
        after.confidence,
    )
