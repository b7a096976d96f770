"""The sides' depths read from the foot's slope are kept only while the yaw they give is
under ``refine.MAX_YAW_DEG`` (``refine.YAW_FROM_FOOT_CAPPED``).

The rooms are tuning rooms (procedural and photo, seeds 100-159 and 700-759): photo 748 is
a thin teal pillar 0.16 m wide, 32 px at 2.3 m; its foot's fit slopes a pixel or two
between the corners (a shadow beside it), which read as a yaw of 57 degrees and added a
quarter of the depth to its width (88 % too wide). Procedural 749 (hard, a face yawed by
up to 3 degrees) reads a yaw of 10.5 degrees: capped, its width is right to a percent.
"""

from __future__ import annotations

import pytest
from obstacle_fusion.vision.fused import refine

from tests.vision_fixtures import room_size_errors


def test_a_thin_pillar_is_measured_at_one_depth() -> None:
    eh, ew = room_size_errors("photo", 748, False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_cap_the_foot_slope_widens_the_pillar(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(refine, "YAW_FROM_FOOT_CAPPED", False)
    _, ew = room_size_errors("photo", 748, False)
    assert ew > 0.5


def test_a_yaw_over_the_limit_is_capped() -> None:
    _, ew = room_size_errors("procedural", 749, True)
    assert ew < 0.015


def test_the_yaw_limit_decides(monkeypatch: pytest.MonkeyPatch) -> None:
    # 749's foot reads a yaw of 10.5 degrees: under a limit of 11 it is kept
    monkeypatch.setattr(refine, "MAX_YAW_DEG", 11.0)
    _, ew = room_size_errors("procedural", 749, True)
    assert ew > 0.025
