#!/usr/bin/env bash
# The README's first command: set up a fresh Debian 12 machine, build in Release and run the
# default suite. Ends with the summary table and the report's path. Extra arguments go to
# `pcbench run` (e.g. --threads 1).
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release
build/release/pcbench run suites/default.json "$@"
