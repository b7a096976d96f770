"""With the rig, a face candidate in the outer part of the sonar's cone keeps less of its
score than one beside the axis (``method.FAR_OFF_AXIS``, ``off_axis_share``): of faces at
the sonar's depth, the one the beam's axis falls on is what it ranged."""

from __future__ import annotations

import pytest
from obstacle_fusion.sim.room_scene import TextureMissing, render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import method
from obstacle_fusion.vision.measure import Measurer


@pytest.mark.parametrize(
    "ul, ur, far",
    [
        # the nearer side 30 px off the axis, the beam's half-width 60: half of it, not beyond
        (130.0, 150.0, False),
        (130.5, 150.0, True),
        # left of the axis, likewise
        (40.0, 70.0, False),
        (40.0, 69.5, True),
    ],
)
def test_a_face_beyond_half_the_beam_keeps_the_far_share(ul: float, ur: float, far: bool) -> None:
    want = method.FAR_OFF_AXIS_SHARE if far else method.OFF_AXIS_SHARE
    assert method.off_axis_share(ul, ur, 100.0, 60.0) == want


def test_the_limit_is_the_beam_share(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method, "FAR_OFF_AXIS_BEAM_SHARE", 0.6)
    assert method.off_axis_share(130.5, 150.0, 100.0, 60.0) == method.OFF_AXIS_SHARE
    assert method.off_axis_share(136.5, 150.0, 100.0, 60.0) == method.FAR_OFF_AXIS_SHARE


def test_under_a_guessed_rig_the_far_share_is_not_used() -> None:
    assert method.off_axis_share(200.0, 250.0, 100.0, 60.0, rig_given=False) == (
        method.OFF_AXIS_SHARE
    )


def test_switched_off_the_off_axis_share_is_kept(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(method, "FAR_OFF_AXIS", False)
    assert method.off_axis_share(200.0, 250.0, 100.0, 60.0) == method.OFF_AXIS_SHARE


def _error(family: str, seed: int, hard: bool) -> float:
    """The larger of the height and width errors with the true rig (a miss: infinite)."""
    cam = CameraModel.paper(500, 375)
    try:
        image, truth, spec = render_room(family, seed, hard, cam)
    except TextureMissing as exc:
        pytest.skip(str(exc))
    res = Measurer(cam, spec.rig).measure(image, truth["range_m"])
    if not res.detected or res.height_m is None or res.width_m is None:
        return float("inf")
    return max(abs(res.height_m / truth["height_m"] - 1), abs(res.width_m / truth["width_m"] - 1))


@pytest.mark.parametrize(
    "family, seed, limit",
    [
        # a floor patch between a cylinder and the face (the face's left side its right
        # side, the floor's far edge its top), 0.82 of the beam's half-width off the axis
        ("procedural", 755, 0.05),
        # the face's right side to a box beside it at the cone's edge (0.503 of it); at the
        # defaults a known regression (method.TOP_FACE_TO_FRONT, session 42: the luminance
        # face, its top moved off a top face, is 1.99 times the face-floor channel's thin
        # strip, under THIN_STRIP_TALLER's 2.0, and the strip stays, -48.6 %; with the rig
        # check by the search, as the method runs, 14.2 -> 9.0 %): a strict xfail, and
        # this rule tested alone with that move off (below)
        pytest.param(
            "photo",
            152,
            0.15,
            marks=pytest.mark.xfail(
                strict=True,
                reason="method.TOP_FACE_TO_FRONT: photo/152 hard's face 1.99 times the strip "
                "(THIN_STRIP_TALLER 2.0), rig check off (session 42)",
            ),
        ),
    ],
)
def test_a_face_at_the_cones_edge_gives_way_to_one_on_the_axis(
    family: str, seed: int, limit: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    assert _error(family, seed, True) <= limit
    monkeypatch.setattr(method, "FAR_OFF_AXIS", False)
    assert _error(family, seed, True) > 0.25


def test_the_box_at_the_cones_edge_gives_way_with_the_top_face_move_off(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """photo/152 hard as before session 42 (method.TOP_FACE_TO_FRONT off): within 15 %."""
    monkeypatch.setattr(method, "TOP_FACE_TO_FRONT", False)
    assert _error("photo", 152, True) <= 0.15
    monkeypatch.setattr(method, "FAR_OFF_AXIS", False)
    assert _error("photo", 152, True) > 0.25


def test_the_far_share_must_be_small(monkeypatch: pytest.MonkeyPatch) -> None:
    """photo/152 hard: at 0.5 of its score the pair at the cone's edge still wins."""
    monkeypatch.setattr(method, "FAR_OFF_AXIS_SHARE", 0.5)
    assert _error("photo", 152, True) > 0.25
