#!/usr/bin/env bash
# Run the whole suite. pytest's exit 5 ("no tests collected") is a failure here, never
# a silent success: a suite that ran nothing proves nothing.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
.venv/bin/python -m pytest "$@"
rc=$?
if [ "$rc" = 5 ]; then
  echo "run_tests: pytest collected no tests; treating that as a failure" >&2
  exit 1
fi
exit "$rc"
