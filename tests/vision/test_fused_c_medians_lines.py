"""The accelerator's float32 medians (profiles.median_of) and line flags
(extent._lines_on_rows) are their numpy fallbacks' bit for bit: random, tied and edge
inputs, strided views, the values at the thresholds; what the C cannot take goes to numpy."""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import extent, profiles, region

cmiddle = pytest.importorskip("obstacle_fusion.vision.fused._cmiddle")


def numpy_median_of(a: npt.NDArray[Any], axis: int | None, mp: pytest.MonkeyPatch) -> Any:
    with mp.context() as m:
        m.setattr(profiles, "_c_median_float32", None)
        return profiles.median_of(a, axis)


def same(got: Any, want: Any) -> bool:
    """The same values, shape, dtype and Python type (0-d array, scalar, array)."""
    return (
        type(got) is type(want)
        and np.shape(got) == np.shape(want)
        and np.asarray(got).dtype == np.asarray(want).dtype
        and np.array_equal(got, want)
    )


def samples(rng: np.random.Generator, shape: tuple[int, ...]) -> list[npt.NDArray[np.float32]]:
    """Continuous values, few distinct ones (ties), 8-bit Lab halves, and a mix of signs."""
    return [
        rng.normal(size=shape).astype(np.float32),
        rng.integers(0, 4, shape).astype(np.float32),
        (rng.integers(0, 511, shape) / 2).astype(np.float32),
        (rng.normal(size=shape) * 1e3).round().astype(np.float32),
    ]


def test_the_accelerator_takes_float32_medians() -> None:
    assert profiles._c_median_float32 is not None, "the C accelerator is not built (make setup)"


@pytest.mark.parametrize("n", [1, 2, 3, 4, 5, 16, 17, 18, 33, 64, 101, 1000, 4001])
def test_median_of_1d_in_c_is_numpy_s(n: int, monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(n)
    for a in samples(rng, (n,)):
        for x in (a, a[::-1], a[::2] if n > 1 else a):
            before = x.copy()
            for axis in (None, 0, -1):
                assert same(profiles.median_of(x, axis), numpy_median_of(x, axis, monkeypatch))
                assert np.array_equal(profiles.median_of(x, axis), np.median(x, axis=axis))
            assert np.array_equal(x, before)  # not sorted in place


@pytest.mark.parametrize("n", [4001, 30000, 30001])
def test_median_of_ordered_inputs_in_c_is_numpy_s(n: int, monkeypatch: pytest.MonkeyPatch) -> None:
    # inputs a quickselect's pivot handles worst (sorted, reversed, organ pipe, sawtooth,
    # all equal): select_kth sorts what is left after ~2 log2(n) partitions
    up = np.arange(n, dtype=np.float32)
    for x in (up, up[::-1], np.minimum(up, up[::-1]), up % 7, np.zeros(n, np.float32)):
        assert same(profiles.median_of(x, None), numpy_median_of(x, None, monkeypatch))


@pytest.mark.parametrize("shape", [(1, 1), (1, 3), (2, 3), (7, 3), (40, 3), (3, 40), (501, 3)])
def test_median_of_2d_in_c_is_numpy_s(
    shape: tuple[int, int], monkeypatch: pytest.MonkeyPatch
) -> None:
    rng = np.random.default_rng(sum(shape))
    for a in samples(rng, shape):
        for x in (a, a.T, a[::-1, ::-1], np.asfortranarray(a)):
            for axis in (None, 0, 1, -1, -2):
                got = profiles.median_of(x, axis)
                assert same(got, numpy_median_of(x, axis, monkeypatch)), (shape, axis)
                assert np.array_equal(got, np.median(x, axis=axis))


def test_median_of_in_c_is_taken(monkeypatch: pytest.MonkeyPatch) -> None:
    """The equality tests compare two paths: the C one is really the one taken."""
    calls: list[int] = []
    real = profiles._c_median_float32
    assert real is not None

    def spied(src: Any, axis: int, out: Any) -> bool:
        calls.append(axis)
        return bool(real(src, axis, out))

    monkeypatch.setattr(profiles, "_c_median_float32", spied)
    a = np.array([[3.0, 1.0], [2.0, 5.0], [4.0, 0.5]], np.float32)
    assert np.array_equal(profiles.median_of(a, 0), [3.0, 1.0])
    assert float(profiles.median_of(a)) == 2.5
    assert calls == [0, 0]


def test_median_of_leaves_nan_negative_zero_and_other_types_to_numpy(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    out = np.empty(1, np.float32)
    for lane in ([1.0, np.nan, 2.0], [0.0, -0.0, 1.0, -1.0], [-0.0]):
        a = np.array(lane, np.float32)
        assert cmiddle.median_float32(a, 0, out) is False
        assert same(profiles.median_of(a), numpy_median_of(a, None, monkeypatch))
    assert cmiddle.median_float32(np.array([0.0, 2.0], np.float32), 0, out) is True
    for other in (
        np.arange(6.0).reshape(2, 3),  # float64
        np.arange(24, dtype=np.float32).reshape(2, 3, 4),  # 3-D
        np.zeros((0, 3), np.float32),  # empty lanes
    ):
        with pytest.warns(RuntimeWarning) if other.size == 0 else _nothing():
            got = profiles.median_of(other, 0)
        with pytest.warns(RuntimeWarning) if other.size == 0 else _nothing():
            want = numpy_median_of(other, 0, monkeypatch)
        assert np.array_equal(got, want, equal_nan=True)


class _nothing:
    def __enter__(self) -> None:
        return None

    def __exit__(self, *exc: object) -> None:
        return None


def test_median_float32_refuses_what_it_cannot_read() -> None:
    f = np.ones((4, 3), np.float32)
    with pytest.raises(TypeError):
        cmiddle.median_float32(f.astype(np.float64), 0, np.empty(3, np.float32))
    with pytest.raises(TypeError):
        cmiddle.median_float32(f, 0, np.empty(3, np.float64))
    with pytest.raises(ValueError):
        cmiddle.median_float32(f, 2, np.empty(3, np.float32))  # no such axis
    with pytest.raises(ValueError):
        cmiddle.median_float32(f[:0], 0, np.empty(3, np.float32))  # empty lanes
    with pytest.raises(ValueError):
        cmiddle.median_float32(f, 0, np.empty(4, np.float32))  # one entry per lane
    with pytest.raises(ValueError):
        cmiddle.median_float32(np.ones((2, 2, 2), np.float32), 0, np.empty(4, np.float32))


def numpy_lines(
    ay: npt.NDArray[np.float32], r0: int, r1: int, noise: Any, mp: pytest.MonkeyPatch
) -> Any:
    with mp.context() as m:
        m.setattr(extent, "_c_lines_on_rows", None)
        return extent._lines_on_rows(ay, r0, r1, noise)


def test_the_accelerator_takes_the_lines() -> None:
    assert extent._c_lines_on_rows is not None, "the C accelerator is not built (make setup)"


@pytest.mark.parametrize("seed", range(6))
def test_lines_on_rows_in_c_are_numpy_s(seed: int, monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(seed)
    b = extent.LINE_SIDE_ROWS[1]
    for _ in range(40):
        h, w = int(rng.integers(2 * b + 1, 40)), int(rng.integers(1, 70))
        ay = [
            rng.integers(0, 200, (h, w)).astype(np.float32),
            np.abs(rng.normal(0, 30, (h, w))).astype(np.float32),
            (rng.integers(0, 60, (h, w)) / 3).astype(np.float32),
        ][int(rng.integers(0, 3))]
        r0 = int(rng.integers(b, h - b))
        r1 = int(rng.integers(r0, h - b + 1))
        for noise in (float(rng.uniform(0.5, 20)), np.float32(rng.uniform(0.5, 20)), 1.0):
            for x in (ay, np.asfortranarray(ay)):
                got = extent._lines_on_rows(x, r0, r1, noise)
                want = numpy_lines(x, r0, r1, noise, monkeypatch)
                assert got.dtype == want.dtype and got.shape == want.shape
                assert np.array_equal(got, want), (h, w, r0, r1, noise)


def test_lines_on_rows_at_the_thresholds(monkeypatch: pytest.MonkeyPatch) -> None:
    """An edge exactly at MIN_EDGE_SNR noise levels (in float32, as numpy compares it),
    and exactly LINE_CONTRAST times the smaller side mean, counts; a float32 step under
    either does not; the C flags are numpy's in every case."""
    a, b = extent.LINE_SIDE_ROWS
    noise = 1.0 / 3.0  # MIN_EDGE_SNR * noise is not a float32: rounded as numpy rounds it
    edge_min = np.float32(extent.MIN_EDGE_SNR * noise)
    w = 6
    ay = np.zeros((2 * b + 1, w), np.float32)
    side = np.float32(0.3)  # each side row: the mean is a float32 sum over its rows
    ay[: b - a + 1] = side
    ay[b + a :] = side
    mean = (side * np.float32(b - a + 1)) / np.float32(b - a + 1)
    contrast_at = np.float32(extent.LINE_CONTRAST) * mean
    on_row = [
        max(edge_min, contrast_at),
        np.nextafter(max(edge_min, contrast_at), np.float32(0)),
        np.float32(edge_min),
        contrast_at,
        np.float32(100.0),
        np.float32(0.0),
    ]
    ay[b] = np.array(on_row, np.float32)
    got = extent._lines_on_rows(ay, b, b + 1, noise)[0]
    want = numpy_lines(ay, b, b + 1, noise, monkeypatch)[0]
    assert np.array_equal(got, want)
    assert got[0] and not got[1] and got[4] and not got[5]


def test_lines_on_rows_refuses_what_it_cannot_read() -> None:
    x = np.zeros((11, 4), np.float32)
    out = np.zeros((1, 4), bool)
    with pytest.raises(TypeError):
        cmiddle.lines_on_rows(x.astype(np.float64), 5, 3, 1, 1.0, 2.0, out)
    with pytest.raises(TypeError):
        cmiddle.lines_on_rows(x, 5, 3, 1, 1.0, 2.0, out.view(np.uint8))
    with pytest.raises(ValueError):
        cmiddle.lines_on_rows(x, 5, 6, 1, 1.0, 2.0, out)  # a > b
    with pytest.raises(ValueError):
        cmiddle.lines_on_rows(x, 5, 3, 1, 1.0, 2.0, np.zeros((2, 4), bool))
    with pytest.raises(ValueError):
        cmiddle.lines_on_rows(x[:9], 5, 3, 1, 1.0, 2.0, out)  # fewer than 2b rows


def numpy_floor_chroma(
    foot: npt.NDArray[Any], floor: npt.NDArray[Any], ref: npt.NDArray[Any], mp: pytest.MonkeyPatch
) -> npt.NDArray[np.bool_]:
    with mp.context() as m:
        m.setattr(region, "_c_floor_chroma", None)
        return region.floor_chroma(foot, floor, ref)


def floor_scene(rng: np.random.Generator, w: int) -> tuple[Any, Any, Any]:
    """A floor band, a foot of the floor, its shade (chroma scaled with its lightness),
    other colours, and a face colour of either kind; values on 8-bit halves at times."""
    floor = (rng.uniform(0, 255, 3) + rng.normal(0, rng.choice([1, 5, 30]), (w, 3))).clip(0, 255)
    foot = rng.uniform(0, 255, (w, 3))
    k = rng.uniform(0.3, 1.0)
    pick = rng.random(w)
    shade = pick < 0.35
    foot[shade, 0] = floor[shade, 0] * k
    foot[shade, 1:] = 128 + k * (floor[shade, 1:] - 128) + rng.normal(0, 2, (int(shade.sum()), 2))
    same = (pick >= 0.35) & (pick < 0.6)
    foot[same] = floor[same] + rng.normal(0, 3, (int(same.sum()), 3))
    ref = rng.uniform(0, 255, 3) if rng.random() < 0.5 else floor[0] * [k, 1, 1]
    if rng.random() < 0.3:
        foot, floor, ref = (np.round(v * 2) / 2 for v in (foot, floor, ref))
    return foot.astype(np.float32), floor.astype(np.float32), np.asarray(ref, np.float32)


def test_the_accelerator_takes_floor_chroma() -> None:
    assert region._c_floor_chroma is not None, "the C accelerator is not built (make setup)"


@pytest.mark.parametrize("shadow_foot", [True, False])
def test_floor_chroma_in_c_is_numpy_s(shadow_foot: bool, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "SHADOW_FOOT", shadow_foot)
    rng = np.random.default_rng(7)
    shadows = 0
    for _ in range(400):
        w = int(rng.integers(1, 60))
        foot, floor, ref = floor_scene(rng, w)
        wide = np.concatenate([foot, floor], axis=1)  # strided views: foot, floor in one
        for f, g in ((foot, floor), (wide[:, :3], wide[:, 3:]), (foot[::-1], floor[::-1])):
            got = region.floor_chroma(f, g, ref)
            want = numpy_floor_chroma(f, g, ref, monkeypatch)
            assert got.dtype == want.dtype and got.shape == want.shape
            assert np.array_equal(got, want)
        shadows += int(region.shadow_columns(foot, floor).sum())
    assert shadows > 1000  # the shade's branch was taken


def test_floor_chroma_at_its_thresholds(monkeypatch: pytest.MonkeyPatch) -> None:
    """Chroma steps exactly at FLOOR_CHROMA and FACE_CHROMA_STEP (3-4-5 triangles: exact
    norms) and a float32 step past them; the shade exactly SHADOW_DARKER darker."""
    c, s = region.FLOOR_CHROMA, region.FACE_CHROMA_STEP
    floor = np.tile(
        np.array([100.0, 128.0, 128.0 + region.SHADOW_FLOOR_CHROMA], np.float32), (6, 1)
    )
    foot = floor.copy()
    foot[0, 1:] += [0.6 * c, 0.8 * c]  # at FLOOR_CHROMA: not under it
    foot[1, 1:] += [0.6 * c, np.nextafter(np.float32(0.8 * c), np.float32(0))]
    foot[2, 1:] += [0.0, 50.0]
    foot[3, 0] -= region.SHADOW_DARKER  # darker by exactly the step, chroma scaled
    foot[3, 2] = 128.0 + region.SHADOW_FLOOR_CHROMA * foot[3, 0] / floor[3, 0]
    for ref in (
        np.array(
            [100.0, 128.0 + 0.6 * s, 128.0 + region.SHADOW_FLOOR_CHROMA + 0.8 * s], np.float32
        ),
        np.array(
            [100.0, 128.0 + 0.5 * s, 128.0 + region.SHADOW_FLOOR_CHROMA + 0.8 * s], np.float32
        ),
    ):
        got = region.floor_chroma(foot, floor, ref)
        assert np.array_equal(got, numpy_floor_chroma(foot, floor, ref, monkeypatch))


def test_floor_chroma_of_other_types_is_numpy_s(monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(9)
    foot, floor, ref = floor_scene(rng, 20)
    for args in (
        (foot.astype(np.float64), floor, ref),
        (foot, floor, ref.astype(np.float64)),
    ):
        assert np.array_equal(region.floor_chroma(*args), numpy_floor_chroma(*args, monkeypatch))
    out = np.empty(20, bool)
    with pytest.raises(TypeError):
        cmiddle.floor_chroma(
            foot, floor, ref.astype(np.float64), 0.2, 12.0, 6.0, 12.0, True, 6.0, 10.0, out
        )
    with pytest.raises(ValueError):
        cmiddle.floor_chroma(foot, floor[:19], ref, 0.2, 12.0, 6.0, 12.0, True, 6.0, 10.0, out)
    with pytest.raises(ValueError):
        cmiddle.floor_chroma(foot, floor, ref[:2], 0.2, 12.0, 6.0, 12.0, True, 6.0, 10.0, out)


def side_strips(rng: np.random.Generator, rows: int, cols: int = 6) -> tuple[Any, Any]:
    """A face's strip inside a side (its colour below a top row, the background's above,
    at times a lightness ramp: the drift) and what is beside it (another colour, or nearly
    the face's: a weak step)."""
    face, bg = rng.uniform(0, 255, 3), rng.uniform(0, 255, 3)
    spread = rng.choice([1.0, 4.0, 15.0])
    inside = face + rng.normal(0, spread, (rows, cols, 3))
    outside = bg + rng.normal(0, spread, (rows, cols, 3))
    top = int(rng.integers(0, rows))
    inside[:top] = bg + rng.normal(0, spread, (top, cols, 3))
    if rng.random() < 0.3:
        inside[:, :, 0] += np.linspace(-40, 40, rows)[:, None]
    if rng.random() < 0.2:
        outside = inside + rng.normal(0, 3, inside.shape)
    return inside.clip(0, 255).astype(np.uint8), outside.clip(0, 255).astype(np.uint8)


def test_the_accelerator_reads_sides() -> None:
    assert region._c_side_walk is not None, "the C accelerator is not built (make setup)"


@pytest.mark.parametrize("held_colour", [True, False])
@pytest.mark.parametrize("shaded", [True, False])
def test_side_reading_in_c_is_numpy_s(
    held_colour: bool, shaded: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The C reading of a side gives the numpy reading's flags (or its False) on random
    strips of 3-60 rows, odd and even counts of columns and face rows, strided views."""
    monkeypatch.setattr(region, "HELD_COLOUR_SIDE", held_colour)
    monkeypatch.setattr(region, "SHADED_SIDE_WALK", shaded)
    rng = np.random.default_rng(11 + 2 * held_colour + shaded)
    weak = weighted = 0
    for _ in range(600):
        rows = int(rng.integers(3, 60))
        k = int(rng.integers(-2, rows - 2))
        inside, outside = side_strips(rng, rows, int(rng.choice([5, 6])))
        for a, b in ((inside, outside), (inside[:, ::-1], outside[::1, ::-1])):
            got = region._side_in_c(a, b, k)
            want = region._side_reading(a, b, k)
            assert got is not None
            if want is False:
                weak += 1
                assert got is False
                continue
            assert got is not False
            assert np.array_equal(got[0], want[0]) and np.array_equal(got[1], want[1])
            own = profiles.median_of(profiles.median_u8(a, axis=1)[k + 2 :], axis=0)
            floor = profiles.median_of(profiles.median_u8(b, axis=1)[k + 2 :], axis=0)
            weighted += int(region._face_colour_weights(own, floor)[0] < 1.0)
    assert weak > 50 and weighted > 100  # both exits, and the shaded weights, were read


def test_side_reading_follows_the_constants(monkeypatch: pytest.MonkeyPatch) -> None:
    """The C reading reads the module's constants at each call (as the numpy one): moved,
    both move alike."""
    rng = np.random.default_rng(12)
    cases = [side_strips(rng, 40) for _ in range(40)]
    for name, value in (
        ("MIN_BESIDE_STEP", 30.0),
        ("SIDE_WALK_SHARE", 0.8),
        ("DRIFT_ROWS", 1),
        ("SPREAD_FACTOR", 1.0),
        ("SHADE_WEIGHT", 0.6),
        ("CHROMATIC_FACE", 5.0),
    ):
        with monkeypatch.context() as m:
            m.setattr(region, name, value)
            for inside, outside in cases:
                got = region._side_in_c(inside, outside, 10)
                want = region._side_reading(inside, outside, 10)
                if want is False:
                    assert got is False
                else:
                    assert got is not None and got is not False
                    assert np.array_equal(got[0], want[0]) and np.array_equal(got[1], want[1])


def _reads(bands: Any) -> Any:
    """A stand-in for region._lab8 handing out the given bands in turn."""

    def lab8(*args: Any, **kwargs: Any) -> Any:
        return next(bands)

    return lab8


def test_sides_walk_is_the_same_with_and_without_c(monkeypatch: pytest.MonkeyPatch) -> None:
    """The whole walk over a band (both sides read from it) ends where it ends without the
    accelerator."""
    rng = np.random.default_rng(13)
    span = 2 * (region.BESIDE_COLUMNS + region.SIDE_SKIP)
    for _ in range(200):
        rows = int(rng.integers(6, 50))
        k = int(rng.integers(0, rows - 3))
        left, right = side_strips(rng, rows), side_strips(rng, rows)
        band = np.zeros((rows, span, 3), np.uint8)
        band[:, span - region.BESIDE_COLUMNS :] = left[0]
        band[:, : region.BESIDE_COLUMNS] = left[1]
        other = np.zeros_like(band)
        other[:, : region.BESIDE_COLUMNS] = right[0]
        other[:, -region.BESIDE_COLUMNS :] = right[1]
        monkeypatch.setattr(region, "_lab8", _reads(iter([band, other] * 2)))
        got = region._sides_walk(None, None, 0, rows, k, 0, span, 2, (True, True), 6, 6)  # type: ignore[arg-type]
        with monkeypatch.context() as m:
            m.setattr(region, "_c_side_walk", None)
            want = region._sides_walk(None, None, 0, rows, k, 0, span, 2, (True, True), 6, 6)  # type: ignore[arg-type]
        assert got == want


def test_side_walk_refuses_what_it_cannot_read() -> None:
    strip = np.zeros((10, 6, 3), np.uint8)
    consts = region._side_walk_constants()
    flags = np.zeros(10, bool)
    with pytest.raises(ValueError):
        cmiddle.side_walk(strip, strip[:9], 2, consts, flags, flags.copy())  # heights differ
    with pytest.raises(ValueError):
        cmiddle.side_walk(np.zeros((10, 17, 3), np.uint8), strip, 2, consts, flags, flags.copy())
    with pytest.raises(ValueError):
        cmiddle.side_walk(strip, strip, 8, consts, flags, flags.copy())  # no face rows
    with pytest.raises(ValueError):
        cmiddle.side_walk(strip, strip, 2, consts[:12], flags, flags.copy())
    with pytest.raises(ValueError):
        cmiddle.side_walk(strip.astype(np.int16), strip, 2, consts, flags, flags.copy())
    assert region._side_in_c(strip, strip, 8) is None  # numpy's answer for no face rows


def _up_to_floor_by_steps(on: list[bool], through: list[bool], start: int, step: int) -> list[bool]:
    """region._up_to_floor as the plain loop it replaces."""
    col, n = start, len(on)
    while 0 <= col < n and not through[col]:
        col += step
    if not 0 <= col < n:
        return on
    out = list(on)
    if step > 0:
        out[col:] = [False] * (n - col)
    else:
        out[: col + 1] = [False] * (col + 1)
    return out


def test_up_to_floor_by_index_is_the_loop_s() -> None:
    rng = np.random.default_rng(14)
    for _ in range(3000):
        n = int(rng.integers(0, 30))
        on = (rng.random(n) < 0.5).tolist()
        through = (rng.random(n) < rng.choice([0.0, 0.05, 0.3, 1.0])).tolist()
        start, step = int(rng.integers(-3, n + 3)), int(rng.choice([-2, -1, 1, 2]))
        got = region._up_to_floor(on, through, start, step)
        assert got == _up_to_floor_by_steps(on, through, start, step)


def test_narrow_max_is_numpy_s() -> None:
    rng = np.random.default_rng(15)
    ax = rng.integers(-300, 1020, (60, 40)).astype(np.int16)
    for rows in (0, 1, 7, 60):
        for c0, c1 in ((3, 4), (3, 5), (3, 6), (3, 7), (5, 13)):
            x = ax[:rows, c0:c1]
            got, want = profiles.narrow_max(x), x.max(axis=1)
            assert got.dtype == want.dtype and np.array_equal(got, want)
    f = rng.normal(size=(9, 3)).astype(np.float32)  # floats: numpy's own reduction
    assert np.array_equal(profiles.narrow_max(f), f.max(axis=1))
    with pytest.raises(ValueError):
        profiles.narrow_max(ax[:, 3:3])  # no columns: numpy's error


def test_colour_steps_of_a_block_by_row_norms_are_numpy_s_sum() -> None:
    """foot_outline's per-pixel colour steps: row_norms over the pixels of a rows x columns
    x 3 float32 block are numpy's root of its sum over the last axis, bit for bit."""
    rng = np.random.default_rng(16)
    for _ in range(100):
        r, c = int(rng.integers(0, 80)), int(rng.integers(0, 90))
        d = rng.normal(0, rng.choice([1.0, 30.0, 100.0]), (r, c, 3)).astype(np.float32)
        if rng.random() < 0.5:
            d = (np.round(d * 8) / 8).astype(np.float32)
        got = profiles.row_norms(d.reshape(-1, 3)).reshape(d.shape[:2])
        assert np.array_equal(got, np.sqrt((d * d).sum(axis=2)))
