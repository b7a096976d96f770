"""A top face is told from the front under a gloss band by band (``region.TOP_FACE_BANDS``,
``TOP_FACE_BAND_COUNT``, :func:`.region._differs_by_bands`): a top face and the front are
two planes, each lit evenly, and differ in colour all along the edge between them; a
gloss's highlight lightens the front unevenly along its rows, and their median colour may
then fall on the top face's own. Where the rows' medians are alike, the rows between the
top and the front top edge and the front under them are compared in column bands, each
against its own; the median band's difference at MIN_TOP_DISTANCE or more is a top face.

Procedural 3234 (ordinary, the new5 rooms), measured with no rig: a green gloss box lower
than the lens, its top face a 5-row band of L 143-146 in every column band, the front
under it L 129, 140, 165, 158 band by band (the highlight right under the top), its median
within 6 of the top face's: the top face was kept in the height, +12 %.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest
from obstacle_fusion.vision.fused import region

from tests.vision_fixtures import room_size_errors


def test_the_top_face_over_the_gloss_is_left_out() -> None:
    eh, ew = room_size_errors("procedural", 3234, False, with_rig=False)
    assert eh < 0.03 and ew < 0.03


def test_without_the_rule_the_top_face_is_in_the_height(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "TOP_FACE_BANDS", False)
    eh, _ = room_size_errors("procedural", 3234, False, with_rig=False)
    assert eh > 0.10


FACE = (145, 120, 140)  # Lab, 8-bit


def _rows(n: int, bands: tuple[int, ...] = ()) -> npt.NDArray[np.uint8]:
    """n rows x 40 columns of FACE, the lightness of each 10-column band set."""
    rows = np.zeros((n, 40, 3), np.uint8)
    rows[:] = FACE
    for i, light in enumerate(bands):
        rows[:, 10 * i : 10 * (i + 1), 0] = light
    return rows


# a front whose bands differ from the even top face by 20, 4, 8 and 4 (median 6, at
# MIN_TOP_DISTANCE), its median lightness 141, within MIN_TOP_DISTANCE of the top face's
GLOSS = (125, 141, 153, 141)


def test_a_front_lit_unevenly_under_an_even_top_face() -> None:
    strip, front = _rows(4), _rows(6, GLOSS)
    whole = np.median(front.reshape(-1, 3), axis=0) - np.array(FACE)
    assert np.linalg.norm(whole) < region.MIN_TOP_DISTANCE
    assert region._differs_by_bands(strip, front)


def test_a_line_inside_the_front_is_no_top_face() -> None:
    # rows above a line with the front's own uneven gloss: refused by the evenness check
    # (their bands 16 L from their median), before any band is compared
    assert not region._differs_by_bands(_rows(4, GLOSS), _rows(6, GLOSS))
    # ... and an even front of the top face's colour neither
    assert not region._differs_by_bands(_rows(4), _rows(6))


def test_the_distance_limit(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(region, "MIN_TOP_DISTANCE", region.MIN_TOP_DISTANCE + 0.5)
    assert not region._differs_by_bands(_rows(4), _rows(6, GLOSS))


@pytest.mark.parametrize("count", [3, 5])
def test_the_band_count(monkeypatch: pytest.MonkeyPatch, count: int) -> None:
    assert region.TOP_FACE_BAND_COUNT == 4
    monkeypatch.setattr(region, "TOP_FACE_BAND_COUNT", count)
    assert not region._differs_by_bands(_rows(4), _rows(6, GLOSS))


def test_the_rows_between_are_lit_evenly() -> None:
    # a strip whose bands stray from their median by more than MIN_TOP_DISTANCE is no
    # plane lit evenly (fresh procedural/2199 hard with no rig: its bands L 54-69, taken
    # for a top face, -19 -> -33 %)
    d = int(region.MIN_TOP_DISTANCE)
    assert region._differs_by_bands(_rows(4, (145 - d, 145, 145, 145)), _rows(6, GLOSS))
    assert not region._differs_by_bands(_rows(4, (145 - d - 1, 145, 145, 145)), _rows(6, GLOSS))
    assert not region._differs_by_bands(_rows(4, (145, 145, 145, 145 + d + 1)), _rows(6, GLOSS))


def test_the_uneven_room_keeps_its_front_edge() -> None:
    eh, _ = room_size_errors("procedural", 2199, True, with_rig=False)
    assert eh < 0.25
