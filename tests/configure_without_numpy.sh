#!/usr/bin/env bash
# Configuring the Python module with an interpreter that has no NumPy (as a pyenv Python
# first on PATH): refused at once, naming the interpreter and the ways out — it used to
# build a module that interpreter cannot use. Usage: configure_without_numpy.sh SOURCE_DIR WORK_DIR
set -euo pipefail
src=$1 work=$2
rm -rf "$work" && mkdir -p "$work"
/usr/bin/python3 -m venv --without-pip "$work/venv"  # no --system-site-packages: no NumPy
if "$work/venv/bin/python" -c "import numpy" 2>/dev/null; then echo "the venv has NumPy: nothing to test"; exit 1; fi
if cmake -S "$src" -B "$work/build" -G Ninja -DPython3_EXECUTABLE="$work/venv/bin/python" >"$work/out" 2>&1; then
  echo "configured without NumPy:"; cat "$work/out"; exit 1
fi
# CMake wraps the message's lines: compare it as one line.
message=$(tr -s ' \n' '  ' <"$work/out")
for expected in "the Python module needs NumPy, and $work/venv/bin/python has none" "-DLIBWAVE_BUILD_PYTHON=OFF"; do
  [[ $message == *"$expected"* ]] || { echo "missing '$expected' in:"; cat "$work/out"; exit 1; }
done
rm -rf "$work"
echo "ok: refused, naming the interpreter"
