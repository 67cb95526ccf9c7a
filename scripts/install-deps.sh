#!/usr/bin/env bash
# Installs every Debian 12 package pcbench builds, tests or plots with. Nothing else is fetched:
# the build uses only these packages. Skips apt entirely when all are already installed.
set -euo pipefail

packages=(
  build-essential cmake ninja-build git clang-format
  libtbb-dev libfmt-dev nlohmann-json3-dev libcli11-dev libmuparser-dev libboost-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libembree-dev libnanoflann-dev libopenexr-dev libimath-dev openexr libtinyobjloader-dev libopenimageio-dev pkgconf
  python3 python3-jsonschema python3-matplotlib python3-openimageio
  chromium
  clang libclang-rt-14-dev
  libopenmpi-dev openmpi-bin
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} Debian packages present"
  exit 0
fi

sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
echo "install-deps: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
