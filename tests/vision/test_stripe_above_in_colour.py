"""A stripe across the face counts only where the face's colour is back above it
(scoring.STRIPE_ABOVE_IN_COLOUR, scoring.stripe_in_colour, wired in score_pairs)."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import scoring
from obstacle_fusion.vision.fused.scoring import (
    STRIPE_CHROMA_STEP,
    STRIPE_PLAIN_TEXTURE,
    STRIPE_SIDES_STOP,
    stripe_in_colour,
)

from tests.vision_fixtures import LOW_CY, low_box_view, measured_room

#: A synthetic pair (ul, ur, inner columns) over rows 0..RB-1: the face near the floor
#: has chroma FACE_AB; the rows above the top candidate TOP (ABOVE rows) another chroma.
RB, TOP, KF = 60, 40, 4
PAIR = (10, 50, 15, 45)
FACE_AB = (150, 128)


def lab_with_above(shift: int) -> npt.NDArray[np.uint8]:
    """Lab rows 0..RB-1: the face's chroma, but ``shift`` more in a over the rows above TOP."""
    lab = np.zeros((RB, 64, 3), np.uint8)
    lab[..., 0] = 120
    lab[..., 1], lab[..., 2] = FACE_AB
    lab[:TOP, :, 1] = FACE_AB[0] + shift
    return lab


def capped(
    shift: int, face_above: float = 0.7, top: int = TOP, stop: float = 1.0, textured: float = 0.0
) -> float:
    """The stripe share :func:`stripe_in_colour` leaves of ``face_above`` at ``top``
    (the view's horizon at row LOW_CY)."""
    lab = lab_with_above(shift)

    def lab_rows(r0: int, r1: int) -> npt.NDArray[np.uint8]:
        return lab[r0:r1]

    out = stripe_in_colour(
        low_box_view(),
        lab_rows,
        [PAIR],
        np.array([top], np.intp),
        np.array([0], np.intp),
        RB,
        KF,
        np.array([face_above]),
        np.array([stop]),
        np.array([textured]),
    )
    return float(out[0])


def test_the_face_colour_above_keeps_the_stripe() -> None:
    assert capped(0) == pytest.approx(0.7)


def test_another_colour_above_is_no_stripe() -> None:
    assert capped(40) == 0.0


def test_chroma_step_limit() -> None:
    # a step of exactly STRIPE_CHROMA_STEP is still the face's colour, one more is not
    assert STRIPE_CHROMA_STEP == 10.0
    assert capped(10) == pytest.approx(0.7)
    assert capped(11) == 0.0


def test_a_top_over_the_horizon_shows_no_top_face() -> None:
    # the lens looks up at a top on or over its horizon: no top face can make the band
    assert capped(40, top=int(LOW_CY)) == pytest.approx(0.7)
    assert capped(40, top=int(LOW_CY) + 1) == 0.0


def test_sides_stop_limit() -> None:
    # sides running on above the top (the face goes on): the grey's match is trusted
    assert STRIPE_SIDES_STOP == 0.9
    assert capped(40, stop=0.9) == 0.0
    assert capped(40, stop=0.89) == pytest.approx(0.7)


def test_plain_texture_limit() -> None:
    # a print's chroma varies over it: the colour speaks only for a plain face
    assert STRIPE_PLAIN_TEXTURE == 0.3
    assert capped(40, textured=0.29) == 0.0
    assert capped(40, textured=0.3) == pytest.approx(0.7)


def test_no_stripe_share_is_left_alone() -> None:
    assert capped(40, face_above=0.0) == 0.0


def test_grey_frame_reads_grey_alone() -> None:
    out = stripe_in_colour(
        low_box_view(),
        lambda r0, r1: None,
        [PAIR],
        np.array([TOP], np.intp),
        np.array([0], np.intp),
        RB,
        KF,
        np.array([0.7]),
        np.array([1.0]),
        np.array([0.0]),
    )
    assert float(out[0]) == pytest.approx(0.7)


def height_error(hard_rig: bool = True) -> float:
    res, truth = measured_room("photo", 3415, True, hard_rig)
    assert res.detected and res.height_m is not None
    return res.height_m / truth["height_m"] - 1.0


def test_photo_3415_box_before_a_wall_of_its_grey() -> None:
    # a purple box with a tape across it before a green wall of the purple's grey: the
    # band right above the true top is the box's top face, then the wall, not the box
    assert abs(height_error()) <= 0.05


def test_photo_3415_without_the_rule_takes_the_tape(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(scoring, "STRIPE_ABOVE_IN_COLOUR", False)
    assert height_error() < -0.5


def test_with_no_rig_the_stripe_is_read_in_grey(monkeypatch: pytest.MonkeyPatch) -> None:
    # a guessed pitch's horizon does not tell whether a top face can show over the top
    from obstacle_fusion.vision.fused import method as method_mod

    given: list[bool] = []
    original = method_mod.score_pairs

    def spy(*args: object) -> object:
        given.append(args[-1] is not None)
        return original(*args)  # type: ignore[arg-type]

    monkeypatch.setattr(method_mod, "score_pairs", spy)
    measured_room("photo", 3415, True, False)
    assert given and not any(given)
    given.clear()
    measured_room("photo", 3415, True, True)
    assert given and all(given)
