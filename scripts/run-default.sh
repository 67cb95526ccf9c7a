#!/usr/bin/env bash
# The README's first command: set up a fresh Debian 12 machine, build pcbench in Release and run
# the default suite. Ends with the summary table, the report's path and the page of its plots.
# Extra arguments go to `pcbench run` (e.g. --threads 1). Exits with pcbench run's status.
set -euo pipefail
cd "$(dirname "$0")/.."

# Only what the default suite and its page need: the packages to build pcbench and plot, and the
# pcbench target, with the Python module beside it (build/release/python: docs/guide/python.md);
# the test command, scripts/test.sh, installs and builds the rest.
bash scripts/install-deps.sh run
cmake --preset release -DPCBENCH_TESTS=OFF -DPCBENCH_BENCHMARKS=OFF >/dev/null
cmake --build --preset release --target pcbench pcbench_python

log=$(mktemp)
trap 'rm -f "$log"' EXIT
status=0
build/release/pcbench run suites/default.json "$@" | tee "$log" || status=${PIPESTATUS[0]}
# The report's path is the line "report: PATH" (also with --out, which results/latest ignores).
report=$(sed -n 's/^report: //p' "$log" | tail -n 1)
if [ -n "$report" ]; then
  build/release/pcbench plot "$report" || echo "run-default: the plots could not be made" >&2
fi
exit "$status"
