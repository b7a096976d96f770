"""With the rig, the edge search's ranking asks for the face the beam's axis falls on:
a side whose ranked places all lie beyond the axis gets candidates towards it
(``search.AXIS_SIDES``), and a face in the cone's outer part keeps less of its score than
one beside the axis (``method.FAR_OFF_AXIS``)."""

from __future__ import annotations

import numpy as np
import pytest
from obstacle_fusion.sim.room_scene import TextureMissing, render_room
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import method, search

AXIS = 30.0
U_LO, U_HI = 5, 55


def _drawn_edges(strengths: dict[int, int]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Gradients of vertical edges running up from the floor-contact row (row 39) at the
    given columns and strengths over a faint noise; their profile and its peaks."""
    rng = np.random.default_rng(3)
    ax3 = rng.integers(0, 3, (40, 60)).astype(np.int16)
    for col, strength in strengths.items():
        ax3[:, col] = strength
    prof = ax3.astype(np.float32).mean(axis=0)
    peaks = np.array(sorted(strengths), np.intp)
    return ax3, prof, peaks


def _axis_sides(
    strengths: dict[int, int], left: list[int], right: list[int], axis: float = AXIS
) -> tuple[list[int], list[int]]:
    ax3, prof, peaks = _drawn_edges(strengths)
    return search._axis_sides(ax3, prof, prof, peaks, left, right, 39, 1.0, 0, U_LO, U_HI, axis)


EDGES = {4: 300, 10: 100, 20: 200, 25: 50, 35: 260, 40: 240, 45: 220, 50: 280}


def test_a_left_side_beyond_the_axis_gets_the_strongest_columns_towards_it() -> None:
    left, right = _axis_sides(EDGES, [35, 40, 45], [40, 45, 50])
    assert left == [35, 40, 45, 20, 10]  # by strength; 4 lies outside the beam (U_LO 5)
    assert right == [40, 45, 50]  # right of the axis already


def test_a_right_side_short_of_the_axis_gets_columns_beyond_it() -> None:
    left, right = _axis_sides(EDGES, [10, 20], [20, 25])
    assert left == [10, 20]
    assert right == [20, 25, 50, 35]  # by strength; none past the beam's edge (U_HI 55)


def test_a_side_with_a_place_on_its_side_of_the_axis_gets_none() -> None:
    assert _axis_sides(EDGES, [35, 40, 20], [40]) == ([35, 40, 20], [40])


def test_the_axis_column_itself_counts_as_on_either_side() -> None:
    # a peak on the axis column is a left side's place towards it (<=) ...
    left, _ = _axis_sides(EDGES, [35, 40, 45], [50], axis=20.0)
    assert 20 in left
    # ... and the axis a column left of a peak leaves that peak beyond it
    left, _ = _axis_sides(EDGES, [35, 40, 45], [50], axis=19.0)
    assert 20 not in left and 10 in left


def test_the_places_added_are_at_most_axis_side_places(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(search, "AXIS_SIDE_PLACES", 1)
    assert _axis_sides(EDGES, [35, 40, 45], [50])[0] == [35, 40, 45, 20]


def test_switched_off_nothing_is_added(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(search, "AXIS_SIDES", False)
    assert _axis_sides(EDGES, [35, 40, 45], [10, 20]) == ([35, 40, 45], [10, 20])


@pytest.mark.parametrize(
    "ul, ur, far",
    [
        (130.0, 150.0, False),  # nearer side 30 px off a beam half-width of 60: 0.5, not beyond
        (130.5, 150.0, True),
        (40.0, 70.0, False),  # left of the axis, 30 px
        (40.0, 69.5, True),
    ],
)
def test_a_face_beyond_half_the_beam_keeps_the_far_share(ul: float, ur: float, far: bool) -> None:
    want = method.FAR_OFF_AXIS_SHARE if far else method.OFF_AXIS_SHARE
    assert method.off_axis_share(ul, ur, 100.0, 60.0) == want


def test_far_off_axis_switched_off_keeps_the_off_axis_share(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(method, "FAR_OFF_AXIS", False)
    assert method.off_axis_share(200.0, 250.0, 100.0, 60.0) == method.OFF_AXIS_SHARE


def _error(family: str, seed: int, hard: bool) -> float:
    """The larger of the height and width errors with the true rig (a miss: infinite)."""
    from obstacle_fusion.vision.measure import Measurer

    cam = CameraModel.paper(500, 375)
    try:
        image, truth, spec = render_room(family, seed, hard, cam)
    except TextureMissing as exc:
        pytest.skip(str(exc))
    res = Measurer(cam, spec.rig).measure(image, truth["range_m"])
    if not res.detected or res.height_m is None or res.width_m is None:
        return float("inf")
    return max(abs(res.height_m / truth["height_m"] - 1), abs(res.width_m / truth["width_m"] - 1))


def test_a_posts_left_edge_is_offered_towards_the_axis(monkeypatch: pytest.MonkeyPatch) -> None:
    """procedural/2022 hard: a post on the axis, its right edge and a box behind it took
    every left place; offered its left edge, the post is measured."""
    assert _error("procedural", 2022, True) <= 0.05
    monkeypatch.setattr(search, "AXIS_SIDE_PLACES", 1)  # its left edge is the 2nd strongest
    assert _error("procedural", 2022, True) > 0.25
    monkeypatch.setattr(search, "AXIS_SIDE_PLACES", 2)
    monkeypatch.setattr(search, "AXIS_SIDES", False)
    assert _error("procedural", 2022, True) > 0.25


@pytest.mark.parametrize(
    "family, seed, limit",
    [
        # a floor patch between a cylinder and the face, the face's left side its right
        ("procedural", 755, 0.05),
        # the face's right side to a box beside it at the cone's edge
        ("photo", 152, 0.15),
    ],
)
def test_a_face_at_the_cones_edge_gives_way_to_one_on_the_axis(
    family: str, seed: int, limit: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    assert _error(family, seed, True) <= limit
    monkeypatch.setattr(method, "FAR_OFF_AXIS", False)
    assert _error(family, seed, True) > 0.25
