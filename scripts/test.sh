#!/usr/bin/env bash
# The README's second command (and CI's): set up a fresh Debian 12 machine, build in Release and
# run the `ci` tests, then build with clang, ASan + UBSan, run the `sanitize` subset and fuzz each
# parser. Prints where the time went. Fails if any step or test fails.
set -euo pipefail
cd "$(dirname "$0")/.."

tally=()
step() {  # step NAME COMMAND...: runs and times one step
  local name=$1 start=$SECONDS
  shift
  echo "== $name"
  "$@"
  tally+=("$(printf '%-28s %5d s' "$name" $((SECONDS - start)))")
}

jobs=$(nproc)
step "install Debian packages" bash scripts/install-deps.sh
step "format check" bash scripts/check-format.sh
step "configure (release)" cmake --preset release
step "build (release)" cmake --build --preset release
step "tests: ci (release)" ctest --preset ci -j "$jobs"
step "configure (asan)" cmake --preset asan
# One clang build serves the sanitize tests and the libFuzzer targets (preset "fuzz" is this
# build): the library is compiled once with ASan + UBSan and coverage instead of twice.
step "build (asan + fuzz)" cmake --build --preset asan --target pcbench_tests fuzz_targets
step "tests: sanitize (asan)" ctest --preset asan -j "$jobs"
# Replays fuzz/regressions/ and fuzzes each parser for 30 s (fuzz/README.md).
step "fuzz: 30 s per target" bash scripts/fuzz.sh all 30

echo "== time by step"
printf '%s\n' "${tally[@]}"
echo "total                        $SECONDS s"
