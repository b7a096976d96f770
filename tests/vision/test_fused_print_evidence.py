"""A face refused for a print of its own is weighed again without its texture
(``method.PRINT_EVIDENCE``, ``scoring.PRINT_COVERS_FACE``, ``Candidate.print_evidence``).

The room is a tuning room (photo, seeds 700-759): photo 747 (ordinary) is a brick-printed
face on a brick floor before a photographed gantry at dusk. The search found the face's
own pair and top, but the print's joints made 96 % of its rows textured, and the texture
term (meant for a textured background inside a pair, books over a box's top) cut its
evidence to 0.068: refused at 0.025, a miss. Weighed without the texture it passes
(0.128 before the doubts), 7.6 % off in height, 0.7 % in width, reported at 0.05.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import method, scoring
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.types import Measurement

from tests.vision_fixtures import room_size_errors

CAM = CameraModel.paper(500, 375)


def measured(family: str, seed: int, hard: bool) -> Measurement:
    """The fused method's answer on a tuning room with its rig."""
    image, truth, spec = render_room(family, seed, hard, CAM)
    return Measurer(CAM, spec.rig).measure(image, truth["range_m"])


def test_a_face_with_a_print_of_its_own_is_found() -> None:
    eh, ew = room_size_errors("photo", 747, False)
    assert eh < 0.10 and ew < 0.05


def test_the_answer_stays_an_unsure_one() -> None:
    res = measured("photo", 747, False)
    assert res.confidence is not None and res.confidence < 0.5


def test_without_the_rule_the_face_is_missed(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method, "PRINT_EVIDENCE", False)
    res = measured("photo", 747, False)
    assert not res.detected
    assert res.reason is not None and res.reason.startswith("no clear face")


def test_the_print_must_cover_the_face(monkeypatch: pytest.MonkeyPatch) -> None:
    # the face is textured over 96 % of its rows: a print asked to cover more is none
    monkeypatch.setattr(scoring, "PRINT_COVERS_FACE", 0.97)
    assert not measured("photo", 747, False).detected


def test_a_print_covering_the_share_asked_for_counts(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(scoring, "PRINT_COVERS_FACE", 0.95)
    assert measured("photo", 747, False).detected
