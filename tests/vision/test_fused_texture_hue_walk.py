"""The texture rescue's face walked up by the face's hue too (``method.TEXTURE_HUE_WALK``,
``region.raise_top_by_hue``).

photo/3168 hard (set new4, seed 3168) is a grey gloss face of a photographed texture
before a night sky: the texture's walk up ended where the highlight starts, and that face
(top on the highlight, 42 % short) outscored the rig's own face, which the colour rescue's
hue walk had found whole, in the check of the rig's answer by the no-rig search
(``measure.RIG_CHECKED_BY_SEARCH``, on in these tests). The face's hue holds from its foot
to its top: walked so, the texture rescue's face is the whole face too.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import method
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.rig import Rig

Room = tuple[npt.NDArray[np.uint8], dict[str, Any], Rig]
CAM = CameraModel.paper(500, 375)


@pytest.fixture(scope="module")
def room() -> Room:
    image, truth, spec = render_room("photo", 3168, True, CAM)
    return image, truth, spec.rig


def errors(room: Room) -> tuple[float, float]:
    image, truth, rig = room
    res = Measurer(CAM, rig).measure(image, float(truth["range_m"]))
    assert res.detected and res.height_m is not None and res.width_m is not None
    return (
        res.height_m / float(truth["height_m"]) - 1,
        res.width_m / float(truth["width_m"]) - 1,
    )


@pytest.mark.rig_checked
def test_the_gloss_face_found_by_its_texture_is_measured_whole(room: Room) -> None:
    eh, ew = errors(room)
    assert abs(eh) < 0.05 and abs(ew) < 0.05


@pytest.mark.rig_checked
def test_without_the_walk_the_top_stays_on_the_highlight(
    room: Room, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(method, "TEXTURE_HUE_WALK", False)
    eh, _ = errors(room)
    assert eh < -0.25
