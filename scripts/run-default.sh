#!/usr/bin/env bash
# The README's first command: set up a fresh Debian 12 machine, build in Release and run the
# default suite. Ends with the summary table, the report's path and the page of its plots.
# Extra arguments go to `pcbench run` (e.g. --threads 1). Exits with pcbench run's status.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release

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
