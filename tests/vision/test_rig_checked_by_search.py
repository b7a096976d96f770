"""With the rig, a miss or an unsure face is checked by the no-rig search, and its face
taken where it stands near the contact row the rig predicts, is a plausible obstacle,
surer, and another face than the rig's (``measure.RIG_CHECKED_BY_SEARCH``,
``measure.Measurer._checked_by_search``).

The rooms are tuning rooms (photo and procedural, seeds 100-159, 700-759, 2000-2099),
measured with their true rig. Photo 2078 (ordinary) is a plank 0.15 m wide: the rig's
search ranked the plank's right side below three stronger edges of a can beside it and
read a strip along the floor, 483 % too wide (reported 0.034 unfloored); the no-rig
search finds the plank 3 % off at 0.131, its foot 0.25 of the band's half-height from
the rig's row, overlapping the strip not at all. Photo 2083 (hard) is read 31 % off by
the rig and 1.4 % off by the search (the two boxes overlap 0.59). Photo 110 (hard): the
search's face is a poster's lower piece (-53 %) whose foot lies 0.73 of the band off the
rig's row: CHECK_FOOT_SHARE keeps the rig's 19 %. Photo 742 (hard): the search reads the
rig's face again (overlap 0.79) with its top 6 rows higher, 28 % off: CHECK_SAME_FACE
keeps the rig's 3 % (at the merge of session 40 the no-rig rules read 742 right; photo
701 hard stands in: the search's top on a line above the face, 22 % off). Photo 731 (ordinary) is a miss with the rig, 9 % off so.
Procedural 108 (hard) is found only by the rows read as with a rig, which the check
leaves out (CHECK_READS_ROWS).
"""

from __future__ import annotations

import dataclasses

import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import confidence, extent, past_seam
from obstacle_fusion.vision.fused.tuning import MIN_SIZE_M
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.types import Measurement

from tests.vision_fixtures import room_size_errors

pytestmark = pytest.mark.rig_checked


def test_a_narrow_plank_beside_a_can_is_found() -> None:
    eh, ew = room_size_errors("photo", 2078, False)
    assert eh < 0.05 and ew < 0.05


def test_without_the_rule_the_strip_is_the_answer(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "RIG_CHECKED_BY_SEARCH", False)
    # the narrow plank on the face's rows (session 41) moves the rig's strip's height too
    # (still 5.2 times too wide, 25 % tall): off, the strip is as the check found it
    monkeypatch.setattr(extent, "NARROW_PLANK_ON_ROWS", False)
    # (past_seam.SIDES_PAST_SEAMS, session 50, moves that strip's side and its top, 25 %
    # tall, still 5.2 times too wide: off, the strip as the check found it)
    monkeypatch.setattr(past_seam, "SIDES_PAST_SEAMS", False)
    eh, ew = room_size_errors("photo", 2078, False)
    assert eh > 0.8 and ew > 4.0


def test_a_miss_with_the_rig_is_found(monkeypatch: pytest.MonkeyPatch) -> None:
    eh, ew = room_size_errors("photo", 731, False)
    assert eh < 0.1 and ew < 0.1
    monkeypatch.setattr(measure, "RIG_CHECKED_BY_SEARCH", False)
    cam = CameraModel.paper(500, 375)
    image, truth, spec = render_room("photo", 731, False, cam)
    assert not Measurer(cam, spec.rig).measure(image, truth["range_m"]).detected


@pytest.mark.parametrize(("limit", "fixed"), [(0.035, True), (0.033, False)])
def test_only_an_unsure_face_is_checked(
    monkeypatch: pytest.MonkeyPatch, limit: float, fixed: bool
) -> None:
    # the rig's strip is reported at 0.034, unfloored
    monkeypatch.setattr(measure, "CHECK_CONFIDENCE", limit)
    # the strip as read before the narrow plank on the face's rows (session 41)
    monkeypatch.setattr(extent, "NARROW_PLANK_ON_ROWS", False)
    # (confidence.FACE_RUNS_ON_DOUBT, session 48, doubts that strip, whose top and foot run
    # on past its side, under the limits read here: off, to keep its 0.034)
    monkeypatch.setattr(confidence, "FACE_RUNS_ON_DOUBT", False)
    # (past_seam.SIDES_PAST_SEAMS, session 50, moves that strip and its confidence under
    # the limits read here: off, to keep its 0.034)
    monkeypatch.setattr(past_seam, "SIDES_PAST_SEAMS", False)
    _, ew = room_size_errors("photo", 2078, False)
    assert (ew < 0.05) is fixed


@pytest.mark.parametrize(("surer", "fixed"), [(3.8, True), (3.9, False)])
def test_the_search_s_face_must_be_surer(
    monkeypatch: pytest.MonkeyPatch, surer: float, fixed: bool
) -> None:
    # 0.131 against 0.034: 3.85 times
    monkeypatch.setattr(measure, "CHECK_SURER", surer)
    # the strip as read before the narrow plank on the face's rows (session 41)
    monkeypatch.setattr(extent, "NARROW_PLANK_ON_ROWS", False)
    # (confidence.FACE_RUNS_ON_DOUBT, session 48, doubts that strip, whose top and foot run
    # on past its side, under the limits read here: off, to keep its 0.034)
    monkeypatch.setattr(confidence, "FACE_RUNS_ON_DOUBT", False)
    # (past_seam.SIDES_PAST_SEAMS, session 50, moves that strip and its confidence under
    # the limits read here: off, to keep its 0.034)
    monkeypatch.setattr(past_seam, "SIDES_PAST_SEAMS", False)
    _, ew = room_size_errors("photo", 2078, False)
    assert (ew < 0.05) is fixed


@pytest.mark.parametrize(("share", "fixed"), [(0.26, True), (0.24, False)])
def test_the_search_s_face_must_stand_on_the_rig_s_row(
    monkeypatch: pytest.MonkeyPatch, share: float, fixed: bool
) -> None:
    # the plank's foot lies 0.25 of the band's half-height off the rig's row
    monkeypatch.setattr(measure, "CHECK_FOOT_SHARE", share)
    _, ew = room_size_errors("photo", 2078, False)
    assert (ew < 0.05) is fixed


def test_a_face_off_the_rig_s_row_is_not_taken(monkeypatch: pytest.MonkeyPatch) -> None:
    # photo 110 hard: the search's poster piece stands 0.73 of the band off the rig's row
    eh, _ = room_size_errors("photo", 110, True)
    assert eh < 0.25
    monkeypatch.setattr(measure, "CHECK_FOOT_SHARE", 0.75)
    eh, _ = room_size_errors("photo", 110, True)
    assert eh > 0.5


@pytest.mark.parametrize(("same", "fixed"), [(0.6, True), (0.58, False)])
def test_another_face_is_taken(monkeypatch: pytest.MonkeyPatch, same: float, fixed: bool) -> None:
    # photo 2083 hard: the rig's face and the search's overlap 0.59
    monkeypatch.setattr(measure, "CHECK_SAME_FACE", same)
    eh, ew = room_size_errors("photo", 2083, True)
    assert (max(eh, ew) < 0.05) is fixed


def test_one_face_read_twice_keeps_the_rig_s_reading(monkeypatch: pytest.MonkeyPatch) -> None:
    # photo 701 hard: the search reads the rig's face again with its top on a line above
    # it (22 % off); however sure, one face read twice keeps the rig's reading
    eh, _ = room_size_errors("photo", 701, True)
    assert eh < 0.05
    monkeypatch.setattr(measure, "CHECK_SAME_FACE", 1.01)  # no overlap counts as one face
    eh, _ = room_size_errors("photo", 701, True)
    assert eh > 0.15


def test_a_stream_s_frames_are_each_searched_afresh(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(measure, "CHECK_REST_FRAMES", 0)  # every frame checked
    cam = CameraModel.paper(500, 375)
    image, truth, spec = render_room("photo", 2078, False, cam)
    measurer = Measurer(cam, spec.rig)
    first = measurer.measure(image, truth["range_m"])
    other, other_truth, _ = render_room("photo", 2083, True, cam)
    measurer.measure(other, other_truth["range_m"])
    again = measurer.measure(image, truth["range_m"])
    assert first.box_px == again.box_px and first.height_m == again.height_m
    assert again.camera_height_m is None  # the search's guessed rig is not reported


def _face(x0: float, x1: float, height_m: float, width_m: float) -> Measurement:
    return Measurement(
        detected=True,
        method="fused",
        range_m=1.0,
        distance_m=1.0,
        height_m=height_m,
        width_m=width_m,
        box_px=(x0, 100.0, x1, 200.0),
    )


@pytest.mark.parametrize(("width_px", "plausible"), [(449.0, True), (451.0, False)])
def test_a_face_as_wide_as_the_image_is_no_obstacle_s(width_px: float, plausible: bool) -> None:
    # CHECK_MAX_WIDTH_SHARE 0.9 of 500 columns: 450
    assert measure._plausible_face(_face(10.0, 10.0 + width_px, 0.3, 0.3), 500) is plausible


@pytest.mark.parametrize(
    ("height_m", "plausible"),
    [
        (MIN_SIZE_M, True),
        (MIN_SIZE_M * 0.99, False),
        (measure.RAISED_FACE_MAX_M, True),
        (measure.RAISED_FACE_MAX_M * 1.01, False),
    ],
)
def test_a_face_the_size_of_an_obstacle(height_m: float, plausible: bool) -> None:
    assert measure._plausible_face(_face(100.0, 200.0, height_m, 0.3), 500) is plausible
    assert measure._plausible_face(_face(100.0, 200.0, 0.3, height_m), 500) is plausible


def test_box_overlap() -> None:
    assert measure.box_overlap((0.0, 0.0, 10.0, 10.0), (0.0, 0.0, 10.0, 10.0)) == 1.0
    assert measure.box_overlap((0.0, 0.0, 10.0, 10.0), (5.0, 0.0, 15.0, 10.0)) == 50.0 / 150.0
    assert measure.box_overlap((0.0, 0.0, 10.0, 10.0), (10.0, 0.0, 20.0, 10.0)) == 0.0
    assert measure.box_overlap(None, (0.0, 0.0, 1.0, 1.0)) == 0.0


def test_the_rows_read_as_with_a_rig_are_left_to_the_no_rig_path(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # procedural 108 hard: only the search's small face grown on its rows finds the face
    # (3 % off); the check leaves them (twice its cost) and the rig's -33 % stays
    eh, _ = room_size_errors("procedural", 108, True)
    assert eh > 0.25
    monkeypatch.setattr(measure, "CHECK_READS_ROWS", True)
    # with the check reading the rows it takes an unsure face on the axis first
    monkeypatch.setattr(measure, "AXIS_UNSURE_TRIAL", False)
    eh, ew = room_size_errors("procedural", 108, True)
    assert eh < 0.05 and ew < 0.05


def _count_searches(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    calls: list[int] = []
    search = Measurer._searched

    def counted(self: Measurer, *args: object, **kwargs: object) -> Measurement:
        calls.append(1)
        return search(self, *args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(Measurer, "_searched", counted)
    return calls


def test_a_stream_rests_the_check_after_it_took_nothing(monkeypatch: pytest.MonkeyPatch) -> None:
    # photo 110 hard: the search's face stands off the rig's row, nothing taken; the
    # check (~10x a rig frame's time) rests CHECK_REST_FRAMES frames, then runs again
    calls = _count_searches(monkeypatch)
    cam = CameraModel.paper(500, 375)
    image, truth, spec = render_room("photo", 110, True, cam)
    measurer = Measurer(cam, spec.rig)
    answers = [
        measurer.measure(image, truth["range_m"]) for _ in range(measure.CHECK_REST_FRAMES + 2)
    ]
    assert len(calls) == 2  # the first frame, and the one after the rest
    assert len({a.box_px for a in answers}) == 1  # the rest changes no answer here


def test_a_check_that_took_its_face_does_not_rest(monkeypatch: pytest.MonkeyPatch) -> None:
    calls = _count_searches(monkeypatch)
    cam = CameraModel.paper(500, 375)
    image, truth, spec = render_room("photo", 2078, False, cam)
    measurer = Measurer(cam, spec.rig)
    for _ in range(3):
        found = measurer.measure(image, truth["range_m"])
        assert found.width_m is not None and abs(found.width_m / truth["width_m"] - 1) < 0.05
    assert len(calls) == 3


@pytest.mark.parametrize("ahead_m", [-0.05, -0.02])
def test_no_face_in_front_of_the_lens_is_a_clean_miss(ahead_m: float) -> None:
    # a sonar mounted behind the lens: a range under the mounting leaves no depth;
    # the check must not search (its pitch sweep would raise on the negative depth)
    cam = CameraModel.paper(500, 375)
    image, _, spec = render_room("photo", 2078, False, cam)
    rig = dataclasses.replace(spec.rig, sonar_ahead_m=ahead_m)
    found = Measurer(cam, rig).measure(image, 0.02)
    assert not found.detected and "depth" in (found.reason or "")


# Sound but unsure answers with the rig (reported under CHECK_CONFIDENCE, within 2 %):
# each is checked by the search, and the shipped default keeps it. The other vision tests
# run with the check off (tests/vision/conftest.py), one rule at a time; these guard the
# whole method as shipped against a search that would swap a sound answer away.
@pytest.mark.parametrize(
    ("family", "seed", "hard"),
    [
        ("procedural", 109, True),
        ("procedural", 149, False),
        ("procedural", 2053, True),
        ("photo", 101, True),
        ("photo", 143, False),
        ("photo", 736, True),
        ("photo", 2062, True),
        ("photo", 2098, True),
    ],
)
def test_a_sound_unsure_answer_is_kept(
    monkeypatch: pytest.MonkeyPatch, family: str, seed: int, hard: bool
) -> None:
    calls = _count_searches(monkeypatch)
    eh, ew = room_size_errors(family, seed, hard)
    assert calls, "the answer is unsure: it must have been checked"
    assert eh < 0.03 and ew < 0.03


def test_a_stream_does_not_check(monkeypatch: pytest.MonkeyPatch) -> None:
    # run and replay measure a stream: the check's ~10x a frame and its search's memory
    # are left out there (STREAM_RIG_CHECK); a single image is checked
    from obstacle_fusion.api import LazyMeasurer

    calls = _count_searches(monkeypatch)
    cam = CameraModel.paper(500, 375)
    image, truth, spec = render_room("photo", 2078, False, cam)
    lazy = LazyMeasurer(cam, spec.rig, "fused")
    lazy.measure(image, truth["range_m"])
    assert not calls
    assert Measurer(cam, spec.rig).rig_check and not measure.STREAM_RIG_CHECK
    Measurer(cam, spec.rig).measure(image, truth["range_m"])
    assert len(calls) == 1
