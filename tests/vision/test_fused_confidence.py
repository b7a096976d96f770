"""The reported confidence: each doubt about how a face's size was reached cuts it
(vision/fused/confidence.py), recorded by the stage that took that way (fused/method.py,
vision/measure.py); the measured size never moves."""

from __future__ import annotations

from typing import Any

import pytest
from obstacle_fusion.sim.room_scene import RoomRenderer, RoomSpec
from obstacle_fusion.vision import measure as measure_mod
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import confidence as conf_mod
from obstacle_fusion.vision.fused import method as method_mod
from obstacle_fusion.vision.fused.confidence import (
    DOUBT_FACTOR,
    DOUBT_FACTORS,
    FRAMED,
    NO_RIG_ONLY,
    PITCH_RERUN_DISAGREES,
    PITCH_UNREAD,
    SMALL_FACE,
    SMALL_FACE_PX,
    TOP_FROM_SIDES,
    pixel_factor,
    reported_confidence,
)
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.pitch import PitchEstimate

from tests.vision.rooms import pitched_plain_room

CAM = CameraModel.paper(500, 375)


# --- the factors themselves ---------------------------------------------------------------


def test_one_doubt_takes_the_surest_face_under_half() -> None:
    assert DOUBT_FACTOR == 0.45
    assert set(DOUBT_FACTORS) == {TOP_FROM_SIDES, FRAMED, PITCH_UNREAD, PITCH_RERUN_DISAGREES}
    for doubt in DOUBT_FACTORS:
        assert reported_confidence(1.0, [doubt], 200.0, 200.0, 0.05, rig_given=False) == (
            0.45,
            [doubt],
        )


def test_doubts_multiply_once_each_and_unknown_names_are_ignored() -> None:
    got = reported_confidence(
        0.9, [TOP_FROM_SIDES, PITCH_UNREAD, TOP_FROM_SIDES, "no_such"], 200.0, 200.0, 0.05, False
    )
    assert got == (round(0.9 * 0.45 * 0.45, 3), [TOP_FROM_SIDES, PITCH_UNREAD])


def test_a_print_margin_cuts_only_with_the_contact_found_in_the_image() -> None:
    assert NO_RIG_ONLY == frozenset({FRAMED})
    assert reported_confidence(0.8, [FRAMED], 200.0, 200.0, 0.05, rig_given=True) == (0.8, [])
    assert reported_confidence(0.8, [FRAMED], 200.0, 200.0, 0.05, rig_given=False) == (
        0.36,
        [FRAMED],
    )
    # the other doubts cut with a rig too
    assert reported_confidence(0.8, [TOP_FROM_SIDES], 200.0, 200.0, 0.05, rig_given=True)[0] == 0.36


def test_pixel_factor_is_each_side_share_of_forty_pixels() -> None:
    assert SMALL_FACE_PX == 40.0
    assert pixel_factor(40.0, 40.0) == 1.0
    assert pixel_factor(400.0, 400.0) == 1.0
    assert pixel_factor(20.0, 400.0) == 0.5
    assert pixel_factor(400.0, 30.0) == 0.75
    assert pixel_factor(20.0, 30.0) == pytest.approx(0.375)
    assert pixel_factor(None, 10.0) == 0.25  # an unknown size cuts nothing
    assert pixel_factor(39.9, 1000.0) < 1.0


def test_a_small_face_is_named_and_cut_by_its_pixels() -> None:
    assert reported_confidence(0.8, [], 20.0, 200.0, 0.05, False) == (0.4, [SMALL_FACE])
    assert reported_confidence(0.8, [], 40.0, 40.0, 0.05, False) == (0.8, [])


def test_doubts_never_take_a_detection_under_the_min_confidence() -> None:
    # the face passed the method's minimum: it stays reported, at that minimum at worst
    assert (
        reported_confidence(0.08, [TOP_FROM_SIDES, PITCH_UNREAD], 200.0, 200.0, 0.05, False)[0]
        == 0.05
    )
    assert reported_confidence(0.08, [TOP_FROM_SIDES], 200.0, 200.0, 0.0, False)[0] == 0.036
    # a face under the minimum given (min confidence lowered since) is not raised to it
    assert reported_confidence(0.04, [TOP_FROM_SIDES], 200.0, 200.0, 0.05, False)[0] == 0.04


# --- the stages that record them ------------------------------------------------------------


def room(pitch: float) -> tuple[Any, dict[str, Any], RoomSpec]:
    """A plain face 0.35 x 0.5 m at 1 m, camera 0.3 m high (a tuning family's room)."""
    spec = pitched_plain_room(4002, pitch)
    image, truth = RoomRenderer(CAM).render(spec)
    return image, truth, spec


@pytest.fixture(scope="module")
def pitched() -> tuple[Any, dict[str, Any], RoomSpec]:
    return room(4.0)


@pytest.fixture(scope="module")
def level() -> tuple[Any, dict[str, Any], RoomSpec]:
    return room(0.0)


def test_a_clear_face_read_whole_has_no_doubt(pitched: tuple) -> None:
    image, truth, spec = pitched
    for rig in (spec.rig, None):
        res = Measurer(CAM, rig).measure(image, truth["range_m"])
        assert res.detected and res.doubts == [] and (res.confidence or 0.0) > 0.9
        assert res.to_dict()["doubts"] == []


def test_no_rig_and_no_pitch_read_is_a_doubt(
    pitched: tuple, monkeypatch: pytest.MonkeyPatch
) -> None:
    image, truth, _ = pitched
    sure = Measurer(CAM, None).measure(image, truth["range_m"])
    monkeypatch.setattr(measure_mod, "pitch_from_undistorted", lambda *a: None)
    m = Measurer(CAM, None)
    res = m.measure(image, truth["range_m"])
    assert res.detected and res.camera_pitch_deg == 0.0
    assert res.doubts == [PITCH_UNREAD] and res.to_dict()["doubts"] == [PITCH_UNREAD]
    assert (res.confidence or 0.0) < 0.5 <= (sure.confidence or 0.0)
    # the next frame reuses that height and pitch: still unread, still doubted
    again = m.measure(image, truth["range_m"])
    assert again.doubts == [PITCH_UNREAD] and again.confidence == res.confidence


def test_a_pitch_read_as_level_is_read(level: tuple, monkeypatch: pytest.MonkeyPatch) -> None:
    image, truth, _ = level
    monkeypatch.setattr(
        measure_mod, "pitch_from_undistorted", lambda *a: PitchEstimate(0.02, 0.1, 100.0, 100.0)
    )
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    assert res.detected and res.camera_pitch_deg == 0.0 and res.doubts == []
    monkeypatch.setattr(measure_mod, "pitch_from_undistorted", lambda *a: None)
    unread = Measurer(CAM, None).measure(image, truth["range_m"])
    assert unread.doubts == [PITCH_UNREAD] and unread.height_m == res.height_m


def test_a_levelled_rerun_that_disagrees_is_a_doubt(
    pitched: tuple, monkeypatch: pytest.MonkeyPatch
) -> None:
    image, truth, _ = pitched
    monkeypatch.setattr(measure_mod, "level_scales", lambda *a: (1.3, 1.3))
    res = Measurer(CAM, None).measure(image, truth["range_m"])
    # the pitch-0 size scaled by 1.3 kept, the rerun's true size refused
    assert res.detected and res.height_m == pytest.approx(1.3 * truth["height_m"], rel=0.03)
    assert res.doubts == [PITCH_RERUN_DISAGREES] and (res.confidence or 0.0) < 0.5


def test_a_top_moved_to_where_the_sides_end_is_a_doubt(
    pitched: tuple, monkeypatch: pytest.MonkeyPatch
) -> None:
    image, truth, spec = pitched
    raise_top = method_mod.raise_top_past_inner_edges
    monkeypatch.setattr(
        method_mod,
        "raise_top_past_inner_edges",
        lambda ay, ax, b, t, *a: raise_top(ay, ax, b, t, *a),
    )
    assert Measurer(CAM, spec.rig).measure(image, truth["range_m"]).doubts == []
    monkeypatch.setattr(
        method_mod,
        "raise_top_past_inner_edges",
        lambda ay, ax, b, t, *a: raise_top(ay, ax, b, t, *a) - 1,
    )
    res = Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    assert res.detected and res.doubts == [TOP_FROM_SIDES] and (res.confidence or 0.0) < 0.5


def test_a_print_margin_round_the_face_is_a_doubt_with_no_rig(
    pitched: tuple, monkeypatch: pytest.MonkeyPatch
) -> None:
    image, truth, spec = pitched
    before = Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    # a margin found, running on below the floor-contact rows: refused as the face
    # (the size stays), but the face found is a print in it
    monkeypatch.setattr(
        method_mod, "enclose_by_margin", lambda im, v, rb, vt, ul, ur, d: (rb + 500, vt, ul, ur)
    )
    with_rig = Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    assert with_rig.height_m == before.height_m and with_rig.width_m == before.width_m
    assert with_rig.doubts == [] and with_rig.confidence == before.confidence
    no_rig = Measurer(CAM, None).measure(image, truth["range_m"])
    assert no_rig.detected and FRAMED in no_rig.doubts and (no_rig.confidence or 0.0) < 0.5


def test_measure_cuts_by_the_result_s_own_pixel_size(
    pitched: tuple, monkeypatch: pytest.MonkeyPatch
) -> None:
    image, truth, spec = pitched
    sure = Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    monkeypatch.setattr(conf_mod, "SMALL_FACE_PX", 400.0)
    res = Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    assert res.doubts == [SMALL_FACE]
    want = (sure.confidence or 0.0) * (res.height_px or 0.0) / 400.0 * (res.width_px or 0.0) / 400.0
    assert res.confidence == pytest.approx(max(want, 0.05), abs=6e-4)
    monkeypatch.setattr(conf_mod, "SMALL_FACE_PX", 1e6)
    tiny = Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    assert tiny.detected and tiny.confidence == 0.05  # the method's minimum, still a detection
