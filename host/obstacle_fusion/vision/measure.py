"""One interface for both measurement methods: ``Measurer(camera, rig, method).measure(image, L)``.

The method registry lives here and imports the methods; the methods import only the shared
types (:mod:`obstacle_fusion.vision.types`), so nothing imports back. Everything that
depends only on the camera, the rig and the image size (undistortion and levelling maps,
buffers) is built once per image size and reused for every frame.
"""

from __future__ import annotations

import copy
import dataclasses
import logging
import math
from collections.abc import Callable
from typing import Any, cast

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.errors import UserError
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import FusedMethod
from obstacle_fusion.vision.fused import method as fused_method
from obstacle_fusion.vision.fused.channel import (
    face_background_grey,
    face_floor_grey,
    side_on_seam,
)
from obstacle_fusion.vision.fused.confidence import (
    DOUBT_FACTOR,
    FLOOR_IN_FACE,
    FOOT_ABOVE_CONTACT,
    FOOT_OFF_FLOOR,
    FRAME_ROUND,
    FRAMED,
    NEAR_RIVALS,
    PITCH_RERUN_DISAGREES,
    PITCH_UNREAD,
    SECOND_TOP,
    SKEWED_EDGES,
    SMALL_FACE,
    TOP_BAND_UNLIKE_FACE,
    TOP_FROM_SIDES,
    TOP_RUNS_ON,
    TRIAL_RIVAL,
    UNEVEN_SIDES,
    pixel_factor,
    reported_confidence,
)
from obstacle_fusion.vision.fused.floor_contact import (
    band_columns,
    contact_rows,
    face_apart_from_floor,
    face_runs_above,
    face_runs_below,
    print_runs_below,
    sides_reach_foot,
    sides_run_down,
    sides_run_up,
    weak_contact_rows,
)
from obstacle_fusion.vision.fused.method import (
    RAISED_FACE_MAX_M,
    contact_band,
    stands_for_strip,
    thin_strip,
)
from obstacle_fusion.vision.fused.tuning import MIN_SIZE_M
from obstacle_fusion.vision.paper import PaperMethod
from obstacle_fusion.vision.pitch import (
    camera_height_for_row,
    level_scales,
    pitch_for_row,
    pitch_from_undistorted,
    refit_side,
)
from obstacle_fusion.vision.rig import Rig, check_range
from obstacle_fusion.vision.types import Box, Line, Measurement, Method, Timer, View

log = logging.getLogger(__name__)


def _paper(camera: CameraModel, rig: Rig, min_confidence: float | None) -> Method:
    return PaperMethod(View(camera, rig, "plain"))


def _fused(
    camera: CameraModel, rig: Rig, min_confidence: float | None, eager_tables: bool = True
) -> FusedMethod:
    fused = FusedMethod(View(camera, rig, "level"), eager_tables=eager_tables)
    if min_confidence is not None:
        fused.min_confidence = min_confidence
    warm_colour_tables()
    return fused


def warm_colour_tables() -> None:
    """Build OpenCV's CIE Lab tables now: its first 8-bit BGR to Lab conversion in a process
    builds them (~90 ms), which would otherwise land on the first colour frame's clock (the
    region stages read the frame in Lab). The tables are fixed: no result changes."""
    cv2.cvtColor(np.zeros((1, 1, 3), np.uint8), cv2.COLOR_BGR2LAB)


METHODS: dict[str, Callable[[CameraModel, Rig, float | None], Method]] = {
    "fused": _fused,
    "paper": _paper,
}


def _spans_band(box_px: tuple[float, float, float, float] | None, band: npt.ArrayLike) -> bool:
    """Whether a face's box (input pixels) spans a band's first and last columns (input
    pixels), within BAND_SPAN_SLACK_PX for the mapping's rounding."""
    if box_px is None:
        return False
    first, last = (float(x) for x in np.asarray(band, np.float64)[:2])
    return box_px[0] <= first + BAND_SPAN_SLACK_PX and last - BAND_SPAN_SLACK_PX <= box_px[2]


class Measurer:
    """Measure an obstacle's height and width from one frame and the sonar's range."""

    def __init__(
        self,
        camera: CameraModel,
        rig: Rig | None = None,
        method: str = "fused",
        min_confidence: float | None = None,
        rig_source: str | None = None,
    ) -> None:
        """``rig_source`` labels a given rig (default "file"; "estimated" for a rig fitted
        online over many frames)."""
        if method not in METHODS:
            raise UserError(f"unknown method {method!r}; choose one of {', '.join(METHODS)}")
        if min_confidence is not None and not 0.0 <= min_confidence <= 1.0:
            raise UserError(f"min_confidence must be within 0..1, got {min_confidence}")
        self.camera = camera
        # No rig given: the fused method finds the floor contact in each frame instead of
        # trusting a guessed camera height ("estimated"); the paper's method never uses the
        # camera height, so it runs with the default rig ("default").
        self.find_floor = rig is None and method == "fused"
        self.rig_source = rig_source or (
            "file" if rig is not None else ("estimated" if method == "fused" else "default")
        )
        self.rig = rig if rig is not None else Rig()
        # whether the sonar's mounting is known (a rig given, or the rig check's searcher
        # keeping the rig's): if not, BEAM_HOLDS_FACE allows BEAM_MOUNT_ALLOWANCE_M for it
        self._mount_known = rig is not None
        self.method = method
        self.min_confidence = min_confidence  # None: the method's default (fused only)
        self._per_size: dict[tuple[int, int], Method] = {}
        # with no rig: the camera height and pitch the last frame gave (None: seek), and
        # the doubts its pitch left (a pitch not read stays unread in the frames reusing it)
        # camera height, pitch and whether the known-floor cues found the face
        self._last_rig: tuple[float, float, bool] | None = None
        self._last_pitch_doubts: list[str] = []
        # ... and whether its face was read allowing the lens to look further down than
        # its read pitch (READ_PITCH_TOP_FACE): the next frame reads it so again
        self._last_slack = False
        self._sweep_rest = 0  # frames still to go without the last-resort pitch sweep
        self._known_rest = 0  # ... and without the rows read as with a rig (KNOWN_RIG_ROWS)
        self._under_rest = 0  # ... and without those rows read under an unsure face only
        # with no rig: fused methods levelled for the pitches recent frames gave
        self._pitched: dict[tuple[int, int, float], FusedMethod] = {}
        self._views_kept = PITCHED_VIEWS_KEPT  # how many of them
        # with a rig: the no-rig search that checks an unsure face (RIG_CHECKED_BY_SEARCH),
        # and the frames still to go without it after a check that took nothing
        self._searcher: Measurer | None = None
        self._check_rest = 0
        # whether this measurer runs the rig check (a stream turns it off: STREAM_RIG_CHECK)
        self.rig_check = True

    def _method_for(self, width: int, height: int) -> Method:
        key = (width, height)
        impl = self._per_size.get(key)
        if impl is None:
            cam = self.camera.scaled_to(width, height)  # CameraModelError if aspect differs
            impl = METHODS[self.method](cam, self.rig, self.min_confidence)
            self._per_size[key] = impl
        return impl

    def prepare_size(self, width: int, height: int) -> None:
        """Build the per-size state now (maps, tables), not on the first frame's clock."""
        self._method_for(width, height)

    def _pitched_method(self, width: int, height: int, pitch_deg: float) -> FusedMethod:
        """A fused method whose view is levelled for ``pitch_deg`` (maps built once per
        pitch; a stream's few recent pitches are kept)."""
        key = (width, height, pitch_deg)
        impl = self._pitched.pop(key, None)
        if impl is None:
            cam = self.camera.scaled_to(width, height)
            rig = dataclasses.replace(self.rig, camera_pitch_deg=pitch_deg)
            impl = _fused(cam, rig, self.min_confidence, eager_tables=False)
        self._pitched[key] = impl  # most recent last
        while len(self._pitched) > self._views_kept:
            del self._pitched[next(iter(self._pitched))]
        return impl

    def _run_estimated(
        self, impl: Method, image: npt.NDArray[Any], range_m: float, timer: Timer
    ) -> Measurement:
        """Each floor-contact row found in the image, lowest first, is one camera height to
        try; the first that gives a face wins (below the face there is only floor, so the
        lowest step that stands a face on it is the contact: ranking the rows by confidence
        instead picked steps inside the face or the box's top on independently made rooms).
        When no row stands a face so, the rows are tried again, lowest first, with the cues
        a known floor row allows (:meth:`FusedMethod.run`'s ``floor_known``). The row
        taken is tried 2 px up and down and at a few usual pitches too, and the surest
        face kept (the level view's face can change with a pixel of row or a guessed
        camera height off by D tan(pitch)).

        Those trials take the pitch as 0. The face found then gives the pitch (its two
        vertical sides converge towards the vertical vanishing point,
        :mod:`obstacle_fusion.vision.pitch`); when that estimate is confident, the camera
        height follows from the face's floor-contact row and that pitch, and the face is
        measured once more in the view levelled for it (kept when it finds the same face,
        else the pitch-0 face's size scaled to that view). A face whose sides gave no pitch
        carries the doubt PITCH_UNREAD (:mod:`obstacle_fusion.vision.fused.confidence`).

        In a stream the camera height and pitch do not change between frames: the ones the
        last frame accepted are tried first, and the rows are sought only when they give no
        sure face (one trial a frame instead of up to eighteen, until the run's online rig
        exists); a pitch only guessed by the sweep, not read from the face's sides, is not
        carried on.

        A face whose pitch stays unread is measured once more allowing for a lens that
        looks down up to UNREAD_PITCH_DOWN_DEG more than guessed (the box's top face may
        then show above the guessed horizon, and its back edge would be taken for the top),
        and that face kept unless clearly less sure. When nothing stands a sure face, the
        surest face a pitched view found near the horizon is reported with its low
        confidence rather than missed; when nothing stands any face, or only an unsure
        one, the rows and the band's weaker steps are tried at the swept pitches
        (:meth:`_pitch_swept_rows`; over an unsure face only as :func:`_swept_over`
        allows)."""
        fused = cast(FusedMethod, impl)
        view: View = fused.view
        depth = self.rig.face_depth(range_m)
        best: Measurement | None = None
        h_img, w_img = image.shape[:2]

        def trial(
            height: float,
            row: float | None = None,
            pitch: float = 0.0,
            floor_known: bool = False,
            slack: float = 0.0,
        ) -> Measurement:
            if not _robot_row(height, pitch, depth):
                # no robot's lens, at any usual pitch, images the floor contact there
                log.debug("no rig: camera %.3f m, pitch %.1f deg: no robot's row", height, pitch)
                return Measurement(
                    False, fused.name, range_m, distance_m=range_m, reason=NO_ROBOT_ROW
                )
            method = fused if pitch == 0.0 else self._pitched_method(w_img, h_img, pitch)
            base = method.view
            method.view = copy.copy(base)
            method.view.rig = dataclasses.replace(
                self.rig, camera_height_m=height, camera_pitch_deg=pitch
            )
            method.view.horizon_slack_px = slack
            if row is None:
                row = base.cy + base.fy * height / depth
            try:
                grey = face_floor_grey(image, base, row, depth)
                result = method.run(
                    grey, range_m, timer, image, floor_known=floor_known, rig_known=False
                )
            finally:
                method.view = base
            if _wall_band(result):
                if result.box_px is not None and not (
                    BAND_ON_FLOOR and _band_on_floor(image, result.box_px)
                ):
                    bands.append(result.box_px)
                # a band along the wall (its foot, a skirting board) on a row taken for the
                # floor contact: no obstacle's face; the rows go on as if it found none
                result = _refused(result, range_m, row, "a band along the wall, not a face")
            elif (
                BEAM_HOLDS_FACE
                and result.detected
                and _outside_beam(result.box_px, view, self.rig, range_m, depth, self._allowance())
            ):
                # the sonar's echo comes from inside its beam: a face wholly beside the
                # cone at the range is another object than the one ranged
                result = _refused(result, range_m, row, "a face outside the sonar's beam")
            elif result.detected and _in_wall_band(result.box_px, bands):
                # the face's foot ends inside a band along the wall another row stood
                # (the wall's foot, a skirting board): the face is on the wall behind the
                # obstacle (a poster, a print, a box farther back), not on the floor
                # before it where the sonar's obstacle stands
                result = _refused(
                    result,
                    range_m,
                    row,
                    "a face standing in a band along the wall, not an obstacle's",
                )
            result.camera_height_m = float(height)
            result.camera_pitch_deg = pitch
            if result.detected:
                readings.append(result)
            if accepted(result):
                sure_trials.append(result)
            if log.isEnabledFor(logging.DEBUG):  # up to ~20 trials a frame: format only if read
                log.debug(
                    "no rig: camera %.3f m, pitch %.1f deg, row %.0f, slack %.0f px%s: %s, "
                    "h %s, w %s, conf %.2f, box %s, doubts %s",
                    height,
                    pitch,
                    row,
                    slack,
                    ", known floor" if floor_known else "",
                    "face" if result.detected else "none",
                    result.height_m,
                    result.width_m,
                    result.confidence or 0.0,
                    result.box_px and tuple(round(b) for b in result.box_px),
                    result.doubts,
                )
            return result

        def accepted(result: Measurement) -> bool:
            return result.detected and (result.confidence or 0.0) >= ESTIMATE_ACCEPT

        def level_height(row: float) -> float:
            return camera_height_for_row(row, depth, 0.0, view.fy, view.cy)

        def plausible(height: float) -> bool:
            return MIN_ESTIMATED_CAMERA_HEIGHT_M <= height < MAX_ESTIMATED_CAMERA_HEIGHT_M

        # rows the true horizon may lie above a guessed pitch's (its top face allowed for)
        unread_slack = view.fy * math.tan(math.radians(UNREAD_PITCH_DOWN_DEG))
        pitch_read = False  # the face's sides gave the pitch best is measured at
        pitch_swept = False  # best's pitch is the sweep's guess
        floor_known = False  # best was found with the known-floor cues
        fallback: Measurement | None = None  # the last frame's rig's face, not sure
        unstood = 0  # faces found on rows they did not stand on
        unsure: Measurement | None = None  # the surest near-horizon face, not accepted
        sure_trials: list[Measurement] = []  # every trial's face of at least ESTIMATE_ACCEPT
        readings: list[Measurement] = []  # every trial's face
        bands: list[tuple[float, float, float, float]] = []  # wall bands the trials found
        slack_best: Measurement | None = None  # best, when read with the top face allowed for
        try:
            last = self._last_rig
            if last is not None:
                # a pitch the last frame did not read, or read and its top face allowed
                # for: the top face allowed for as there
                slack = PITCH_UNREAD in self._last_pitch_doubts or self._last_slack
                first = trial(last[0], None, last[1], last[2], unread_slack if slack else 0.0)
                if accepted(first):
                    best, floor_known = first, last[2]
                    slack_best = first if slack else None
                    best.doubts = [*best.doubts, *self._last_pitch_doubts]
                    pitch_read = True  # (its doubts are the last frame's)
                    return best
                if first.detected:
                    fallback = first  # taken only if the rows give no face
            rows = contact_rows(image, view, depth)
            timer.lap("floor_contact")
            near_horizon: list[int] = []
            pitch_tried = False  # the pitch is settled already (a near-horizon face)
            best_row: int | None = None  # the floor-contact row best was found on
            lower_faces: list[tuple[int, Measurement]] = []  # rows' faces not accepted
            frame_foot = False  # best is a frame taken round a print (JITTER_FRAME_HOLDS)
            for row in rows:
                height = level_height(row)
                if height >= MAX_ESTIMATED_CAMERA_HEIGHT_M:
                    continue
                if height < MIN_ESTIMATED_CAMERA_HEIGHT_M:
                    near_horizon.append(row)
                    continue
                result = trial(height, row)
                if result.detected and not sides_reach_foot(image, result.lines):
                    unstood += 1
                    continue  # a line on the floor below the face: its sides end above it
                if (
                    best is None
                    or (result.detected and not best.detected)
                    or (
                        result.detected
                        and FLOOR_IN_FACE in best.doubts
                        and FLOOR_IN_FACE not in result.doubts
                    )
                    or (result.detected and _small(best) and not _small(result))
                ):
                    # with no row accepted, the lowest that stands a face: below the face
                    # there is only floor (a surer face higher up stands on a line on it).
                    # A face whose lowest band has the colour under it (FLOOR_IN_FACE)
                    # took floor in, its row below the foot (a floor tile between two
                    # joints, a face's strip run down over its shadow): it settles no row,
                    # and the lowest face above it without that doubt replaces it. Nor
                    # does a small face (a stone, a mark on the floor: _small) under a
                    # face of full size
                    best, best_row = result, row
                if accepted(result) and FLOOR_IN_FACE not in result.doubts:
                    best, best_row = result, row
                    # a print on the face stands on its own lower edge, surer than the
                    # face found on the row below it: that face, when the print's margin
                    # runs down to its foot
                    # (not accepted itself: the next frame seeks the rows again)
                    for low_row, low in lower_faces:
                        if (
                            result.box_px is not None
                            and low.box_px is not None
                            and face_runs_below(image, result.box_px, low.box_px)
                        ):
                            best, best_row = low, low_row
                            break
                        # a line across the face (a panel joint, a label's or a band's
                        # lower edge) stands the face's upper part on it: that part has
                        # the face's own top and sides, and the sides run on below it to
                        # the lower face's foot (_same_outline, sides_run_down)
                        if (
                            FLOOR_IN_FACE not in low.doubts
                            and result.box_px is not None
                            and _same_outline(result.box_px, low.box_px)
                            and sides_run_down(image, low.lines, result.box_px[3])
                        ):
                            log.debug(
                                "no rig: row %d's face is the upper part of row %d's", row, low_row
                            )
                            best, best_row = low, low_row
                            break
                        # a line of the face's own print (a row of its pattern) stands the
                        # face's upper part on it: the print runs on below that foot, to a
                        # lower face's foot with the same top, which its lowest band's
                        # likeness to the floor (FLOOR_IN_FACE: a dark print's margin on a
                        # dark floor) does not stop (print_runs_below)
                        if PRINT_LINE_FOOT and _print_line_foot(image, result, low):
                            log.debug(
                                "no rig: row %d's face stands on a line of its print; row %d's "
                                "is the face",
                                row,
                                low_row,
                            )
                            best, best_row = low, low_row
                            break
                    else:
                        # a face standing on the top of a wider face found, less surely,
                        # on a lower row stands on that box (or behind it), not on the
                        # floor: the lower face is nearer, and the sonar ranges it
                        for low_row, low in lower_faces:
                            if (
                                FLOOR_IN_FACE not in low.doubts
                                and not _small(low)
                                and low.box_px is not None
                                and _stands_on_top(result.box_px, low.box_px)
                                and face_apart_from_floor(image, low.box_px)
                            ):
                                best, best_row = low, low_row
                                break
                    break
                if result.detected:
                    lower_faces.append((row, result))
            off_floor = best is not None and FOOT_OFF_FLOOR in best.doubts
            if (
                best is not None
                and best.detected
                and best_row is not None
                and (not accepted(best) or off_floor)
            ):
                # an accepted face whose foot its own outline finds off the floor
                # (FOOT_OFF_FLOOR) stands on no floor contact either: a weak step below
                # it may be the foot, when the face standing there is on the floor
                nearer = self._nearer_weak_contact(
                    image,
                    view,
                    depth,
                    best_row,
                    set(rows),
                    trial,
                    best.box_px,
                    _small(best),
                    need_floor_foot=off_floor and accepted(best),
                )
                if nearer is not None:
                    best, best_row = nearer
            elif (
                best is not None
                and best.box_px is not None
                and best_row is not None
                and FRAMED in best.doubts
            ):
                # a print in a frame, accepted on the print's lower edge: a weak step below
                # it standing a face that covers it, the strip between them the frame's
                # colour, is the box's own foot (face_runs_below)
                framed = self._framed_print_foot(
                    image, view, depth, best_row, set(rows), trial, best.box_px
                )
                if framed is not None:
                    best, best_row = framed
            if best is not None and best.detected and best_row is not None:
                # the row is found to a pixel or two, and the face a level view finds can
                # change with it: the surest of the row and its neighbours, a face whose
                # outline finds its foot off the floor (or floor in it) the less sure
                # (JITTER_WEIGHS_FOOT)
                for row in (best_row - ROW_JITTER_PX, best_row + ROW_JITTER_PX):
                    height = level_height(row)
                    if not plausible(height):
                        continue
                    result = trial(height, row)
                    if JITTER_FRAME_HOLDS and result.detected:
                        # a print in a frame: of the two faces, the one round the other
                        # standing lower is the surface, the inner one's foot the print's
                        # lower edge (_frame_holds), however the two are weighed
                        if _frame_holds(result, best) and sides_reach_foot(image, result.lines):
                            log.debug("no rig: row %d's face holds row %d's print", row, best_row)
                            best, best_row, frame_foot = result, row, True
                            continue
                        if _frame_holds(best, result):
                            # the row's own face is the frame: guarded as one found here
                            frame_foot = True
                            continue
                    if (
                        result.detected
                        and _foot_weighed(result, best) > _foot_weighed(best, result)
                        and sides_reach_foot(image, result.lines)
                    ):
                        best, best_row, frame_foot = result, row, False
                # the pitch is not known yet, and a level view's guess of the camera's
                # height from the row is off by D tan(pitch): a box's top face seen or not
                # changes with it. The row at a few usual pitches: of the faces clearly
                # surer than the level view's, the surest is taken (its sides may still
                # read the pitch below). A level face that sure already is kept, and a
                # surer face beside it (under half its columns shared) is another face,
                # not the level face read again: not taken; nor is one over
                # SWEPT_MAX_GROWTH times as tall (something above the face taken in),
                # unless its sides run on above the level face's top (sides_run_up)
                level = best
                level_conf = best.confidence or 0.0
                level_box = best.box_px
                # a frame taken round a print (JITTER_FRAME_HOLDS): a face a pitch stands
                # higher than the frame's foot (by more than the rows' own jitter,
                # ROW_JITTER_PX) stands on the print's lower edge again
                foot_at_least = (
                    level_box[3] - ROW_JITTER_PX
                    if frame_foot and level_box is not None
                    else -math.inf
                )
                for pitch in SWEPT_PITCHES_DEG if level_conf + SWEPT_PITCH_MARGIN < 1.0 else ():
                    height = camera_height_for_row(best_row, depth, pitch, view.fy, view.cy)
                    if not plausible(height):
                        continue
                    result = trial(height, None, pitch)
                    conf = result.confidence or 0.0
                    if not (
                        result.detected
                        and sides_reach_foot(image, result.lines)
                        and not _beside(result.box_px, level_box)
                    ):
                        continue
                    if result.box_px is not None and result.box_px[3] < foot_at_least:
                        continue
                    if _taller(result.box_px, level_box):
                        # the level face's top a line on the face (a print's edge, a tape,
                        # the wall's line behind a face of nearly its colour) when the
                        # taller face's sides run on above it, at their own columns, to
                        # its top: that face as sure is the face
                        if (
                            conf >= level_conf
                            and (conf > (best.confidence or 0.0) or best is level)
                            and level_box is not None
                            and sides_run_up(image, result.lines, level_box[1])
                        ):
                            best, pitch_swept = result, True
                        continue
                    if conf > level_conf + SWEPT_PITCH_MARGIN and conf > (best.confidence or 0.0):
                        if (
                            result.box_px is not None
                            and _taller(level_box, result.box_px)
                            and sides_run_up(image, level.lines, result.box_px[1])
                        ):
                            continue  # a line on the level face, whose sides run on above it
                        best, pitch_swept = result, True
            if best is None or not best.detected:
                # no face stands on any row a level camera allows: a contact this near the
                # horizon would put a level lens on the floor, but a camera pitched down
                # sees it there. Each such row is tried at a usual height and the pitch
                # that puts the contact on it (the face's sides then give the pitch).
                above = view.fy * math.tan(math.radians(MAX_ESTIMATED_PITCH_DEG))
                lowest = view.cy + view.fy * MIN_ESTIMATED_CAMERA_HEIGHT_M / depth
                near_horizon += [r for r in contact_rows(image, view, depth, above) if r < lowest]
                # (NEAR_HORIZON_HEIGHTS: the nominal height first, then a lower lens on
                # the same row, pitched less to put the contact there; only on a row the
                # nominal lens's pitch reaches)
                heights = (
                    (NOMINAL_CAMERA_HEIGHT_M, *NEAR_HORIZON_OTHER_HEIGHTS_M)
                    if NEAR_HORIZON_HEIGHTS
                    else (NOMINAL_CAMERA_HEIGHT_M,)
                )
                tries = [
                    (row, lens)
                    for row in sorted(set(near_horizon), reverse=True)
                    for lens in heights
                ]
                for row, lens in tries:
                    pitch = pitch_for_row(row, depth, lens, view.fy, view.cy)
                    nominal_pitch = pitch_for_row(
                        row, depth, NOMINAL_CAMERA_HEIGHT_M, view.fy, view.cy
                    )
                    if max(pitch, nominal_pitch) > MAX_ESTIMATED_PITCH_DEG:
                        continue
                    result = trial(lens, None, round(pitch, PITCH_DECIMALS))
                    if not accepted(result):
                        if (
                            result.detected
                            and (result.confidence or 0.0)
                            > (unsure.confidence or 0.0 if unsure else 0.0)
                            and sides_reach_foot(image, result.lines)
                        ):
                            unsure = result  # kept if nothing else stands a face
                        continue
                    # kept when the face's own sides confirm a pitch that stands the lens
                    # at least MIN_ESTIMATED_CAMERA_HEIGHT_M above the floor, or, with the
                    # pitch guessed, when the face is a sure one
                    confirmed = self._with_pitch(result, image, view, depth, trial)
                    timer.lap("pitch")
                    pitch_tried = True
                    pitch_read = confirmed is not None
                    if confirmed is None and (result.confidence or 0.0) >= GUESSED_PITCH_SURE:
                        confirmed = result
                    if confirmed is not None:
                        best = confirmed
                        break
            if best is None or not best.detected:
                # no row stands a face by its edges or colour: each row again, lowest
                # first, with every cue a known floor row allows (the face's texture, the
                # beam's axis); the first that stands a face is taken
                for row in rows:
                    height = level_height(row)
                    if not plausible(height):
                        continue
                    result = trial(height, row, floor_known=True)
                    if result.detected and sides_reach_foot(image, result.lines):
                        best, floor_known = result, True
                        break
            if (best is None or not best.detected) and fallback is not None:
                best = fallback  # the last frame's camera height and pitch, not sure here
            if (best is None or not accepted(best)) and unsure is None:
                # still no face, or only an unsure one: the rows, and weaker steps, at a
                # few pitches; a face whose sides read the pitch is taken, else the lowest
                # sure one. Up to ~90 trials: in a stream that saw no face in its last
                # sweep (nothing in view, most likely), the next SWEEP_REST_FRAMES frames
                # go without
                if self._sweep_rest > 0:
                    self._sweep_rest -= 1
                else:
                    swept, read = self._pitch_swept_rows(image, view, depth, rows, trial)
                    timer.lap("pitch_sweep")
                    self._sweep_rest = SWEEP_REST_FRAMES if swept is None else 0
                    if swept is not None and (
                        _swept_over(best, swept, read)
                        or (SWEPT_WHOLE_FACE and _swept_whole(best, swept, read, image))
                    ):
                        # a face the sides did not confirm keeps its guessed pitch, doubted
                        # (PITCH_UNREAD) and not carried on to the next frame
                        best, pitch_read, pitch_tried = swept, read, True
                        pitch_swept = not read
            if (best is None or not best.detected) and unsure is not None:
                # nothing surer anywhere: the surest face a pitched view found near the
                # horizon, reported with its low confidence rather than missed
                best = unsure
            if best is not None and accepted(best) and not pitch_tried:
                known = floor_known  # the levelled face is sought with best's cues

                def levelled_trial(height: float, row: float | None, pitch: float) -> Measurement:
                    return trial(height, row, pitch, known)

                levelled = self._with_pitch(best, image, view, depth, levelled_trial)
                timer.lap("pitch")
                if levelled is not None:
                    best = levelled
                    pitch_read = True
            if best is not None and best.detected and (READ_PITCH_TOP_FACE or not pitch_read):
                # a lens looking down more than its pitch says sees the box's top face above
                # that pitch's horizon, where the level view allows none: measured again
                # allowing for it (the trial stays among the frame's readings)
                again = trial(
                    best.camera_height_m or 0.0,
                    None,
                    best.camera_pitch_deg or 0.0,
                    floor_known,
                    unread_slack,
                )
                moved = _top_moved(best.box_px, again.box_px)
                if pitch_read:
                    # a read pitch a few degrees too level: only the same face with its top
                    # lowered is taken (READ_PITCH_TOP_FACE)
                    if again.detected and moved is not None and moved < 0.0:
                        log.debug("no rig: a read pitch allowed down lowers the top %.1f", -moved)
                        best = slack_best = again
                elif again.detected and moved is not None:
                    # a guessed pitch, the same face, its top moved: the allowance shows a top
                    # face above the front, whose front edge is lower; it makes no face
                    # taller. Lowered, the front edge under the top face the guessed horizon
                    # hid, however sure (the band cuts the top edge's evidence); raised, a
                    # line above the face taken in (UNREAD_TOP_FACE_LOWERS)
                    if UNREAD_TOP_FACE_LOWERS:
                        if (
                            moved < 0.0
                            and TOP_FACE_DEPTH_BOUND
                            and _top_face_too_deep(best, again, view, depth)
                        ):
                            log.debug(
                                "no rig: the top %.1f rows lower would need a top face "
                                "deeper than an obstacle's; the top kept",
                                -moved,
                            )
                        elif moved < 0.0:
                            log.debug("no rig: the pitch allowed lowers the top %.1f rows", -moved)
                            best = again
                    elif _doubted(again) >= _doubted(best) - UNREAD_PITCH_CONFIDENCE_MARGIN:
                        best = again
                elif again.detected and (
                    _doubted(again) >= _doubted(best) - UNREAD_PITCH_CONFIDENCE_MARGIN
                ):
                    best = again  # a guessed pitch: kept unless clearly less sure
            if AXIS_PICKS_TRIAL and best is not None and best.detected:
                # the sonar ranges what its beam's axis hits: a face beside the axis is
                # another surface the guessed rig stood (a print, a can beside the box);
                # the surest sure trial's face on the axis, standing on its foot, is the
                # sonar's face (its pitch a guess unless read again)
                on_axis = self._on_axis_trial(best, sure_trials, view, depth, image)
                if on_axis is None and AXIS_UNSURE_TRIAL:
                    # no sure face on the axis: the surest unsure one there, still the
                    # sonar's rather than a face beside its beam
                    on_axis = self._on_axis_trial(best, readings, view, depth, image, unsure=True)
                if on_axis is not None:
                    best, pitch_read, floor_known = on_axis, False, False
            if NEARER_ON_AXIS and best is not None and best.detected:
                # the sonar ranges the nearest surface on its axis: a face standing on the
                # axis with its foot lower (nearer) than the face reported, wholly in front
                # of it or beside a face that leaves the axis out, is the sonar's face
                in_front = self._nearer_on_axis(best, readings, view, depth, image)
                if in_front is not None:
                    best, pitch_read, floor_known = in_front, False, False
                elif NEARER_UNSURE_RIVAL and _doubted(best) >= NEARER_RIVAL_SURE:
                    # an unsure face stands on the axis in front of the sure one: too
                    # unsure to be taken for the sonar's face, but the beam hits it first,
                    # so the face found may be a surface behind it that the guessed camera
                    # height stood on the range (a print on the wall over a low box). Only
                    # a face of a colour of its own against the floor under its foot: a
                    # stretch of the floor before the face (gravel) has the floor's colour.
                    # Sure: by the face's doubts and the search's so far, before the
                    # PITCH_UNREAD the search adds below (a doubt about the pitch, not about
                    # which surface the guessed height stood on the range)
                    rival = self._nearer_on_axis(
                        best, readings, view, depth, image, accept=NEARER_RIVAL_ACCEPT
                    )
                    if (
                        rival is not None
                        and rival.box_px is not None
                        and face_apart_from_floor(image, rival.box_px)
                    ):
                        log.debug("no rig: an unsure face stands nearer on the axis: a rival")
                        best.doubts = [*best.doubts, TRIAL_RIVAL]
        finally:
            if best is not None and best.detected and not pitch_read:
                best.doubts = [*best.doubts, PITCH_UNREAD]
            if (
                best is not None
                and best.detected
                and TRIAL_RIVAL not in best.doubts
                and _rival_trial(best, sure_trials, lambda r: sides_reach_foot(image, r.lines))
            ):
                best.doubts = [*best.doubts, TRIAL_RIVAL]
            self._last_rig = (
                (
                    best.camera_height_m or 0.0,
                    best.camera_pitch_deg or 0.0,
                    floor_known,
                )
                if best is not None and accepted(best) and (pitch_read or not pitch_swept)
                else None
            )
            self._last_slack = self._last_rig is not None and best is slack_best
            self._last_pitch_doubts = [
                d for d in (best.doubts if best is not None else []) if d in PITCH_DOUBTS
            ]
        if best is None:
            found = (
                f"the faces found on the floor-contact rows ({unstood}) did not stand on them"
                if unstood
                else "no floor contact found below the beam"
            )
            return Measurement(
                False,
                self.method,
                range_m,
                reason=f"no rig given and {found}; "
                "give --rig (obstacle-fusion calibrate-rig writes one)",
            )
        if best.detected and _doubted(best, REFUSAL_IGNORES) < MIN_DOUBTED_CONFIDENCE:
            # the same face read by another trial without some of the doubts: those belong
            # to that reading (a guessed pitch or row), not to the face
            reread = _less_doubted_reading(
                best, readings, lambda r: sides_reach_foot(image, r.lines)
            )
            if reread is None and WHOLE_FACE_READING:
                reread = _whole_face_reading(
                    best, readings, lambda r: sides_reach_foot(image, r.lines)
                )
            if reread is not None:
                self._last_rig = None
                self._last_pitch_doubts = []
                return reread
            # every cue against it: the guessed rig stood a face its own outline doubts on
            # every count (a stripe, a print, a wall band read as a face), wrong by a
            # multiple of its size more often than not; no answer is better than that one
            self._last_rig = None
            self._last_pitch_doubts = []
            return Measurement(
                False,
                self.method,
                range_m,
                confidence=best.confidence,
                reason=f"no rig given and the face found is doubted on every count "
                f"({', '.join(best.doubts)}): its confidence with them is "
                f"{_doubted(best, REFUSAL_IGNORES):.3f}, under {MIN_DOUBTED_CONFIDENCE}; "
                "give --rig (obstacle-fusion calibrate-rig writes one)",
            )
        if CLEAN_WHOLE_FACE and best.detected:
            whole = _clean_whole_face(best, readings, lambda r: sides_reach_foot(image, r.lines))
            if whole is not None:
                self._last_rig = None
                self._last_pitch_doubts = []
                return whole
        return best

    def _on_axis_trial(
        self,
        best: Measurement,
        trials: list[Measurement],
        view: View,
        depth: float,
        image: npt.NDArray[Any],
        unsure: bool = False,
    ) -> Measurement | None:
        """When ``best``'s box (input pixels) leaves the beam's axis column out, the surest
        of the sure no-rig trials (``trials``, each of at least ESTIMATE_ACCEPT) whose box
        covers that column and that stands on its foot (:func:`sides_reach_foot`), and that
        the refusal would not turn down with AXIS_SWAP_DOUBTS added; else None. The column
        is the sonar's lateral offset seen at the face's depth (the rig's default, 0, with
        none given: the lens beside the sonar). With ``unsure`` (``trials`` every trial's
        face, AXIS_UNSURE_TRIAL), only a face of full size (not :func:`_small`) whose foot
        is not doubted (FOOT_DOUBTS) is taken."""
        u_axis = _axis_column(view, self.rig, depth)
        if best.box_px is None or _covers(best.box_px, u_axis):
            return None
        chosen: Measurement | None = None
        for other in trials:
            if (
                other is best
                or other.box_px is None
                or not _covers(other.box_px, u_axis)
                or (chosen is not None and (other.confidence or 0.0) <= (chosen.confidence or 0.0))
                or not sides_reach_foot(image, other.lines)
                or (unsure and (_small(other) or bool(FOOT_DOUBTS & set(other.doubts))))
            ):
                continue
            # as it would be reported (its pitch a guess, the face beside it a rival):
            # one the refusal would turn down leaves the face beside the axis standing
            reported = dataclasses.replace(other, doubts=[*other.doubts, *AXIS_SWAP_DOUBTS])
            if _doubted(reported, REFUSAL_IGNORES) < MIN_DOUBTED_CONFIDENCE:
                continue
            chosen = other
        if chosen is not None:
            log.debug("no rig: the face beside the beam's axis gives way to one on it")
        return chosen

    def _nearer_on_axis(
        self,
        best: Measurement,
        readings: list[Measurement],
        view: View,
        depth: float,
        image: npt.NDArray[Any],
        accept: float | None = None,
    ) -> Measurement | None:
        """The no-rig trial's face (of ``readings``, every trial's face) that stands nearer
        than ``best`` on the beam's axis, or None. The sonar ranges the nearest surface on
        its axis, and of two faces standing on the floor the one whose foot is lower in the
        image is the nearer. A face qualifies when its box covers the axis column (as for
        :meth:`_on_axis_trial`), it stands on its foot (:func:`sides_reach_foot`), is not
        small (:func:`_small`), doubts not its foot (FOOT_DOUBTS), reaches
        NEARER_AXIS_ACCEPT, its foot lies at least MIN_NEARER_DROP_PX under ``best``'s and
        either ``best`` leaves the axis out, the face lies wholly under ``best``'s foot
        (something in front of it: a face overlapping ``best``'s rows may be its own
        lower part or its shadow), or ``best`` is a band across it (NEARER_ACROSS_BAND:
        ``best`` reaches past both its sides and it is ACROSS_TALLER times as tall,
        reaching above and below ``best``). Of those, the lowest foot (within ROW_JITTER_PX),
        the surest with its doubts applied, that the refusal would not turn down with
        PITCH_UNREAD added (its pitch a guess). ``accept`` (NEARER_RIVAL_ACCEPT, for
        NEARER_UNSURE_RIVAL) replaces NEARER_AXIS_ACCEPT; then any such face is returned,
        whatever the refusal would do with it (it is not reported, only a rival)."""
        if best.box_px is None:
            return None
        rival = accept is not None
        least = accept if accept is not None else NEARER_AXIS_ACCEPT
        u_axis = _axis_column(view, self.rig, depth)
        off_axis = not _covers(best.box_px, u_axis)
        foot = best.box_px[3]
        found: list[tuple[float, Measurement]] = []  # (foot row, face)
        for other in readings:
            box = other.box_px
            if (
                other is best
                or box is None
                or not _covers(box, u_axis)
                or box[3] < foot + MIN_NEARER_DROP_PX
                or not (
                    off_axis
                    or box[1] >= foot
                    or (NEARER_ACROSS_BAND and _band_across(best.box_px, box))
                )
                or (other.confidence or 0.0) < least
                or _small(other)
                or FOOT_DOUBTS & set(other.doubts)
            ):
                continue
            reported = dataclasses.replace(other, doubts=[*other.doubts, PITCH_UNREAD])
            if not rival and _doubted(reported, REFUSAL_IGNORES) < MIN_DOUBTED_CONFIDENCE:
                continue
            if sides_reach_foot(image, other.lines):
                found.append((box[3], other))
        if not found:
            return None
        lowest = max(row for row, _ in found)
        chosen = max((m for row, m in found if row >= lowest - ROW_JITTER_PX), key=_doubted)
        log.debug("no rig: a face on the beam's axis stands nearer than the face found")
        return chosen

    def _nearer_weak_contact(
        self,
        image: npt.NDArray[Any],
        view: View,
        depth: float,
        row: int,
        tried: set[int],
        trial: Callable[[float, float | None], Measurement],
        upper_box: tuple[float, float, float, float] | None = None,
        upper_small: bool = True,
        need_floor_foot: bool = False,
    ) -> tuple[Measurement, int] | None:
        """A face on a weaker step of the band below ``row`` (nearer the robot), when the
        face on ``row`` (its box ``upper_box``, input pixels) is not a sure one: the first,
        lowest first, that stands a face of at least ESTIMATE_ACCEPT on its own foot, that
        foot at least MIN_NEARER_DROP_PX under the unsure face's (else it is that face
        again, the step its foot's blur or shadow), with that row; else None.

        The sonar measured the nearest surface in its beam, so the face's foot is the
        lowest floor contact under the beam; the wall's foot, the farthest, is a clear step
        while a face of nearly the floor's colour steps little where it meets the floor
        (under the noise bar of :func:`contact_rows`). A wall's foot (or a band between
        legs at it) standing only an unsure face, with a weak step below it that stands an
        accepted one, is behind that face. So is an unsure face spanning the lower face's
        columns and SPAN_FACTOR times its width or more (a strip along the wall behind
        it), when the lower face reaches SPANNED_NEARER_ACCEPT. A small face (:func:`_small`)
        under an unsure face of full size (``upper_small`` False) is a stone or a mark on
        the floor before it, no nearer foot. With ``need_floor_foot`` (the face on ``row`` was
        accepted but its foot is off the floor: FOOT_OFF_FLOOR) only a face without
        FOOT_DOUBTS is the nearer foot."""
        lowest = view.cy + view.fy * MIN_ESTIMATED_CAMERA_HEIGHT_M / depth
        for low in weak_contact_rows(image, view, depth):  # lowest first
            if low <= row + MIN_NEARER_DROP_PX:
                break
            if low in tried or low < lowest:
                continue
            height = camera_height_for_row(low, depth, 0.0, view.fy, view.cy)
            if not MIN_ESTIMATED_CAMERA_HEIGHT_M <= height < MAX_ESTIMATED_CAMERA_HEIGHT_M:
                continue
            result = trial(height, low)
            if not (
                result.detected
                and result.box_px is not None
                and (upper_box is None or result.box_px[3] >= upper_box[3] + MIN_NEARER_DROP_PX)
            ):
                continue  # no face, or the unsure face again on its own foot's blur
            if not upper_small and _small(result):
                continue  # a stone or a mark on the floor before the face, no nearer face
            if need_floor_foot and FOOT_DOUBTS & set(result.doubts):
                continue  # its foot off the floor too: no nearer foot
            conf = result.confidence or 0.0
            if (
                conf >= ESTIMATE_ACCEPT
                or (conf >= SPANNED_NEARER_ACCEPT and _spans(upper_box, result.box_px))
            ) and sides_reach_foot(image, result.lines):
                log.debug("no rig: weak row %d below row %d stands a face", low, row)
                return result, low
        return None

    def _framed_print_foot(
        self,
        image: npt.NDArray[Any],
        view: View,
        depth: float,
        row: int,
        tried: set[int],
        trial: Callable[[float, float | None], Measurement],
        print_box: tuple[float, float, float, float],
    ) -> tuple[Measurement, int] | None:
        """A face on a weaker step of the band below ``row`` that the framed print found on
        ``row`` (its box ``print_box``, input pixels) runs down to (:func:`face_runs_below`:
        the lower face covers it and the strip between their feet has the margin's
        colour), lowest first, with that row; else None. The weak steps are not among the
        rows tried for a contact, so the print's own lower edge stood for the foot."""
        for low in weak_contact_rows(image, view, depth):  # lowest first
            if low <= row + MIN_NEARER_DROP_PX:
                break
            if low in tried:
                continue
            height = camera_height_for_row(low, depth, 0.0, view.fy, view.cy)
            if not MIN_ESTIMATED_CAMERA_HEIGHT_M <= height < MAX_ESTIMATED_CAMERA_HEIGHT_M:
                continue
            result = trial(height, low)
            if (
                accepted_face(result)
                and result.box_px is not None
                and face_runs_below(image, print_box, result.box_px)
                and sides_reach_foot(image, result.lines)
            ):
                log.debug("no rig: weak row %d below the framed print's row %d", low, row)
                return result, low
        return None

    def _pitch_swept_rows(
        self,
        image: npt.NDArray[Any],
        view: View,
        depth: float,
        rows: list[int],
        trial: Callable[[float, float | None, float], Measurement],
    ) -> tuple[Measurement | None, bool]:
        """For a frame where nothing else stood a face: each floor-contact row, and each
        weaker step of the band (:func:`weak_contact_rows`), lowest first, at the swept
        pitches (and level, for a row not tried yet); the first face whose own sides then
        read the pitch (:meth:`_with_pitch`) is returned, measured at that pitch, with True.
        A lens pitched a few degrees down puts the level guess of its height off by
        D tan(pitch), and a face's foot little apart from the floor's colour steps less
        than the floor's texture: either left the frame without a face. When no face's
        sides confirm a pitch, the first sure face standing on its foot (the lowest row's:
        below the face there is only floor) with False, its pitch a guess; (None, False)
        when there is none. (Such faces were dropped before; with bands along the wall
        no longer taken for faces on the rows above, on the tuning rooms taking them
        turned three misses into two faces within 3 % and one 33 % off.) When no face is
        sure, the surest unsure face that several trials, at more than one pitch, found
        on the same foot (:func:`_repeated_face`, REPEATED_FACE), with False."""
        tried = set(rows)
        unconfirmed: Measurement | None = None
        unsure: list[Measurement] = []  # faces under ESTIMATE_ACCEPT standing on their foot
        candidates = sorted(tried | set(weak_contact_rows(image, view, depth)), reverse=True)
        for row in candidates:
            pitches = SWEPT_PITCHES_DEG if row in tried else (0.0, *SWEPT_PITCHES_DEG)
            for pitch in pitches:
                height = camera_height_for_row(row, depth, pitch, view.fy, view.cy)
                if not MIN_ESTIMATED_CAMERA_HEIGHT_M <= height < MAX_ESTIMATED_CAMERA_HEIGHT_M:
                    continue
                result = trial(height, None, pitch)
                if not (result.detected and sides_reach_foot(image, result.lines)):
                    continue
                if (result.confidence or 0.0) < ESTIMATE_ACCEPT:
                    if (
                        REPEATED_FACE
                        and not FOOT_DOUBTS & set(result.doubts)
                        and not _small(result)
                    ):
                        unsure.append(result)
                    continue
                confirmed = self._with_pitch(result, image, view, depth, trial)
                if confirmed is not None:
                    log.debug("no rig: row %d, swept pitch %.1f deg: the sides confirm", row, pitch)
                    return confirmed, True
                if unconfirmed is None:
                    unconfirmed = result
        if unconfirmed is None and REPEATED_FACE:
            unconfirmed = _repeated_face(unsure)
        return unconfirmed, False

    def _with_pitch(
        self,
        found: Measurement,
        image: npt.NDArray[Any],
        view: View,
        depth: float,
        trial: Callable[[float, float | None, float], Measurement],
    ) -> Measurement | None:
        """The face with the pitch its sides give, or None (no confident pitch, or a camera
        height out of range). Measured again in the view levelled for that pitch; when that
        finds no face, or another one no surer than the pitch-0 face, the pitch-0 face's size
        scaled to the levelled view; another, surer face is taken (the levelled view is the
        lens's geometry as the sides read it). Either way with the doubt
        PITCH_RERUN_DISAGREES. A face found at pitch 0 whose sides read
        a pitch of 0 is returned as it is (its pitch is read: it is level)."""
        if (found.confidence or 0.0) < PITCH_MIN_CONFIDENCE:
            return None
        if len(found.lines) != 4:
            return None
        pts = view.camera.undistort_points(np.array(found.lines).reshape(-1, 2)).reshape(4, 4)
        row = float(pts[0, 1::2].mean())  # the face's floor contact in the pitch-0 view
        # the sides fitted again, free to lean, in the pitch-0 view (undistorted pixels)
        seen = cv2.remap(image, view.map1, view.map2, cv2.INTER_LINEAR)
        left = refit_side(seen, cast(Line, tuple(pts[2])))
        right = refit_side(seen, cast(Line, tuple(pts[3])))
        if left is None or right is None:
            return None  # a side whose lean cannot be read: no pitch
        est = pitch_from_undistorted(left, right, view.fy, view.cy)
        if est is None:
            return None
        pitch = round(est.pitch_deg, PITCH_DECIMALS)
        if pitch == 0.0 and not found.camera_pitch_deg:
            return found  # read, and level: the face as found
        height = camera_height_for_row(row, depth, pitch, view.fy, view.cy)
        if not MIN_ESTIMATED_CAMERA_HEIGHT_M <= height < MAX_ESTIMATED_CAMERA_HEIGHT_M:
            return None
        if not _robot_lens(height):
            log.debug("pitch %.1f deg read puts the lens %.2f m up: not a robot's", pitch, height)
            return None
        if found.camera_pitch_deg:
            # found in a view levelled for a guessed pitch: measured again at this one and
            # the camera height its floor-contact row gives
            again = trial(height, None, pitch)
            accepted = again.detected and (again.confidence or 0.0) >= ESTIMATE_ACCEPT
            if accepted and not _reread_confirms(found, again):
                # another face, no surer, at the pitch the sides read: a pitch changes a
                # face's metres, not its outline, so the sides' pitch is not confirmed
                log.debug("pitch %.1f deg read: another face, no surer; unread", pitch)
                return None
            return again if accepted else None
        h_scale, w_scale = level_scales(found.lines, view.camera, pitch)
        fixed = copy.copy(found)
        fixed.height_m = (found.height_m or 0.0) * h_scale
        fixed.width_m = (found.width_m or 0.0) * w_scale
        if found.height_px is not None:
            fixed.height_px = found.height_px * h_scale
        if found.width_px is not None:
            fixed.width_px = found.width_px * w_scale
        fixed.camera_height_m = float(height)
        fixed.camera_pitch_deg = pitch
        fixed.doubts = [*found.doubts, PITCH_RERUN_DISAGREES]
        result = trial(height, None, pitch)
        if not (result.detected and (result.confidence or 0.0) >= ESTIMATE_ACCEPT):
            log.debug("pitch %.1f deg: no face levelled; the pitch-0 face scaled", pitch)
            return fixed
        agree = (
            abs((result.height_m or 0.0) / fixed.height_m - 1.0) <= RERUN_AGREE
            and abs((result.width_m or 0.0) / fixed.width_m - 1.0) <= RERUN_AGREE
        )
        if agree:
            return result
        if _levelled_taken(found, result):
            # the levelled view (the lens's true geometry, near enough) finds a surer face
            # than the level guess did: that face, doubted as the two disagree
            result.doubts = [*result.doubts, PITCH_RERUN_DISAGREES]
            return result
        return fixed

    def _run_rig(
        self,
        fused: FusedMethod,
        rig: Rig,
        image: npt.NDArray[Any],
        range_m: float,
        timer: Timer,
    ) -> Measurement:
        """The fused method with ``rig`` known (``fused``'s view's rig): the face-floor
        channel, then luminance, then the channel turned against the background; where all
        miss and a seam's edges left out a side beyond them, all again with it
        (``method.SEAM_MISS_RERUN``)."""
        fused.seam_sides = []
        result = self._run_rig_channels(fused, rig, image, range_m, timer)
        if fused_method.SEAM_MISS_RERUN and not result.detected and fused.seam_sides:
            # the seam's sides: a last resort, after every channel missed without them
            fused.beside_seam = True
            try:
                again = self._run_rig_channels(fused, rig, image, range_m, timer)
            finally:
                fused.beside_seam = False
            if again.detected:
                return again
        return result

    def _run_rig_channels(
        self,
        fused: FusedMethod,
        rig: Rig,
        image: npt.NDArray[Any],
        range_m: float,
        timer: Timer,
    ) -> Measurement:
        """:meth:`_run_rig`'s channels, one after another where the last missed."""
        view: View = fused.view
        depth = rig.face_depth(range_m)
        if depth <= 0.0:
            return fused.run(image, range_m, timer)  # its miss names the depth (no contact row)
        contact = view.cy + view.fy * rig.camera_height_m / depth
        grey = face_floor_grey(image, view, contact, depth)
        timer.lap("face_channel")
        result = fused.run(grey, range_m, timer, image, rescue=grey is image)
        if not result.detected and grey is not image:
            # the colour turn can also fade an edge luminance had: try luminance
            result = fused.run(image, range_m, timer)
        elif grey is not image and thin_strip(result):
            # a thin strip at the foot, barely sure: luminance, with the colour
            # rescue, may find the face it stands for (taken when surer and taller)
            again = fused.run(image, range_m, timer)
            log.debug(
                "thin strip %.0f px high at %.3f; luminance: %s %.0f px at %.3f",
                result.height_px or 0.0,
                result.confidence or 0.0,
                again.detected,
                again.height_px or 0.0,
                again.confidence or 0.0,
            )
            if stands_for_strip(again, result):
                result = again
        if not result.detected and BACKGROUND_TURN:
            # a face in the lightness of what stands beside it shows its sides in
            # hue only: its colour against the background's (a last try: only a miss)
            turned = face_background_grey(image, view, contact, depth)
            if turned is not None:
                again = fused.run(turned, range_m, timer, image, rescue=False)
                seam = (
                    again.detected
                    and again.box_px is not None
                    and side_on_seam(turned, again.box_px, view, depth)
                )
                # ... and standing on the contact row the rig predicts: a face
                # doubting its foot there is some other surface's outline
                off = again.detected and bool(LAST_TRY_FOOT_DOUBTS.intersection(again.doubts))
                log.debug(
                    "face against background: %s, on a seam %s, foot off %s",
                    again.detected,
                    seam,
                    off,
                )
                if again.detected and not seam and not off:
                    result = again
        return result

    def _run_guessed_rig(
        self,
        fused: FusedMethod,
        image: npt.NDArray[Any],
        range_m: float,
        timer: Timer,
        height: float,
        pitch: float,
    ) -> Measurement:
        """The rig path (:meth:`_run_rig`) with a camera height and pitch guessed from the
        image taken as known, on the method levelled for that pitch; its view restored."""
        if not _robot_row(height, pitch, self.rig.face_depth(range_m)):
            return Measurement(False, fused.name, range_m, distance_m=range_m, reason=NO_ROBOT_ROW)
        h_img, w_img = image.shape[:2]
        method = fused if pitch == 0.0 else self._pitched_method(w_img, h_img, pitch)
        base = method.view
        rig = dataclasses.replace(self.rig, camera_height_m=height, camera_pitch_deg=pitch)
        method.view = copy.copy(base)
        method.view.rig = rig
        method.view.horizon_slack_px = 0.0
        guessed, method.rig_guessed = method.rig_guessed, True
        try:
            return self._run_rig(method, rig, image, range_m, timer)
        finally:
            method.view = base
            method.rig_guessed = guessed

    def _as_if_known(
        self,
        fused: FusedMethod,
        found: Measurement,
        image: npt.NDArray[Any],
        range_m: float,
        timer: Timer,
    ) -> Measurement:
        """With no rig, an unsure face ``found`` (reported under AGAIN_CONFIDENCE) measured
        once more with the rig its search estimated (camera height and pitch) taken as
        known, so the stages that need a rig run (the foot outline among them); that
        reading is taken where it is the same face read more fully: its foot within
        AGAIN_FOOT_ROWS of the found one, its sides over the found face's, at least as
        sure, AGAIN_TALLER times as high (a piece of a print grown to its face), its sides
        doubted no more than the found face's (AGAIN_SIDES_DOUBTED)."""
        sure, _ = reported_confidence(
            found.confidence or 0.0, found.doubts, found.height_px, found.width_px, 0.0, False
        )
        if sure >= AGAIN_CONFIDENCE or found.camera_height_m is None or found.box_px is None:
            return found
        pitch = found.camera_pitch_deg or 0.0
        again = self._run_guessed_rig(fused, image, range_m, timer, found.camera_height_m, pitch)
        timer.lap("rig_again")
        if not again.detected or again.box_px is None:
            return found
        on_found = _on_found(found, again)
        same = (
            on_found
            and (again.confidence or 0.0) >= (found.confidence or 0.0)
            and (again.height_px or 0.0) >= AGAIN_TALLER * (found.height_px or 0.0)
        )
        if AGAIN_ABOVE_LENS and on_found and not same:
            same = _top_above_lens(found, again)
        if AGAIN_ENCLOSES and not same:
            same = _encloses_print(found, again)
        log.debug(
            "no rig, the estimated rig as known: %s box %s at %.3f (found %s at %.3f): %s",
            again.detected,
            again.box_px,
            again.confidence or 0.0,
            found.box_px,
            found.confidence or 0.0,
            "taken" if same else "not the same face",
        )
        if not same:
            return found
        again.camera_height_m = found.camera_height_m
        again.camera_pitch_deg = found.camera_pitch_deg
        again.doubts = [*again.doubts, *(d for d in found.doubts if d in SEARCH_DOUBTS)]
        return again

    def _known_rig_rows(
        self,
        fused: FusedMethod,
        image: npt.NDArray[Any],
        range_m: float,
        timer: Timer,
        below: float = -math.inf,
    ) -> Measurement | None:
        """With no rig and no face from the search (a miss or a refusal), or a small unsure
        one (:meth:`_grown_small_face`): each floor-contact
        row and weaker step of the band, lowest first, is measured as with a rig, the camera
        height and pitch that put the contact there at each of KNOWN_RIG_PITCHES_DEG taken
        as known, so the stages that need a rig run (the foot outline, the seams' and the
        band's walks, the luminance and background-turn tries). A face is a surface in the
        world: on its true foot row it stays one box however the pitch is guessed. The
        first row where at least KNOWN_RIG_AGREE of those readings are one face on one foot
        (:func:`_same_face`), each standing on its foot (:func:`sides_reach_foot`), none
        of FOOT_DOUBTS, not small, not doubted on every count (its pitch a guess,
        PITCH_UNREAD, counted: MIN_DOUBTED_CONFIDENCE), gives the surest of them; then the
        side bands' rows (SIDE_BAND_ROWS) and the rows round the band's lowest step
        (REFINED_ROWS); None when no row does. Only rows under ``below`` (a pixel row of the
        input image) are read: a face wholly under a found face's foot stands on none
        higher (SMALL_FACE_UNDER), and each row read costs up to four rig readings."""
        view: View = fused.view
        depth = self.rig.face_depth(range_m)
        rows = sorted(
            set(contact_rows(image, view, depth)) | set(weak_contact_rows(image, view, depth)),
            reverse=True,
        )
        for row in rows:
            if row <= below:
                break  # (lowest first)
            face = self._known_rig_row(fused, image, range_m, timer, row, KNOWN_RIG_PITCHES_DEG)
            if face is not None:
                timer.lap("known_rig_rows")
                return face
        tried: set[int] = set()  # the side bands' rows read
        if SIDE_BAND_ROWS:
            # no row of the band on the beam's axis agrees: a stripe of the floor's shade
            # down the face on the axis (a seam, a tape, a print's band) shows no foot step
            # there. The steps of the bands one band width either side, lowest first, and a
            # row so near the horizon that a guessed pitch would put the lens under
            # MIN_ESTIMATED_CAMERA_HEIGHT_M is read at steeper pitches instead (a camera
            # looking down sees the contact there), as many readings as on any other row
            side: dict[int, list[tuple[int, int]]] = {}
            for shift in (-1, 1):
                for r in contact_rows(image, view, depth, 0.0, shift):
                    if r not in rows:
                        side.setdefault(r, []).append(band_columns(view, depth, shift))
            for row in sorted(side, reverse=True):
                if row <= below:
                    break
                low = [
                    p
                    for p in KNOWN_RIG_PITCHES_DEG
                    if camera_height_for_row(row, depth, p, view.fy, view.cy)
                    < MIN_ESTIMATED_CAMERA_HEIGHT_M
                ]
                top = max(KNOWN_RIG_PITCHES_DEG)
                step = SIDE_BAND_PITCH_STEP_DEG
                steeper = tuple(
                    top + step * (i + 1)
                    for i in range(len(low))
                    if top + step * (i + 1) <= MAX_ESTIMATED_PITCH_DEG
                )
                pitches = (*(p for p in KNOWN_RIG_PITCHES_DEG if p not in low), *steeper)
                face = self._known_rig_row(fused, image, range_m, timer, row, pitches)
                tried.add(row)
                # the face that shows its foot in a band beside the axis spans that band
                # (a pole or a print's edge standing on the step is no face round a stripe);
                # the band's columns are the view's, the box the input image's
                if face is not None and any(
                    _spans_band(face.box_px, view.to_input([[c0, row], [c1 - 1, row]])[:, 0])
                    for c0, c1 in side[row]
                ):
                    log.debug("no rig, row %d of a band beside the axis", row)
                    timer.lap("known_rig_rows")
                    return face
        if REFINED_ROWS:
            # no row agrees, on the axis or beside it: a step's row is read from rows
            # averaged either side of it (STEP_ROWS), and a face's foot blurred over a few
            # rows (its shadow, a gloss) puts the step a row or three off the foot, where
            # the readings as with a rig lose the face (procedural 709: the step at 278,
            # only 275 agrees). The lowest REFINED_ROWS_STEPS steps' neighbours, nearest
            # first (below the face there is only floor: the higher steps are lines on the
            # face or the wall, whose neighbours agreed on prints and wrong faces)
            refined = [
                r + d
                for r in contact_rows(image, view, depth)[:REFINED_ROWS_STEPS]
                for d in _refine_offsets(REFINED_ROWS_PX)
                if r + d not in rows and r + d not in tried
            ]
            for row in dict.fromkeys(r for r in refined if r > below):
                face = self._known_rig_row(fused, image, range_m, timer, row, KNOWN_RIG_PITCHES_DEG)
                if face is not None:
                    log.debug("no rig, row %d refined from a band step", row)
                    timer.lap("known_rig_rows")
                    return face
        timer.lap("known_rig_rows")
        return None

    def _known_rig_row(
        self,
        fused: FusedMethod,
        image: npt.NDArray[Any],
        range_m: float,
        timer: Timer,
        row: int,
        pitches: tuple[float, ...],
    ) -> Measurement | None:
        """One row of :meth:`_known_rig_rows`: read as with a rig at each of ``pitches``;
        the surest of KNOWN_RIG_AGREE readings that are one face on one foot, or None."""
        view: View = fused.view
        depth = self.rig.face_depth(range_m)
        faces: list[Measurement] = []
        for k, pitch in enumerate(pitches):
            if len(faces) + len(pitches) - k < KNOWN_RIG_AGREE:
                break  # too few pitches left to agree
            height = camera_height_for_row(row, depth, pitch, view.fy, view.cy)
            if not MIN_ESTIMATED_CAMERA_HEIGHT_M <= height < MAX_ESTIMATED_CAMERA_HEIGHT_M:
                continue
            result = self._run_guessed_rig(fused, image, range_m, timer, height, pitch)
            if not result.detected or not _obstacle_size(result):
                continue
            if BEAM_HOLDS_FACE and _outside_beam(
                result.box_px, view, self.rig, range_m, depth, self._allowance()
            ):
                log.debug("no rig, row %d: a face outside the sonar's beam, %s", row, result.box_px)
                continue
            # its pitch a guess: doubted so, and refused as the search refuses a face
            # doubted on every count
            result.doubts = [*result.doubts, PITCH_UNREAD]
            if (
                sides_reach_foot(image, result.lines)
                and not FOOT_DOUBTS.intersection(result.doubts)
                and not _small(result)
                and _doubted(result, REFUSAL_IGNORES) >= MIN_DOUBTED_CONFIDENCE
            ):
                result.camera_height_m = float(height)
                result.camera_pitch_deg = pitch
                faces.append(result)
        for face in sorted(faces, key=lambda f: f.confidence or 0.0, reverse=True):
            if KNOWN_ROWS_ROBOT_LENS and not _robot_lens_reading(face):
                continue  # no robot's lens (a line of the floor near the image's foot)
            same = [f for f in faces if _same_face(face.box_px, f.box_px)]
            if len(same) >= KNOWN_RIG_AGREE:
                log.debug(
                    "no rig, row %d as with a rig: %d readings agree, box %s at %.3f",
                    row,
                    len(same),
                    face.box_px,
                    face.confidence or 0.0,
                )
                return face
        return None

    def _grown_small_face(
        self,
        fused: FusedMethod,
        found: Measurement,
        image: npt.NDArray[Any],
        range_m: float,
        timer: Timer,
    ) -> Measurement:
        """With no rig, a small face ``found`` reported unsure (under GROWN_CONFIDENCE,
        SMALL_FACE among its doubts) is often a piece of the obstacle's face (a print's
        band, the face's lower strip) that the no-rig trials, which leave the rig's stages
        out, stood on the wrong row or cut short. The rows read as with a rig
        (:meth:`_known_rig_rows`) then give the face round it: taken when that reading is
        at least GROWN_SURE, covers ``found``'s middle column and is GROWN_FACTOR times as
        high or as wide (the same face read again, a few rows off, is no reason to move);
        else ``found``. A face the rows read wholly under ``found``'s foot (SMALL_FACE_UNDER)
        needs only UNDER_SURE: a small face is then still taken only when it grows as
        above; an unsure face that is not small (UNDER_ANY_UNSURE) has only the rows under
        its foot read and gives way to such a face alone. In a stream, rows that gave no
        face taken rest for the next SWEEP_REST_FRAMES frames that would read them (up to
        ~130 rig readings a frame); the under-foot read rests on its own counter."""
        sure, applied = reported_confidence(
            found.confidence or 0.0, found.doubts, found.height_px, found.width_px, 0.0, False
        )
        small = SMALL_FACE in applied
        if found.box_px is None:
            return found
        # a face the method saw in a margin of another colour (FRAMED) is read under its
        # foot however sure: the frame's foot lay past the tried row's view, and the face
        # round the print stands there (PRINT_HELD_BELOW)
        framed_only = sure >= GROWN_CONFIDENCE
        if framed_only and not (PRINT_HELD_BELOW and FRAMED_READ_SURE and FRAMED in found.doubts):
            return found
        small = small and not framed_only
        if not small and not (SMALL_FACE_UNDER and UNDER_ANY_UNSURE):
            return found
        # a read of only the rows under an unsure face rests on its own counter: it read
        # no row above that foot, so it says nothing of the rows a miss would read
        if (self._known_rest if small else self._under_rest) > 0:
            self._count_rest(small)  # in a stream, as after a miss whose rows found nothing
            return found
        # an unsure face that is not small is only looked under: the rows below its foot
        # (the rows are the level view's, the box the input image's: UNDER_ROWS_SLACK_PX)
        below = -math.inf if small else found.box_px[3] - UNDER_ROWS_SLACK_PX
        grown = self._known_rig_rows(fused, image, range_m, timer, below)
        if grown is None or grown.box_px is None:
            self._start_rest(small)
            return found
        x0, _, x1, y1 = found.box_px
        g0, gy0, g1, _ = grown.box_px
        # a face wholly under the found face's foot, spanning its columns, stands nearer
        # the robot on the beam's axis: the surface the sonar ranged, the found one a thing
        # behind it (photo 726 ordinary: a 28 px patch on the wall above a brick face),
        # where the lens it stands for is a small robot's (photo 721 hard: a row near the
        # image's foot stood a face under a lens 1.1 m up, 237 % off)
        # (UNDER_ON_AXIS: or, not spanning them, covering the beam's axis column while
        # the found face is not small: the sonar ranges the nearest surface on its axis)
        depth = self.rig.face_depth(range_m)
        u_axis = _axis_column(fused.view, self.rig, depth)
        under = (
            SMALL_FACE_UNDER
            and gy0 >= y1
            and (
                (g0 <= x0 and g1 >= x1)
                or (UNDER_ON_AXIS and not small and _covers(grown.box_px, u_axis))
            )
            and (grown.confidence or 0.0) >= UNDER_SURE
            and (grown.camera_height_m or math.inf) <= UNDER_MAX_CAMERA_HEIGHT_M
        )
        # a face whose own outline finds its foot off the floor (FOOT_OFF_FLOOR: a print's
        # lower edge, a band or a shadow's edge taken for the contact) stood on no floor:
        # the rows' face on the same columns and top with its foot lower, on the floor,
        # is that face down to its contact (_foot_moves_down)
        lower = FOOT_OFF_FLOOR_LOWER and _foot_moves_down(found, grown)
        # the rows' face on the same columns and top, its foot a few rows higher and surer
        # than the found face: the found foot a shadow's or a bevel's lower edge under the
        # contact (_foot_moves_up, SURER_FOOT_RAISES)
        lower = lower or (SURER_FOOT_RAISES and _foot_moves_up(found, grown))
        # the rows' face on the same foot and columns, its top higher and surer: the found
        # top a line across the face (a brick course, a tape) (_top_moves_up)
        lower = lower or (
            SURER_TOP_RAISES
            and _top_moves_up(found, grown)
            and face_runs_above(image, found.box_px, grown.box_px)
        )
        # ... or a surer answer's, when the rows' face is far the surer and its top far
        # higher (_top_moves_far_up)
        lower = lower or (
            FAR_TOP_RAISES
            and _top_moves_far_up(found, grown)
            and face_runs_above(image, found.box_px, grown.box_px)
        )
        # the rows' face holding the found face inside its sides and top, its foot lower:
        # the found face stands on no floor (a print, a label, a panel on the face: its
        # lower edge above the contact), the rows' face is the surface round it
        # (only a face read as a piece already: small, in a margin of another colour, or
        # the strip between the two feet the margin's colour beside it, not the floor's:
        # face_runs_below; a plain face gives way to no box round it, which may be the
        # background's outline round the face on a floor line: photo 3050 ordinary)
        held = (
            PRINT_HELD_BELOW
            and _holds_print(found, grown)
            and (
                small
                or FRAMED in found.doubts
                or (HELD_BY_MARGIN and face_runs_below(image, found.box_px, grown.box_px))
            )
        )
        # a found face that leaves the beam's axis out, where the rows read a surer face
        # on it: the sonar ranges what its axis hits (the obstacle's face, which the
        # level trials stood on no row of theirs: a camera pitched away from level), the
        # found face is a patch beside it (a skirting's stretch, a floor mark)
        # (with the sonar's mounting unknown, the found face leaves out every column the
        # axis may stand on: Rig()'s axis widened by BEAM_MOUNT_ALLOWANCE_M each side)
        mount_px = fused.view.camera.fx * self._allowance() / depth
        beside = ROWS_ON_AXIS and _axis_face_beside(found, grown, u_axis, mount_px)
        if framed_only:
            under = lower = beside = False  # a sure face gives way to the face round it alone
        if (grown.confidence or 0.0) < GROWN_SURE and not (under or lower or held or beside):
            self._start_rest(small)
            return found
        taller = (grown.height_px or 0.0) >= GROWN_FACTOR * (found.height_px or 0.0)
        wider = (grown.width_px or 0.0) >= GROWN_FACTOR * (found.width_px or 0.0)
        taken = g0 <= (x0 + x1) / 2.0 <= g1 and (taller or wider)  # covers it, and grows
        if not small:  # only the face under it
            taken = under
        taken = taken or lower or held or beside
        log.debug(
            "no rig, %s face %s at %.3f; rows as with a rig: %s at %.3f: %s",
            "small" if small else "unsure",
            found.box_px,
            found.confidence or 0.0,
            grown.box_px,
            grown.confidence or 0.0,
            "taken" if taken else "kept",
        )
        if taken:
            return grown
        self._start_rest(small)
        return found

    def _start_rest(self, every_row: bool) -> None:
        """Rows read as with a rig gave no face taken: rest them SWEEP_REST_FRAMES frames
        (all of them after a whole read, only the under-face read after a partial one)."""
        if every_row:
            self._known_rest = SWEEP_REST_FRAMES
        else:
            self._under_rest = SWEEP_REST_FRAMES

    def _count_rest(self, every_row: bool) -> None:
        if every_row:
            self._known_rest -= 1
        else:
            self._under_rest -= 1

    def _search_floor(
        self,
        impl: Method,
        image: npt.NDArray[Any],
        range_m: float,
        timer: Timer,
        rows: bool = True,
    ) -> Measurement:
        """With no rig: the floor-contact rows sought in the image (:meth:`_run_estimated`),
        then an unsure face read as with its estimated rig, and (``rows``) a small or
        unsure one grown and a miss read on every row as with a rig (confidence as the
        method decided, unreported)."""
        result = self._run_estimated(impl, image, range_m, timer)
        if ESTIMATED_RIG_AGAIN and result.detected:
            result = self._as_if_known(cast(FusedMethod, impl), result, image, range_m, timer)
        if not rows:
            return result
        # (on a reading _as_if_known just took too: it is a face read as with a rig on the
        # search's foot, the rows below it may stand its foot a few rows better: photo 3021
        # hard, AGAIN_ENCLOSES then the rows, 5.4 -> 1.3 % off)
        if SMALL_FACE_GROWN and result.detected:
            result = self._grown_small_face(cast(FusedMethod, impl), result, image, range_m, timer)
        if KNOWN_RIG_ROWS and not result.detected:
            # (in a stream where they gave nothing, here or for a small face, the next
            # SWEEP_REST_FRAMES frames that would read them go without: up to ~130 rig
            # readings a frame)
            if self._known_rest > 0:
                self._known_rest -= 1
            else:
                found = self._known_rig_rows(cast(FusedMethod, impl), image, range_m, timer)
                self._known_rest = SWEEP_REST_FRAMES if found is None else 0
                if found is not None:
                    result = found
        return result

    def _checked_by_search(
        self,
        fused: FusedMethod,
        result: Measurement,
        image: npt.NDArray[Any],
        range_m: float,
        timer: Timer,
    ) -> Measurement:
        """With the rig, a miss or an unsure face (reported under CHECK_CONFIDENCE, its
        doubts applied, unfloored) checked by the no-rig search (:meth:`_search_floor`,
        the rig's sonar mounting kept, its camera height and pitch sought in the image,
        the rows read as with a rig only with CHECK_READS_ROWS):
        the search's face is taken where its foot stands near the floor-contact row the
        rig predicts at the sonar's depth (:func:`_foot_off_rig_row` within
        CHECK_FOOT_SHARE; a face on another row is some other surface), it is a plausible
        obstacle (:func:`_plausible_face`), reported surer than the rig's by CHECK_SURER
        (the no-rig doubts applied), and another face than the rig's (overlapping it under
        CHECK_SAME_FACE: one face read twice keeps the rig's reading, at its true pitch).
        The rig's search keeps a few side columns per floor-contact row, ranked by
        strength (a narrow face beside a stronger edge loses its side: photo 2078); the
        no-rig search reads each contact row of the image, and a face it finds standing
        on the rig's row is one more reading of the surface the range measured: where
        guessing finds such a face and the rig's path does not, the rig's path answers
        with it."""
        if result.detected:
            sure, _ = reported_confidence(
                result.confidence or 0.0,
                result.doubts,
                result.height_px,
                result.width_px,
                0.0,
                rig_given=True,
            )
            if sure >= CHECK_CONFIDENCE:
                return result
        else:
            sure = 0.0
        if self.rig.face_depth(range_m) <= 0.0:
            return result  # nothing in front of the lens to search for (the miss says so)
        if self._check_rest > 0:
            # a stream held on a face the search did not better: ~10x a frame's time each
            self._check_rest -= 1
            return result
        self._check_rest = CHECK_REST_FRAMES  # until a check takes its face
        found = self._searched(image, range_m, timer)
        if not found.detected:
            return result
        found_sure, _ = reported_confidence(
            found.confidence or 0.0,
            found.doubts,
            found.height_px,
            found.width_px,
            0.0,
            rig_given=False,
        )
        off = _foot_off_rig_row(fused.view, found, range_m)
        plausible = _plausible_face(found, image.shape[1])
        overlap = box_overlap(result.box_px, found.box_px) if result.detected else 0.0
        log.debug(
            "rig checked by the search: rig face %s at %.3f, search's %s at %.3f, "
            "foot off the rig's row %s bands, plausible %s, overlap %.2f",
            result.box_px,
            sure,
            found.box_px,
            found_sure,
            off,
            plausible,
            overlap,
        )
        if (
            off is None
            or off > CHECK_FOOT_SHARE
            or not plausible
            or found_sure <= CHECK_SURER * sure
        ):
            return result
        if overlap >= CHECK_SAME_FACE and not (
            CHECK_DOUBTED_TOP_LOWERS and _doubted_top_lowered(result, found, image)
        ):
            return result  # one face read twice: the rig's reading (its true pitch) stands
        # the face keeps the size read at the search's guessed pitch; the camera height
        # and pitch reported are the given rig's, not the search's guess
        found.camera_height_m = None
        found.camera_pitch_deg = None
        self._check_rest = 0
        return found

    def _searched(self, image: npt.NDArray[Any], range_m: float, timer: Timer) -> Measurement:
        """The no-rig search of the frame with the rig's sonar mounting kept (the rig
        check's reading), its time under ``rig_checked`` (its stages kept apart from the
        rig path's)."""
        h_img, w_img = image.shape[:2]
        searcher = self._rig_searcher()
        searcher.reset_stream()  # each frame searched afresh: a stream's rig is given
        found = searcher._search_floor(
            searcher._method_for(w_img, h_img), image, range_m, Timer(), CHECK_READS_ROWS
        )
        timer.lap("rig_checked")  # the whole search (its stages timed apart)
        return found

    def _allowance(self) -> float:
        """The sonar's lateral offset BEAM_HOLDS_FACE allows for (m): none when the
        mounting is known, BEAM_MOUNT_ALLOWANCE_M when Rig()'s is assumed."""
        return 0.0 if self._mount_known else BEAM_MOUNT_ALLOWANCE_M

    def _rig_searcher(self) -> Measurer:
        """The rig check's no-rig searcher (the rig's sonar mounting kept), made once; it
        keeps CHECK_PITCHED_VIEWS_KEPT levelled views (each is a view's maps, megabytes;
        a view rebuilt costs milliseconds against the check's ~0.3 s)."""
        searcher = self._searcher
        if searcher is None:
            searcher = Measurer(self.camera, None, self.method, self.min_confidence)
            searcher.rig = dataclasses.replace(
                self.rig, camera_height_m=Rig().camera_height_m, camera_pitch_deg=0.0
            )
            searcher._views_kept = CHECK_PITCHED_VIEWS_KEPT
            searcher._mount_known = True  # the rig's sonar mounting, not Rig()'s guess
            self._searcher = searcher
        return searcher

    def reset_stream(self) -> None:
        """Forget what earlier frames gave (the no-rig camera height and pitch, the
        readings' rests): the next frame is searched as a stream's first."""
        self._last_rig = None
        self._last_pitch_doubts = []
        self._last_slack = False
        self._sweep_rest = self._known_rest = self._under_rest = 0
        self._check_rest = 0

    def measure(self, image: npt.NDArray[Any], range_m: float) -> Measurement:
        if not isinstance(image, np.ndarray) or image.ndim not in (2, 3) or image.size == 0:
            raise UserError("image must be a non-empty grey or BGR array")
        if image.ndim == 3 and image.shape[2] not in (3, 4):
            raise UserError(f"image has {image.shape[2]} channels; give grey or BGR")
        if image.ndim == 3 and image.shape[2] == 4:
            image = cv2.cvtColor(image, cv2.COLOR_BGRA2BGR)
        if image.dtype != np.uint8:
            raise UserError(f"image must be 8-bit, got {image.dtype}")
        range_m = check_range(range_m)
        timer = Timer()
        impl = self._method_for(image.shape[1], image.shape[0])
        timer.lap("setup")
        if self.find_floor:
            result = self._search_floor(impl, image, range_m, timer)
        elif self.method == "fused":
            result = self._run_rig(cast(FusedMethod, impl), self.rig, image, range_m, timer)
            if RIG_CHECKED_BY_SEARCH and self.rig_check:
                result = self._checked_by_search(
                    cast(FusedMethod, impl), result, image, range_m, timer
                )
        else:
            result = impl.run(image, range_m, timer)
        result.rig_source = self.rig_source
        if result.camera_height_m is None and self.rig_source == "estimated":
            result.camera_height_m = self.rig.camera_height_m  # a rig fitted online
            result.camera_pitch_deg = self.rig.camera_pitch_deg
        if result.detected and result.confidence is not None and self.method == "fused":
            floor = self.min_confidence
            if floor is None:
                floor = cast(FusedMethod, impl).min_confidence
            result.confidence, result.doubts = reported_confidence(
                result.confidence,
                result.doubts,
                result.height_px,
                result.width_px,
                floor,
                rig_given=not self.find_floor,
            )
        else:
            result.doubts = []
        # the image's borders, and those the method's working view cuts short
        cut = set(clipped_sides(result.box_px, image.shape[1], image.shape[0]))
        cut.update(result.clipped)
        result.clipped = [s for s in SIDES if s in cut]
        result.timings_ms = dict(timer.ms)
        result.timings_ms["total"] = sum(timer.ms.values())
        return result


#: With the rig, a miss or an unsure face is checked by the no-rig search, whose face is
#: taken where it stands on the rig's contact band, is a plausible obstacle and is surer
#: (:meth:`Measurer._checked_by_search`). Session 40, branch ``wt-d-40``; a switch for
#: the tests.
RIG_CHECKED_BY_SEARCH = True
#: ... resting this many frames of a stream after a check that took nothing (the check
#: costs about ten times a rig frame: 0.3-0.4 s against 20-40 ms, loaded machine) ...
CHECK_REST_FRAMES = 10
#: ... in a single image's measurement (`measure`, the API's one-shot calls, the
#: benchmarks), not in a stream (`run`, `replay`: :data:`STREAM_RIG_CHECK`): on the frames
#: it runs on it costs ~10 times a rig frame (0.3-0.4 s, a live stream's frames dropped
#: meanwhile) and its search's working memory (tools/soak.py: RSS +35 % on the first
#: check, past the warm-up, then flat); a stream's rig is refined online instead.
STREAM_RIG_CHECK = False
#: ... its searcher keeping this many levelled views (PITCHED_VIEWS_KEPT's 8 took ~40 MB
#: on a stream's first unsure frame: tools/soak.py's flat-memory check) ...
CHECK_PITCHED_VIEWS_KEPT = 2
#: ... the search without the rows read as with a rig (`_grown_small_face`,
#: `_known_rig_rows`): with them a checked frame took twice as long (20 own frames:
#: 0.76-0.80 s instead of 0.36-0.38 s, loaded machine), for one own answer more
#: (procedural 108 hard, 33 -> 3.1 %) ...
CHECK_READS_ROWS = False
#: ... a rig face reported under this (its doubts applied, unfloored) is checked ...
CHECK_CONFIDENCE = 0.1
#: ... and the search's face taken when reported (with the no-rig doubts) over this many
#: times the rig face's confidence (a miss: 0).
CHECK_SURER = 1.0
#: ... its foot within the rig's contact band (:func:`contact_band`) widened by this many
#: rows (the two views' mapping)
CHECK_BAND_SLACK_PX = 1.0
#: ... its foot within this share of the band's half-height of the row the rig predicts
#: (the band allows for the range's and the rig's errors in finding the rig's own
#: contact edge; a face the search stood elsewhere, nearer its edge, is some other
#: surface: photo 110 hard's poster piece at 0.73, -53 %) ...
CHECK_FOOT_SHARE = 0.6
#: ... where the two boxes overlap (intersection over union) by less than this: over it
#: they are one face read twice, and the rig's reading (at its true pitch) stands ...
CHECK_SAME_FACE = 0.7
#: ... and its box narrower than the image by this share (a face as wide as the image is
#: clipped, not measured) ...
CHECK_MAX_WIDTH_SHARE = 0.9
#: ... and one face read twice keeps the rig's reading unless the rig's top is doubted
#: for the band under it being unlike the face (TOP_BAND_UNLIKE_FACE) and the search, on
#: the same foot, stops the face lower by over CHECK_TOP_LOWER_PX with no doubt of
#: CHECK_TOP_DOUBTS on its own top, the band between the two tops framing no part of the
#: face (:func:`_doubted_top_lowered`). Session 49, branch ``wt-b-49``; a switch for the
#: tests.
CHECK_DOUBTED_TOP_LOWERS = True
#: ... the doubts that say a top may stand on something above the face ...
CHECK_TOP_DOUBTS = frozenset({SECOND_TOP, TOP_RUNS_ON, TOP_BAND_UNLIKE_FACE})
#: ... the search's top lower than the rig's by more than this (input rows; both tops
#: read on one blurred edge differ by a row or two) ...
CHECK_TOP_LOWER_PX = 2.0
#: ... its foot within this many rows of the rig's (the same contact edge) ...
CHECK_SAME_FOOT_PX = 3.0
#: ... and the band between the two tops (median Lab between the sides, inset by
#: CHECK_BAND_INSET of the width) further than this from the median of both strips just
#: inside the face's sides under the search's top: a band of the margins' colour is a
#: frame round a print (procedural 137, 3026: the rig's top the frame's, right), a band
#: the sides do not share is what stands behind the face.
CHECK_FRAME_LAB = 15.0
CHECK_BAND_INSET = 0.15


def _doubted_top_lowered(result: Measurement, found: Measurement, image: npt.NDArray[Any]) -> bool:
    """Whether the search's reading of the rig's face (same foot) stops it lower where the
    rig doubts its own top for the band under it being unlike the face, the search doubts
    its top not at all, and the band between the two tops is not the colour of the face's
    side margins: the rig's path raised its top onto what stands behind the face (the
    background's edge, a wall line), and the search, reading the same surface from the
    same contact row, found the face's material ending lower (photo 3480 and 3410
    ordinary: the rig's top on the sky or a gantry over a plank or seam box, the
    search's on the box's front top edge). The face is one surface: a band that belongs
    to it (a print's frame) runs down its sides too."""
    if result.box_px is None or found.box_px is None:
        return False
    if TOP_BAND_UNLIKE_FACE not in result.doubts or CHECK_TOP_DOUBTS & set(found.doubts):
        return False
    if abs(found.box_px[3] - result.box_px[3]) > CHECK_SAME_FOOT_PX:
        return False
    top, low = result.box_px[1], found.box_px[1]
    if low - top <= CHECK_TOP_LOWER_PX:
        return False
    return not _band_frames_face(image, found.box_px, top)


def _band_frames_face(image: npt.NDArray[Any], box: Box, top: float) -> bool:
    """Whether the band from ``top`` down to the box's top (between its sides, inset)
    has the colour of a strip just inside either side of the box below its top (each as
    wide as the band is tall, within CHECK_BAND_INSET of the width): one material framing
    the face, so the band is the face's own. A band or strip with no whole row or column
    to read (a top under two rows lower, a sliver of a face) is taken as the face's: the
    frame test is what keeps the swap off prints, and unread it does not let the swap
    through (review F, session 49)."""
    x0, y0, x1, y1 = box
    h_img, w_img = image.shape[:2]
    gap = y0 - top
    width = x1 - x0
    inset = CHECK_BAND_INSET * width
    c0, c1 = max(0, round(x0 + inset)), min(w_img, round(x1 - inset))
    b0, b1 = max(0, math.ceil(top) + 1), min(h_img, math.floor(y0))
    margin = int(min(max(round(gap), 2), max(2.0, inset)))
    r0, r1 = math.ceil(y0) + 2, min(h_img, math.floor(y1) - margin)
    l0, r_end = max(0, math.ceil(x0) + 2), min(w_img, math.floor(x1) - 2)
    if c1 <= c0 or b1 <= b0 or r1 <= r0 or r_end - margin <= l0:
        return True  # nothing to read: the rig's reading stands
    grey = image if image.ndim == 2 else None
    lab = (
        cv2.cvtColor(cv2.cvtColor(grey, cv2.COLOR_GRAY2BGR), cv2.COLOR_BGR2LAB)
        if grey is not None
        else cv2.cvtColor(image[:, :, :3], cv2.COLOR_BGR2LAB)
    ).astype(np.float32)

    def median(part: npt.NDArray[Any]) -> npt.NDArray[Any]:
        return np.asarray(np.median(part.reshape(-1, 3), axis=0))

    band = median(lab[b0:b1, c0:c1])
    sides = (lab[r0:r1, l0 : l0 + margin], lab[r0:r1, r_end - margin : r_end])
    return any(float(np.linalg.norm(median(s) - band)) <= CHECK_FRAME_LAB for s in sides)


def _foot_off_rig_row(view: View, found: Measurement, range_m: float) -> float | None:
    """How far a face's foot (its bottom line's middle, input pixels) lies from the
    contact row the view's rig predicts for the sonar's depth, in the band's half-heights
    (:func:`contact_band`; its row seen in the view levelled for the rig's pitch, the band
    widened by CHECK_BAND_SLACK_PX); None for a face with no bottom line."""
    if not found.lines:
        return None
    x0, y0, x1, y1 = found.lines[0]
    ray = view.camera.unproject([[0.5 * (x0 + x1), 0.5 * (y0 + y1)]])[0]
    level = view.rotation @ ray  # camera -> level frame
    if level[2] <= 0.0:
        return None
    row = view.cy + view.fy * level[1] / level[2]
    vb0, tol = contact_band(view, view.rig.face_depth(range_m))
    return float(abs(row - vb0) / (tol + CHECK_BAND_SLACK_PX))


def box_overlap(a: Box | None, b: Box | None) -> float:
    """Intersection over union of two boxes (x0, y0, x1, y1); 0 when either is None."""
    if a is None or b is None:
        return 0.0
    w = min(a[2], b[2]) - max(a[0], b[0])
    h = min(a[3], b[3]) - max(a[1], b[1])
    if w <= 0.0 or h <= 0.0:
        return 0.0
    inter = w * h
    union = (a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1]) - inter
    return inter / union if union > 0.0 else 0.0


def _plausible_face(found: Measurement, w_img: int) -> bool:
    """A face the size of an obstacle: its box narrower than CHECK_MAX_WIDTH_SHARE of the
    image, its height and width from MIN_SIZE_M to RAISED_FACE_MAX_M."""
    if found.box_px is None or found.height_m is None or found.width_m is None:
        return False
    if found.box_px[2] - found.box_px[0] > CHECK_MAX_WIDTH_SHARE * w_img:
        return False
    return all(MIN_SIZE_M <= s <= RAISED_FACE_MAX_M for s in (found.height_m, found.width_m))


#: With no rig, when the search gives no face (a miss or a refusal), each floor-contact
#: row and weaker step, lowest first, measured as with a rig at a few guessed pitches; the
#: first whose readings agree on one face gives it (:meth:`Measurer._known_rig_rows`).
#: Session 37, branch ``wt-c-37``; a switch for the tests.
KNOWN_RIG_ROWS = True
#: ... the pitches the row is measured at (degrees, down positive) ...
KNOWN_RIG_PITCHES_DEG = (-2.0, 0.0, 2.0, 4.0)
#: ... and how many of those readings must be one face on one foot.
KNOWN_RIG_AGREE = 3
#: ... the face given being one of those readings taken under a lens at most
#: KNOWN_ROWS_MAX_LENS_M up (the issue's robots carry it 0.2-0.5 m up;
#: :func:`_robot_lens_reading`): readings that agree only under lenses higher than a
#: robot's stand for no robot. A row near the image's foot puts the lens 0.9-1.2 m up at
#: every guessed pitch, where the floor's own pattern (paving, its joints converging on the
#: vanishing point like a face's sides) agrees with itself as one face (photo 3414 hard:
#: row 332 of a paved floor read as a face 0.81 m high under a lens 0.87-1.22 m up,
#: +108 %, the box standing on row 197, where the rows then agree: +0.5 %). A row whose
#: readings agree under a robot's lens among others keeps that face (photo 3411 hard: a
#: lens 0.34 m up looking up 4.7 degrees; row 274 read at 0.50-0.82 m). Session 48,
#: branch ``wt-e-48``; a switch for the tests.
KNOWN_ROWS_ROBOT_LENS = True
#: ... (metres; the bound UNDER_MAX_CAMERA_HEIGHT_M puts on a face under a small one, for
#: the same robots, kept apart so that each rule's limit moves alone)
KNOWN_ROWS_MAX_LENS_M = 0.6
#: ... or, where higher, KNOWN_ROWS_ROBOT_MAX_M plus the face's depth times the tangent of
#: KNOWN_ROWS_UP_SLACK_DEG: the issue's robots carry the lens at most 0.5 m up and look up
#: to 5 degrees, the readings' steepest is KNOWN_RIG_PITCHES_DEG's 2 up, and a lens looking
#: up further than the reading is read higher by the depth times the tangent of the
#: difference (photo 1190 ordinary: a lens 0.49 m up looking up 4.2 degrees, the box 3.1 m
#: off, read at 0.61 m under the steepest reading; under the 0.6 m alone the can on the
#: box was taken, 4.7 -> 58 %). Within 1.9 m the 0.6 m holds (a limit 0.6 m plus the
#: depth's allowance gave back the paving-like faces the rule removes: own photo 2070,
#: procedural 3191 hard 4.3 -> 240 %). Session 48, after the merge of ``wt-e-48``.
KNOWN_ROWS_ROBOT_MAX_M = 0.5
#: ... (degrees)
KNOWN_ROWS_UP_SLACK_DEG = 3.0
#: ... when no row agrees, the steps of the bands one band width either side of the beam's
#: axis read so too, a row near the horizon at pitches this much steeper than
#: KNOWN_RIG_PITCHES_DEG's steepest in place of those that put the lens under the floor's
#: minimum (up to MAX_ESTIMATED_PITCH_DEG). Session 38, branch ``wt-d-38``; a switch for
#: the tests.
SIDE_BAND_ROWS = True
SIDE_BAND_PITCH_STEP_DEG = 2.0
#: ... the face read on such a row must span that band (its columns mapped to the input
#: image's) within this many pixels.
BAND_SPAN_SLACK_PX = 1.0

#: ... when no row agrees there either, the rows within this many pixels of the lowest
#: steps of the band on the axis (:func:`contact_rows`), nearest first (:func:`_refine_offsets`),
#: read so too: the step lies a row or three off a blurred foot. Session 38, branch
#: ``wt-f-38``; a switch for the tests.
REFINED_ROWS = True
REFINED_ROWS_PX = 3
#: ... of the band's this many lowest steps (its next step up, photo 2085's, agreed on a
#: print's face 47 % off, refused by the search as doubted on every count).
REFINED_ROWS_STEPS = 1

#: With no rig, a small face reported unsure is checked against the rows read as with a
#: rig (:meth:`Measurer._grown_small_face`): the face round it, if they agree on one, is
#: taken. Session 38, branch ``wt-d-38``; a switch for the tests.
SMALL_FACE_GROWN = True
#: ... only for a face reported under this confidence (the no-rig doubts applied,
#: unfloored), SMALL_FACE among them ...
GROWN_CONFIDENCE = 0.2
#: ... the rows' face taken when at least this sure (the wrong faces they read on the
#: tuning rooms' small answers were at 0.16-0.30, the faces round a piece at 0.40-0.79) ...
GROWN_SURE = 0.35
#: ... and at least this many times as high or as wide as the small face.
GROWN_FACTOR = 1.5
#: ... or, the rows' face lying wholly under the found face's foot and spanning its
#: columns (nearer the robot on the beam's axis), from this confidence up. Session 39,
#: branch ``wt-c-39``; a switch for the tests.
SMALL_FACE_UNDER = True
UNDER_SURE = 0.15
#: ... the camera height that row stands for at most this (metres): the issue's robots
#: carry the lens 0.2-0.5 m up.
UNDER_MAX_CAMERA_HEIGHT_M = 0.6
#: ... and, under an unsure face that is not small (UNDER_ANY_UNSURE; or a framed one,
#: however sure, that FRAMED_READ_SURE has read under), a face the rows
#: read wholly under its foot is taken when it covers the beam's axis column, though it
#: spans not all of the found face's columns: the sonar ranges the nearest surface on its
#: axis, and of two faces on the axis the one standing lower in the image is nearer
#: (photo 3439 ordinary: a cup printed on the wall, 193 px wide, stood on the wall's foot
#: by the known-floor pass, +226 %; the low box before it on the axis, 148 px wide, read
#: by the rows at 0.49). Session 48, branch ``wt-e-48``; a switch for the tests.
UNDER_ON_AXIS = True
#: ... and a found face leaving the beam's axis column out gives way to a surer face the
#: rows read across it, wherever its foot (:func:`_axis_face_beside`): the sonar ranges
#: what its axis hits, and the obstacle stands across it; the level trials, with a camera
#: pitched away from level, stood a patch beside it instead (new11 procedural 3520
#: ordinary: a stretch of the skirting beside a plain box, -78 %; photo 3504 ordinary: a
#: patch of floor tiles under and beside a green box, -82 %). Session 50, branch
#: ``wt-d-50``; a switch for the tests.
ROWS_ON_AXIS = True
#: ... and the face under is looked for below any unsure face, small or not (a thing
#: standing behind the obstacle on its top edge: photo 2088 hard, a drum on a poster's
#: top, +192 %). A switch for the tests.
UNDER_ANY_UNSURE = True
#: ... reading for such a face only the rows this many pixels above its foot and lower
#: (the rows' view and the input image part by a pixel or two near the middle; a face
#: under the foot stands on a row lower by its height): on 20 of own's unsure answers
#: that are not small, all rows read doubled the frame's time.
UNDER_ROWS_SLACK_PX = 6.0
#: ... and an unsure face whose outline finds its foot off the floor (FOOT_OFF_FLOOR) gives
#: way to the rows' face over its columns, its top no lower, its foot lower
#: (:func:`_foot_moves_down`):
#: the face carried down to its floor contact. Session 40, branch ``wt-a-40``; a switch
#: for the tests.
FOOT_OFF_FLOOR_LOWER = True
#: ... the two faces' columns overlapping by at least this share of the wider (no narrower
#: face, a plank of it, takes the width; since the review of session 40).
LOWER_FOOT_SIDES_SHARE = 0.8
#: With no rig, an unsure answer (or a framed one: FRAMED_READ_SURE) read as a piece
#: (small, framed, or the strip under its foot the margin's colour: face_runs_below) gives
#: way to the rows' face (read as with a rig) that holds it inside its sides and top with
#: its foot lower (:func:`_holds_print`): the answer is a print, a label or a panel on
#: that face, its lower edge above the floor contact (procedural 3057, 3092, 3097 hard).
#: Session 41, branch ``wt-b-41``; a switch for the tests.
PRINT_HELD_BELOW = True
#: ... a framed answer (FRAMED: a margin of another colour round it, whose foot the tried
#: row's view cut off) checked so however sure it is reported.
FRAMED_READ_SURE = True
#: ... an answer neither small nor framed counted a piece where the strip between the two
#: feet has the colour of the margin beside it, not the floor's (:func:`face_runs_below`;
#: photo 3076 hard, a brick print). A switch for the tests.
HELD_BY_MARGIN = True
#: With no rig, an unsure answer gives way likewise to the rows' face (read as with a rig:
#: readings that agree on one face, each standing on its foot) on the same top (within
#: ROW_JITTER_PX) and columns (LOWER_FOOT_SIDES_SHARE) with its foot more than
#: ROW_JITTER_PX rows higher, when that face is surer than the answer and its lens at most
#: UNDER_MAX_CAMERA_HEIGHT_M up: the no-rig rows stood the face on a shadow's or a bevel's
#: lower edge under the contact (procedural 750 hard, photo 2056 hard: 3-4 rows low,
#: +9 %). Session 40, branch ``wt-e-40``; a switch for the tests.
SURER_FOOT_RAISES = True
#: With no rig, an unsure answer found with little evidence (TOP_RAISE_MAX_FOUND_CONFIDENCE)
#: gives way likewise to the rows' face on the same foot (within ROW_JITTER_PX) and
#: columns (LOWER_FOOT_SIDES_SHARE) with its top more than ROW_JITTER_PX rows higher
#: (:func:`_top_moves_up`), when that face is at least GROWN_SURE (so surer than the
#: answer), its lens at most UNDER_MAX_CAMERA_HEIGHT_M up, and the rows it adds the face's
#: colour (:func:`face_runs_above`): the face is one surface from its contact up to where
#: its sides end, and the answer's top a line across it (a brick course, a tape, a row of
#: text) that the no-rig trials, which leave the rig's walks up the sides out, stopped at.
#: Session 44, branch ``wt-d-44``; a switch for the tests.
SURER_TOP_RAISES = True
#: ... only for an answer whose raw confidence (as measured, before the no-rig doubts are
#: applied; GROWN_CONFIDENCE is a limit on the reported one) is under this: an answer
#: surer than that is a face whose top edge held (procedural 145 hard, 108 ordinary: 0.31
#: and 0.63, the rows' top 3-5 rows higher on what stands behind or a top face, 0.6 ->
#: 8-11 %). It lies under GROWN_SURE (asserted below): the rows' face taken is the surer.
TOP_RAISE_MAX_FOUND_CONFIDENCE = 0.2
assert TOP_RAISE_MAX_FOUND_CONFIDENCE < GROWN_SURE
#: ... and an unsure answer found surer than that (its raw confidence under
#: FAR_TOP_MAX_FOUND_CONFIDENCE) gives way too, when the rows' face on its foot and
#: columns is far the surer (at least FAR_TOP_SURE and FAR_TOP_RATIO times the answer's
#: raw confidence) and raises the top by at least FAR_TOP_SHARE of the answer's height
#: (:func:`_top_moves_far_up`), the rows it adds the face's colour (face_runs_above): one
#: surface from its contact up to where its sides end, read by the rig's walks up the
#: sides, against a level trial's top on a line across it or on what stands behind at
#: that row (photo 3465 hard: a plain blue box, the trials' top 33 rows low at 0.40,
#: -14 %; the rows' face at 0.81 on the same foot and sides). The surer answers
#: SURER_TOP_RAISES leaves alone (procedural 145 hard, 108 ordinary) had the rows' top
#: only 3-5 rows higher. Session 49, branch ``wt-d-49``; a switch for the tests.
FAR_TOP_RAISES = True
FAR_TOP_MAX_FOUND_CONFIDENCE = 0.5
FAR_TOP_SURE = 0.6
FAR_TOP_RATIO = 1.5
FAR_TOP_SHARE = 0.1

#: With no rig, an unsure face the search settled (ESTIMATED_RIG_AGAIN) is measured once
#: more with the camera height and pitch the search estimated taken as known: the stages
#: that need the rig (the foot outline, the seams', the band's walks) then run on the
#: face. Session 36, branch ``wt-b-36c``; a switch for the tests.
ESTIMATED_RIG_AGAIN = True
#: ... only for a face reported under this confidence (the no-rig doubts applied,
#: unfloored; the foot outline's FOOT_OUTLINE_CONFIDENCE): a second measurement costs a
#: whole run, and a sure face is no piece of a print.
AGAIN_CONFIDENCE = 0.25
#: ... its reading taken where its foot lies within this many rows of the found face's
#: (the estimated rig puts the contact row on the found foot: the same face) ...
AGAIN_FOOT_ROWS = 3.0
#: ... its sides overlapping the narrower of the two faces by at least this share ...
AGAIN_SIDES_SHARE = 0.5
#: ... at least as sure, and at least this many times as high: a piece of a print grown to
#: the face round it (the rig's stages raising a top by a few rows more, a seam's or a
#: band's walk, moved the tuning rooms' answers both ways: taller by 14-21 %, procedural
#: 108 and 734 and photo 736 ordinary went 0.6-17 % -> 8-41 % off).
AGAIN_TALLER = 1.3
#: ... and doubting its sides (uneven, skewed) no more than the found face: a face grown
#: round a piece has the sides of one surface standing on the floor (fresh photo/2105
#: hard, a tape face 22 px high, read 36 % taller with both side doubts new, 1.7 -> 37 %
#: off; set reading that fresh room: the fresh figure is not independent of it).
AGAIN_SIDES_DOUBTED = frozenset({UNEVEN_SIDES, SKEWED_EDGES})
#: ... or, whatever the confidences and under AGAIN_TALLER, where the found face's top is
#: in doubt (TOP_DOUBTS) and stands above the lens the search estimated
#: (:func:`_top_above_lens`): a face taller than the lens shows no top face, so a reading
#: reaching higher on the same foot and sides found the face's own top, the found top a
#: print's upper edge inside it. The top faces that set AGAIN_TALLER (procedural 108, 734,
#: photo 736 ordinary) all belong to faces lower than the lens. Session 40, branch
#: ``wt-a-40``; a switch for the tests.
AGAIN_ABOVE_LENS = True
#: ... or, whatever the confidences, where the reading encloses the found face on all four
#: sides, its foot under the found one by more than AGAIN_FOOT_ROWS and at most this share
#: of its own height: the found face a print lying on it, the print's lower edge above the
#: floor contact (:func:`_encloses_print`; session 41, branch ``wt-a-41``; a switch for
#: the tests).
AGAIN_ENCLOSES = True
AGAIN_ENCLOSE_FOOT_SHARE = 0.15
#: ... the found face spanning at least this share of the reading's width (a print covers
#: most of its face: photo 733 ordinary, a 31 px patch on the floor before a box, read
#: again as 419 px of floor, 1.0 -> 101 % off without it).
AGAIN_ENCLOSE_WIDTH_SHARE = 0.5
#: ... and the reading one surface up to its top (``AGAIN_ENCLOSE_ONE_SURFACE``): the face a
#: print lies on has the print's margin, its own colour, above the print as below it, so a
#: reading whose top band looks like the background above it rather than like its face
#: (TOP_BAND_UNLIKE_FACE, where the found face carries no such doubt) is no face round a
#: print but what stands behind in line with it taken in (procedural/3244 hard with no
#: rig: a gloss box found whole, +-7 %, read again as the box with a stool's frame and a
#: pole behind it, its top on the frame's rail, +118 %). A switch for the tests.
AGAIN_ENCLOSE_ONE_SURFACE = True
#: ... the doubts that put the found top in question ...
TOP_DOUBTS = frozenset({TOP_FROM_SIDES, SECOND_TOP})
#: ... and how many times as high the reading must be (a row or two is the same top).
AGAIN_ABOVE_LENS_TALLER = 1.05
#: With the rig, a frame where neither the face-floor channel nor luminance gives a face is
#: tried once more on a channel turned towards the face's colour against the background
#: beside it (:func:`~obstacle_fusion.vision.fused.channel.face_background_grey`; session
#: 31, branch `photomiss31`). A switch for the tests.
BACKGROUND_TURN = True
#: ... whose face is taken only where it stands on that row: none of these doubts (a foot
#: above the contact row, off the floor, or floor within the face).
LAST_TRY_FOOT_DOUBTS = frozenset({FOOT_ABOVE_CONTACT, FOOT_OFF_FLOOR, FLOOR_IN_FACE})

#: With no rig, the rows read as with a rig (:meth:`Measurer._known_rig_row`) count only
#: readings of a face no taller and no wider than RAISED_FACE_MAX_M at the sonar's depth:
#: a wider one is the wall's foot or a floor line across the view read under a guessed lens
#: (photo 3083 hard: a row under the face, 2.0 m wide, +192 %). Session 41, branch
#: ``wt-c-41``; a switch for the tests.
KNOWN_RIG_SIZE_BOUND = True

#: With no rig, a face found at a guessed pitch and measured again at the pitch its sides
#: read is taken only when that reading has the same outline near enough (the boxes
#: overlapping by SAME_FACE_IOU: procedural 134 hard, its foot 5 rows up, is the face read
#: better) or is a surer face: a pitch a few degrees off changes a face's metres by a few
#: percent, not what the face is; another, less sure face there (photo 3065 ordinary: the
#: top moved down to a skirting band's edge, -50 % at 0.52) leaves the pitch unread.
#: Session 41, branch ``wt-c-41``; a switch for the tests.
REREAD_PITCH_SAME_FACE = True

#: With no rig, a floor-contact row that would put the lens lower than this above the floor
#: is not tried: it is a line on the wall or a print's edge far above the floor, not the
#: obstacle's foot (on textured rooms such rows gave most of the gross errors with no rig).
MIN_ESTIMATED_CAMERA_HEIGHT_M = 0.10
#: ... and at most this (metres): a row giving more is no floor contact of this range (a
#: mobile robot's camera stands well under it; on the tuning rooms no trial reached it, so
#: it only keeps rows far below a face from standing one 3-5 m under a guessed lens).
MAX_ESTIMATED_CAMERA_HEIGHT_M = 1.5
#: With no rig, a trial's floor-contact row is tried only where a lens at most
#: UNDER_MAX_CAMERA_HEIGHT_M up, pitched within MAX_ESTIMATED_PITCH_DEG of level, images
#: the contact at the sonar's depth on it (:func:`_robot_row`); the cap above is one
#: height for every range, this one follows the range (at 1.5 m a row under 0.86 m of
#: level lens, at 3 m under 1.05 m). A line far below the face (a floor board's or a
#: rug's edge) stood a face 2 m wide under a lens 1.2 m up (photo 3141 hard, 430 %).
#: Session 42, branch ``wt-e-42``; a switch for the tests.
ROW_FITS_ROBOT = True
#: With no rig, a trial's face that lies wholly beside the sonar's beam at the range
#: (:func:`_outside_beam`) is refused: the echo the range comes from is inside the beam
#: (Rig.beam_width_deg about the sonar's axis, whose columns at the face's depth follow
#: from the sonar's mounting and the lens's fx and cx alone, not from the camera height
#: or pitch the search guesses), so such a face is another object (new4 procedural 3183
#: hard: a bigger box far right measured while the small box on the axis was left).
#: Session 43, branch ``wt-a-43``; a switch for the tests.
BEAM_HOLDS_FACE = True
#: ... the beam's edge columns widened by this many pixels (the lens's distortion near
#: the beam's edge, a side's blur; and the camera's pitch: the columns are the levelled
#: view's pinhole columns, a box's the input's: a pitch of 20 degrees moves the beam's
#: edge by 1.9-3.4 px, so the slack covers a pitch of about 10 degrees or less) before a
#: face counts as beside it.
BEAM_EDGE_SLACK_PX = 2.0
#: ... and with no rig the sonar's mounting is unknown: Rig()'s (the sonar on the lens's
#: column, 15-degree cone) is assumed, so the beam's columns are widened each side by
#: fx * this / depth px, a sonar mounted up to this far left or right of the lens (a
#: robot's sonar and camera sit on its front, within ~10 cm of each other). Not applied
#: when the mounting is known (the rig check's searcher keeps the rig's).
BEAM_MOUNT_ALLOWANCE_M = 0.10
#: The reason a trial on such a row finds no face.
NO_ROBOT_ROW = "no robot's lens sees the floor contact on that row"
#: With no rig, a contact row nearer the horizon than that height allows is tried as seen
#: by a camera this high, pitched down to put the contact there ...
NOMINAL_CAMERA_HEIGHT_M = 0.3
#: ... by at most this much (a robot's camera is mounted near level).
MAX_ESTIMATED_PITCH_DEG = 8.0
#: ... and such a face whose sides give no pitch is kept only from this confidence up.
GUESSED_PITCH_SURE = 0.5
#: With no rig, a near-horizon contact row on which the nominal lens stands no sure face
#: is also tried as seen by a lens this low (metres), pitched less to put the contact on
#: the row: the face's size at the sonar's depth hardly changes with how its foot row is
#: split between the lens's height and pitch, but the face's outline in the levelled view
#: does (procedural 724 hard, a lens 0.21 m up pitched 4.8 degrees: at 0.3 m and 6.7
#: degrees no face, at 0.15 m and 3.6 degrees the face within 8 %; at 0.2 m none either).
#: Only rows the nominal lens reaches within MAX_ESTIMATED_PITCH_DEG: a row higher still is
#: no foot a usual lens sees (procedural 135 ordinary: a row 60 px above its foot, 6.4
#: degrees at 0.15 m, stood the wall's panel, 140 % off, at 0.92).
NEAR_HORIZON_OTHER_HEIGHTS_M = (0.15,)
#: Switch for the other lens heights on near-horizon rows (for the tests).
NEAR_HORIZON_HEIGHTS = True

#: With no rig, a face whose confidence with all its doubts applied (each a factor
#: DOUBT_FACTOR, a small face its pixel share; unfloored) stays under this is no answer
#: (``detected: false``): on the tuning rooms, 4 of the 6 such faces were 67-115 % off,
#: the others 7 % and 18 %; a rig file's face is never turned down so.
MIN_DOUBTED_CONFIDENCE = 0.01
#: ... counting every doubt but these: a doubt about how high the face reaches, not
#: whether a face stands there (added after the threshold was chosen; counted, a first
#: version of it turned an 18 %-off face on the tuning rooms into none).
#: FRAME_ROUND (session 48, branch ``wt-a-48``) is one such: a frame round the face says
#: the thing reaches out past the face found, not that no face stands there; counted, it
#: turned fresh photo 2109 hard (no rig, -11 / -14 % at 0.05) into no answer.
REFUSAL_IGNORES = frozenset({TOP_BAND_UNLIKE_FACE, FRAME_ROUND})
#: The doubts the no-rig search adds to the face it reports (about the rig it guessed), as
#: against those read off the face as measured.
SEARCH_DOUBTS = frozenset({PITCH_UNREAD, PITCH_RERUN_DISAGREES, TRIAL_RIVAL})
#: Two no-rig trials' face boxes overlapping by this much (intersection over union) are
#: the same face read twice (on the fresh rooms the same face's readings overlapped by
#: 0.93-1.0, a face widened over its neighbour by 0.75).
SAME_FACE_IOU = 0.9
#: ... and such a reading still doubting the foot is no reading of a face on the floor (on
#: the tuning scenes 92-100 % of the faces carrying one were off by more than 5 %).
FOOT_DOUBTS = frozenset({FOOT_OFF_FLOOR, FLOOR_IN_FACE})

#: With no rig, a face refused as doubted on every count gives way to another trial's
#: reading of a face that takes it in whole on the same foot (:func:`_whole_face_reading`):
#: the refused face is a part of that face (a patch of a print, a panel or a band on it,
#: whose edges are no face's sides and give the doubts). Of the 52 no-rig refusals on the
#: own rooms (seeds 100-159, 700-759, 2000-2099) and seeds 900-1499 it takes 4, 0.2-21 %
#: off (procedural 2033 h, 942 h, 1137 o, photo 735 h; fresh: procedural 2116 o, 3 %);
#: the rest stay refused, 35 of the 48 rightly (over 25 % off). A switch for the tests.
WHOLE_FACE_READING = True
#: With no rig, an unsure face its own outline doubts gives way to another trial's
#: undoubted reading of a face that takes it in whole on the same foot
#: (:func:`_clean_whole_face`). Session 39, branch ``wt-c-39``; a switch for the tests.
CLEAN_WHOLE_FACE = True
#: ... that reading at least this sure (a trial's raw confidence) ...
CLEAN_WHOLE_SURE = 0.05
#: ... its doubts, and the doubts that make ``best`` a doubted face, counted without these
#: (about the rig's guess, or other faces near it, not about the face's own outline).
CLEAN_WHOLE_IGNORES = frozenset({NEAR_RIVALS})
#: ... or, whatever ``best``'s own confidence, an undoubted reading on its foot sharing
#: its columns, from this confidence up and surer than ``best`` with its face doubts
#: applied. A switch for the tests.
CLEAN_RIVAL = True
CLEAN_RIVAL_SURE = 0.3
#: ... and at least this many times as wide as ``best`` (the same face read a few pixels
#: off, undoubted, moved five right answers of the tuning rooms by 2.4-13 points, none
#: of them better: procedural 130 ordinary 3.3 -> 16.4 %).
CLEAN_RIVAL_WIDER = 1.5
#: ... its box holding the refused face's box within this many pixels on every side, its
#: foot no more than this many pixels under the refused face's either (the same floor
#: contact; a guessed pitch moves one face's top and foot by a few pixels: procedural/942
#: hard's containing face stood its foot 5 px above the refused one's, 1137 ordinary 6 px;
#: at 10 px faces cut short under a refused one's top came in, photo/1155 hard 248 % off;
#: a foot far below is a floor patch under the face, photo/1331 ordinary 61 px, 61 % off)
WHOLE_FACE_MARGIN_PX = 6.0
#: ... and no more than this many times as tall as it is wide: a slender box over the
#: face is a column in line with it (photo/2085 hard: a rocket behind the box read as the
#: face's sides running on, 9.7 times as tall as wide, 133 % off; the faces taken stood at
#: most 2.6 times as tall as wide).
WHOLE_FACE_MAX_ASPECT = 4.0
#: ... and covering at least this many times the refused face's box area: a reading
#: hardly larger is the refused face read again on a foot a few pixels lower, no face it
#: is a part of (photo/2085 hard: the patch at the foot read 1.2 times as large, 82 % off;
#: the containing faces taken covered 1.8-13 times the refused one's area).
WHOLE_FACE_MIN_GROWTH = 1.5
#: ... and not doubting its sides on both counts (uneven and skewed): those are the
#: refused part's doubts, its edges no face's sides; a face read round it with sides
#: doubted alike is the same patch read larger (procedural/1301 ordinary: a floor tile
#: under the box, the refused one's foot shared, 86 % off).
SIDE_DOUBTS = frozenset({UNEVEN_SIDES, SKEWED_EDGES})

#: With no rig, the lowest floor-contact row whose face reaches this confidence is taken;
#: when none does, the most confident of the rows tried.
ESTIMATE_ACCEPT = 0.2

#: With no rig, a face found at pitch 0 with at least this confidence gives the pitch (any
#: face the estimate accepts: on the tuning rooms 0.3 left a fifth of the faces unlevelled
#: for no fewer gross errors).
PITCH_MIN_CONFIDENCE = ESTIMATE_ACCEPT

#: The face measured again in the levelled view replaces the pitch-0 one scaled to that
#: view (:func:`~obstacle_fusion.vision.pitch.level_scales`) only when its height and width
#: agree with those within this share: a new search can settle on another face (a seam,
#: the box's top), and the pitch changes a face's size by a few percent, never more.
RERUN_AGREE = 0.05
#: ... and a levelled face that disagrees is taken over the pitch-0 one, as a surer face
#: is, when its confidence with its doubts applied (:func:`_doubted`) is more than
#: LEVELLED_DOUBTED_MARGIN over the pitch-0 face's: the sides read the pitch, the view
#: levelled for it is the lens's geometry near enough, and a face found there with none
#: of the doubts the level guess's face carries (its foot above the contact its row
#: stands for, rivals near its score: the level guess stood it on a wrong row) is the
#: face, however the raw scores tie (photo 3454 hard: a planked box, the level face 13
#: columns short on one side and 8 rows high at 0.61 with near_rivals and
#: foot_above_contact, 0.27 with them (0.12 as reported, the two views' disagreement added);
#: the levelled face at 0.60 with none, the pitch read 4.2 degrees against the true 4.1;
#: 11.5 -> 0.8 %). Only a levelled face on the pitch-0
#: face's foot (within ROW_JITTER_PX): the pitch read and that foot's row give the camera
#: height, and a face on another foot is another reading (procedural 3499 hard: a levelled
#: face 4 rows up and 8 columns in, 1.9 -> 10.2 % without this). Session 49, branch
#: ``wt-d-49``; a switch for the tests.
LEVELLED_LESS_DOUBTED = True
LEVELLED_DOUBTED_MARGIN = 0.2
#: ... but not a levelled face with both sides inside the pitch-0 face's (each by over
#: ROW_JITTER_PX): on the same foot and within both sides it is a print on that face, not
#: the surface read again (procedural 3247 hard: a text print inside an olive frame, the
#: frame's face 0.4 % wide with framed_print, the print's 11 columns in on each side, 7.9
#: -> 13.0 % without this). Session 49, found on the stop's full run; a switch for the tests.
LEVELLED_NOT_INSIDE = True
#: ... and a levelled face surer as measured is not taken either where it lies on the
#: pitch-0 face as a print: on its foot, its sides and top inside the pitch-0 face's, each
#: by over ROW_JITTER_PX (:func:`_print_on_face`); the pitch-0 face, scaled to the levelled
#: view, stands (new11 procedural 3525 ordinary: a teal brick print in a pink box's face,
#: the box at 0.90 level, the print at 0.94 levelled, -17 % wide). Session 50, branch
#: ``wt-d-50``; a switch for the tests.
LEVELLED_PRINT_REFUSED = True

#: The pitch estimate is rounded to this many decimals of a degree (the levelled views
#: built for a stream are keyed by it; 0.05 degrees moves no measurement).
PITCH_DECIMALS = 1
#: With no rig, the pitches (degrees) the chosen floor-contact row is tried at besides 0
#: (and every row and weak step when nothing stands a face, or only an unsure one) ...
SWEPT_PITCHES_DEG = (-4.0, -2.0, 2.0, 4.0)
#: ... and how much surer a face found at one of them must be to be taken.
SWEPT_PITCH_MARGIN = 0.15
#: ... nor one over this many times as tall as the level face (on the tuning rooms the
#: faces taken stood 0.58-1.25 times as tall; a wall print above the box taken in, 2.4).
SWEPT_MAX_GROWTH = 1.5
#: With no rig, the pitch the face's sides read (their lean) is taken only where the camera
#: height it and the face's floor-contact row stand for is one a robot carries (at most
#: UNDER_MAX_CAMERA_HEIGHT_M; the issue's robots carry the lens 0.2-0.5 m up): the pitch
#: the sides give must agree with the lens height the foot row implies. A lens pitched
#: down further raises that height; a lean read the wrong way (a seam, a shadow's edge
#: along a side) stands the lens too high and reads a line above the face as its top
#: (photo 2089 ordinary: the sides read 2.2 degrees down against 3.7 up, the lens 0.71 m
#: up against 0.49 m, the top 35 rows high, +19 %). Session 40, branch ``wt-e-40``; a
#: switch for the tests.
SIDES_PITCH_LENS_BOUND = True
#: With no rig, a trial's face whose pixel factor (:func:`~obstacle_fusion.vision.fused.
#: confidence.pixel_factor`) is under this is small: a stone or a mark on the floor before
#: a face of full size settles no floor-contact row (on the fresh rooms the floor's marks
#: taken stood at about 0.25 and 0.3; a box 0.15 m tall at 2.5 m, 27 px, at 0.69).
SMALL_SHARE = 0.5
#: With no rig, the last-resort sweep's face replaces an unsure face (under
#: ESTIMATE_ACCEPT) only when its sides read the pitch and it reaches this confidence.
SWEPT_OVER_UNSURE = 0.5
#: ... or, standing on the unsure face's own foot (the two feet under MIN_NEARER_DROP_PX
#: apart), when the unsure face's top edge is doubted by one of these (another edge just
#: under it, or a line running on beside it) and the sweep's face's top by none
#: (:func:`_swept_top_over`).
TOP_EDGE_DOUBTS = frozenset({SECOND_TOP, TOP_RUNS_ON})
#: ... or when it is the unsure face seen whole (:func:`_swept_whole`: the same foot and
#: sides, over SWEPT_MAX_GROWTH times as tall, its sides running on above the unsure
#: face's top). A switch for the tests.
SWEPT_WHOLE_FACE = True
#: With no rig, when no trial stood a sure face, the last-resort sweep's unsure faces
#: (under ESTIMATE_ACCEPT, standing on their own foot, none of FOOT_DOUBTS, not small)
#: found again by several guesses of the camera's height and pitch: the surest reported
#: with its low confidence rather than missed (:func:`_repeated_face`). A face is a
#: surface in the world: its foot and sides stay where they are however the camera is
#: guessed, while an edge of the floor's texture or a stripe read as a face moves or goes
#: with the guess. On gravel the face's foot steps no more than the stones do, so no
#: sure face stands anywhere (session 35: photo 156 o, 159 h, 2013 o, missed before, now
#: within 1.8-7.2 %). A switch for the tests.
REPEATED_FACE = True
#: ... found by at least this many of the sweep's trials (the face itself counted).
REPEATED_FACE_TRIALS = 3
#: ... in views levelled for at least this many pitches (trials at one pitch on other rows
#: read the same view again: a patch of gravel near the lens, photo/2121 o, was found alike
#: on three rows at pitch 0 and at no other pitch).
REPEATED_FACE_PITCHES = 2
#: With no rig, a sure face standing on the top of a lower, unsure one (:func:`_stands_on_top`:
#: an object on a box or behind it, its foot on the box's top edge) gives way to that
#: face when it is this many times as wide or more ...
ON_TOP_WIDER = 1.3
#: ... the upper face's foot at most this many pixels under the lower face's top ...
ON_TOP_BELOW_PX = 3.0
#: ... and at most this share of the lower face's height above it.
ON_TOP_ABOVE = 0.5
#: With no rig, a sure face whose top and sides match (:func:`_same_outline`) those of an
#: unsure face found on a lower row, within this share of its width ...
OUTLINE_MATCH = 0.06
#: ... or this many pixels, whichever is more ...
OUTLINE_MATCH_PX = 3.0
#: ... that lower face's foot at least this many pixels lower (over twice ROW_JITTER_PX:
#: nearer feet are one edge's blur, the row jitter's business), is that face's upper part.
OUTLINE_MIN_DROP_PX = 5.0
#: A face accepted on a line of its own print gives way to the same face found on a lower
#: row when the print's texture runs on between the two feet (:func:`_print_line_foot`;
#: with no rig, the rows are the trials' own guesses).
PRINT_LINE_FOOT = True
#: With no rig, the rows this far above and below the chosen floor-contact row are tried
#: too (pixels); the surest face of the three is kept.
ROW_JITTER_PX = 2
#: ... and of the faces the row and those neighbours stand, the surest is taken with each
#: of its FOOT_DOUBTS cutting its confidence by DOUBT_FACTOR (as in the reported figure):
#: a neighbour row whose face's foot its own outline finds off the floor, or with floor
#: taken in, stands that face on a line of the face or the floor, not on the contact
#: (procedural/100 hard: the row 2 px up stood the face on a line above its foot, surer by
#: its raw figure, 0.38 against 0.28, height -7.6 %; the row 2 px down stood it on its
#: foot, 0.7 %). A switch for the tests.
JITTER_WEIGHS_FOOT = True
#: ... and a face whose foot stands above the row its own trial tried (FOOT_ABOVE_CONTACT,
#: recorded with no rig though it cuts no reported figure there) is weighed as doubted on
#: its foot too, against a neighbour row's face that holds it (:func:`_holds_above`: that
#: face's foot more than ROW_JITTER_PX rows lower, its top and sides round it, reaching
#: past it by more than ROW_JITTER_PX at the top or a side): the trial put the floor
#: contact on its row, and a face ending above it inside a larger face standing lower is
#: a print or a course on that face, its lower edge taken for the contact (procedural 3366
#: hard, -23 %). The same face read on its own foot a row or two over the tried row
#: (photo 119 ordinary, procedural 2082 hard), or with only the foot lower (a shadow's or a
#: bevel's lower edge under the face: procedural 2086 ordinary), is not. Session 47,
#: branch ``wt-b-47``; a switch for the tests.
JITTER_FOOT_ABOVE_WEIGHED = True
#: ... but of two faces a row and a neighbour stand, one holding the other inside its
#: sides and top with its foot lower, a margin of one colour seen round the inner one
#: (FRAMED),
#: the outer one is taken and the inner one never replaces it (:func:`_frame_holds`: the
#: inner one is a print on the face, its lower edge taken for the contact). Session 43,
#: branch ``wt-e-43``; a switch for the tests.
JITTER_FRAME_HOLDS = True
#: ... the outer face found (its raw confidence) at least this surely (photo 3157 hard's
#: frame reads 0.15; a face under 0.1 is too unsure to overrule the row's own) ...
JITTER_FRAME_SURE = 0.1
#: ... its margin over the inner face at most this share of its wider side margin.
JITTER_FRAME_TOP_SHARE = 1.0
#: A weaker step tried as a nearer foot lies at least this many rows below the row whose
#: face was unsure (closer steps are that row's own edge blur, tried by the jitter).
MIN_NEARER_DROP_PX = 2 * ROW_JITTER_PX
#: With no rig, a face refused as doubted on every count gives way to another trial's
#: reading of its face with the top lower (:func:`_lower_top_reading`): on the same foot
#: and sides (each within LOWER_TOP_EDGE_PX), its top at least LOWER_TOP_MIN_PX lower but
#: overlapping the refused face by LOWER_TOP_MIN_IOU, and doubted by none of
#: TOP_EDGE_DOUBTS, where the refused face's top carries one (:func:`_top_doubt_cleared`).
#: The face is one surface standing on its foot between its sides: two readings sharing
#: those are the same face, differing only in where its top was put; a top whose edge
#: runs on past the sides (a line of the wall behind) or with another edge under it is
#: where one reading went on past the face's top, and the reading stopping at an edge
#: neither doubts is the face's (procedural 3231 ordinary, planks: the level trials' top
#: 25 rows up the wall, refused; the trials pitched 2 and 4 degrees read it right).
#: Session 44, branch ``wt-e-44``; a switch for the tests.
LOWER_TOP_READING = True
#: ... the two readings' feet and each side within this many pixels (a trial's row
#: jitter: another guess of the pitch on the same floor-contact row) ...
LOWER_TOP_EDGE_PX = float(ROW_JITTER_PX)
#: ... the other reading's top at least this many pixels lower (nearer, it is the same
#: top within the jitter's blur: as a nearer foot, MIN_NEARER_DROP_PX) ...
LOWER_TOP_MIN_PX = float(MIN_NEARER_DROP_PX)
#: ... and the two boxes overlapping by at least this (IoU; with foot and sides shared,
#: the lower height's share of the refused one): a guessed pitch a few degrees off moves
#: where the top is sought by a few rows, so the top went on past the face by a line of
#: what is behind it just over it; a reading whose top lies further down is a band or a
#: print on the face, a part of it, not its top read again (procedural 3231 ordinary:
#: 0.87; under SAME_FACE_IOU, 0.9, where the two are one reading anyway).
LOWER_TOP_MIN_IOU = 0.8

#: With no rig and the pitch not read from the face's sides, the lens may look down by up
#: to this much more than the guess (degrees): a box's top face may show that far above
#: the guessed horizon ...
UNREAD_PITCH_DOWN_DEG = 5.0
#: ... and the face measured allowing for it is kept unless its confidence (doubts
#: applied) is lower by more than this.
UNREAD_PITCH_CONFIDENCE_MARGIN = 0.05
#: ... but where that face is the guessed pitch's face with its top moved (:func:`_top_moved`):
#: the allowance shows a top face above the guessed horizon, whose front edge lies under
#: its back edge, so the face lowered to it is taken however its confidence compares (the
#: band over the front cuts the top edge's evidence: procedural 147 hard, 0.78 -> 0.61,
#: +15 -> +1 %; photo 742 hard, 0.41 -> 0.07, +28 -> +3 %), and a face it raised is not
#: (nothing a steeper pitch changes makes the front taller: procedural 752 hard, raised
#: 5 rows to a line above the top, +4 -> +22 %). Session 40, branch ``wt-c-40``; a switch
#: for the tests.
UNREAD_TOP_FACE_LOWERS = True
#: ... but not where the two tops cannot be a top face's edges: the lowered top its front
#: edge, the guessed face's top its back edge. A top face shows above the guessed horizon
#: only to a lens looking down more than guessed, at most UNREAD_PITCH_DOWN_DEG more, and,
#: the foot's row fixed, a lens pitched further down stands higher: at most
#: UNDER_MAX_CAMERA_HEIGHT_M (the issue's robots carry the lens 0.2-0.5 m up). At the
#: steepest pitch both allow, the back edge must lie on the floor side of the horizon and
#: at most MAX_TOP_FACE_DEPTH_M behind the front (:func:`_top_face_too_deep`; a steeper
#: pitch only brings it nearer); else the guessed top is the face's own top edge, and the
#: lower one a line across the face (a brick course, a panel joint). Procedural 3327 hard
#: (new7): a brick face taller than the lens, a course 12.6 rows under its top taken as a
#: top face's front edge, -12.7 %; the back edge would lie 3.8 m behind the front. Session
#: 46, branch ``wt-e-46``; a switch for the tests.
TOP_FACE_DEPTH_BOUND = True
#: ... the deepest top face an obstacle the sonar's beam stops at shows (metres; the rooms'
#: boxes are 0.2-0.8 m deep, and a deeper thing is a wall or a bench, not a box whose top
#: face is seen past its front).
MAX_TOP_FACE_DEPTH_M = 1.5
#: ... and where the pitch was read (from the face's sides, a few degrees off on a small or
#: near-centre face): the face measured at the read pitch allowing the lens
#: UNREAD_PITCH_DOWN_DEG more down is taken only where it is the read face with its top
#: lowered (:func:`_top_moved` < 0: a top face's front edge under its back edge; a box lower
#: than the lens shows one, and a read pitch too level hides it above the horizon). Never
#: raised, and no other face: the read pitch stands otherwise. Session 40, branch
#: ``wt-f-40`` (new rooms procedural 3034 ordinary +12 -> +1.6 %, 3042 hard +13 -> -0.6 %,
#: photo 3023 ordinary +28 -> +2.5 %); a switch for the tests.
READ_PITCH_TOP_FACE = True
#: ... one face: each side within this many columns of the other's (feet within
#: ROW_JITTER_PX) ...
TOP_FACE_SIDES_PX = 3.0
#: ... its top moved by more than this many rows (a top's sub-pixel fit moves by a pixel).
TOP_FACE_MOVE_PX = 1.5

#: With no rig, a face whose columns leave the beam's axis out gives way to the surest sure
#: trial's face covering it (:meth:`Measurer._on_axis_trial`): the sonar ranges what its
#: axis hits. On the tuning rooms none of the 682 no-rig answers within 5 % lay off the
#: axis; the 11 that did were 24-269 % off. A switch for the tests.
AXIS_PICKS_TRIAL = True
#: ... and where no sure trial's face covers the axis, the surest unsure one that does
#: (of full size, standing on its undoubted foot): the sonar ranges what its axis hits, so
#: a face beside the beam is not its face however sure (photo 3078 hard: a wall band left
#: of the beam, 1.6 m wide, +320 %, against the poster box on the axis at 0.15, -15 %).
#: Session 42, branch ``wt-e-42``; a switch for the tests.
AXIS_UNSURE_TRIAL = True
#: With no rig, a face standing on the beam's axis with its foot lower in the image (nearer
#: the robot) than the face found, wholly under that face's foot or beside a face that
#: leaves the axis out, is the sonar's face (:meth:`Measurer._nearer_on_axis`): the sonar
#: ranges the nearest surface on its axis. A switch for the tests.
NEARER_ON_AXIS = True
#: ... from this confidence up (a trial's, doubts not applied): on the tuning rooms such
#: faces read right stood at 0.17 and 0.25, and a floor mark's face under one at 0.10.
NEARER_AXIS_ACCEPT = 0.15
#: ... and also when the face reported is a band running across that nearer face, past
#: both its sides (:func:`_band_across`): a wall's band behind a box, read as a face
#: across the box's own surface. A switch for the tests.
NEARER_ACROSS_BAND = True
#: ... the nearer face at least this many times as tall as the band.
ACROSS_TALLER = 2.0
#: With no rig, a sure face (its confidence with its doubts at least NEARER_RIVAL_SURE)
#: that keeps the answer while a face too unsure for NEARER_ON_AXIS (at least
#: NEARER_RIVAL_ACCEPT, otherwise as :meth:`Measurer._nearer_on_axis` asks: on the axis,
#: standing on its undoubted foot, not small, wholly in front of it) stands nearer on the
#: beam's axis is doubted TRIAL_RIVAL: the sonar ranges the nearest surface on its axis,
#: which is that face if it is one, and the guessed camera height that stood the sure face
#: on the range may have stood a surface behind it (procedural 3350 ordinary: a dark
#: print on the wall, 0.74 m tall at 0.97, over a low plank box on the axis, read right at
#: 0.08). A switch for the tests (session 47, branch ``wt-a-47``).
NEARER_UNSURE_RIVAL = True
#: ... the nearer face's trial confidence from this up (a trial's least reported one, the
#: fused method's min_confidence: any face a trial reports). With the default
#: min_confidence (DEFAULT_MIN_CONFIDENCE, also 0.05) every trial's face reaches it; it
#: bites only when the method is run with a lower min_confidence.
NEARER_RIVAL_ACCEPT = 0.05
#: ... the sure face's confidence with its doubts from this up (a sure answer's: the rival
#: takes it under; an unsure one already says the face may be another). Its doubts when
#: the search ends, before the PITCH_UNREAD the search then adds for a guessed pitch: that
#: doubt is the pitch's, not which surface the guessed height stood, so a face sure but
#: for it is doubted too (fresh procedural 2186 hard: 0.66 before it, reported 0.295 ->
#: 0.133, a face 26 % short).
NEARER_RIVAL_SURE = 0.5
#: ... the doubts such a face is reported with (its pitch a guess, the face beside the axis
#: a rival trial's): one doubted under MIN_DOUBTED_CONFIDENCE with them is not taken (on
#: the fresh rooms taking one turned a face 23 % off into a refusal).
AXIS_SWAP_DOUBTS = (PITCH_UNREAD, TRIAL_RIVAL)

#: The doubts about the pitch a stream's next frames inherit with it.
PITCH_DOUBTS = frozenset({PITCH_UNREAD, PITCH_RERUN_DISAGREES})

#: Levelled views kept for the pitches of recent frames and of the swept pitches (each
#: holds its maps and buffers; fewer than the sweep needs rebuilt them every frame).
PITCHED_VIEWS_KEPT = 8

#: A face box within this many pixels of an image border is cut by it.
CLIP_MARGIN_PX = 1.5
#: A sure face of another no-rig trial sharing under this share of the narrower face's
#: columns with the face reported is another face beside it (a face and its own parts or
#: a wider reading of it share most of them).
RIVAL_SHARED_WIDTH = 0.5
#: With no rig, an unsure face spanning the columns of a face on a weaker step below it,
#: this many times as wide or more, is a strip along the wall behind it ...
SPAN_FACTOR = 2.0
#: ... and under this share as tall as it is wide (a face taller for its width is one,
#: and a lower face under it its reflection on a glossy floor)
STRIP_MAX_ASPECT = 0.2
#: ... and the lower face is taken from this confidence up (ESTIMATE_ACCEPT otherwise).
SPANNED_NEARER_ACCEPT = 0.08
#: With no rig, a face under this share as tall as it is wide is a band along the wall,
#: not taken (the flattest faces of the tuning rooms stand 0.13 as tall as wide; the bands
#: taken for faces on wrong rows 0.04-0.09).
BAND_MAX_ASPECT = 0.1
#: With no rig, a face whose foot lies more than this many pixels above the lower edge of
#: a band along the wall found by another trial, and not more than this above its upper
#: edge ...
BAND_FOOT_MARGIN_PX = 2.0
#: ... sharing at least this share of the narrower one's columns is on the wall, not taken.
BAND_SHARED_WIDTH = 0.5
#: With no rig, a band a trial found (BAND_MAX_ASPECT) whose rows just above it and just
#: below it both have the floor's colour at the image's foot (:func:`_band_on_floor`) lies
#: on the floor, not along the wall: a shade on the floor (a cast shadow, a patch of the
#: floor's texture) with floor before and behind it, where a wall's foot or skirting has
#: the wall above it. It refuses no face standing in it (photo 3493 ordinary: a faint
#: strip of a grey gravel floor under a seamed box's foot, running out to one side,
#: refused the box's own face at 0.77; the search then took a face 15 rows low, +14 %).
#: Session 49, branch ``wt-d-49``; a switch for the tests.
BAND_ON_FLOOR = True
#: ... the rows read above and below the band (from, to, pixels past its edge) ...
BAND_FLOOR_ROWS = (3, 9)
#: ... the floor's colour read on this many rows at the image's foot, the band's columns ...
BAND_FLOOR_FOOT_ROWS = 12
#: ... and each strip within this of it (median Lab, 8-bit; the floor strips round the
#: gravel's band 2-3 off, a wall above a skirting tens).
BAND_FLOOR_MATCH = 8.0
#: ... unless the band is the face's contact shadow: under this share of the face's
#: columns or more ...
SHADOW_COVER = 0.9
#: ... its centre within this share of the face's width from the face's (a shadow lies
#: under the face; a wall's foot or skirting runs on regardless of it: on the fresh rooms
#: the shadow taken for a band lay 0.08 face widths off centre, the skirting a poster
#: stood on 0.38).
SHADOW_CENTRE_SHARE = 0.25
#: The order ``clipped`` lists the cut sides in.
SIDES = ("left", "right", "top", "bottom")
#: With no rig, after a last-resort pitch sweep that found no face, this many frames of a
#: stream go without one (a frame with nothing in view would pay ~90 trials each time).
SWEEP_REST_FRAMES = 10


def beam_columns_px(
    view: View, rig: Rig, range_m: float, depth: float, allowance_m: float = 0.0
) -> tuple[float, float]:
    """The pinhole columns (first, last) of the levelled view the sonar's beam covers at
    the face's ``depth`` (its lateral bounds at ``range_m``, widened by ``allowance_m``
    each side, seen through the lens's fx and cx). Not the input's columns: the lens's
    distortion and the camera's pitch move them slightly (BEAM_EDGE_SLACK_PX)."""
    xb0, xb1 = rig.beam_x_bounds(range_m)
    cam = view.camera
    return (
        cam.cx + cam.fx * (xb0 - allowance_m) / depth,
        cam.cx + cam.fx * (xb1 + allowance_m) / depth,
    )


def _outside_beam(
    box: tuple[float, float, float, float] | None,
    view: View,
    rig: Rig,
    range_m: float,
    depth: float,
    allowance_m: float = 0.0,
) -> bool:
    """Whether a face box (input pixels) lies wholly beside the sonar's beam at the face's
    depth (:func:`beam_columns_px` with ``allowance_m``, widened by BEAM_EDGE_SLACK_PX each
    side); False when the box is unknown, the depth is not in front of the lens, sensor
    0's axis is yawed (its beam is not about the lens's axis) or the beam's columns miss
    the image (nothing in view to check against)."""
    if box is None or depth <= 0.0:
        return False
    if any(m.id == 0 and m.yaw_deg != 0.0 for m in rig.sonar_mounts()):
        return False
    u_lo, u_hi = beam_columns_px(view, rig, range_m, depth, allowance_m)
    u_lo, u_hi = u_lo - BEAM_EDGE_SLACK_PX, u_hi + BEAM_EDGE_SLACK_PX
    if u_hi < 0.0 or u_lo > view.camera.width:
        return False
    return box[2] < u_lo or box[0] > u_hi


def _refine_offsets(reach: int) -> list[int]:
    """The offsets from a step's row to its neighbours within ``reach`` rows, nearest
    first, the lower of each pair first (rows are tried lowest first): +1, -1, +2, -2, ..."""
    return [sign * d for d in range(1, reach + 1) for sign in (1, -1)]


def _axis_column(view: View, rig: Rig, depth: float) -> float:
    """The input image's column of the beam's axis at ``depth`` (metres): the sonar's
    lateral offset seen at the face's depth (the rig's default, 0, with none given: the
    lens beside the sonar). One formula for the axis swaps and UNDER_ON_AXIS, so that
    they cannot disagree on which column the sonar ranges."""
    return view.camera.cx + view.camera.fx * rig.sonar_right_m / depth


def _covers(box: tuple[float, float, float, float], u: float) -> bool:
    """Whether the columns of ``box`` (left, top, right, bottom) take column ``u`` in."""
    return box[0] <= u <= box[2]


def _rival_trial(
    best: Measurement,
    trials: list[Measurement],
    stands: Callable[[Measurement], bool],
) -> bool:
    """Whether a sure face of another no-rig trial lies beside ``best``: its columns share
    under RIVAL_SHARED_WIDTH of the narrower face's width, and it stands on its foot
    (``stands``). The trials differ only in the guessed camera height and pitch, so the face
    measured is one of two the unknown rig decides between (TRIAL_RIVAL)."""
    return any(
        other is not best and _beside(best.box_px, other.box_px) and stands(other)
        for other in trials
    )


def _less_doubted_reading(
    best: Measurement,
    readings: list[Measurement],
    stands: Callable[[Measurement], bool],
) -> Measurement | None:
    """Another no-rig trial's reading of ``best``'s face (:func:`_same_face`: the same face
    on the same foot, seen with another guessed camera height or pitch) whose face doubts
    are a strict subset of ``best``'s and none of FOOT_DOUBTS (the foot is the same in
    every reading), standing on its foot (``stands``): the surest such reading, its doubted
    confidence (``best``'s doubts about the rig search added: PITCH_UNREAD, TRIAL_RIVAL,
    PITCH_RERUN_DISAGREES) at least MIN_DOUBTED_CONFIDENCE; else None. The doubts the
    other reading lacks come from the guess of the rig, not from the face, so the face is
    not doubted on every count."""
    search = [d for d in best.doubts if d in SEARCH_DOUBTS]
    face = {d for d in best.doubts if d not in SEARCH_DOUBTS}
    chosen: Measurement | None = None
    chosen_conf = MIN_DOUBTED_CONFIDENCE
    for other in readings:
        if (
            other is best
            or not other.detected
            or not (
                _same_face(best.box_px, other.box_px)
                or (LOWER_TOP_READING and _lower_top_reading(best, other))
            )
        ):
            continue
        own = set(other.doubts)
        if not own < face or own & FOOT_DOUBTS:
            continue
        again = dataclasses.replace(other, doubts=[*other.doubts, *search])
        conf = _doubted(again, REFUSAL_IGNORES)
        if conf >= chosen_conf and stands(other):
            chosen, chosen_conf = again, conf
    return chosen


def _lower_top_reading(best: Measurement, other: Measurement) -> bool:
    """Whether ``other`` (another no-rig trial's reading) reads ``best``'s face with its top
    lower: the same foot and sides (each within LOWER_TOP_EDGE_PX), its top at least
    LOWER_TOP_MIN_PX under ``best``'s, the boxes overlapping by LOWER_TOP_MIN_IOU,
    ``best``'s top edge doubted by one of TOP_EDGE_DOUBTS and ``other``'s by none
    (LOWER_TOP_READING)."""
    box, low = best.box_px, other.box_px
    if box is None or low is None:
        return False
    return (
        all(abs(box[i] - low[i]) <= LOWER_TOP_EDGE_PX for i in (0, 2, 3))
        and low[1] - box[1] >= LOWER_TOP_MIN_PX
        and _iou(box, low) >= LOWER_TOP_MIN_IOU
        and _top_doubt_cleared(best, other)
    )


def _top_doubt_cleared(best: Measurement, other: Measurement) -> bool:
    """Whether ``best``'s top edge carries one of TOP_EDGE_DOUBTS (a line running on past
    its sides, another edge under it) and ``other``'s, a reading of the same face, none."""
    return bool(TOP_EDGE_DOUBTS & set(best.doubts)) and not TOP_EDGE_DOUBTS & set(other.doubts)


def _whole_face_reading(
    best: Measurement,
    readings: list[Measurement],
    stands: Callable[[Measurement], bool],
) -> Measurement | None:
    """Another no-rig trial's reading of a face that takes ``best``'s face in whole
    (:func:`_holds`: its box holds ``best``'s within WHOLE_FACE_MARGIN_PX, its foot no
    further under it either), not the same face read again (:func:`_same_face`), of none
    of FOOT_DOUBTS nor both SIDE_DOUBTS, no more than
    WHOLE_FACE_MAX_ASPECT times as tall as wide, covering at least WHOLE_FACE_MIN_GROWTH
    times ``best``'s box area, standing on its foot (``stands``): the
    surest such reading, its doubted confidence (``best``'s doubts about the rig search
    added) at least MIN_DOUBTED_CONFIDENCE; else None. ``best`` is then a part of that
    face (a print, a panel or a band on it), doubted for its edges, not a face."""
    search = [d for d in best.doubts if d in SEARCH_DOUBTS]
    if best.box_px is None:
        return None
    chosen: Measurement | None = None
    chosen_conf = MIN_DOUBTED_CONFIDENCE
    for other in readings:
        box = other.box_px
        if (
            other is best
            or not other.detected
            or box is None
            or not _holds(box, best.box_px, WHOLE_FACE_MARGIN_PX)
            or box[3] > best.box_px[3] + WHOLE_FACE_MARGIN_PX
            or SIDE_DOUBTS <= set(other.doubts)
            or _same_face(best.box_px, box)
            or FOOT_DOUBTS & set(other.doubts)
            or box[3] - box[1] > WHOLE_FACE_MAX_ASPECT * (box[2] - box[0])
            or _area(box) < WHOLE_FACE_MIN_GROWTH * _area(best.box_px)
        ):
            continue
        again = dataclasses.replace(other, doubts=[*other.doubts, *search])
        conf = _doubted(again, REFUSAL_IGNORES)
        if conf >= chosen_conf and stands(other):
            chosen, chosen_conf = again, conf
    if chosen is not None:
        log.debug("no rig: the refused face is a part of a face another trial read whole")
    return chosen


def _clean_whole_face(
    best: Measurement,
    readings: list[Measurement],
    stands: Callable[[Measurement], bool],
) -> Measurement | None:
    """With no rig, a face ``best`` that its own outline doubts (a doubt of its face, not
    of the rig's guess, nor CLEAN_WHOLE_IGNORES) gives way to another trial's reading of an
    undoubted face standing on its foot (``stands``), no more than WHOLE_FACE_MAX_ASPECT
    times as tall as wide, not the same face read again (:func:`_same_face`), either

    - taking ``best`` in whole on the same foot when ``best`` is unsure (raw confidence
      under ESTIMATE_ACCEPT), as :func:`_whole_face_reading` asks (its box holding
      ``best``'s within WHOLE_FACE_MARGIN_PX, its foot no further under,
      WHOLE_FACE_MIN_GROWTH times the area), from CLEAN_WHOLE_SURE up: ``best`` is a patch
      of that face (photo 2060 hard: a brick face's middle panel, 71 % narrow, the whole
      face undoubted on the same foot); or
    - (CLEAN_RIVAL) on ``best``'s foot within WHOLE_FACE_MARGIN_PX, sharing its columns
      (not :func:`_beside` it), CLEAN_RIVAL_WIDER times as wide, from CLEAN_RIVAL_SURE
      up and surer than ``best`` with its face doubts applied: one face read two ways on
      one foot, the undoubted reading the face (photo 2022 ordinary: a face run up a pole
      behind it, doubted thrice, 58 % off).

    The surest such reading, ``best``'s doubts about the rig search added; else None."""
    if best.box_px is None:
        return None
    if not set(best.doubts) - SEARCH_DOUBTS - CLEAN_WHOLE_IGNORES:
        return None
    unsure = (best.confidence or 0.0) < ESTIMATE_ACCEPT
    face_only = dataclasses.replace(best, doubts=[d for d in best.doubts if d not in SEARCH_DOUBTS])
    doubted = _doubted(face_only, REFUSAL_IGNORES)
    search = [d for d in best.doubts if d in SEARCH_DOUBTS]
    chosen: Measurement | None = None
    for other in readings:
        box = other.box_px
        if (
            other is best
            or not other.detected
            or box is None
            or set(other.doubts) - SEARCH_DOUBTS - CLEAN_WHOLE_IGNORES
            or _same_face(best.box_px, box)
            or box[3] - box[1] > WHOLE_FACE_MAX_ASPECT * (box[2] - box[0])
        ):
            continue
        conf = other.confidence or 0.0
        whole = (
            unsure
            and conf >= CLEAN_WHOLE_SURE
            and _holds(box, best.box_px, WHOLE_FACE_MARGIN_PX)
            and box[3] <= best.box_px[3] + WHOLE_FACE_MARGIN_PX
            and _area(box) >= WHOLE_FACE_MIN_GROWTH * _area(best.box_px)
        )
        rival = (
            CLEAN_RIVAL
            and conf >= CLEAN_RIVAL_SURE
            and conf > doubted
            and abs(box[3] - best.box_px[3]) <= WHOLE_FACE_MARGIN_PX
            and not _beside(best.box_px, box)
            and box[2] - box[0] >= CLEAN_RIVAL_WIDER * (best.box_px[2] - best.box_px[0])
        )
        if not (whole or rival):
            continue
        if (chosen is None or conf > (chosen.confidence or 0.0)) and stands(other):
            chosen = other
    if chosen is None:
        return None
    log.debug(
        "no rig: the doubted face %s gives way to the undoubted face %s on its foot",
        best.box_px,
        chosen.box_px,
    )
    return dataclasses.replace(chosen, doubts=[*chosen.doubts, *search])


def _area(box: tuple[float, float, float, float]) -> float:
    """The area of a box (x0, y0, x1, y1), square pixels."""
    return (box[2] - box[0]) * (box[3] - box[1])


def _holds(
    box: tuple[float, float, float, float],
    part: tuple[float, float, float, float],
    margin: float,
) -> bool:
    """Whether ``box`` (x0, y0, x1, y1) holds ``part`` within ``margin`` pixels on every
    side."""
    return (
        box[0] <= part[0] + margin
        and box[1] <= part[1] + margin
        and box[2] >= part[2] - margin
        and box[3] >= part[3] - margin
    )


def _foot_moves_down(found: Measurement, grown: Measurement) -> bool:
    """Whether ``grown`` (the rows' face read as with a rig: its readings agree on one face
    standing on its foot, none doubting it) is ``found`` carried down to its floor contact:
    ``found``'s outline doubts its foot (FOOT_OFF_FLOOR), ``grown``'s foot lies more than
    ROW_JITTER_PX rows lower, its top no more than that under ``found``'s (it may reach
    higher), the two faces' columns overlapping by LOWER_FOOT_SIDES_SHARE of the wider (no
    narrower face takes the width), it is at least UNDER_SURE and its
    lens at most UNDER_MAX_CAMERA_HEIGHT_M up. A face's sides run down to the floor: a
    foot found off the floor is a line on the face (a print's lower edge, a band)."""
    if FOOT_OFF_FLOOR not in found.doubts or found.box_px is None or grown.box_px is None:
        return False
    _, y0, _, y1 = found.box_px
    _, gy0, _, gy1 = grown.box_px
    return (
        gy1 - y1 > ROW_JITTER_PX
        and gy0 - y0 <= ROW_JITTER_PX
        and _rows_face_on_columns(found.box_px, grown, UNDER_SURE)
    )


def _rows_face_on_columns(
    found: tuple[float, float, float, float], grown: Measurement, sure: float
) -> bool:
    """Whether ``grown`` (the rows' face read as with a rig) stands on ``found``'s columns
    (input pixel boxes), overlapping by LOWER_FOOT_SIDES_SHARE of the wider of the two (no
    narrower face takes the width: a plank of the face), at least ``sure`` and its lens at
    most UNDER_MAX_CAMERA_HEIGHT_M up: the checks the rows' face moving a found face's foot
    or top (:func:`_foot_moves_down`, :func:`_foot_moves_up`, :func:`_top_moves_up`) share."""
    if grown.box_px is None:
        return False
    x0, _, x1, _ = found
    g0, _, g1, _ = grown.box_px
    overlap = min(x1, g1) - max(x0, g0)
    return (
        overlap >= LOWER_FOOT_SIDES_SHARE * max(x1 - x0, g1 - g0)
        and (grown.confidence or 0.0) >= sure
        and (grown.camera_height_m or math.inf) <= UNDER_MAX_CAMERA_HEIGHT_M
    )


def _box_round(
    outer: tuple[float, float, float, float], inner: tuple[float, float, float, float]
) -> bool:
    """Whether box ``outer`` holds ``inner`` as a face holds a print on it: its foot more
    than ROW_JITTER_PX rows lower, each side more than ROW_JITTER_PX columns outside (not
    the same sides read again), its top no more than ROW_JITTER_PX rows under."""
    x0, y0, x1, y1 = inner
    g0, gy0, g1, gy1 = outer
    return (
        gy1 - y1 > ROW_JITTER_PX
        and x0 - g0 > ROW_JITTER_PX
        and g1 - x1 > ROW_JITTER_PX
        and gy0 - y0 <= ROW_JITTER_PX
    )


def _holds_print(found: Measurement, grown: Measurement) -> bool:
    """Whether ``grown`` (the rows' face read as with a rig: its readings agree on one face
    standing on its foot) holds ``found`` as a face holds a print on it: its foot more than
    ROW_JITTER_PX rows lower, each side more than ROW_JITTER_PX columns outside ``found``'s
    (not the same sides read again), its top no more than ROW_JITTER_PX rows under
    ``found``'s, at least UNDER_SURE, its lens at most UNDER_MAX_CAMERA_HEIGHT_M up. A face
    is one surface whose sides run down to the floor-contact row; a box inside it whose
    foot ends above that row is something on the surface (a print, a label, a panel), and
    a lower foot is a nearer one, the surface the sonar ranged (a thing behind the face,
    farther, stands on a higher row)."""
    if found.box_px is None or grown.box_px is None:
        return False
    return (
        _box_round(grown.box_px, found.box_px)
        and (grown.confidence or 0.0) >= UNDER_SURE
        and (grown.camera_height_m or math.inf) <= UNDER_MAX_CAMERA_HEIGHT_M
    )


def _foot_moves_up(found: Measurement, grown: Measurement) -> bool:
    """Whether ``grown`` (the rows' face read as with a rig) is ``found`` standing on its
    contact: its foot more than ROW_JITTER_PX and at most UNDER_ROWS_SLACK_PX rows higher,
    its top within ROW_JITTER_PX of ``found``'s, the two faces' columns overlapping by
    LOWER_FOOT_SIDES_SHARE of the wider (no narrower face takes the width: a plank of the
    face), surer than ``found`` and at least UNDER_SURE, its lens at most
    UNDER_MAX_CAMERA_HEIGHT_M up. The rows read the
    contact where each reading's sides stand; the band under it, which the no-rig rows took
    in, is a shadow's or a bevel's."""
    if found.box_px is None or grown.box_px is None:
        return False
    _, y0, _, y1 = found.box_px
    _, gy0, _, gy1 = grown.box_px
    return (
        ROW_JITTER_PX < y1 - gy1 <= UNDER_ROWS_SLACK_PX
        and abs(gy0 - y0) <= ROW_JITTER_PX
        and (grown.confidence or 0.0) > (found.confidence or 0.0)
        and _rows_face_on_columns(found.box_px, grown, UNDER_SURE)
    )


def _top_moves_up(found: Measurement, grown: Measurement) -> bool:
    """Whether ``grown`` (the rows' face read as with a rig) is ``found`` up to its top: its
    foot within ROW_JITTER_PX of ``found``'s, its top more than ROW_JITTER_PX rows higher,
    on ``found``'s columns at least GROWN_SURE with its lens at most
    UNDER_MAX_CAMERA_HEIGHT_M up (:func:`_rows_face_on_columns`), and ``found`` found with
    little evidence (its raw confidence under TOP_RAISE_MAX_FOUND_CONFIDENCE, which lies
    under GROWN_SURE: the rows' face is the surer). The face is one surface standing on
    that contact between those sides; the rows read it up to where its sides end, the
    no-rig trials stopped at a line across it."""
    if found.box_px is None or grown.box_px is None:
        return False
    _, y0, _, y1 = found.box_px
    _, gy0, _, gy1 = grown.box_px
    return (
        abs(gy1 - y1) <= ROW_JITTER_PX
        and y0 - gy0 > ROW_JITTER_PX
        and (found.confidence or 0.0) < TOP_RAISE_MAX_FOUND_CONFIDENCE
        and _rows_face_on_columns(found.box_px, grown, GROWN_SURE)
    )


def _top_moves_far_up(found: Measurement, grown: Measurement) -> bool:
    """Whether ``grown`` (the rows' face read as with a rig) is ``found`` up to its top,
    ``found`` surer than :func:`_top_moves_up` allows (raw confidence under
    FAR_TOP_MAX_FOUND_CONFIDENCE): its foot within ROW_JITTER_PX of ``found``'s, its top
    higher by at least FAR_TOP_SHARE of ``found``'s height, on ``found``'s columns at least
    FAR_TOP_SURE with its lens at most UNDER_MAX_CAMERA_HEIGHT_M up, and at least
    FAR_TOP_RATIO times ``found``'s confidence. A face read far the surer up to a top far
    higher is the one surface; a top a few rows up on what stands behind is no such move."""
    if found.box_px is None or grown.box_px is None:
        return False
    _, y0, _, y1 = found.box_px
    _, gy0, _, gy1 = grown.box_px
    conf = found.confidence or 0.0
    return (
        abs(gy1 - y1) <= ROW_JITTER_PX
        and y0 - gy0 >= FAR_TOP_SHARE * (y1 - y0)
        and y0 - gy0 > ROW_JITTER_PX
        and conf < FAR_TOP_MAX_FOUND_CONFIDENCE
        and (grown.confidence or 0.0) >= FAR_TOP_RATIO * conf
        and _rows_face_on_columns(found.box_px, grown, FAR_TOP_SURE)
    )


def _axis_face_beside(
    found: Measurement, grown: Measurement, u_axis: float, mount_px: float = 0.0
) -> bool:
    """Whether ``grown`` (the rows' face read as with a rig) is the face the sonar ranged
    and ``found`` a face beside it: ``found``'s columns leave the beam's axis column
    ``u_axis`` out by more than ROW_JITTER_PX + ``mount_px`` (the columns the axis may
    stand on with the sonar's mounting unknown, BEAM_MOUNT_ALLOWANCE_M at the face's depth:
    a face beside Rig()'s axis by less may be on the sonar's), ``grown``'s take ``u_axis``
    in by more than ROW_JITTER_PX, and
    ``grown`` is surer than ``found`` (raw confidences, both under their own doubts), at
    least UNDER_SURE, its lens at most UNDER_MAX_CAMERA_HEIGHT_M up. The sonar ranges what
    its axis hits; the obstacle stands across it, and a patch the trials stood beside it
    (a skirting's stretch, a mark on the floor) is not what was ranged."""
    if found.box_px is None or grown.box_px is None:
        return False
    x0, _, x1, _ = found.box_px
    g0, _, g1, _ = grown.box_px
    off = x0 - u_axis > ROW_JITTER_PX + mount_px or u_axis - x1 > ROW_JITTER_PX + mount_px
    on = u_axis - g0 > ROW_JITTER_PX and g1 - u_axis > ROW_JITTER_PX
    conf = grown.confidence or 0.0
    return (
        off
        and on
        and conf > (found.confidence or 0.0)
        and conf >= UNDER_SURE
        and (grown.camera_height_m or math.inf) <= UNDER_MAX_CAMERA_HEIGHT_M
    )


def _on_found(found: Measurement, again: Measurement) -> bool:
    """Whether a second reading ``again`` stands on ``found``'s foot (within AGAIN_FOOT_ROWS)
    between its sides (overlapping the narrower by AGAIN_SIDES_SHARE), doubting its sides
    no more than ``found`` (AGAIN_SIDES_DOUBTED): the same face, its top aside."""
    if found.box_px is None or again.box_px is None:
        return False
    x0, _, x1, y1 = found.box_px
    a0, _, a1, b1 = again.box_px
    overlap = min(x1, a1) - max(x0, a0)
    return (
        abs(b1 - y1) <= AGAIN_FOOT_ROWS
        and overlap >= AGAIN_SIDES_SHARE * min(x1 - x0, a1 - a0)
        and not AGAIN_SIDES_DOUBTED.intersection(again.doubts).difference(found.doubts)
    )


def _encloses_print(found: Measurement, again: Measurement) -> bool:
    """Whether ``again`` (the found face read once more with its estimated rig taken as
    known) is the surface a print ``found`` lies on: a print lies inside its face, so the
    face's outline encloses it on all four sides (its sides outside both of ``found``'s,
    its top above), a print covers most of it (``found`` at least AGAIN_ENCLOSE_WIDTH_SHARE
    of ``again``'s width: a patch of the floor or the wall is no face's print), and the
    print's lower edge stands above the face's floor contact
    (``again``'s foot under ``found``'s by more than AGAIN_FOOT_ROWS, the same foot's
    jitter, and by at most AGAIN_ENCLOSE_FOOT_SHARE of ``again``'s height: a print's lower
    margin), ``again`` AGAIN_TALLER times as high and doubting its sides no more
    (AGAIN_SIDES_DOUBTED). Whatever the confidences: the print's piece, plain or edged by
    the picture, is read surer than the face it covers. A reading on the found foot itself
    gives no such evidence (a top walked up into what stands behind is as tall), nor does
    one doubting its top band where ``found`` does not (AGAIN_ENCLOSE_ONE_SURFACE: the
    face a print lies on is one surface, its margin above the print as below)."""
    if found.box_px is None or again.box_px is None:
        return False
    x0, y0, x1, y1 = found.box_px
    a0, b0, a1, b1 = again.box_px
    return (
        a0 < x0
        and a1 > x1
        and b0 < y0
        and x1 - x0 >= AGAIN_ENCLOSE_WIDTH_SHARE * (a1 - a0)
        and AGAIN_FOOT_ROWS < b1 - y1 <= AGAIN_ENCLOSE_FOOT_SHARE * (b1 - b0)
        and (again.height_px or 0.0) >= AGAIN_TALLER * (found.height_px or 0.0)
        and not AGAIN_SIDES_DOUBTED.intersection(again.doubts).difference(found.doubts)
        and not (
            AGAIN_ENCLOSE_ONE_SURFACE
            and TOP_BAND_UNLIKE_FACE in again.doubts
            and TOP_BAND_UNLIKE_FACE not in found.doubts
        )
    )


def _top_above_lens(found: Measurement, again: Measurement) -> bool:
    """Whether ``again`` (the found face read once more with its estimated rig taken as
    known, on its foot and between its sides) is the face whose top ``found`` cut short:
    ``found``'s top is in doubt (TOP_DOUBTS: another edge under it, or the top put where
    the sides end), it stands higher than the lens the search estimated (a face taller
    than the lens shows no top face, so nothing above its front top edge is a top face's
    back edge), and ``again`` reaches at least AGAIN_ABOVE_LENS_TALLER times as high. The
    band between the two tops is then the face's own (a print's margin above the print),
    whatever the two readings' confidences: a face of the box's own colour round a
    print is as sure read whole as cut at the print's upper edge."""
    lens = found.camera_height_m
    return (
        bool(TOP_DOUBTS.intersection(found.doubts))
        and lens is not None
        and (found.height_m or 0.0) > lens
        and (again.height_px or 0.0) >= AGAIN_ABOVE_LENS_TALLER * (found.height_px or 0.0)
    )


def _reread_confirms(found: Measurement, again: Measurement) -> bool:
    """Whether ``again`` (``found``, a face read at a guessed pitch, read once more at the
    pitch its sides gave) confirms that pitch: the same outline, near enough (boxes
    overlapping by SAME_FACE_IOU or more: a foot or a top a few rows off is that face read
    better), or a surer face (the levelled view is the lens's geometry as the sides read
    it); always with REREAD_PITCH_SAME_FACE off."""
    if not REREAD_PITCH_SAME_FACE or _iou(found.box_px, again.box_px) >= SAME_FACE_IOU:
        return True
    return (again.confidence or 0.0) > (found.confidence or 0.0)


def _obstacle_size(found: Measurement) -> bool:
    """Whether a reading's face is one the sonar's beam sees as one obstacle's face: no
    taller and no wider than RAISED_FACE_MAX_M at the sonar's depth (KNOWN_RIG_SIZE_BOUND;
    always with it off)."""
    if not KNOWN_RIG_SIZE_BOUND:
        return True
    return all(s is None or s <= RAISED_FACE_MAX_M for s in (found.height_m, found.width_m))


def _same_face(
    box: tuple[float, float, float, float] | None,
    other: tuple[float, float, float, float] | None,
) -> bool:
    """Whether two no-rig trials' face boxes (input pixels) are one face on one foot: they
    overlap by SAME_FACE_IOU or more and their feet lie within ROW_JITTER_PX rows (another
    guess of the pitch on the same floor-contact row, not a face standing on another)."""
    return (
        box is not None
        and other is not None
        and _iou(box, other) >= SAME_FACE_IOU
        and abs(box[3] - other[3]) <= ROW_JITTER_PX
    )


def _iou(
    box: tuple[float, float, float, float] | None,
    other: tuple[float, float, float, float] | None,
) -> float:
    """Intersection over union of two boxes (x0, y0, x1, y1); 0 when either is unknown."""
    if box is None or other is None:
        return 0.0
    wide = min(box[2], other[2]) - max(box[0], other[0])
    tall = min(box[3], other[3]) - max(box[1], other[1])
    inter = max(0.0, wide) * max(0.0, tall)
    union = (box[2] - box[0]) * (box[3] - box[1]) + (other[2] - other[0]) * (other[3] - other[1])
    return inter / (union - inter) if union - inter > 0 else 0.0


def _beside(
    box: tuple[float, float, float, float] | None,
    other: tuple[float, float, float, float] | None,
) -> bool:
    """Whether two face boxes (input pixels) share under RIVAL_SHARED_WIDTH of the narrower
    one's columns: another face beside it, not the same face read with another guess of
    the rig (a guessed pitch or camera height moves a face's top and foot, not its sides).
    False when either box is unknown."""
    if box is None or other is None:
        return False
    narrower = min(box[2] - box[0], other[2] - other[0])
    shared = min(box[2], other[2]) - max(box[0], other[0])
    return narrower > 0 and shared < RIVAL_SHARED_WIDTH * narrower


def _robot_row(height: float, pitch_deg: float, depth: float) -> bool:
    """Whether the floor-contact row a no-rig trial's lens (``height`` metres up, pitched
    ``pitch_deg`` down) images at ``depth`` is one a robot's camera can see the floor
    contact on: some pitch within MAX_ESTIMATED_PITCH_DEG of level puts the lens at most
    UNDER_MAX_CAMERA_HEIGHT_M up (always, with ROW_FITS_ROBOT off). The row's angle below
    the optical axis of a level lens is fixed by the image; a lens looking up by the most
    pitch stands lowest for it (scale consistency: contact row = cy + fy h / D)."""
    if not ROW_FITS_ROBOT:
        return True
    below = math.atan2(height, depth) - math.radians(pitch_deg)  # the row's level angle
    lowest = depth * math.tan(below - math.radians(MAX_ESTIMATED_PITCH_DEG))
    return lowest <= UNDER_MAX_CAMERA_HEIGHT_M


def _robot_lens_reading(face: Measurement) -> bool:
    """Whether a reading of :meth:`Measurer._known_rig_row` was taken under a lens a robot
    carries: at most KNOWN_ROWS_MAX_LENS_M up, or a robot's highest lens plus the face's
    depth times the tangent of KNOWN_ROWS_UP_SLACK_DEG for a lens looking up past the
    steepest reading (KNOWN_ROWS_ROBOT_LENS)."""
    depth = face.distance_m or face.range_m or 0.0
    looking_up = KNOWN_ROWS_ROBOT_MAX_M + depth * math.tan(math.radians(KNOWN_ROWS_UP_SLACK_DEG))
    return (face.camera_height_m or math.inf) <= max(KNOWN_ROWS_MAX_LENS_M, looking_up)


def _robot_lens(height: float) -> bool:
    """Whether the camera height ``height`` (metres) a pitch read from the sides stands
    for is one a robot carries (at most UNDER_MAX_CAMERA_HEIGHT_M; any, with
    SIDES_PITCH_LENS_BOUND off)."""
    return not SIDES_PITCH_LENS_BOUND or height <= UNDER_MAX_CAMERA_HEIGHT_M


def _taller(
    box: tuple[float, float, float, float] | None,
    level: tuple[float, float, float, float] | None,
) -> bool:
    """Whether a face a swept pitch found (``box``, input pixels) stands over
    SWEPT_MAX_GROWTH times as tall as the level view's face on the same row (``level``):
    not that face read again (a guessed pitch shows or hides a box's top face, a band a
    fraction of the face's height) but the face with something above it taken in (a print
    or a panel on the wall behind, in line with its sides). False when either is unknown."""
    if box is None or level is None:
        return False
    return box[3] - box[1] > SWEPT_MAX_GROWTH * (level[3] - level[1])


def _top_moved(
    box: tuple[float, float, float, float] | None,
    again: tuple[float, float, float, float] | None,
) -> float | None:
    """How many rows ``again``'s top lies above ``box``'s (negative: below) when the two
    boxes (input pixels) are one face with its top moved: feet within ROW_JITTER_PX rows,
    each side within TOP_FACE_SIDES_PX columns, the top more than TOP_FACE_MOVE_PX rows
    off; else None."""
    if box is None or again is None or abs(box[3] - again[3]) > ROW_JITTER_PX:
        return None
    if abs(box[0] - again[0]) > TOP_FACE_SIDES_PX or abs(box[2] - again[2]) > TOP_FACE_SIDES_PX:
        return None
    moved = box[1] - again[1]
    return moved if abs(moved) > TOP_FACE_MOVE_PX else None


def _top_face_too_deep(best: Measurement, again: Measurement, view: View, range_m: float) -> bool:
    """Whether ``again``'s lowered top cannot be the front edge of a top face whose back
    edge is ``best``'s top: at the steepest pitch the lens may have (the guessed pitch,
    ``best``'s, plus UNREAD_PITCH_DOWN_DEG, no steeper than stands the lens
    UNDER_MAX_CAMERA_HEIGHT_M up over ``best``'s foot row at ``range_m``), the back edge
    lies on or above the horizon, or more than MAX_TOP_FACE_DEPTH_M behind the front
    (the front at ``range_m``). A steeper pitch brings the back edge nearer, so no pitch
    allowed makes the two tops one top face. The boxes are input pixels: their rows, at
    each box's middle column, are taken into the pitch-0 (undistorted) view the pitch
    and the lens's height are reckoned in. False where a box is missing."""
    box, low = best.box_px, again.box_px
    if box is None or low is None:
        return False
    mid, low_mid = 0.5 * (box[0] + box[2]), 0.5 * (low[0] + low[2])
    seen = view.camera.undistort_points([[mid, box[3]], [mid, box[1]], [low_mid, low[1]]])
    foot, back, front = (float(r) for r in seen[:, 1])
    lens_bound = pitch_for_row(foot, range_m, UNDER_MAX_CAMERA_HEIGHT_M, view.fy, view.cy)
    pitch = min((best.camera_pitch_deg or 0.0) + UNREAD_PITCH_DOWN_DEG, lens_bound)
    # the lens's height over the top face's plane were each edge at range_m: the back
    # edge lies as many times farther than the front as the front's height is the back's
    over_back = camera_height_for_row(back, range_m, pitch, view.fy, view.cy)
    if over_back <= 0.0:
        return True
    over_front = camera_height_for_row(front, range_m, pitch, view.fy, view.cy)
    return range_m * (over_front / over_back - 1.0) > MAX_TOP_FACE_DEPTH_M


def _small(found: Measurement) -> bool:
    """Whether a no-rig trial's face is small: its pixel factor (the product of its
    height and width in pixels, each over SMALL_FACE_PX, at most 1) under SMALL_SHARE."""
    return found.detected and pixel_factor(found.height_px, found.width_px) < SMALL_SHARE


def _repeated_face(faces: list[Measurement]) -> Measurement | None:
    """The surest of ``faces`` (the sweep's unsure trials standing on their own feet) that
    at least REPEATED_FACE_TRIALS of them find (itself counted; :func:`_same_face`: one
    box on one foot), else None."""
    for face in sorted(faces, key=lambda f: f.confidence or 0.0, reverse=True):
        same = [f for f in faces if _same_face(face.box_px, f.box_px)]
        pitches = {f.camera_pitch_deg for f in same}
        if len(same) >= REPEATED_FACE_TRIALS and len(pitches) >= REPEATED_FACE_PITCHES:
            return face
    return None


def _swept_over(best: Measurement | None, swept: Measurement, read: bool) -> bool:
    """Whether the last-resort sweep's face ``swept`` (its sides reading the pitch:
    ``read``) is taken over ``best``, the search's face so far. With no face, any; over an
    unsure face (under ESTIMATE_ACCEPT), only another face above it (the unsure face's
    box wholly below the swept face's foot) whose own sides read the pitch, of at least
    SWEPT_OVER_UNSURE, or the unsure face read again on its own foot with its doubted top
    right (:func:`_swept_top_over`). On a coarse floor (gravel near the lens) the band's
    lowest steps are the floor's texture and the unsure face one of its stones in front of
    the obstacle, while the obstacle's foot, farther up, was never among the rows tried (a
    lens pitched up puts it above them); a face sure there, whose sides agree on a pitch,
    is the obstacle. The same face read at a swept pitch (its top not doubted), or a
    weaker or unconfirmed sweep's face, is no better than the unsure one (on the tuning
    rooms most unsure faces were within 10 %, and the sweep's faces over them worse)."""
    if best is None or not best.detected:
        return True
    if _swept_top_over(best, swept, read):
        return True
    return (
        read
        and (swept.confidence or 0.0) >= SWEPT_OVER_UNSURE
        and best.box_px is not None
        and swept.box_px is not None
        and best.box_px[1] >= swept.box_px[3]
    )


def _swept_whole(
    best: Measurement | None, swept: Measurement, read: bool, image: npt.NDArray[Any]
) -> bool:
    """Whether the last-resort sweep's face ``swept``, its sides reading the pitch it was
    levelled at (``read``) and sure (ESTIMATE_ACCEPT), is the unsure face ``best`` seen
    whole: standing on the same foot (feet under MIN_NEARER_DROP_PX apart), between the
    same sides (each within OUTLINE_MATCH of ``best``'s width, at least OUTLINE_MATCH_PX),
    over SWEPT_MAX_GROWTH times as tall (:func:`_taller`), its own sides running on above
    ``best``'s top (:func:`sides_run_up`). A face stands on one foot between its two
    sides, and ends where they end: the unsure face's top, below that, is a line across
    the face (a panel joint, a band's edge) that the level guess of the camera height
    stood its top on. Photo/2091 o: a panelled face, the lens looking up 3.8 degrees; the
    level rows stood only a strip of its lower panels (-74 %), the sweep read the whole
    face at -3.9 degrees (0.4 %); on its own foot, not above the strip, so
    :func:`_swept_over` did not take it."""
    if not (read and best is not None and best.detected):
        return False
    low, whole = best.box_px, swept.box_px
    if low is None or whole is None:
        return False
    tol = max(OUTLINE_MATCH_PX, OUTLINE_MATCH * (low[2] - low[0]))
    return (
        (swept.confidence or 0.0) >= ESTIMATE_ACCEPT
        and abs(low[3] - whole[3]) < MIN_NEARER_DROP_PX
        and abs(low[0] - whole[0]) <= tol
        and abs(low[2] - whole[2]) <= tol
        and _taller(whole, low)
        and sides_run_up(image, swept.lines, low[1])
    )


def _swept_top_over(best: Measurement, swept: Measurement, read: bool) -> bool:
    """Whether the sweep's face ``swept`` is the unsure face ``best`` read again with its
    top right: standing on the same foot (feet under MIN_NEARER_DROP_PX apart), its sides
    reading the pitch it was levelled at (``read``), and sure (ESTIMATE_ACCEPT, as every
    sweep's face), while ``best``'s top edge carries a doubt of TOP_EDGE_DOUBTS and
    ``swept``'s none. The foot is the same edge at any pitch; the top is sought above it
    in the view levelled for the guessed pitch, and a lens pitched a few degrees off level
    moves where the face's top is sought (the band above the foot the view allows), so the
    level reading may stop at a line of the background (one running on beside the face)
    or a band inside the face (an edge just under the top): the outline doubts it itself.
    The reading whose own sides agree with its pitch, finding a top nothing doubts, is
    the face seen in its true geometry (photo/1411 o: the level face stopped at a line of
    the wall, -31 %; the sweep's at -4.6 degrees, its sides confirming, 0.4 %). An unsure
    face with a clear top keeps it (on the tuning rooms the same face read again by the
    sweep was worse: procedural/1007 o 0.9 -> 8.8 %, and fresh 1461 o 0.4 -> -55 %)."""
    if not (read and best.box_px is not None and swept.box_px is not None):
        return False
    return (
        (swept.confidence or 0.0) >= ESTIMATE_ACCEPT
        and abs(best.box_px[3] - swept.box_px[3]) < MIN_NEARER_DROP_PX
        and _top_doubt_cleared(best, swept)
    )


def _refused(result: Measurement, range_m: float, row: float | None, reason: str) -> Measurement:
    """A no-rig trial's face refused for ``reason``: logged, and no face for the search."""
    log.debug(
        "no rig: row %.0f: %s, box %s, h %s, w %s, conf %.2f",
        row if row is not None else -1.0,
        reason,
        result.box_px,
        result.height_m,
        result.width_m,
        result.confidence or 0.0,
    )
    return Measurement(False, result.method, range_m, confidence=result.confidence, reason=reason)


def _wall_band(found: Measurement) -> bool:
    """Whether a face found with no rig is a band along the wall rather than an obstacle's
    face: its box under BAND_MAX_ASPECT as tall as wide (a wall's foot, a skirting board or a
    floor board's edge standing on a row guessed for the floor contact reads as a long low
    strip; an obstacle the sonar's beam sees stands taller for its width)."""
    if not found.detected or found.box_px is None:
        return False
    x0, y0, x1, y1 = found.box_px
    return x1 > x0 and (y1 - y0) < BAND_MAX_ASPECT * (x1 - x0)


def _band_on_floor(image: npt.NDArray[Any], band: tuple[float, float, float, float]) -> bool:
    """Whether a band a no-rig trial found (input pixel box ``band``) lies on the floor:
    the strips just above and just below it (BAND_FLOOR_ROWS past its edges) both within
    BAND_FLOOR_MATCH (median Lab) of the floor at the image's foot (BAND_FLOOR_FOOT_ROWS,
    the band's columns). A band along the wall (its foot, a skirting) has the wall above
    it; a shade on the floor has the floor on both sides. A grey image, a band at the
    image's foot or a strip with no pixel: False (the band kept)."""
    if image.ndim != 3:
        return False
    h = image.shape[0]
    x0, y0, x1, y1 = band
    a, b = BAND_FLOOR_ROWS
    if y1 + b > h - BAND_FLOOR_FOOT_ROWS:
        return False
    floor = _median_lab(image, h - BAND_FLOOR_FOOT_ROWS, h, x0, x1)
    above = _median_lab(image, y0 - b, y0 - a, x0, x1)
    below = _median_lab(image, y1 + a, y1 + b, x0, x1)
    if floor is None or above is None or below is None:
        return False
    return all(float(np.linalg.norm(p - floor)) <= BAND_FLOOR_MATCH for p in (above, below))


def _median_lab(
    image: npt.NDArray[Any], y0: float, y1: float, x0: float, x1: float
) -> npt.NDArray[np.float32] | None:
    """The median Lab colour (8-bit) of a box of the image, clipped to it; None if empty."""
    h, w = image.shape[:2]
    r0, r1 = max(0, int(y0)), min(h, int(y1))
    c0, c1 = max(0, int(x0)), min(w, int(x1))
    if r1 <= r0 or c1 <= c0:
        return None
    lab = cv2.cvtColor(np.ascontiguousarray(image[r0:r1, c0:c1]), cv2.COLOR_BGR2Lab)
    return np.median(lab.reshape(-1, 3).astype(np.float32), axis=0).astype(np.float32)


def _in_wall_band(
    box: tuple[float, float, float, float] | None,
    bands: list[tuple[float, float, float, float]],
) -> bool:
    """Whether a face found with no rig stands in a band along the wall another trial
    found (``bands``, input pixel boxes): its foot inside the band's rows (over
    BAND_FOOT_MARGIN_PX above the band's lower edge, and not above its upper edge by more
    than that), and the two sharing at least BAND_SHARED_WIDTH of the narrower one's
    columns. A wall's foot or skirting band lies farther than the obstacle the sonar sees,
    so higher in the image than that obstacle's foot: a face whose foot ends inside it
    is on the wall (a poster, a print, something farther back standing on it), and its
    size taken at the sonar's range is several times too large. A band wholly below the
    face's foot (a floor line before it), or one under the whole face and centred on it
    (its contact shadow: covering SHADOW_COVER of the face's columns, its centre within
    SHADOW_CENTRE_SHARE of the face's width from the face's), says nothing of it."""
    if box is None:
        return False
    for band in bands:
        width = box[2] - box[0]
        narrower = min(width, band[2] - band[0])
        shared = min(box[2], band[2]) - max(box[0], band[0])
        shadow = (
            shared >= SHADOW_COVER * width
            and abs((band[0] + band[2]) - (box[0] + box[2])) / 2.0 <= SHADOW_CENTRE_SHARE * width
        )
        if (
            narrower > 0
            and not shadow
            and shared >= BAND_SHARED_WIDTH * narrower
            and band[1] - BAND_FOOT_MARGIN_PX <= box[3] < band[3] - BAND_FOOT_MARGIN_PX
        ):
            return True
    return False


def accepted_face(result: Measurement) -> bool:
    """Whether a no-rig trial found a face of at least ESTIMATE_ACCEPT."""
    return result.detected and (result.confidence or 0.0) >= ESTIMATE_ACCEPT


def _spans(
    upper: tuple[float, float, float, float] | None,
    lower: tuple[float, float, float, float] | None,
) -> bool:
    """Whether a face box is a strip along the wall behind a lower one: under
    STRIP_MAX_ASPECT as tall as wide, spanning the lower box's columns and at least
    SPAN_FACTOR times as wide (input pixel boxes x0, y0, x1, y1)."""
    if upper is None or lower is None:
        return False
    return (
        upper[3] - upper[1] < STRIP_MAX_ASPECT * (upper[2] - upper[0])
        and upper[0] <= lower[0]
        and upper[2] >= lower[2]
        and upper[2] - upper[0] >= SPAN_FACTOR * (lower[2] - lower[0])
    )


def _stands_on_top(
    upper: tuple[float, float, float, float] | None,
    lower: tuple[float, float, float, float] | None,
) -> bool:
    """Whether a face box stands on the top of a lower one (input pixel boxes x0, y0, x1,
    y1): its foot at most ON_TOP_BELOW_PX under the lower box's top and no more than
    ON_TOP_ABOVE of the lower box's height above it (the top surface seen from above, the
    upper thing set back on it or behind it), its columns within the lower box's (to
    ROW_JITTER_PX), the lower box at least ON_TOP_WIDER times as wide and no strip (at
    least STRIP_MAX_ASPECT as tall as wide: not a shadow or a floor mark before the
    upper face, nor its reflection on a glossy floor, as wide as the face)."""
    if upper is None or lower is None:
        return False
    low_w = lower[2] - lower[0]
    low_h = lower[3] - lower[1]
    return (
        low_h >= STRIP_MAX_ASPECT * low_w
        and low_w >= ON_TOP_WIDER * (upper[2] - upper[0])
        and upper[0] >= lower[0] - ROW_JITTER_PX
        and upper[2] <= lower[2] + ROW_JITTER_PX
        and lower[1] - ON_TOP_ABOVE * low_h <= upper[3] <= lower[1] + ON_TOP_BELOW_PX
    )


def _same_outline(
    upper: tuple[float, float, float, float],
    lower: tuple[float, float, float, float] | None,
) -> bool:
    """Whether a face box found on a higher row is the upper part of one found on a lower
    row (input pixel boxes x0, y0, x1, y1): its top and both sides within OUTLINE_MATCH of
    its width (at least OUTLINE_MATCH_PX) of the lower box's, and the lower foot at least
    OUTLINE_MIN_DROP_PX lower. A face is bounded by its sides and top; a line across it
    ends neither, while another object standing on the floor nearer or farther would not
    share all three."""
    if lower is None:
        return False
    tol = max(OUTLINE_MATCH_PX, OUTLINE_MATCH * (upper[2] - upper[0]))
    return (
        abs(upper[0] - lower[0]) <= tol
        and abs(upper[2] - lower[2]) <= tol
        and abs(upper[1] - lower[1]) <= tol
        and lower[3] >= upper[3] + OUTLINE_MIN_DROP_PX
    )


def _print_line_foot(image: npt.NDArray[Any], upper: Measurement, lower: Measurement) -> bool:
    """Whether the face ``upper`` (accepted on a higher tried row) stands on a line of its
    own print and ``lower`` (found on a lower row, not accepted) is the same face on its
    floor contact: their tops within OUTLINE_MATCH of the upper face's width (at least
    OUTLINE_MATCH_PX), the lower face of full size (not :func:`_small`), and the print's
    texture running on between the two feet (:func:`print_runs_below`)."""
    up, low = upper.box_px, lower.box_px
    if up is None or low is None or _small(lower):
        return False
    tol = max(OUTLINE_MATCH_PX, OUTLINE_MATCH * (up[2] - up[0]))
    return abs(up[1] - low[1]) <= tol and print_runs_below(image, up, low)


def _band_across(
    band: tuple[float, float, float, float], face: tuple[float, float, float, float]
) -> bool:
    """Whether the face found ``band`` (input pixel boxes x0, y0, x1, y1) is a band running
    across a nearer, taller face ``face`` (a wall's band, a skirting, a poster's strip seen
    on both sides of the box in front of it): ``band`` reaches past both of ``face``'s
    sides, and ``face`` rises above its top and stands below its foot, ACROSS_TALLER times
    as tall or more. Across the nearer face's columns the band is that face's own surface,
    so no face stands there but the nearer one."""
    return (
        band[0] <= face[0]
        and band[2] >= face[2]
        and face[1] < band[1]
        and face[3] > band[3]
        and face[3] - face[1] >= ACROSS_TALLER * (band[3] - band[1])
    )


def _frame_holds(outer: Measurement, inner: Measurement) -> bool:
    """Whether ``outer`` (a no-rig trial's face on a row next to ``inner``'s) holds
    ``inner`` as a face holds a framed print: a margin of one colour was seen round
    ``inner`` (FRAMED), ``outer``'s foot more than ROW_JITTER_PX rows lower, each of its
    sides more than ROW_JITTER_PX columns outside ``inner``'s, its top no more than
    ROW_JITTER_PX rows under ``inner``'s, and it found at least JITTER_FRAME_SURE. The face
    is the outermost surface at the sonar's depth standing on the floor; a box inside it
    whose foot ends above its foot is a print on it, its lower edge taken for the contact
    (procedural 3189, photo 3157 hard). A frame is a ring: its margin over the print is
    at most JITTER_FRAME_TOP_SHARE times its wider side margin (a box reaching farther up
    took in what stands over the face: photo 969 o, 31 rows over against 7 and 20 beside,
    +21 %)."""
    if outer.box_px is None or inner.box_px is None or not outer.detected:
        return False
    if FRAMED not in inner.doubts:
        # (a margin seen round the outer face only is no print inside it: photo 969 o's
        # face, held by a box reaching 31 rows over it on its contact shadow, +21 %)
        return False
    x0, y0, x1, _ = inner.box_px
    g0, gy0, g1, _ = outer.box_px
    return (
        _box_round(outer.box_px, inner.box_px)
        and y0 - gy0 <= JITTER_FRAME_TOP_SHARE * max(x0 - g0, g1 - x1)
        and (outer.confidence or 0.0) >= JITTER_FRAME_SURE
    )


def _foot_weighed(found: Measurement, other: Measurement | None = None) -> float:
    """A trial's face's confidence cut by DOUBT_FACTOR for each of its FOOT_DOUBTS (its
    foot off the floor, or floor taken into it): how surely it stands on the row tried,
    to compare the faces a row and its neighbours stand (JITTER_WEIGHS_FOOT); and for its
    foot standing above its own row (FOOT_ABOVE_CONTACT) where ``other``, the face it is
    weighed against, holds it standing lower (:func:`_holds_above`,
    JITTER_FOOT_ABOVE_WEIGHED)."""
    conf = found.confidence or 0.0
    if not JITTER_WEIGHS_FOOT:
        return conf
    doubts = set(FOOT_DOUBTS)
    if JITTER_FOOT_ABOVE_WEIGHED and other is not None and _holds_above(other, found):
        doubts.add(FOOT_ABOVE_CONTACT)
    return conf * DOUBT_FACTOR ** len(doubts.intersection(found.doubts))


def _holds_above(outer: Measurement, inner: Measurement) -> bool:
    """Whether ``outer`` (a no-rig trial's face on a row next to ``inner``'s) holds
    ``inner`` as a face holds a print on it: its foot more than ROW_JITTER_PX rows lower,
    its top no more than ROW_JITTER_PX rows under ``inner``'s, neither side more than
    ROW_JITTER_PX columns inside ``inner``'s, and reaching past ``inner`` by more than
    ROW_JITTER_PX over its top or beside one of its sides (not the same face with only its
    foot moved: a shadow's or a bevel's lower edge under it). The tolerance is the rows'
    own step, as in :func:`_box_round` and :func:`_frame_holds`: the two faces were stood
    on rows ROW_JITTER_PX apart, so a foot that moved no more than that is the one foot
    read from the moved row, and the top and sides the same edges read again."""
    if outer.box_px is None or inner.box_px is None or not outer.detected:
        return False
    x0, y0, x1, y1 = inner.box_px
    g0, gy0, g1, gy1 = outer.box_px
    j = ROW_JITTER_PX
    return (
        gy1 - y1 > j
        and _holds(outer.box_px, inner.box_px, j)
        and max(y0 - gy0, x0 - g0, g1 - x1) > j
    )


def _levelled_taken(found: Measurement, levelled: Measurement) -> bool:
    """Whether the face found in the view levelled for the pitch the sides read
    (``levelled``), disagreeing with the pitch-0 face ``found`` on its size, is taken over
    it: surer as measured, or (LEVELLED_LESS_DOUBTED) standing on ``found``'s foot (within
    ROW_JITTER_PX) and surer by more than LEVELLED_DOUBTED_MARGIN with each face's doubts
    applied (:func:`_doubted`). The pitch read and ``found``'s foot row give the camera
    height: a levelled face on another foot is not that surface read again."""
    if (levelled.confidence or 0.0) > (found.confidence or 0.0):
        return not (LEVELLED_PRINT_REFUSED and _print_on_face(levelled, found))
    return (
        LEVELLED_LESS_DOUBTED
        and found.box_px is not None
        and levelled.box_px is not None
        and abs(levelled.box_px[3] - found.box_px[3]) <= ROW_JITTER_PX
        and not (LEVELLED_NOT_INSIDE and _inside_both_sides(levelled.box_px, found.box_px))
        and _doubted(levelled) > _doubted(found) + LEVELLED_DOUBTED_MARGIN
    )


def _print_on_face(levelled: Measurement, found: Measurement) -> bool:
    """Whether ``levelled`` lies on ``found`` as a print on its face: on ``found``'s foot
    (within ROW_JITTER_PX), both sides and its top inside ``found``'s, each by over
    ROW_JITTER_PX. A pitch changes a face's metres, not its outline; a smaller outline
    inside the face on three sides is a print's (a margin of the face round it)."""
    if levelled.box_px is None or found.box_px is None:
        return False
    return (
        abs(levelled.box_px[3] - found.box_px[3]) <= ROW_JITTER_PX
        and levelled.box_px[1] > found.box_px[1] + ROW_JITTER_PX
        and _inside_both_sides(levelled.box_px, found.box_px)
    )


def _inside_both_sides(
    inner: tuple[float, float, float, float], outer: tuple[float, float, float, float]
) -> bool:
    """Whether ``inner``'s sides both stand inside ``outer``'s, each by over ROW_JITTER_PX
    (a print on a face, not the face read again)."""
    return inner[0] > outer[0] + ROW_JITTER_PX and inner[2] < outer[2] - ROW_JITTER_PX


def _doubted(found: Measurement, ignore: frozenset[str] = frozenset()) -> float:
    """A face's confidence with its doubts (but those in ``ignore``) applied, unfloored, to
    compare two trials."""
    doubts = [d for d in found.doubts if d not in ignore]
    return reported_confidence(
        found.confidence or 0.0, doubts, found.height_px, found.width_px, 0.0, False
    )[0]


def clipped_sides(
    box: tuple[float, float, float, float] | None, width: int, height: int
) -> list[str]:
    """The image borders a face box touches: its size there is a lower bound."""
    if box is None:
        return []
    x0, y0, x1, y1 = box
    sides = []
    if x0 <= CLIP_MARGIN_PX:
        sides.append("left")
    if x1 >= width - 1 - CLIP_MARGIN_PX:
        sides.append("right")
    if y0 <= CLIP_MARGIN_PX:
        sides.append("top")
    if y1 >= height - 1 - CLIP_MARGIN_PX:
        sides.append("bottom")
    return sides
