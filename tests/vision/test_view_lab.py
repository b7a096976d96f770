"""A view's Lab blocks of a held frame are the blocks converted one by one, never stale."""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import View


def pitched_view() -> View:
    """The paper's lens (distorted) pitched down: every block a real remap."""
    return View(CameraModel.paper(500, 375), Rig(camera_pitch_deg=6.0), "level")


def frame(seed: int) -> npt.NDArray[np.uint8]:
    rng = np.random.default_rng(seed)
    img = rng.integers(0, 256, (375, 500, 3), np.uint8)
    return np.asarray(cv2.GaussianBlur(img, (5, 5), 1.0), np.uint8)


def converted(view: View, img: npt.NDArray[np.uint8], *block: int | None) -> npt.NDArray[np.uint8]:
    """The block undistorted and converted on its own (what the stages read before)."""
    r0, r1, c0, c1, step = (*block, *(None,) * (5 - len(block)))[:5]
    rows, cols = slice(r0, r1, step or 1), slice(c0 or 0, c1, step or 1)
    band = cv2.remap(
        img, view.map1[rows, cols], view.map2[rows, cols], cv2.INTER_LINEAR,
        borderMode=cv2.BORDER_REPLICATE,
    )  # fmt: skip
    return np.asarray(cv2.cvtColor(band, cv2.COLOR_BGR2LAB))


BLOCKS = [
    (100, 140),  # rows across the view
    (110, 120, 200, 260),  # inside the rows before
    (100, 140, 0, 500),  # the same rows again
    (90, 130, 200, 260),  # overlapping, not inside
    (95, 125, 210, 230),  # inside the one before
    (300, 375, 480, 500),  # the corner
    (-20, -5, -30, -10),  # counted from the ends, as numpy's slices
    (120, 160, 150, 400, 3),  # every third row and column
]


def test_a_held_frame_s_blocks_are_each_block_converted_alone() -> None:
    view, img = pitched_view(), frame(1)
    view.hold_colour(img)
    for block in BLOCKS:
        got = view.lab(img, *block)
        want = converted(view, img, *block)
        assert got.shape == want.shape and got.dtype == np.uint8, block
        assert np.array_equal(got, want), block
    # an empty block is OpenCV's error, held or not, as before
    with pytest.raises(cv2.error):
        view.lab(img, 130, 130, 0, 10)
    view.hold_colour(None)
    with pytest.raises(cv2.error):
        view.lab(img, 130, 130, 0, 10)


def test_a_new_frame_or_none_held_is_read_afresh() -> None:
    """Each run holds its own frame: a frame changed in place (a camera's reused buffer)
    after its hold ended, or another frame, is converted anew."""
    view, img = pitched_view(), frame(2)
    view.hold_colour(img)
    first = view.lab(img, 100, 140).copy()
    view.hold_colour(None)
    img[:] = frame(3)
    assert np.array_equal(
        view.lab(img, 110, 120, 200, 260), converted(view, img, 110, 120, 200, 260)
    )
    view.hold_colour(img)
    assert not np.array_equal(view.lab(img, 100, 140), first)
    assert np.array_equal(
        view.lab(img, 110, 120, 200, 260), converted(view, img, 110, 120, 200, 260)
    )
    other = frame(4)  # a frame other than the held one is never read from its blocks
    assert np.array_equal(view.lab(other, 110, 120), converted(view, other, 110, 120))
    view.hold_colour(None)


def test_a_grey_frame_holds_nothing() -> None:
    view = pitched_view()
    grey = frame(5)[:, :, 0].copy()
    view.hold_colour(grey)
    assert view._held is None and view._lab_boxes == []


def test_a_reused_block_cannot_be_written_into_the_frames_cache() -> None:
    """A block of a held frame is a view of the frame's cache, converted in place there
    (the first one too) or taken from an earlier one: read-only, so a stage writing into
    it fails loudly instead of spoiling later blocks."""
    view, img = pitched_view(), frame(11)
    view.hold_colour(img)
    first = view.lab(img, 100, 140)
    assert not first.flags.writeable
    with pytest.raises(ValueError):
        first[:] = 0
    inside = view.lab(img, 110, 120, 200, 260)
    assert not inside.flags.writeable
    with pytest.raises(ValueError):
        inside[:] = 0
    np.testing.assert_array_equal(inside, converted(view, img, 110, 120, 200, 260))
    view.hold_colour(None)


#: Blocks overlapping earlier ones without lying inside any one of them (rows, columns).
OVERLAPS = [
    (100, 140, 100, 200),  # nothing before it
    (120, 160, 150, 250),  # its corner read before
    (110, 150, 120, 230),  # across both
    (90, 170, 90, 260),  # around all of them
    (100, 160, 100, 250),  # inside the union of those before, not inside one
    (0, 5, 490, 500),  # a corner of the view
    (2, 30, 480, 500),  # that corner again, and more
]


def test_an_overlapping_block_converts_only_what_no_block_before_covered(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Each pixel is converted once a frame (what the stages read overlaps by a third),
    and every block read is still the block converted alone."""
    view, img = pitched_view(), frame(21)
    pixels: list[int] = []
    lab_into = view._lab_into  # a held frame's pieces are converted in its buffer

    def counted(image: npt.NDArray[np.uint8], out: npt.NDArray[np.uint8], *box: int) -> None:
        lab_into(image, out, *box)
        pixels.append(out.shape[0] * out.shape[1])

    monkeypatch.setattr(view, "_lab_into", counted)
    view.hold_colour(img)
    seen = np.zeros(view.out.shape, bool)  # the view pixels read so far
    for r0, r1, c0, c1 in OVERLAPS:
        pixels.clear()
        got = view.lab(img, r0, r1, c0, c1)
        assert sum(pixels) == np.count_nonzero(~seen[r0:r1, c0:c1]), (r0, r1, c0, c1)
        seen[r0:r1, c0:c1] = True
        np.testing.assert_array_equal(got, converted(view, img, r0, r1, c0, c1))
    view.hold_colour(None)


def test_the_held_blocks_bookkeeping_in_c_is_the_python_one() -> None:
    """The accelerator's uncovered() gives uncovered_pieces' answers, pieces in the same
    order: no boxes, a block inside one box (the first, the last) or across several, on
    their edges exactly, beside them, covered whole by boxes together (no pieces), empty
    boxes; many boxes (its piece lists grow). Boxes that are not 4-tuples are its error."""
    from obstacle_fusion.vision.fused import _cmiddle
    from obstacle_fusion.vision.fused.method import _c_uncovered
    from obstacle_fusion.vision.types import uncovered_pieces

    assert _c_uncovered is not None, "the C accelerator is not built (make setup)"
    rng = np.random.default_rng(61)
    for _ in range(4000):
        boxes = []
        for _ in range(int(rng.integers(0, 40 if rng.random() < 0.1 else 12))):
            a, c = int(rng.integers(0, 60)), int(rng.integers(0, 80))
            boxes.append((a, int(rng.integers(a, 61)), c, int(rng.integers(c, 81))))
        ra, ca = int(rng.integers(0, 60)), int(rng.integers(0, 80))
        block = (ra, int(rng.integers(ra + 1, 61)), ca, int(rng.integers(ca + 1, 81)))
        assert _cmiddle.uncovered(boxes, *block) == uncovered_pieces(boxes, *block)
    halves = [(0, 10, 0, 5), (0, 10, 5, 10)]
    assert _cmiddle.uncovered(halves, 0, 10, 0, 10) == [] == uncovered_pieces(halves, 0, 10, 0, 10)
    assert _cmiddle.uncovered([], 1, 3, 2, 4) == [(1, 3, 2, 4)]
    assert _cmiddle.uncovered([(0, 9, 0, 9), (5, 6, 5, 6)], 1, 3, 2, 4) is None
    assert _cmiddle.uncovered([(0, 2, 0, 9)], 1, 3, 2, 4) == [(2, 3, 2, 4)]
    with pytest.raises(TypeError):
        _cmiddle.uncovered([[0, 2, 0, 9]], 1, 3, 2, 4)
    with pytest.raises(TypeError):
        _cmiddle.uncovered([(0, 2, 0)], 1, 3, 2, 4)


def test_a_view_with_the_c_bookkeeping_converts_the_same_blocks() -> None:
    """A view using the accelerator's bookkeeping gives each block a view of the frame's
    Lab pixels equal to the block converted alone, as the Python bookkeeping does."""
    from obstacle_fusion.vision.fused.method import _c_uncovered

    img = frame(3)
    for uncovered in (_c_uncovered, None):
        view = pitched_view()
        view.use_uncovered(uncovered)
        view.hold_colour(img)
        for block in BLOCKS:
            assert np.array_equal(view.lab(img, *block), converted(view, img, *block)), block
        view.hold_colour(None)
