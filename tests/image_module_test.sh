#!/usr/bin/env bash
# OpenImageIO is loaded only by the commands that read images (harness/plan/image_file_reader.h):
# pcbench itself does not link it, `verify --images` still reads EXR through the module, and a
# module that cannot be loaded is bad input (exit 2, the path named, nothing written).
set -uo pipefail
binary=$1
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cd "$scratch"

failed=0
check() {  # check DESCRIPTION COMMAND...
  if "${@:2}"; then echo "ok      $1"; else echo "FAILED  $1"; failed=$((failed + 1)); fi
}

check "pcbench does not link OpenImageIO" \
  bash -c "! readelf -d '$binary' | grep -q 'OpenImageIO'"

"$binary" run -e pt -i furnace -p resolution=8 -n 4 -r 4 --replicate-images -q --out reps >/dev/null
images=(reps/images/*_rep*.exr)
check "four replicate images written (got ${#images[@]})" test "${#images[@]}" -eq 4

"$binary" verify --images 'reps/images/*_rep*.exr' --constant 1 -q --out read >/dev/null 2>read.txt
status=$?
# Exit 0 or 1 is a verdict on the images (1: not consistent with the constant), so they were read.
check "verify --images reads them through the module (exit 0 or 1, got $status: $(cat read.txt))" \
  test "$status" -le 1
check "and writes its report" test -f read/report.json

PCBENCH_IMAGE_MODULE=$scratch/missing.so "$binary" verify --images 'reps/images/*_rep*.exr' \
  --constant 1 -q --out missing >/dev/null 2>missing.txt
status=$?
check "a missing module is exit 2 (got $status)" test "$status" -eq 2
check "naming the path tried (got: $(cat missing.txt))" grep -q "missing.so" missing.txt
check "and writing nothing" test ! -e missing

exit $((failed > 0))
