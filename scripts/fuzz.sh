#!/usr/bin/env bash
# Fuzzes pcbench's input parsers with libFuzzer (fuzz/README.md):
#   bash scripts/fuzz.sh TARGET|all SECONDS
# TARGET is suite, scene or expression. Builds the preset "fuzz" (the asan build: clang, ASan +
# UBSan), replays
# fuzz/regressions/TARGET (every input once), then fuzzes for SECONDS from the committed seeds
# fuzz/corpus/TARGET with fuzz/dict/TARGET.dict. Inputs it finds go to build/fuzz/corpus/TARGET
# (kept between runs, not committed), crashes to build/fuzz/artifacts/TARGET/. Fails if any
# target crashes, hangs, runs out of memory or reports a sanitizer error.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

if [ $# -ne 2 ] || ! [[ $2 =~ ^[0-9]+$ ]]; then
  echo "usage: bash scripts/fuzz.sh suite|scene|expression|all SECONDS" >&2
  exit 2
fi
case $1 in
  all) targets=(suite scene expression) ;;
  suite | scene | expression) targets=("$1") ;;
  *)
    echo "fuzz.sh: unknown target '$1'; valid: suite, scene, expression, all" >&2
    exit 2
    ;;
esac
seconds=$2

cmake --preset fuzz > /dev/null
cmake --build --preset fuzz

# Longest input each target makes: suites and scenes (with an OBJ part) need room for a few
# rows or shapes; an expression longer than this says nothing new.
declare -A max_len=([suite]=4096 [scene]=4096 [expression]=512)

status=0
for target in "${targets[@]}"; do
  binary=$root/build/asan/fuzz/fuzz_$target  # the preset "fuzz" builds into build/asan
  work=$root/build/fuzz/work/$target  # the working directory: scene files named in suites
  found=$root/build/fuzz/corpus/$target
  artifacts=$root/build/fuzz/artifacts/$target
  mkdir -p "$work" "$found" "$artifacts"
  regressions=("$root"/fuzz/regressions/"$target"/*)
  if [ -e "${regressions[0]}" ]; then
    echo "== fuzz $target: replaying ${#regressions[@]} regression inputs"
    (cd "$work" && "$binary" -runs=1 "${regressions[@]}" > "$work/replay.log" 2>&1) || {
      tail -n 40 "$work/replay.log"
      echo "fuzz.sh: $target: a regression input fails again (log: $work/replay.log)" >&2
      status=1
      continue
    }
  fi
  echo "== fuzz $target: $seconds s"
  log=$work/fuzz.log
  if (cd "$work" && nice -n "${PCBENCH_FUZZ_NICE:-0}" "$binary" -max_total_time="$seconds" \
    -max_len="${max_len[$target]}" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -dict="$root/fuzz/dict/$target.dict" -artifact_prefix="$artifacts/" \
    "$found" "$root/fuzz/corpus/$target" > "$log" 2>&1); then
    last=$(grep -E '^#[0-9]+' "$log" | tail -n 1)
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
    echo "fuzz $target: ${execs} runs, ${rate} exec/s, no crash; last: ${last}"
  else
    tail -n 60 "$log"
    echo "fuzz.sh: $target found a crash (log: $log; input: $artifacts/)" >&2
    status=1
  fi
done
exit $status
