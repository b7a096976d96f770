"""The vision tests' shared switches.

``measure.RIG_CHECKED_BY_SEARCH`` (session 40) checks an unsure or missed face with the
rig by the no-rig search, which reads the room along other paths: a test that switches
one rule off to see its room go wrong with the rig would find that room rescued by it
(45 such tests at session 40). The vision tests therefore run with it off, one rule
tried at a time, unless marked ``rig_checked`` (its own tests; the benchmarks run the
whole method in a subprocess, the rule on)."""

from __future__ import annotations

import pytest
from obstacle_fusion.vision import measure


@pytest.fixture(autouse=True)
def _rig_checked_only_where_marked(
    request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch
) -> None:
    if request.node.get_closest_marker("rig_checked") is None:
        monkeypatch.setattr(measure, "RIG_CHECKED_BY_SEARCH", False)
