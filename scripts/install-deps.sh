#!/usr/bin/env bash
# Installs the Debian 12 packages pcbench builds, tests or plots with. Nothing else is fetched:
# the build uses only these packages. Skips apt entirely when all are already installed.
#
# Usage: bash scripts/install-deps.sh [run|all]
#   run  what building pcbench and its Python module and drawing its page need (the README's
#        first command, scripts/run-default.sh)
#   all  (the default) also the tests, benchmarks, format check, the clang sanitizer and fuzz
#        build, Open MPI, the browser of the page test and Blender (Cycles, which the test
#        export.cycles renders pcbench's exported scenes with) (scripts/test.sh)
set -euo pipefail

profile=${1:-all}
run_packages=(
  build-essential cmake ninja-build git pkgconf
  libtbb-dev libfmt-dev nlohmann-json3-dev libcli11-dev libmuparser-dev libboost-dev
  libembree-dev libnanoflann-dev libopenexr-dev libimath-dev libtinyobjloader-dev
  libopenimageio-dev
  python3 python3-matplotlib python3-openimageio
  python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pandas
)
test_packages=(
  clang-format openexr
  libgtest-dev libgmock-dev libbenchmark-dev
  python3-jsonschema
  chromium
  clang libclang-rt-14-dev
  libopenmpi-dev openmpi-bin
  blender
)
case "$profile" in
  run) packages=("${run_packages[@]}") ;;
  all) packages=("${run_packages[@]}" "${test_packages[@]}") ;;
  *)
    echo "install-deps: unknown profile '$profile'; valid: run, all" >&2
    exit 2
    ;;
esac

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} Debian packages of profile $profile present"
  exit 0
fi

sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
echo "install-deps: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
