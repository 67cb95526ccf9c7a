#!/usr/bin/env bash
# Runs the microbenchmarks and compares them with results/baseline/bench.json (see
# scripts/check-perf.py for the rule). `--update` rewrites the baseline instead.
# Timing depends on the machine: refresh the baseline when the machine changes.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --preset release >/dev/null
cmake --build --preset release --target pcbench_bench >/dev/null
filter='PhiloxBlock|PhiloxMany|UniformDouble|TallyAdd|PlainGenzGaussianBatch|SamplePool|ImportanceS|BM_Connect/(genz-gaussian|blocker|door)$|HarnessPlain|HandWritten|RayRate|EmitterCandidate'
out=$(mktemp --suffix=.json)
trap 'rm -f "$out"' EXIT
build/release/pcbench_bench --benchmark_filter="$filter" --benchmark_repetitions=5 \
  --benchmark_min_time=0.2 --benchmark_format=json >"$out"
if [ "${1:-}" = "--update" ]; then
  cp "$out" results/baseline/bench.json
  echo "baseline updated: results/baseline/bench.json"
  exit 0
fi
/usr/bin/python3 scripts/check-perf.py results/baseline/bench.json "$out"
