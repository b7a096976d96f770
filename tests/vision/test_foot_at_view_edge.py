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
row), with the rule +0.1 / -0.2 % at 0.4, ``bottom`` flagged.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import method
from obstacle_fusion.vision.fused.method import foot_at_view_edge

from tests.vision_fixtures import room_size_errors

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
