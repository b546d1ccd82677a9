#!/usr/bin/env bash
# Installs the Debian 12 packages libwave builds, tests and runs with.
# Idempotent: packages already installed are skipped; `apt-get update` runs only
# when something is missing. Needs root (or sudo) only when it installs.
set -euo pipefail

packages=(
  build-essential cmake ninja-build ccache pkg-config git
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  libopenmesh-dev libosd-dev libdraco-dev libtinygltf-dev libstb-dev
  libfftw3-dev libtbb-dev libeigen3-dev
  nlohmann-json3-dev libcli11-dev
  libgdal-dev gdal-bin
  libgtest-dev libgmock-dev libbenchmark-dev
  pybind11-dev python3-pybind11 python3
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  exit 0
fi

echo "install-deps: installing ${missing[*]}" >&2
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
