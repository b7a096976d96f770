"""With the rig, a face whose predicted floor-contact row lies in the view's last
FOOT_EDGE_FLOOR_ROWS rows (or just past them, its contact band still reaching into the
view), which neither the edges nor the colour rescue find, or find only unclearly
(refused), is sought from the view's foot up as a face whose foot lies below the view
(``method.FOOT_AT_VIEW_EDGE``, ``method.foot_at_view_edge``): with no floor rows below it
the contact edge does not show, and the band's search stops four rows short of the
view's foot.

Rooms: procedural 3253 (ordinary, new6): a pink gloss box 0.62 m ahead whose foot the rig
puts at row 379 of 375; no face was found ("no face with a floor-contact edge"), with
the rule +0.2 / -1.7 %. Photo 2106 (ordinary, fresh): the foot at row 374.6, missed the
same way, with the rule +0.1 / -2.2 %. Photo 2177 (ordinary, fresh): the foot at row 376,
the edges' face a strip along the view's foot refused at 0.042 ("no clear face"), with
the rule +0.4 / +0.3 % at 0.34. Photo 1303 (ordinary, a clipped truth: the foot past the
view's): missed (the background channel's last try refused for its foot above the contact
row), with the rule +0.1 / -0.2 % at 0.4, ``bottom`` flagged. Procedural 2031 (hard,
own): the edges' face refused at 0.002 at the first refusal, with the rule its height
within 1 % (its width 34 % short: the colour walk stops at a lighter plank) at 0.31.

The face is as sure as the colour rescue's at most (``method.RESCUE_MAX_CONFIDENCE``
0.4 times its sides' and top's evidence): never a sure answer. Its foot is flagged
clipped only where the predicted row lies past the view's last row
(``method.foot_below_view``): a foot in the view is not cut, the height is read from it.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import pytest
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import method
from obstacle_fusion.vision.fused.method import foot_at_view_edge, foot_below_view
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.types import Measurement

from tests.vision_fixtures import _paper_room, room_size_errors

ROOMS = [
    ("procedural", 3253, False),
    ("photo", 2106, False),
    ("photo", 2177, False),
    ("photo", 1303, False),
]


@pytest.mark.parametrize(("family", "seed", "hard"), ROOMS)
def test_the_face_at_the_view_foot_is_found(family: str, seed: int, hard: bool) -> None:
    eh, ew = room_size_errors(family, seed, hard)
    assert eh < 0.03 and ew < 0.03


@pytest.mark.parametrize(("family", "seed", "hard"), ROOMS)
def test_without_the_rule_it_is_missed(
    monkeypatch: pytest.MonkeyPatch, family: str, seed: int, hard: bool
) -> None:
    monkeypatch.setattr(method, "FOOT_AT_VIEW_EDGE", False)
    with pytest.raises(AssertionError):
        room_size_errors(family, seed, hard)


@pytest.mark.parametrize(
    ("vb0", "at_edge"),
    [
        (371.0, False),  # FOOT_EDGE_FLOOR_ROWS rows above the foot of a 375-row view
        (371.1, True),  # inside the last four rows
        (370.1, False),  # a fifth row: the band reads its contact edge
        (380.0, True),  # past the view's foot
        (200.0, False),
    ],
)
def test_the_limits(vb0: float, at_edge: bool) -> None:
    assert foot_at_view_edge(vb0, 375) is at_edge


def test_a_face_refused_at_the_first_refusal_is_found_by_its_height() -> None:
    # procedural 2031 hard: the edges' face refused before its top is settled (the first
    # refusal's call site); the colour walk along the view's foot stops at a lighter plank
    eh, ew = room_size_errors("procedural", 2031, True)
    assert eh < 0.01 and 0.30 < ew < 0.40


def read_from_view_foot(
    monkeypatch: pytest.MonkeyPatch, family: str, seed: int, hard: bool
) -> tuple[Measurement, list[Measurement]]:
    """The room measured with its rig, and the faces the method read from the view's foot
    up on the way (as the method returned them, before the measurer adds the image's
    borders to their clipped sides)."""
    read: list[Measurement] = []
    past_foot = method.FusedMethod._past_foot

    def kept(self: method.FusedMethod, *args: Any) -> Measurement | None:
        found = past_foot(self, *args)
        if found is not None:  # (a copy: the measurer adds to the face it returns)
            read.append(dataclasses.replace(found, clipped=list(found.clipped)))
        return found

    monkeypatch.setattr(method.FusedMethod, "_past_foot", kept)
    image, truth, spec = _paper_room(family, seed, hard)
    res = Measurer(CameraModel.paper(500, 375), spec.rig).measure(image, truth["range_m"])
    return res, read


@pytest.mark.parametrize(
    ("family", "seed", "hard", "confidence"),
    [
        ("procedural", 3253, False, 0.4),  # the sides and top fully agreed: the cap itself
        ("photo", 2106, False, 0.4),
        ("photo", 2177, False, 0.337),  # 0.4 x 0.84
    ],
)
def test_the_face_is_never_a_sure_one(
    monkeypatch: pytest.MonkeyPatch, family: str, seed: int, hard: bool, confidence: float
) -> None:
    # RESCUE_MAX_CONFIDENCE 0.4 times the evidence: under the 0.5 a sure answer needs
    res, read = read_from_view_foot(monkeypatch, family, seed, hard)
    assert len(read) == 1 and res.detected
    assert res.confidence == pytest.approx(confidence, abs=0.001)
    assert (res.confidence or 0.0) < 0.5


@pytest.mark.parametrize(
    ("family", "seed", "hard", "cut"),
    [
        ("photo", 752, False, False),  # the predicted row 373.7 of a 375-row view
        ("photo", 2106, False, False),  # 374.6: in the view's last row
        ("photo", 2177, False, True),  # 376
        ("procedural", 3253, False, True),  # 379.2
    ],
)
def test_the_foot_is_flagged_clipped_only_past_the_view(
    monkeypatch: pytest.MonkeyPatch, family: str, seed: int, hard: bool, cut: bool
) -> None:
    _, read = read_from_view_foot(monkeypatch, family, seed, hard)
    assert len(read) == 1
    assert ("bottom" in read[0].clipped) is cut


@pytest.mark.parametrize(
    ("vb0", "below"),
    [
        (374.0, False),  # the view's last row (rows 0..374)
        (374.99, False),
        (375.0, True),  # past it
        (380.0, True),
    ],
)
def test_the_foot_below_the_view(vb0: float, below: bool) -> None:
    assert foot_below_view(vb0, 375) is below
