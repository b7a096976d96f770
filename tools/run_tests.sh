#!/usr/bin/env bash
# Run the whole suite. pytest's exit 5 ("no tests collected") is a failure here, never
# a silent success: a suite that ran nothing proves nothing.
#
# With no arguments the suite runs in two parts: tests/vision (CPU-bound, no clocks, each
# test independent) on OF_TEST_WORKERS pytest-xdist workers (default 2, the machine's
# cores), then everything else in one process, since those tests run the emulated robot
# in real time and must not share the cores with vision work. Arguments run one plain
# pytest with them (`make test PYTEST_ARGS='-k clock'`).
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

run_pytest -n "${OF_TEST_WORKERS:-2}" tests/vision
vision_rc=$?
run_pytest --ignore=tests/vision tests
rest_rc=$?
if [ "$vision_rc" != 0 ]; then
  echo "run_tests: tests/vision failed (exit $vision_rc); see its summary above" >&2
  exit "$vision_rc"
fi
exit "$rest_rc"
