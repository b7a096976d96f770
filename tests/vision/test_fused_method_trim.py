"""The fused method's stages in order: the sides' trim to the face's foot (method.py)."""

from __future__ import annotations

from typing import Any

import pytest
from obstacle_fusion.sim.room_scene import RoomRenderer
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import method
from obstacle_fusion.vision.measure import Measurer

from tests.vision.rooms import plain_room

CAM = CameraModel.paper(500, 375)


def measure_spying(monkeypatch: pytest.MonkeyPatch) -> list[tuple[Any, ...]]:
    """A plain room measured with its rig; the trim's calls (their arguments) recorded."""
    calls: list[tuple[Any, ...]] = []
    trim = method.trim_to_foot

    def spy(*args: Any, **kwargs: Any) -> tuple[int, int]:
        calls.append(args)
        return trim(*args, **kwargs)

    monkeypatch.setattr(method, "trim_to_foot", spy)
    spec = plain_room(4000)
    image, truth = RoomRenderer(CAM).render(spec)
    res = Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    assert res.detected
    return calls


def test_the_sides_are_trimmed_to_the_foot_knowing_the_searched_sides(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """After the seam walk, with the search's own sides (a side the seams moved out comes
    back no farther in than those)."""
    calls = measure_spying(monkeypatch)
    assert len(calls) == 1
    left, right, _depth, searched = calls[0][5:9]
    assert searched[0] <= searched[1] and left <= searched[0] + 1 and right >= searched[1] - 1


def test_a_prints_frame_is_not_trimmed(monkeypatch: pytest.MonkeyPatch) -> None:
    """A frame found by its margin's colour (room photo/734, hard, no rig) keeps that
    margin's sides: the trim left one of its sides inside and a wrong face passed."""
    monkeypatch.setattr(
        method, "enclose_by_margin", lambda _seen, _v, rb, vt, ul, ur, _depth: (rb, vt, ul, ur)
    )
    assert measure_spying(monkeypatch) == []
