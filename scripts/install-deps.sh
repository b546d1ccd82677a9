#!/usr/bin/env bash
# Installs the Debian 12 packages libwave builds, tests and runs with.
# Idempotent: packages already installed are skipped; `apt-get update` runs only
# when something is missing. Needs root (or sudo) only when it installs.
set -euo pipefail

packages=(
  build-essential cmake ninja-build ccache pkg-config git
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  libopenmesh-dev libosd-dev libdraco-dev libmeshoptimizer-dev libtinygltf-dev libstb-dev
  libfftw3-dev libtbb-dev libeigen3-dev libembree-dev liblapack-dev libpng-dev libopenvdb-dev
  nlohmann-json3-dev libcli11-dev
  libgdal-dev gdal-bin
  libgtest-dev libgmock-dev libbenchmark-dev
  pybind11-dev python3-pybind11 python3 python3-dev python3-numpy python3-pytest python3-jsonschema
  python3-venv python3-pip doxygen
  nodejs
  slurm-wlm munge
  libcpp-httplib-dev libssl-dev
)
# `--tests`: also what only the tests need (Chromium for the viewer's browser test,
# clang and its runtimes for the libFuzzer targets, clang-tidy for CI's check of changed
# code, mypy for the Python stubs' check).
if [[ ${1:-} == --tests ]]; then packages+=(chromium clang clang-tidy libclang-rt-14-dev python3-mypy); fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
updated=0
apt_install() {
  echo "install-deps: installing $*" >&2
  if ((updated == 0)); then "${sudo_cmd[@]}" apt-get update -qq; updated=1; fi
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "$@" >/dev/null
}
if ((${#missing[@]} > 0)); then apt_install "${missing[@]}"; fi
# Debian's nodejs ships npm separately (NodeSource's includes it).
if ! command -v npm >/dev/null 2>&1; then apt_install npm; fi

# The Khronos glTF validator (npm), pinned by package-lock.json, for the tests.
validator_dir="$(cd "$(dirname "$0")" && pwd)/gltf-validator"
if [[ ! -f "$validator_dir/node_modules/gltf-validator/package.json" ]]; then
  echo "install-deps: installing the Khronos glTF validator (npm ci)" >&2
  (cd "$validator_dir" && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
fi

# The viewer's JavaScript (three.js, esbuild; playwright-core for its test), pinned by
# package-lock.json; bundled by the build (bindings-cli/CMakeLists.txt).
viewer_dir="$(cd "$(dirname "$0")/.." && pwd)/bindings-cli/viewer"
if [[ ! -f "$viewer_dir/node_modules/.package-lock.json" || "$viewer_dir/package-lock.json" -nt "$viewer_dir/node_modules/.package-lock.json" ]]; then
  echo "install-deps: installing the viewer's npm packages (npm ci)" >&2
  (cd "$viewer_dir" && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
fi
