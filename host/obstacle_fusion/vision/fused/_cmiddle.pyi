"""Types of the fused vision method's optional C accelerator (_cmiddle.c)."""

from typing import Any

def middle_u8(src: Any, network: bytes, lo: Any, hi: Any, /) -> None: ...
def median_f32(src: Any, axis: int, network: bytes, out: Any, /) -> None: ...
def walk_on(on: Any, start: int, step: int, max_gap: int, /) -> int | None: ...
def first_gap(on: Any, out: Any, /) -> None: ...
def next_true(flags: Any, fill: int, out: Any, /) -> None: ...
def remap_table(src: Any, stride: int, offsets: Any, fx: Any, fy: Any, dst: Any, /) -> None: ...
def remap_table3(
    src: Any, offsets: Any, wtop: Any, wbot: Any, r0: int, c0: int, dst: Any, /
) -> None: ...
def kth_counted(src: Any, k: int, /) -> float | None: ...
def project3(src: Any, m0: float, m1: float, m2: float, m3: float, dst: Any, /) -> None: ...
def ramp_spans(
    strip: Any, cols: Any, min_cols: int, beside: int, /
) -> list[tuple[int, int, int]]: ...
def row_norms(x: Any, out: Any, /) -> None: ...
def line_columns(
    strip: Any, cols: Any, beside: int, contrast: float, same: float, same_max: float, /
) -> list[int]: ...
def side_tables(
    ax3: Any,
    cols: Any,
    thresholds: Any,
    rb: int,
    counts: Any,
    below: Any,
    nxt: Any,
    csum: Any,
    /,
) -> list[int] | None: ...
def rank_sides(
    ax3: Any,
    prof_v: Any,
    prof_short: Any,
    groups: Any,
    rb: int,
    cap: float,
    low: float,
    late_rows: int,
    keep: int,
    /,
) -> list[list[int]] | None: ...
def score_tops(
    ay: Any,
    ax3: Any,
    counts: Any,
    nxt: Any,
    grey: Any,
    pairs: Any,
    bands: int,
    noise: float,
    rb: int,
    top_limit: int,
    kf: int,
    label_rows: int,
    label_share: float,
    tops: Any,
    pp: Any,
    f64: Any,
    f32: Any,
    i32: Any,
    /,
) -> int: ...
def uncovered(
    boxes: Any, r0: int, r1: int, c0: int, c1: int, /
) -> list[tuple[int, int, int, int]] | None: ...
def median_float32(src: Any, axis: int, out: Any, /) -> bool: ...
def lines_on_rows(
    x: Any, b: int, a: int, e: int, edge_min: float, contrast: float, out: Any, /
) -> None: ...
def floor_chroma(
    foot: Any,
    floor: Any,
    ref: Any,
    near_share: float,
    far: float,
    chroma: float,
    face_step: float,
    shadow: bool,
    darker: float,
    floor_chroma_min: float,
    out: Any,
    /,
) -> None: ...
def side_walk(
    inside: Any, outside: Any, k: int, consts: Any, stands: Any, held: Any, /
) -> bool: ...
