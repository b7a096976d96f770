"""A face in the lightness of what stands beside it: a last try on a channel turned towards
the face's colour against the background (``channel.face_background_grey``, with the rig,
only where the face-floor channel and luminance gave no face)."""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.sim.room_scene import render_room
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import channel, extent, method, past_seam, region, top
from obstacle_fusion.vision.fused.channel import (
    BACKGROUND_ROWS_M,
    MIN_CHROMA_STEP,
    SEAM_STRIP_M,
    face_background_grey,
    side_on_seam,
)
from obstacle_fusion.vision.fused.confidence import (
    FLOOR_IN_FACE,
    FOOT_ABOVE_CONTACT,
    FOOT_OFF_FLOOR,
    TOP_FROM_SIDES,
)
from obstacle_fusion.vision.fused.method import FusedMethod
from obstacle_fusion.vision.measure import Measurer
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import Measurement, View

H, W = 240, 320
FY = 300.0
DEPTH = 1.0  # metres: a metre at the face is FY rows
CONTACT = 200  # the face's floor-contact row
TOP, LEFT, RIGHT = 80, 110, 210  # the drawn face
WALL = (180, 110, 60)  # BGR: a blue wall, luminance 103
FACE = (103, 103, 103)  # a grey face of the wall's luminance
FLOOR = (40, 50, 60)  # a dark floor
LUMA = np.array([0.114, 0.587, 0.299])
CAM = CameraModel.paper(500, 375)


def level_view() -> View:
    """A distortion-free camera with no pitch: the levelled view is the image itself."""
    k = np.array([[FY, 0.0, W / 2], [0.0, FY, H / 2], [0.0, 0.0, 1.0]])
    return View(CameraModel(k, np.zeros(5), W, H), Rig(), "level")


def room(
    face: tuple[float, float, float] = FACE,
    wall: tuple[float, float, float] = WALL,
    wall_from_m: float = 0.0,
    behind: tuple[float, float, float] = FLOOR,
) -> npt.NDArray[np.uint8]:
    """The wall down to ``wall_from_m`` above the contact row (at the face's depth), below
    it ``behind`` (the floor seen past the face) down to the contact row, the floor below;
    the face LEFT..RIGHT x TOP..CONTACT."""
    img = np.empty((H, W, 3), np.float64)
    img[:] = wall
    if wall_from_m > 0.0:
        img[int(round(CONTACT - FY * wall_from_m / DEPTH)) : CONTACT] = behind
    img[CONTACT:] = FLOOR
    img[TOP:CONTACT, LEFT:RIGHT] = face
    return np.clip(img, 0, 255).astype(np.uint8)


def side_step(out: npt.NDArray[np.uint8], row: int = 120) -> float:
    """The channel's step across the face's left side on ``row``."""
    return abs(float(out[row, LEFT + 5]) - float(out[row, LEFT - 5]))


def test_the_sides_of_a_face_in_the_walls_lightness_show_in_the_turned_channel() -> None:
    img = room()
    luma = img.astype(np.float64) @ LUMA
    assert abs(luma[120, LEFT + 5] - luma[120, LEFT - 5]) < 2  # luminance: no side
    out = face_background_grey(img, level_view(), float(CONTACT), DEPTH)
    assert out is not None and out.ndim == 2
    assert side_step(out) > 12


def test_a_grey_frame_or_a_background_of_the_faces_colour_gives_no_channel() -> None:
    view = level_view()
    img = room()
    assert face_background_grey(img[:, :, 1].copy(), view, float(CONTACT), DEPTH) is None
    assert face_background_grey(room(wall=FACE), view, float(CONTACT), DEPTH) is None


def test_a_background_a_shade_off_the_faces_colour_gives_no_channel() -> None:
    # the face's grey a few levels lighter: no colour step to turn towards
    view = level_view()
    assert face_background_grey(room(wall=(108, 108, 108)), view, float(CONTACT), DEPTH) is None


@pytest.mark.parametrize("shift, turned", [(-2.0, False), (2.0, True)])
def test_the_chroma_step_limit(shift: float, turned: bool) -> None:
    # the wall's colour a grey plus a chroma just under or just over MIN_CHROMA_STEP
    # (a blue-yellow direction of zero luminance change: B up, R and G down)
    d = np.array([1.0, -0.114 / (0.587 + 0.299), -0.114 / (0.587 + 0.299)])
    d /= np.linalg.norm(d - (d @ LUMA) / (LUMA @ LUMA) * LUMA)
    wall = tuple(np.array(FACE, np.float64) + (MIN_CHROMA_STEP + shift) * d)
    out = face_background_grey(room(wall=wall), level_view(), float(CONTACT), DEPTH)  # type: ignore[arg-type]
    assert (out is not None) is turned


def test_the_background_is_read_above_the_floor_seen_past_the_face() -> None:
    # the floor behind the face in the face's own colour up to just under the lowest
    # background row: the wall above is what the face is told from
    below = 0.09  # metres: under BACKGROUND_ROWS_M's lowest
    assert below < min(BACKGROUND_ROWS_M)
    assert (
        face_background_grey(
            room(wall_from_m=below, behind=FACE), level_view(), float(CONTACT), DEPTH
        )
        is not None
    )
    # ... and where it reaches over most of the rows read, it is the background
    over = 0.22  # metres: over two of the three rows
    assert sorted(BACKGROUND_ROWS_M)[1] < over < max(BACKGROUND_ROWS_M)
    assert (
        face_background_grey(
            room(wall_from_m=over, behind=FACE), level_view(), float(CONTACT), DEPTH
        )
        is None
    )


def test_a_face_filling_the_rows_read_is_its_own_background() -> None:
    img = room()
    img[TOP:CONTACT, :] = FACE
    assert face_background_grey(img, level_view(), float(CONTACT), DEPTH) is None


def _seams_room() -> tuple[npt.NDArray[np.uint8], dict[str, float], Rig]:
    """A photo room whose face, in the lightness of the wall behind it, has a seam: with
    the rig, the seam and a side were the only pair found, unsure (photo 1278 ordinary)."""
    image, truth, spec = render_room("photo", 1278, False, CAM)
    return image, truth, spec.rig


def test_a_face_missed_on_luminance_is_found_on_the_background_channel(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    image, truth, rig = _seams_room()
    # region.BRIDGE_STRIPES (session 41) crosses the seam on the luminance already (h -3 %,
    # w +1 %, at 0.05): without it the background channel is the only way to the face
    monkeypatch.setattr(region, "BRIDGE_STRIPES", False)
    # ... and so does extent.TOP_ALONE_LINE (session 43: the top, one line on its row, walked
    # alone past the seam; h -3 %, w +1 %, at 0.05)
    monkeypatch.setattr(extent, "TOP_ALONE_LINE", False)
    monkeypatch.setattr(measure, "BACKGROUND_TURN", False)
    assert not Measurer(CAM, rig).measure(image, truth["range_m"]).detected
    monkeypatch.setattr(measure, "BACKGROUND_TURN", True)
    res = Measurer(CAM, rig).measure(image, truth["range_m"])
    assert res.detected, res.reason
    assert res.height_m == pytest.approx(truth["height_m"], rel=0.05)
    assert res.width_m == pytest.approx(truth["width_m"], rel=0.05)
    assert res.confidence is not None and res.confidence < 0.5  # a last try: unsure


def test_a_face_found_before_is_not_tried_again(monkeypatch: pytest.MonkeyPatch) -> None:
    image, truth, spec = render_room("photo", 100, False, CAM)

    def never(*_: object) -> None:
        raise AssertionError("the background channel was tried after a face was found")

    monkeypatch.setattr(measure, "face_background_grey", never)
    assert Measurer(CAM, spec.rig).measure(image, truth["range_m"]).detected
    assert channel.face_background_grey is not never


SEAM = 150  # a dark seam's columns SEAM..SEAM+2 on the face


def seamed(seam_from_m: float = 0.0, shade: int = 40) -> npt.NDArray[np.uint8]:
    """The face in front of the wall, a seam of grey ``shade`` running up it from
    ``seam_from_m`` above its foot (metres at the face)."""
    img = room()
    img[TOP : int(round(CONTACT - FY * seam_from_m / DEPTH)), SEAM : SEAM + 3] = shade
    return cv2.cvtColor(img, cv2.COLOR_BGR2GRAY)


def test_a_side_on_a_seam_is_told_from_a_side_between_two_shades() -> None:
    view = level_view()
    grey = seamed()
    assert side_on_seam(grey, (SEAM + 1, TOP, RIGHT, CONTACT), view, DEPTH)
    assert side_on_seam(grey, (LEFT, TOP, SEAM + 1, CONTACT), view, DEPTH)
    # the face's own sides part the face from the wall (and a dark box from the floor's
    # colour): no seam
    dark = grey.copy()
    dark[:CONTACT, :LEFT] = 20
    dark[:CONTACT, RIGHT:] = 20
    assert not side_on_seam(dark, (LEFT, TOP, RIGHT, CONTACT), view, DEPTH)


@pytest.mark.parametrize("off, on_seam", [(3, True), (4, False)])
def test_a_side_reads_the_columns_next_to_it(off: int, on_seam: bool) -> None:
    # a side taken SEAM_SIDE_COLUMNS from the seam's reach still stands on it
    grey = seamed()
    box = (float(SEAM + 2 + off), float(TOP), float(RIGHT), float(CONTACT))
    assert side_on_seam(grey, box, level_view(), DEPTH) is on_seam


def test_a_seam_is_read_just_above_the_foot() -> None:
    # a seam from a little over SEAM_STRIP_M up (over a plinth): not at the foot
    grey = seamed(seam_from_m=0.06)
    assert SEAM_STRIP_M < 0.06
    assert not side_on_seam(grey, (SEAM + 1, TOP, RIGHT, CONTACT), level_view(), DEPTH)
    assert side_on_seam(seamed(0.0), (SEAM + 1, TOP, RIGHT, CONTACT), level_view(), DEPTH)


@pytest.mark.parametrize(("plinth_rows", "on_seam"), [(13, True), (14, True), (16, False)])
def test_a_seam_over_a_plinth_is_read_within_the_strip(plinth_rows: int, on_seam: bool) -> None:
    """A black seam running up from ``plinth_rows`` above the foot, over a plinth: the
    strip read reaches 5 cm (SEAM_STRIP_M, 15 rows) above the foot and stops a row short
    of it (the foot's blur). From 13 rows (4.3 cm) it holds the seam's 3 lowest rows, from
    14 its 2 lowest, enough for a line (a strip of 4 cm or less would hold none, one a row
    lower 1); from 16 rows (5.3 cm) none (one of 6 cm would hold 3 of them)."""
    grey = seamed(seam_from_m=plinth_rows / FY, shade=0)
    box = (SEAM + 1.0, float(TOP), float(RIGHT), float(CONTACT))
    assert side_on_seam(grey, box, level_view(), DEPTH) is on_seam


def stripe(height_m: float, shift: int = 0) -> npt.NDArray[np.uint8]:
    """:func:`room` with a 3-row stripe of the face's colour across the frame (a shelf, a
    rail on the wall) centred ``shift`` rows under ``height_m`` above the contact row."""
    img = room()
    row = int(round(CONTACT - FY * height_m / DEPTH)) + shift
    img[row - 1 : row + 2] = FACE
    return img


@pytest.mark.parametrize("height_m", [0.1, 0.2, 0.3])
def test_the_background_is_read_on_its_rows(height_m: float) -> None:
    """The background is the median colour of the rows 10, 20 and 30 cm above the contact
    row (BACKGROUND_ROWS_M), the face's own columns among them: a stripe of the face's
    colour on one of them makes the face's colour their median (no channel); the same
    stripe 3 rows (1 cm) off that row is not read."""
    view = level_view()
    assert face_background_grey(stripe(height_m), view, float(CONTACT), DEPTH) is None
    for shift in (-3, 3):
        assert (
            face_background_grey(stripe(height_m, shift), view, float(CONTACT), DEPTH) is not None
        )


def test_a_last_try_face_on_a_seam_is_not_taken(monkeypatch: pytest.MonkeyPatch) -> None:
    # photo 1113 ordinary: a face of two planks, missed on luminance; on the background
    # channel the left plank alone, its right side the joint, 31 % narrow (since session
    # 50 past_seam.SIDES_PAST_SEAMS finds the face before the last try, w +1.0 % at 0.07:
    # off here, the last try is this test's)
    monkeypatch.setattr(past_seam, "SIDES_PAST_SEAMS", False)
    image, truth, spec = render_room("photo", 1113, False, CAM)
    assert not Measurer(CAM, spec.rig).measure(image, truth["range_m"]).detected
    monkeypatch.setattr(measure, "side_on_seam", lambda *_: False)
    res = Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    assert res.detected and res.width_m is not None
    assert abs(res.width_m / truth["width_m"] - 1.0) > 0.25


def test_a_last_try_face_off_the_contact_row_is_not_taken(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # photo 1303 ordinary: on the background channel a face whose foot stands above the
    # contact row the rig predicts (56 % short, 39 % wide): another surface's outline
    # (the rig puts the face's foot past the view's: since session 45 FOOT_AT_VIEW_EDGE
    # finds the face before the last try, tests/vision/test_foot_at_view_edge.py; off
    # here, the last try is this test's)
    monkeypatch.setattr(method, "FOOT_AT_VIEW_EDGE", False)
    # (top.STAIRS_CHAINED, session 48, reads that outline's top on down a staircase, and
    # no face is then found at all: off, to keep the outline this test refuses)
    monkeypatch.setattr(top, "STAIRS_CHAINED", False)
    image, truth, spec = render_room("photo", 1303, False, CAM)
    assert not Measurer(CAM, spec.rig).measure(image, truth["range_m"]).detected
    assert FOOT_ABOVE_CONTACT in measure.LAST_TRY_FOOT_DOUBTS
    monkeypatch.setattr(
        measure, "LAST_TRY_FOOT_DOUBTS", measure.LAST_TRY_FOOT_DOUBTS - {FOOT_ABOVE_CONTACT}
    )
    res = Measurer(CAM, spec.rig).measure(image, truth["range_m"])
    assert res.detected and res.height_m is not None
    assert FOOT_ABOVE_CONTACT in res.doubts
    assert abs(res.height_m / truth["height_m"] - 1.0) > 0.25


@pytest.mark.parametrize(
    "doubt, taken",
    [
        (FOOT_ABOVE_CONTACT, False),
        (FOOT_OFF_FLOOR, False),
        (FLOOR_IN_FACE, False),
        (TOP_FROM_SIDES, True),
    ],
)
def test_a_last_try_face_doubting_its_foot_is_not_taken(
    monkeypatch: pytest.MonkeyPatch, doubt: str, taken: bool
) -> None:
    """The last try's face is taken only where it stands on the contact row the rig
    predicts: a face doubting its foot there (above it, off the floor, floor within the
    face) is some other surface's outline; a doubt about its top does not refuse it. (The
    runs are faked: none finds a face but the one on the background channel.)"""
    turned = np.zeros((CAM.height, CAM.width), np.uint8)

    def run(
        self: FusedMethod, image: npt.NDArray[np.uint8], range_m: float, *_: object, **__: object
    ) -> Measurement:
        if image is not turned:
            return Measurement(detected=False, method="fused", range_m=range_m)
        return Measurement(
            detected=True,
            method="fused",
            range_m=range_m,
            height_m=0.3,
            width_m=0.3,
            box_px=(200.0, 150.0, 300.0, 250.0),
            confidence=0.9,
            doubts=[doubt],
        )

    monkeypatch.setattr(FusedMethod, "run", run)
    monkeypatch.setattr(measure, "face_background_grey", lambda *_: turned)
    monkeypatch.setattr(measure, "side_on_seam", lambda *_: False)
    image = np.full((CAM.height, CAM.width, 3), 100, np.uint8)
    assert Measurer(CAM, Rig()).measure(image, 1.0).detected is taken
