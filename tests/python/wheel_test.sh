#!/usr/bin/env bash
# `pip wheel --no-build-isolation` of this checkout, installed into a fresh virtual environment,
# and the pytest suite run against the installed package (not the build tree).
# Usage: wheel_test.sh PYTHON SOURCE BUILD WORK
# The wheel reuses the CMake build tree BUILD (FQ_CMAKE_BUILD_DIR): packaging costs seconds,
# where configuring and compiling the module's libraries afresh costs minutes on 2 cores.
# The venv sees the system's site-packages for numpy and pytest (Debian's), nothing of fq.
set -euo pipefail
python=$1 source=$2 build=$3 work=$4
rm -rf "$work"
mkdir -p "$work"
"$python" -m venv --system-site-packages "$work/venv"
venv_python="$work/venv/bin/python"
FQ_CMAKE_BUILD_DIR="$build" "$venv_python" -m pip wheel -q --no-build-isolation --no-deps --no-index \
  -w "$work/dist" "$source"
"$venv_python" -m pip install -q --no-deps --no-index "$work"/dist/fq-*.whl
cd "$work"  # away from the sources: `import fq` must find the installed package
"$venv_python" - <<'PY'
import os, sys
import fq
where = os.path.dirname(fq.__file__)
assert where.startswith(sys.prefix), f"fq imported from {where}, not from the venv {sys.prefix}"
for name in ("py.typed", "__init__.pyi", "mesh.py"):
    assert os.path.exists(os.path.join(where, name)), f"the wheel has no fq/{name}"
print("fq", fq.__version__, "installed in", where)
PY
"$venv_python" -m pytest -q -p no:cacheprovider "$source/tests/python"
