#!/usr/bin/env bash
# Runs every pcbench example of README.md and of each page of docs/guide/ as written (docs that
# cannot go stale). An example is a line in a ```sh block that starts with `build/release/pcbench`
# or, for the Python module, `PYTHONPATH=build/release/python /usr/bin/python3`; it must exit 0,
# or N when the line ends with `# exits N`. Each ```python block is run whole, with the module on
# the path, and must exit 0. Commands too slow for CI (or whose
# result depends on the machine) go in ```console or ```text blocks, which are not run.
# Runs in one scratch folder holding the repo's suites/, fuzz/ (its scene files) and examples/
# and the build's python/, the pages in order (README.md first, then docs/guide/ by name), so a
# page's later lines may use its earlier ones' output. Prints each command's wall time and the total.
set -uo pipefail
binary=$1
source_dir=$2

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch/build/release"
ln -s "$binary" "$scratch/build/release/pcbench"
ln -s "$(dirname "$binary")/python" "$scratch/build/release/python"
ln -s "$source_dir/examples" "$scratch/examples"
ln -s "$source_dir/suites" "$scratch/suites"
ln -s "$source_dir/fuzz" "$scratch/fuzz"
cd "$scratch"

pages=("$source_dir/README.md")
for page in "$source_dir"/docs/guide/*.md; do pages+=("$page"); done

now() { date +%s.%N; }
passed=0
failed=0
# Runs one example (a command line) and counts it; it must exit `expected`; `shown` names it.
run_example() {
  local line=$1 expected=$2 shown=$3 start status seconds
  start=$(now)
  bash -c "$line" >"$scratch/out.txt" 2>&1
  status=$?
  seconds=$(awk -v a="$start" -v b="$(now)" 'BEGIN { printf "%5.1f", b - a }')
  if [ "$status" -eq "$expected" ]; then
    passed=$((passed + 1))
    echo "ok      ${seconds} s  $shown"
  else
    failed=$((failed + 1))
    echo "FAILED  ${seconds} s  $shown  (exit $status, expected $expected)"
    sed 's/^/    /' "$scratch/out.txt" | tail -n 20
  fi
}
start_all=$(now)
for page in "${pages[@]}"; do
  name=${page#"$source_dir"/}
  examples=$(awk '/^```sh/{inside=1; next} /^```/{inside=0} inside && /^(build\/release\/pcbench|PYTHONPATH=build\/release\/python )/' \
    "$page")
  # Each ```python block is a whole program, run by Debian's python with the module on its path.
  blocks=$(mktemp -d -p "$scratch")
  awk -v dir="$blocks" '/^```python/{n++; inside=1; next} /^```/{inside=0}
    inside { print > (sprintf("%s/block%02d.py", dir, n)) }' "$page"
  [ -n "$examples" ] || [ -n "$(ls "$blocks")" ] || continue
  echo "== $name"
  while IFS= read -r line; do
    [ -n "$line" ] || continue
    expected=0
    if [[ $line =~ \#\ exits\ ([0-9]+)$ ]]; then expected=${BASH_REMATCH[1]}; fi
    run_example "$line" "$expected" "$line"
  done <<<"$examples"
  for block in "$blocks"/*.py; do
    [ -e "$block" ] || continue
    run_example "PYTHONPATH=build/release/python /usr/bin/python3 $block" 0 \
      "the \`\`\`python block $(basename "$block" .py | tr -dc 0-9) of $name"
  done
done

[ $((passed + failed)) -gt 0 ] || { echo "no examples found in README.md or docs/guide/"; exit 1; }
total=$(awk -v a="$start_all" -v b="$(now)" 'BEGIN { printf "%.0f", b - a }')
echo "$passed passed, $failed failed, ${total} s"
[ "$failed" -eq 0 ]
