"""The top decided again between the settled sides walks the colour walk and the sides'
walk in turn (``method.SETTLED_WALKS_ALTERNATE``): each stops where the other may go on.
The colour walk stops at a band across the face's middle; the sides' walk stops where a
print next to a side takes that side's step away for more than its gap, while the
middle keeps the face's colour.

The room is a diagnosis room (new9). Procedural 3402 (hard), with the rig: a red poster
box on a green wall, printed with patches; the search found a narrow face on two patches'
edges, its sides settled on the box's (183-311); between them the colour walk went up
8 rows (224 -> 216) and the sides' walk 72 (-> 144), stopping at a patch by the left
side 22 rows under the box's top: height -19 %. Walked in turn again, the colour walk
from 144 reaches the top (122): -2.7 %, and no doubt is left (0.30 -> 0.67).
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import method

from tests.vision_fixtures import measured_room


def test_the_poster_box_is_measured_to_its_top() -> None:
    res, truth = measured_room("procedural", 3402, True, True)
    assert res.detected and res.height_m is not None
    assert abs(res.height_m / truth["height_m"] - 1) < 0.05


def test_without_the_rule_the_walks_stop_short(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method, "SETTLED_WALKS_ALTERNATE", False)
    res, truth = measured_room("procedural", 3402, True, True)
    assert res.detected and res.height_m is not None
    assert res.height_m / truth["height_m"] - 1 < -0.15
