#!/usr/bin/env bash
# Run the whole suite. pytest's exit 5 ("no tests collected") is a failure here, never
# a silent success: a suite that ran nothing proves nothing.
#
# With no arguments the suite runs in two parts: first the tests marked cpu_only (all of
# tests/vision, and the modules or tests elsewhere that neither run the emulated robot
# nor judge wall-clock time: lint, firmware builds and fuzzing, protocol, fusion, the
# clock model on its simulated link, ...) on OF_TEST_WORKERS pytest-xdist workers
# (default 2, the machine's cores); then everything else in one process, since those
# tests run the emulated robot in real time and must not share the cores. A test is in the
# second part unless marked cpu_only, and a cpu_only test that asks for the emulator is
# refused at collection (tests/conftest.py). Arguments run one plain pytest with them
# (`make test PYTEST_ARGS='-k clock'`).
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

run_pytest() {
  .venv/bin/python -m pytest "$@"
  local rc=$?
  if [ "$rc" = 5 ]; then
    echo "run_tests: pytest collected no tests ($*); treating that as a failure" >&2
    return 1
  fi
  return "$rc"
}

if [ $# -gt 0 ]; then
  run_pytest "$@"
  exit $?
fi

# The two parts' marker expressions are complements: every test runs in exactly one.
parallel='cpu_only and not realtime'
run_pytest -n "${OF_TEST_WORKERS:-2}" --dist loadgroup -m "$parallel" tests
parallel_rc=$?
run_pytest -m "not ($parallel)" tests
rest_rc=$?
if [ "$parallel_rc" != 0 ]; then
  echo "run_tests: the cpu_only part failed (exit $parallel_rc); see its summary above" >&2
  exit "$parallel_rc"
fi
exit "$rest_rc"
