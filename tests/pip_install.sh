#!/usr/bin/env bash
# `pip install .` into a fresh venv (Debian's NumPy through --system-site-packages; no
# index: nothing may be downloaded), then the stage-by-stage example with the venv's
# Python: the module imports from the venv and its frame equals the scene pipeline's bit
# for bit. Usage: pip_install.sh SOURCE_DIR BUILD_DIR WORK_DIR
set -euo pipefail
src=$1 build=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
/usr/bin/python3 -m venv --system-site-packages "$work/venv"
"$work/venv/bin/pip" install -q --no-build-isolation --no-index --config-settings=build-dir="$build" "$src"
cd "$work"  # not the source tree: the import must come from the venv
where=$("$work/venv/bin/python" -c "import libwave; print(libwave.__file__)")
[[ $where == "$work/venv/"* ]] || { echo "libwave imported from $where, not the venv"; exit 1; }
files=$("$work/venv/bin/pip" show -f libwave)  # (not piped into grep -q: pip would see a broken pipe)
[[ $files == *_libwave.pyi* && $files == *py.typed* ]] || { echo "the wheel has no stubs:"; echo "$files"; exit 1; }
env -u PYTHONPATH "$work/venv/bin/python" "$src/examples/pipeline.py" \
  "$src/data/bathymetry/okushiri_monai_lab1to400_1p4cm.asc" "$work/frame3.glb" 3
