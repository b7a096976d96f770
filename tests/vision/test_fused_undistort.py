"""The fused method's table remap gives OpenCV's remap of the levelled view, value for value."""

from __future__ import annotations

import cv2
import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.fused import undistort
from obstacle_fusion.vision.fused.undistort import TAB_BITS, TableRemap, _axis, remap_table
from obstacle_fusion.vision.rig import Rig
from obstacle_fusion.vision.types import View


def _opencv(view: View, src: npt.NDArray[np.uint8], rows: int) -> npt.NDArray[np.uint8]:
    return np.asarray(
        cv2.remap(
            src,
            view.map1[:rows],
            view.map2[:rows],
            cv2.INTER_LINEAR,
            borderMode=cv2.BORDER_REPLICATE,
        )
    )


def _frames(rng: np.random.Generator, h: int, w: int) -> list[npt.NDArray[np.uint8]]:
    """Noise (every weight shows), a smooth frame and one with a hard step."""
    noise = rng.integers(0, 256, (h, w), np.uint8)
    step = np.zeros((h, w), np.uint8)
    step[:, w // 2 :] = 255
    return [noise, cv2.GaussianBlur(noise, (9, 9), 3), step]


def test_the_border_folds_onto_one_pixel() -> None:
    """Where OpenCV's replicated border reads one pixel twice, the table reads the pair
    inside the image with all the weight on that pixel; inside, it is the map's own."""
    at = np.array([-5, -1, 0, 3, 8, 9, 15])
    frac = np.full(at.shape, 7)
    first, weight = _axis(at, frac, 10)
    assert first.tolist() == [0, 0, 0, 3, 8, 8, 8]
    assert weight.tolist() == [0, 0, 7, 7, 7, 1 << TAB_BITS, 1 << TAB_BITS]


@pytest.mark.parametrize(
    ("kind", "pitch", "width"),
    [
        ("level", 0.0, 320),
        ("level", 9.0, 320),
        ("plain", 0.0, 320),
        ("level", -25.0, 320),
        ("level", 3.0, 324),  # not a multiple of 8: the scalar loop ends each row
        ("level", 0.0, 500),
    ],
)
def test_the_table_remap_in_c_is_opencvs(kind: str, pitch: float, width: int) -> None:
    """Every row count and frame: the C remap by the view's table gives cv2.remap's
    values, also where the maps reach past the frame's borders (a steep pitch)."""
    assert undistort._c_remap_table is not None, "the C accelerator is not built (make setup)"
    rng = np.random.default_rng(11)
    camera = CameraModel.paper(width, width * 3 // 4)
    view = View(camera, Rig(camera_pitch_deg=pitch), kind)
    off, fx, fy = remap_table(view, camera.width)
    h = camera.height
    for src in _frames(rng, h, camera.width):
        for rows in (h, h // 3, 1):
            want = _opencv(view, src, rows)
            got = np.empty_like(want)
            undistort._c_remap_table(src, camera.width, off[:rows], fx[:rows], fy[:rows], got)
            assert np.array_equal(got, want)


@pytest.mark.parametrize("pitch", [-25.0, 9.0])
def test_the_views_above_read_past_the_frame(pitch: float) -> None:
    """The views of the test above do read past the frame's borders (columns past both
    sides, rows above the top): folded entries, the weight on the border pixel, exist."""
    camera = CameraModel.paper(320, 240)
    view = View(camera, Rig(camera_pitch_deg=pitch), "level")
    x = view.map1[..., 0].astype(np.int64)
    assert (x < 0).any() and (x >= camera.width - 1).any()
    off, fx, _ = remap_table(view, camera.width)
    assert (fx[x >= camera.width - 1] == 1 << TAB_BITS).all()
    assert (fx[x < 0] == 0).all()
    assert int(off.max()) <= (camera.height - 2) * camera.width + camera.width - 2


def test_the_table_remap_in_c_follows_any_map() -> None:
    """Maps of every fraction reaching far past all four borders (a view's maps replaced):
    the C remap by the table is still cv2.remap, pixel for pixel."""
    c = undistort._c_remap_table
    assert c is not None
    rng = np.random.default_rng(3)
    camera = CameraModel.paper(320, 240)
    view = View(camera, Rig(), "plain")
    h, w = camera.height, camera.width
    view.map1 = np.stack(
        [rng.integers(-40, w + 40, (h, w)), rng.integers(-40, h + 40, (h, w))], axis=-1
    ).astype(np.int16)
    view.map2 = rng.integers(0, 1 << 16, (h, w)).astype(np.uint16)  # high bits ignored
    off, fx, fy = remap_table(view, w + 3)
    for src in _frames(rng, h, w + 3):
        frame = src[:, :w]  # rows w + 3 bytes apart
        want = _opencv(view, frame, h)
        got = np.empty_like(want)
        c(frame, w + 3, off, fx, fy, got)
        assert np.array_equal(got, want)


def test_warp_with_the_table_is_warp_with_opencv(monkeypatch: pytest.MonkeyPatch) -> None:
    """View.warp by TableRemap, with and without the accelerator, equals OpenCV's warp:
    grey and colour frames, a strided grey frame, every row count."""
    rng = np.random.default_rng(5)
    camera = CameraModel.paper(320, 240)
    h, w = camera.height, camera.width
    for pitch in (0.0, 7.0):
        view = View(camera, Rig(camera_pitch_deg=pitch), "level")
        remap = TableRemap(view)
        wide = np.zeros((h, w + 9), np.uint8)
        wide[:, :w] = rng.integers(0, 256, (h, w), np.uint8)
        frames = [*_frames(rng, h, w), rng.integers(0, 256, (h, w, 3), np.uint8), wide[:, :w]]
        for image in frames:
            for rows in (h, 100, 2, 1):
                want = view.warp(image, rows).copy()
                assert np.array_equal(view.warp(image, rows, remap), want)
                with monkeypatch.context() as m:
                    m.setattr(undistort, "_c_remap_table", None)
                    assert np.array_equal(view.warp(image, rows, remap), want)


def test_the_table_remap_refuses_what_it_cannot_read() -> None:
    """Offsets past the frame (a table for a taller frame, a forged entry) are refused
    before anything is read; TableRemap then remaps by OpenCV."""
    c = undistort._c_remap_table
    assert c is not None
    camera = CameraModel.paper(320, 240)
    view = View(camera, Rig(camera_pitch_deg=20.0), "level")
    off, fx, fy = remap_table(view, camera.width)
    src = np.zeros((camera.height, camera.width), np.uint8)
    out = np.empty((camera.height, camera.width), np.uint8)
    bad = off.copy()
    bad[5, 17] = camera.height * camera.width
    with pytest.raises(ValueError):
        c(src, camera.width, bad, fx, fy, out)
    bad[5, 17] = -1
    with pytest.raises(ValueError):
        c(src, camera.width, bad, fx, fy, out)
    with pytest.raises(ValueError):
        c(src[:10], camera.width, off, fx, fy, out)  # rows the short frame does not have
    with pytest.raises(ValueError):
        c(src, camera.width + 1, off, fx, fy, out)  # not the frame's row stride
    with pytest.raises(TypeError):
        c(src, camera.width, off.astype(np.int64), fx, fy, out)
    short = src[:10]
    got = np.empty((view.map1.shape[0], camera.width), np.uint8)
    TableRemap(view)(short, got)  # the C call refuses: OpenCV's values all the same
    assert np.array_equal(got, _opencv(view, short, view.map1.shape[0]))


@pytest.mark.parametrize("weight", [-1, 33, -32768])
@pytest.mark.parametrize("column", [3, 322])  # in the 8-wide loop, in the scalar tail
def test_the_table_remap_refuses_a_weight_outside_0_to_32(weight: int, column: int) -> None:
    """A forged weight is refused (both loops), never read as arithmetic past its range."""
    c = undistort._c_remap_table
    assert c is not None
    camera = CameraModel.paper(324, 243)
    view = View(camera, Rig(), "level")
    off, fx, fy = remap_table(view, camera.width)
    src = np.zeros((camera.height, camera.width), np.uint8)
    out = np.empty((camera.height, camera.width), np.uint8)
    for table in (fx, fy):
        bad = table.copy()
        bad[7, column] = weight
        args = (bad, fy) if table is fx else (fx, bad)
        with pytest.raises(ValueError, match="weight"):
            c(src, camera.width, off, *args, out)


def test_view_warp_takes_the_c_path_for_grey_and_colour_frames(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """TableRemap's fallback to OpenCV would hide a C path that refused every frame: the
    packed grey frames the method reads, and colour frames' grey, go through C."""
    c = undistort._c_remap_table
    assert c is not None
    calls: list[bool] = []

    def spy(*args: object) -> None:
        try:
            c(*args)  # type: ignore[arg-type]
        except ValueError:
            calls.append(False)
            raise
        calls.append(True)

    monkeypatch.setattr(undistort, "_c_remap_table", spy)
    rng = np.random.default_rng(9)
    camera = CameraModel.paper(500, 375)
    view = View(camera, Rig(camera_pitch_deg=4.0), "level")
    remap = TableRemap(view)
    grey = rng.integers(0, 256, (375, 500), np.uint8)
    for rows in (375, 200, 2):
        view.warp(grey, rows, remap)
        view.warp(cv2.cvtColor(grey, cv2.COLOR_GRAY2BGR), rows, remap)
    assert calls and all(calls)


def test_a_lazy_remap_makes_its_table_on_a_strides_second_frame() -> None:
    """Not eager (a view levelled for a pitch tried once): the first frame is OpenCV's,
    the table comes with the second; both give OpenCV's values."""
    rng = np.random.default_rng(4)
    camera = CameraModel.paper(324, 243)
    view = View(camera, Rig(camera_pitch_deg=3.0), "level")
    remap = TableRemap(view, eager=False)
    src = rng.integers(0, 256, (camera.height, camera.width), np.uint8)
    want = _opencv(view, src, camera.height)
    for made in (False, True):
        got = np.empty_like(want)
        remap(src, got)
        assert np.array_equal(got, want)
        assert (camera.width in remap._tables) is made
    assert camera.width in TableRemap(view)._tables  # eager: made with the view


def test_no_table_for_rows_reversed() -> None:
    """A frame read bottom-up (a negative row stride) is OpenCV's to remap, every time."""
    rng = np.random.default_rng(6)
    camera = CameraModel.paper(320, 240)
    view = View(camera, Rig(), "level")
    remap = TableRemap(view, eager=False)
    src = rng.integers(0, 256, (camera.height, camera.width), np.uint8)[::-1]
    want = _opencv(view, src, 100)
    for _ in range(2):
        got = np.empty_like(want)
        remap(src, got)
        assert np.array_equal(got, want)
    assert remap._tables == {}


def _colour_frames(rng: np.random.Generator, h: int, w: int) -> list[npt.NDArray[np.uint8]]:
    """BGR noise (every weight and channel shows), smoothed, and a hard colour step."""
    noise = rng.integers(0, 256, (h, w, 3), np.uint8)
    step = np.zeros((h, w, 3), np.uint8)
    step[:, w // 2 :] = (255, 0, 128)
    return [noise, cv2.GaussianBlur(noise, (9, 9), 3), step]


@pytest.mark.parametrize(("kind", "pitch"), [("level", 0.0), ("level", 9.0), ("level", -25.0)])
def test_the_colour_block_remap_in_c_is_opencvs(kind: str, pitch: float) -> None:
    """Blocks of a BGR frame by the C colour remap: cv2.remap's values channel for
    channel, the whole view (past the frame's borders: the last row and column's pixels)
    and blocks inside it, one pixel wide too."""
    assert undistort._c_remap_table3 is not None, "the C accelerator is not built (make setup)"
    rng = np.random.default_rng(17)
    camera = CameraModel.paper(320, 240)
    view = View(camera, Rig(camera_pitch_deg=pitch), kind)
    remap = TableRemap(view)
    h, w = camera.height, camera.width
    blocks = [(0, h, 0, w), (50, 90, 7, 301), (h - 1, h, 0, w), (0, h, w - 1, w), (3, 4, 5, 6)]
    for image in _colour_frames(rng, h, w):
        for r0, r1, c0, c1 in blocks:
            want = cv2.remap(
                image,
                view.map1[r0:r1, c0:c1],
                view.map2[r0:r1, c0:c1],
                cv2.INTER_LINEAR,
                borderMode=cv2.BORDER_REPLICATE,
            )
            got = remap.colour_block(image, r0, r1, c0, c1)
            assert got is not None
            assert np.array_equal(got, want.reshape(got.shape))
            # into a block of a larger buffer (the held frame's Lab buffer), in place
            buf = np.zeros((h + 2, w + 4, 3), np.uint8)
            out = buf[1 : 1 + r1 - r0, 2 : 2 + c1 - c0]
            assert remap.colour_block(image, r0, r1, c0, c1, out) is out
            assert np.array_equal(buf[1 : 1 + r1 - r0, 2 : 2 + c1 - c0], got)
            assert not buf[0].any() and not buf[:, :2].any()  # nothing outside it


def test_the_colour_block_remap_leaves_what_it_cannot_read_to_opencv() -> None:
    """A grey frame, a frame of another size or with gaps between its rows: no block
    (the caller remaps with OpenCV); a table's entry outside the frame is refused."""
    camera = CameraModel.paper(320, 240)
    view = View(camera, Rig(), "level")
    remap = TableRemap(view)
    h, w = camera.height, camera.width
    assert remap.colour_block(np.zeros((h, w), np.uint8), 0, 4, 0, 4) is None
    assert remap.colour_block(np.zeros((h, w + 1, 3), np.uint8), 0, 4, 0, 4) is None
    assert remap.colour_block(np.zeros((h, w + 2, 3), np.uint8)[:, :w], 0, 4, 0, 4) is None
    c = undistort._c_remap_table3
    assert c is not None
    off, fx, fy = remap_table(view, w)
    top, bottom = undistort.pair_weights((off, fx, fy))
    bad = off.copy()
    bad[2, 3] = (h - 1) * w  # the last row's first pixel: no row below it
    with pytest.raises(ValueError, match="outside the image"):
        c(np.zeros((h, w, 3), np.uint8), bad, top, bottom, 0, 0, np.empty((4, 5, 3), np.uint8))
    with pytest.raises(ValueError, match="table for this image and block"):
        c(np.zeros((h, w, 3), np.uint8), off, top, bottom, h - 2, 0, np.empty((4, 5, 3), np.uint8))


def test_lab_blocks_by_the_c_colour_remap_are_opencvs(monkeypatch: pytest.MonkeyPatch) -> None:
    """The fused method's view converts its Lab blocks from the C colour remap: the same
    values as with OpenCV's remap (the accelerator off), held frame or not, and a block
    inside one converted before is that one's."""
    from obstacle_fusion.vision.fused import FusedMethod

    rng = np.random.default_rng(23)
    camera = CameraModel.paper(320, 240)
    view = View(camera, Rig(camera_pitch_deg=6.0), "level")
    FusedMethod(view)  # hands the view its colour remap
    image = cv2.GaussianBlur(rng.integers(0, 256, (240, 320, 3), np.uint8), (5, 5), 2)
    blocks = [(100, 160, 0, 320), (120, 140, 30, 90), (90, 130, 20, 80), (150, 200, 10, 60)]

    def lab_blocks(hold: bool) -> list[npt.NDArray[np.uint8]]:
        view.hold_colour(image if hold else None)
        out = [view.lab(image, *b).copy() for b in blocks]
        view.hold_colour(None)
        return out

    with_c = lab_blocks(True) + lab_blocks(False)
    with monkeypatch.context() as m:
        m.setattr(undistort, "_c_remap_table3", None)
        without = lab_blocks(True) + lab_blocks(False)
    view.use_colour_remap(None)
    plain = lab_blocks(True) + lab_blocks(False)
    for a, b, c in zip(with_c, without, plain, strict=True):
        assert np.array_equal(a, b) and np.array_equal(a, c)
    n = len(blocks)
    for held, fresh in zip(with_c[:n], with_c[n:], strict=True):  # the cache's: its own
        assert np.array_equal(held, fresh)
    # a frame that is not packed 8-bit BGR is not held (its blocks: OpenCV's, one by one)
    bgra = cv2.cvtColor(image, cv2.COLOR_BGR2BGRA)
    view.hold_colour(bgra)
    assert view._held is None
    for b, want in zip(blocks, plain[n:], strict=True):
        assert np.array_equal(view.lab(bgra, *b), want)
    view.hold_colour(None)
