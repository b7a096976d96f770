"""Which of the two parts of `make test` a test runs in (tools/run_tests.sh).

The suite runs in two pytest processes: the tests marked ``cpu_only`` (and not
``realtime``) on pytest-xdist workers, then all the others alone in one process, since
those run the emulated robot in real time or judge wall-clock time and must not share the
cores. A test is in the second, lone part unless it says otherwise: ``pytestmark =
pytest.mark.cpu_only`` opts a module in, ``@pytest.mark.realtime`` takes one of its tests
back out. Every test in tests/vision is ``cpu_only`` (CPU-bound, no clocks, each test
independent).

A module marked ``cpu_only`` whose test asks for the emulator (its fixtures start it in
real time) without ``realtime`` is refused at collection, so the marker cannot quietly put
a real-time test on a loaded core.
"""

from __future__ import annotations

from pathlib import Path

import pytest

VISION = Path(__file__).resolve().parent / "vision"
#: Fixtures that start the emulated robot (tests/emulator_fixtures.py): real time.
EMULATOR_FIXTURES = frozenset({"uno_elf", "emulator_factory"})


def parallel(item: pytest.Item) -> bool:
    """True when the item runs in the xdist part (the run_tests.sh expression)."""
    return (
        item.get_closest_marker("cpu_only") is not None
        and item.get_closest_marker("realtime") is None
    )


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    wrong = []
    for item in items:
        if item.path.is_relative_to(VISION):
            item.add_marker(pytest.mark.cpu_only)
        if parallel(item) and EMULATOR_FIXTURES & set(getattr(item, "fixturenames", ())):
            wrong.append(item.nodeid)
    if wrong:
        raise pytest.UsageError(
            "marked cpu_only but start the emulator (mark them realtime): " + ", ".join(wrong)
        )
