#!/usr/bin/env bash
# Progress on stderr: one line per finished run when stderr is not a terminal, one updating line
# (carriage returns, erase to end of line) when it is (a pseudo-terminal from `script`), nothing
# with --quiet.
set -uo pipefail
binary=$1
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cd "$scratch"
run=(run -e plain,pcbpt -i form-factor,genz-gaussian -n 20000 -r 4)

failed=0
check() {  # check DESCRIPTION COMMAND...
  if "${@:2}"; then echo "ok      $1"; else echo "FAILED  $1"; failed=$((failed + 1)); fi
}

"$binary" "${run[@]}" --out lines >/dev/null 2>lines.txt
check "one line per run, numbered (got: $(tr '\n' '|' <lines.txt))" \
  test "$(grep -cE '^\[[1-4]/4\] (plain|pcbpt) × (form-factor|genz-gaussian) .*: ok, raw p ' lines.txt)" -eq 4
check "the last run's line is [4/4]" grep -q '^\[4/4\]' lines.txt

"$binary" "${run[@]}" --out quiet --quiet >/dev/null 2>quiet.txt
check "nothing with --quiet" test ! -s quiet.txt

# `script` gives pcbench a terminal; its stdout and stderr both land in terminal.txt. A run long
# enough (~2 s) for the line to be redrawn at least once.
script -qec "'$binary' run -e pcbpt -i genz-gaussian -n 2000000 -r 4 --out tty" terminal.txt \
  >/dev/null
check "a terminal gets an updating line" grep -q $'\r\[1/1\] pcbpt × genz-gaussian' terminal.txt
check "which is erased before the summary" grep -q $'\x1b\[K' terminal.txt
check "and no per-run log line" bash -c "! grep -q ': ok, raw p' terminal.txt"
echo "$((6 - failed)) passed, $failed failed"
[ "$failed" -eq 0 ]
