#!/usr/bin/env bash
# `pip install .` where an installed libwave of this version is found (the prefix the
# install_and_consume test installs): only the module is built, against it (no library
# source compiled), and it runs the stage-by-stage example equal bit for bit to the
# scene pipeline. Usage: pip_installed.sh SOURCE_DIR PREFIX WORK_DIR
set -euo pipefail
src=$1 prefix=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
/usr/bin/python3 -m venv --system-site-packages "$work/venv"
CMAKE_PREFIX_PATH="$prefix" "$work/venv/bin/pip" install -v --no-build-isolation --no-index "$src" > "$work/pip.log" 2>&1 ||
  { tail -40 "$work/pip.log"; exit 1; }
grep -q "libwave build: found one; building the module alone against it" "$work/pip.log" ||
  { echo "the installed libwave in $prefix was not used:"; grep "libwave build" "$work/pip.log"; exit 1; }
# Only the module's three sources are compiled: no object of the library's components.
if grep "Building CXX object" "$work/pip.log" | grep -v "CMakeFiles/libwave_python.dir/"; then
  echo "library sources were compiled, though an installed libwave was found"; exit 1
fi
cd "$work"  # not the source tree: the import must come from the venv
env -u PYTHONPATH "$work/venv/bin/python" "$src/examples/pipeline.py" \
  "$src/data/bathymetry/okushiri_monai_lab1to400_1p4cm.asc" "$work/frame3.glb" 3
echo "pip built the module alone against $prefix"
