"""Two rules about where a face's top is, with the rig (session 28, branch `hardtop`):

* the sides' walk up a coloured face holds its strips to the face's hue, its lightness
  weighed SHADE_WEIGHT (`region.SHADED_SIDE_WALK`): a gloss's highlight lightens a tall
  face half way up, and the walk stopped under it; a row so held keeps the face's hue
  (`region.SHADED_HUE_STEP`);
* the colour rescue's face is raised to where its sides end only where the face's colour
  is back under that row (`method.RESCUE_RAISE_BY_COLOUR`): a rail standing behind a low
  face in line with its sides carried its top up the wall.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import method, region, top
from obstacle_fusion.vision.measure import Measurer


def _errors(fam: str, seed: int, hard: bool, rig: bool = True) -> tuple[float, float]:
    """(height error, width error) as signed shares, or (9, 9) when no face is found."""
    cam = CameraModel.paper(500, 375)
    image, truth, spec = render_room(fam, seed, hard, cam)
    res = Measurer(cam, spec.rig if rig else None).measure(image, truth["range_m"])
    if not res.detected or res.height_m is None or res.width_m is None:
        return 9.0, 9.0
    return res.height_m / truth["height_m"] - 1, res.width_m / truth["width_m"] - 1


# a tall orange face, glossy: its highlight half way up lightens it by 35-40 (Lab L) at
# one hue; the top was taken at the skirting line behind its foot and the walk up its
# sides stopped under the highlight (-45 %)
GLOSS = ("procedural", 1220, True)
# a low face of the floor's shade in grey, found by its colour; a dark rail behind it runs
# up from its top in line with its sides and stood for them (+71 %)
RAIL = ("procedural", 1124, True)


def test_a_glossy_face_is_walked_up_past_its_highlight() -> None:
    eh, ew = _errors(*GLOSS)
    assert abs(eh) < 0.05 and abs(ew) < 0.05


def test_without_the_shade_weight_the_walk_stops_under_the_highlight(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(region, "SHADED_SIDE_WALK", False)
    # (the outline read from the foot round the unsure short face finds it whole too)
    monkeypatch.setattr(method, "FOOT_OUTLINE", False)
    # (nor does the walk up the face's hue, which finds its top past the highlight too)
    monkeypatch.setattr(method, "HUE_HOLDS_TOP", False)
    eh, _ = _errors(*GLOSS)
    assert eh < -0.25


# a green face under an orange band of lights, no rig: that band's hue is the face's in no
# light; read at any hue, a dark strip above the band passed as the face and the face
# found was refused (7 % otherwise)
DARK_BAND = ("photo", 1156, False)


def test_a_band_of_another_hue_is_no_shade_of_the_face() -> None:
    eh, ew = _errors(*DARK_BAND, rig=False)
    assert abs(eh) < 0.1 and abs(ew) < 0.05


def test_without_the_hue_limit_the_band_passes_for_the_face(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(region, "SHADED_HUE_STEP", 1e9)
    # (the face is found as well where a front top edge must be a step of its own,
    # top.FRONT_EDGE_STEPS: without that)
    monkeypatch.setattr(top, "FRONT_EDGE_STEPS", False)
    assert _errors(*DARK_BAND, rig=False) == (9.0, 9.0)


# a light print in a green margin (procedural/146 ordinary, its top at the print's, 9 %
# short): the margin is the print's hue 9.5 units off, 32 darker; at a hue step of 12 the
# walk took the margin for the print in shade and stopped in its top edge's blur, and the
# face with that top was refused (a shadow beside it measured, 84 %)
MARGIN = ("procedural", 146, False)


def test_a_margin_of_a_near_hue_is_no_shade_of_the_print() -> None:
    eh, ew = _errors(*MARGIN)
    assert abs(eh) < 0.12 and abs(ew) < 0.12


def test_at_a_looser_hue_step_the_margin_passes(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "SHADED_HUE_STEP", 12.0)
    eh, _ = _errors(*MARGIN)
    assert abs(eh) > 0.25


def test_a_rail_behind_a_rescued_face_is_not_its_top() -> None:
    eh, ew = _errors(*RAIL)
    assert abs(eh) < 0.05 and abs(ew) < 0.05


def test_without_the_colour_check_the_rail_is_the_top(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method, "RESCUE_RAISE_BY_COLOUR", False)
    eh, _ = _errors(*RAIL)
    assert eh > 0.25
