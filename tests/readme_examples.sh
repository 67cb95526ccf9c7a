#!/usr/bin/env bash
# Runs every pcbench example of README.md as written (docs that cannot go stale).
# An example is a line in a ```sh block that starts with `build/release/pcbench`; it must exit 0,
# or N when the line ends with `# exits N`. Runs in a scratch folder holding the repo's suites/.
set -uo pipefail
binary=$1
source_dir=$2

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch/build/release"
ln -s "$binary" "$scratch/build/release/pcbench"
ln -s "$source_dir/suites" "$scratch/suites"
cd "$scratch"

examples=$(awk '/^```sh/{inside=1; next} /^```/{inside=0} inside && /^build\/release\/pcbench/' \
  "$source_dir/README.md")
passed=0
failed=0
while IFS= read -r line; do
  [ -n "$line" ] || continue
  expected=0
  if [[ $line =~ \#\ exits\ ([0-9]+)$ ]]; then expected=${BASH_REMATCH[1]}; fi
  bash -c "$line" >"$scratch/out.txt" 2>&1
  status=$?
  if [ "$status" -eq "$expected" ]; then
    passed=$((passed + 1))
    echo "ok      $line"
  else
    failed=$((failed + 1))
    echo "FAILED  $line  (exit $status, expected $expected)"
    sed 's/^/    /' "$scratch/out.txt" | tail -n 20
  fi
done <<<"$examples"

[ $((passed + failed)) -gt 0 ] || { echo "no examples found in README.md"; exit 1; }
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
