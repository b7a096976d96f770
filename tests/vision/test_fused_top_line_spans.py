"""The face's top line spans it (``extent.TOP_LINE_SPANS``, ``extent.trim_to_top_line``)
and a face in the floor's shade is widened across its seams by its top edge alone from
``extent.TOP_ALONE_SNR`` (session 38).

The rooms are tuning rooms (procedural, seeds 100-159 and 2000-2099; photo 700-759):
procedural 116 (hard, with the rig) is a low plank box in the floor's shade beside a
cylinder; the search's right side was the cylinder's edge, 70 px past the box's (39 % of
the pair's width), where the box's top line had ended (+58 % wide). Photo 718 (hard, with
the rig) is a poster face whose top at this stage is still a background line over 42 % of
the pair: the share limit keeps it from being trimmed. Procedural 2090 (hard, with the
rig) is a seam face in the floor's shade whose top edge stands 6.8 noise levels: measured
as one panel (-68 %) where the top edge alone had to stand 10.
"""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import extent

from tests.vision_fixtures import gradients, room_size_errors


def _low_box() -> float:
    eh, ew = room_size_errors("procedural", 116, True)
    assert eh < 0.1
    return ew


def test_a_side_past_where_the_top_line_ends_is_moved_in() -> None:
    assert _low_box() < 0.1


def test_without_the_rule_the_cylinder_is_the_side(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(extent, "TOP_LINE_SPANS", False)
    assert _low_box() > 0.25


@pytest.mark.parametrize(("limit", "trimmed"), [(0.40, True), (0.38, False)])
def test_the_longest_stretch_decides(
    monkeypatch: pytest.MonkeyPatch, limit: float, trimmed: bool
) -> None:
    # the stretch with no top line next to the right side: 0.39 of the pair's width
    monkeypatch.setattr(extent, "TOP_SPAN_MAX_SHARE", limit)
    assert (_low_box() < 0.1) is trimmed


@pytest.mark.parametrize(("limit", "trimmed"), [(0.38, True), (0.40, False)])
def test_the_shortest_stretch_decides(
    monkeypatch: pytest.MonkeyPatch, limit: float, trimmed: bool
) -> None:
    monkeypatch.setattr(extent, "TOP_SPAN_MIN_SHARE", limit)
    assert (_low_box() < 0.1) is trimmed


def test_the_new_side_must_stand(monkeypatch: pytest.MonkeyPatch) -> None:
    # the box's right side is present over most of its rows, not every one
    monkeypatch.setattr(extent, "TOP_SPAN_SIDE_COVERAGE", 1.0)
    assert _low_box() > 0.25


def test_a_top_over_less_than_half_the_pair_trims_nothing() -> None:
    assert max(room_size_errors("photo", 718, True)) < 0.05


def test_past_the_share_limit_the_poster_is_cut(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(extent, "TOP_SPAN_MAX_SHARE", 0.6)
    _, ew = room_size_errors("photo", 718, True)
    assert ew > 0.25


def _seam_face() -> float:
    _, ew = room_size_errors("procedural", 2090, True)
    return ew


@pytest.mark.parametrize(("snr", "widened"), [(6.0, True), (6.7, True), (6.9, False)])
def test_the_top_edge_alone_from_six_noise_levels(
    monkeypatch: pytest.MonkeyPatch, snr: float, widened: bool
) -> None:
    # the face's top edge stands 6.8 noise levels, its foot under 3
    monkeypatch.setattr(extent, "TOP_ALONE_SNR", snr)
    # (its top is one line on its row: under TOP_ALONE_SNR, extent.TOP_ALONE_LINE, session
    # 43, walks it alone too; off to read TOP_ALONE_SNR's own limit)
    monkeypatch.setattr(extent, "TOP_ALONE_LINE", False)
    assert (_seam_face() < 0.05) is widened
    if not widened:
        assert _seam_face() > 0.25


def _drawn(gap: int = 0) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.int16], float]:
    """A drawn face (rows 40-100, columns 50-150) with a darker object beside it (rows
    70-100, columns 151-190) whose right edge the pair 50-190 took for the face's side;
    ``gap`` columns of the face from column 60 in the background's shade (no top line)."""
    img = np.full((140, 240), 100, np.uint8)
    img[40:101, 50:151] = 150
    if gap:
        img[40:101, 60 : 60 + gap] = 100
    img[70:101, 151:191] = 50
    img[101:, :] = 80
    img = cv2.GaussianBlur(img, (3, 3), 0)
    noise = np.random.default_rng(1).integers(-2, 3, img.shape)
    return gradients(np.clip(img.astype(np.int16) + noise, 0, 255).astype(np.uint8))


def test_a_drawn_side_beside_the_face_is_moved_to_where_its_top_ends() -> None:
    ay, ax3, noise = _drawn()
    assert extent.trim_to_top_line(ay, ax3, 100, 40, 50, 190, noise) == (50, 150)


@pytest.mark.parametrize(("gap", "held", "right"), [(10, 0.9, 150), (15, 0.9, 190), (15, 0.8, 150)])
def test_the_top_line_must_hold_over_the_rest(
    monkeypatch: pytest.MonkeyPatch, gap: int, held: float, right: int
) -> None:
    # a 10-column gap leaves the line over ~0.9 of columns 50-150, a 15-column one ~0.84
    monkeypatch.setattr(extent, "TOP_SPAN_HELD", held)
    ay, ax3, noise = _drawn(gap)
    assert extent.trim_to_top_line(ay, ax3, 100, 40, 50, 190, noise) == (50, right)


def test_the_drawn_side_stays_with_the_rule_off(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(extent, "TOP_LINE_SPANS", False)
    ay, ax3, noise = _drawn()
    assert extent.trim_to_top_line(ay, ax3, 100, 40, 50, 190, noise) == (50, 190)
