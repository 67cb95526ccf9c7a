#!/usr/bin/env bash
# Ctrl-C during a suite: pcbench stops between chunks, writes the report of what finished (the
# rest marked not_run) and exits 130. Ctrl-C during calibrate: exit 130 and no report.
set -uo pipefail
binary=$1
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cd "$scratch"

# Sends SIGINT to PID 1 s after it catches SIGINT (bit 2 of SigCgt in /proc/PID/status). Until
# pcbench installs its handler, a background job of this non-interactive shell ignores SIGINT, and
# on a loaded machine loading its libraries can take more than 1 s: a signal sent blindly after
# 1 s was lost there and the run went on to the end (tests/validate_reports.py waits the same way).
interrupt_when_ready() {
  local pid=$1 tries=0 mask
  while [ -r "/proc/$pid/status" ] && [ "$tries" -lt 600 ]; do
    mask=$(awk '/^SigCgt:/ {print $2}' "/proc/$pid/status" 2>/dev/null)
    if [ -n "$mask" ] && (( (16#$mask >> 1) & 1 )); then break; fi
    sleep 0.1
    tries=$((tries + 1))
  done
  sleep 1
  kill -INT "$pid"
}

# Two runs of ~10 s each on this machine; the signal comes 1 s in.
"$binary" run -e plain -i genz-gaussian,genz-oscillatory -n 50000000 -r 32 --out out --quiet &
pid=$!
interrupt_when_ready "$pid"
wait "$pid"
status=$?

failed=0
check() {  # check DESCRIPTION COMMAND...
  if "${@:2}"; then echo "ok      $1"; else echo "FAILED  $1"; failed=$((failed + 1)); fi
}
check "exit status 130 (got $status)" test "$status" -eq 130
check "the report was written" test -f out/report.json
check "no temporary file left behind" bash -c '! ls out/*.tmp 2>/dev/null | grep -q .'
check "unfinished runs are marked not_run" /usr/bin/python3 -c "
import json, sys
runs = json.load(open('out/report.json'))['runs']
sys.exit(0 if len(runs) == 2 and all(r['status'] == 'not_run' for r in runs[1:]) else 1)"

# Ctrl-C during calibrate: the runs stop, no report (a self-test over part of its seeds would be
# another test), exit 130. Without the check it would run all 1000 seeds (minutes).
"$binary" calibrate -e plain --seeds 1000 -n 200000 -r 16 --out cal --quiet 2>cal.err &
pid=$!
interrupt_when_ready "$pid"
wait "$pid"
status=$?
check "calibrate: exit status 130 (got $status)" test "$status" -eq 130
check "calibrate: no report written" test ! -e cal/report.json
check "calibrate: says so" grep -q "calibration interrupted" cal.err

# The same for the tile calibration (scenes): 1000 seeds of 64x64 images would take many minutes.
"$binary" calibrate -i furnace,cornell -p resolution=64 --seeds 1000 -n 16 --out tiles --quiet \
  2>tiles.err &
pid=$!
interrupt_when_ready "$pid"
wait "$pid"
status=$?
check "tile calibrate: exit status 130 (got $status)" test "$status" -eq 130
check "tile calibrate: no report written" test ! -e tiles/report.json
check "tile calibrate: says so" grep -q "calibration interrupted" tiles.err
echo "$((10 - failed)) passed, $failed failed"
[ "$failed" -eq 0 ]
