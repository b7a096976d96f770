"""A face whose sides run on up the edges of what stands in line behind it keeps the top
where its own surface starts.

Photo 3255 (hard, with the rig): a narrow green seamed face (0.16 x 0.72 m at 2.7 m) in
front of a photographed rocket of the same width; the face's sides run on up the rocket's
to the image's top. The surface rule (``method.SURFACE_UP_TO_TOP``) lowers the top from
the rocket's nose to row 121, where the face's green begins; then:

- the outline read from the face's foot (``foot_outline.outline_from_foot``) raised it
  back to row 18 up the rocket's edges (+85 %): the outline's top is now lowered to where
  the face's surface starts as well (``method.OUTLINE_SURFACE_TOP``);
- the rig check's no-rig search (``measure._checked_by_search``) then found the same face
  (its foot, its sides) with its top up the rocket (+76 %), less than CHECK_SAME_FACE over
  the rig's box, and took it: a search face on the rig face's foot and sides, only taller,
  is one surface read twice, and the rig's top stands (``measure.CHECK_SAME_SIDES``,
  ``measure._same_sides_taller``) where the rows the search adds over the rig's top are
  something else than the face (``measure._added_unlike_face``, 29.9 apart here): the
  same colour over it is the face itself, the rig's top a line across it (photo 152
  hard, a tape: 1.4 apart, the search's face taken as before).

With both, +0.7 % high (the width +7 % as before). The room tests run with the rig
check on (``rig_checked``): the second rule is the check's. Without the check, the first
rule alone fixes the room (also tested).
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from obstacle_fusion.vision import measure
from obstacle_fusion.vision.fused import method
from obstacle_fusion.vision.measure import _added_unlike_face, _same_sides_taller

from tests.vision_fixtures import room_size_errors


@pytest.mark.rig_checked
def test_the_face_under_the_rocket_keeps_its_top() -> None:
    eh, ew = room_size_errors("photo", 3255, True, with_rig=True)
    assert eh < 0.1 and ew < 0.1


@pytest.mark.rig_checked
def test_without_the_outline_rule_the_top_runs_up_the_rocket(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(method, "OUTLINE_SURFACE_TOP", False)
    eh, _ = room_size_errors("photo", 3255, True, with_rig=True)
    assert eh > 0.5


@pytest.mark.rig_checked
def test_without_the_check_rule_the_search_face_is_taken(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(measure, "CHECK_SAME_SIDES", False)
    eh, _ = room_size_errors("photo", 3255, True, with_rig=True)
    assert eh > 0.5


def test_the_outline_rule_alone_without_the_check() -> None:
    # (the vision tests' default: measure.RIG_CHECKED_BY_SEARCH off)
    eh, _ = room_size_errors("photo", 3255, True, with_rig=True)
    assert eh < 0.1


def test_without_the_check_the_outline_rule_still_needed(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(method, "OUTLINE_SURFACE_TOP", False)
    eh, _ = room_size_errors("photo", 3255, True, with_rig=True)
    assert eh > 0.5


RIG = (100.0, 120.0, 200.0, 240.0)  # 100 px wide: slack max(2, 0.1 * 100) = 10 px


@pytest.mark.parametrize(
    ("found", "same"),
    [
        ((100.0, 30.0, 200.0, 240.0), True),  # the same foot and sides, taller
        ((90.0, 30.0, 210.0, 250.0), True),  # each 10 px off: within the slack
        ((89.9, 30.0, 200.0, 240.0), False),  # left side past CHECK_SAME_SIDES_SHARE
        ((100.0, 30.0, 210.1, 240.0), False),  # right side past it
        ((100.0, 30.0, 200.0, 250.1), False),  # foot past it: another surface
        ((100.0, 30.0, 200.0, 229.9), False),  # foot higher past it
        ((100.0, 119.9, 200.0, 240.0), True),  # any higher top
        ((100.0, 120.0, 200.0, 240.0), False),  # not taller: the overlap rule's case
        ((100.0, 130.0, 200.0, 240.0), False),  # lower: a shorter reading, weighed as ever
    ],
)
def test_the_limits(found: tuple[float, float, float, float], same: bool) -> None:
    assert _same_sides_taller(RIG, found) is same


@pytest.mark.parametrize(("right", "same"), [(112.0, True), (112.1, False)])
def test_a_narrow_face_keeps_the_pixel_slack(right: float, same: bool) -> None:
    # 10 px wide: 0.1 of it is 1 px, under CHECK_SAME_SIDES_PX (2 px)
    assert _same_sides_taller((100.0, 50.0, 110.0, 90.0), (100.0, 10.0, right, 90.0)) is same


def test_no_box_is_no_same_face() -> None:
    assert not _same_sides_taller(None, RIG)
    assert not _same_sides_taller(RIG, None)


def _greys(face: int, added: int, edge: int = 0) -> np.ndarray:
    """A grey image: the rig face (columns 100-200, rows 120-240) of grey ``face``, the
    rows the search adds over it (30-120) of ``added``, and the ``edge`` grey in the
    CHECK_EDGE_ROWS just under the search's top and over the rig face's foot."""
    img = np.full((300, 300, 3), 60, np.uint8)
    img[120:240, 100:201] = face
    img[30:120, 100:201] = added
    if edge:
        img[30 : 30 + measure.CHECK_EDGE_ROWS, 100:201] = edge
        img[240 - measure.CHECK_EDGE_ROWS : 240, 100:201] = edge
    return img


def _apart(a: int, b: int) -> float:
    lab = cv2.cvtColor(np.array([[[a] * 3, [b] * 3]], np.uint8), cv2.COLOR_BGR2Lab)
    return float(np.linalg.norm(lab[0, 0].astype(np.float32) - lab[0, 1]))


def test_the_added_rows_apart_from_the_face() -> None:
    # the first grey over the face's 100 at least CHECK_ADDED_APART (18) from it, and the
    # one before it
    far = next(g for g in range(100, 200) if _apart(100, g) >= measure.CHECK_ADDED_APART)
    assert _apart(100, far - 1) < measure.CHECK_ADDED_APART
    found = (100.0, 30.0, 200.0, 240.0)
    assert _added_unlike_face(_greys(100, far), RIG, found)
    assert not _added_unlike_face(_greys(100, far - 1), RIG, found)
    assert not _added_unlike_face(_greys(100, 100), RIG, found)  # the face itself
    assert not _added_unlike_face(_greys(100, far)[:, :, 0], RIG, found)  # grey: no colour


def test_the_edges_blur_is_skipped() -> None:
    # the CHECK_EDGE_ROWS rows under the search's top and over the foot are not read
    found = (100.0, 30.0, 200.0, 240.0)
    assert not _added_unlike_face(_greys(100, 100, edge=250), RIG, found)


def test_the_face_is_read_on_its_lower_part() -> None:
    # CHECK_FACE_REF_SHARE 0.35 of the rig face's 120 rows (42) over its foot's blur: a
    # face whose upper part above those rows is the added rows' colour is still read
    img = _greys(100, 200)
    img[120 : 240 - measure.CHECK_EDGE_ROWS - 42, 100:201] = 200
    assert _added_unlike_face(img, RIG, (100.0, 30.0, 200.0, 240.0))
    img[240 - measure.CHECK_EDGE_ROWS - 42 : 240 - measure.CHECK_EDGE_ROWS - 20, 100:201] = 200
    assert not _added_unlike_face(img, RIG, (100.0, 30.0, 200.0, 240.0))


def test_no_added_rows_no_check() -> None:
    assert not _added_unlike_face(_greys(100, 200), RIG, RIG)
    assert not _added_unlike_face(_greys(100, 200), None, RIG)


@pytest.mark.rig_checked
def test_a_tape_across_the_face_is_no_background(monkeypatch: pytest.MonkeyPatch) -> None:
    # photo 152 hard: the rig's top on a tape across a blue face (-49 %); the search's
    # whole face on its foot and sides adds rows of the same blue (1.4 apart) and is taken
    eh, _ = room_size_errors("photo", 152, True, with_rig=True)
    assert eh < 0.05
    monkeypatch.setattr(measure, "CHECK_ADDED_APART", 0.0)
    eh, _ = room_size_errors("photo", 152, True, with_rig=True)
    assert eh > 0.4
