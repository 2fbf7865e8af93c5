#!/usr/bin/env bash
# `pip wheel --no-build-isolation` of this checkout, installed into a fresh virtual environment,
# and the pytest suite run against the installed package (not the build tree). The wheel must
# be self-contained: with no LD_LIBRARY_PATH, every library the module loads beyond the
# system's (setup.py's SYSTEM_LIBRARIES) resolves inside the wheel's fq.libs/ (ldd), the
# import loads them from there (/proc/self/maps) and fq.filter smooths a small mesh.
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
export LD_LIBRARY_PATH=
"$venv_python" - "$source" <<'PY'
import os, re, subprocess, sys
import numpy as np  # first: a library the process already has is not loaded again by fq


def mapped():
    with open("/proc/self/maps") as maps:
        return {line.split()[-1] for line in maps if "/" in line}


before = mapped()
import fq
where = os.path.dirname(fq.__file__)
assert where.startswith(sys.prefix), f"fq imported from {where}, not from the venv {sys.prefix}"
for name in ("py.typed", "__init__.pyi", "mesh.py"):
    assert os.path.exists(os.path.join(where, name)), f"the wheel has no fq/{name}"
libs = os.path.realpath(os.path.join(where, "..", "fq.libs"))  # as the loader and /proc name it
bundled = sorted(os.listdir(libs))
draco = next((name for name in bundled if name.startswith("libdraco")), None)
assert draco, f"fq.libs/ has no Draco: {bundled}"
sys.path.insert(0, sys.argv[1])  # setup.py's list of system libraries
from setup import SYSTEM_LIBRARIES  # noqa: E402
ldd = subprocess.run(["ldd", fq._fq.__file__], check=True, capture_output=True, text=True).stdout
for name, path in re.findall(r"^\s*(\S+) => (\S+)", ldd, re.M):
    inside = os.path.realpath(path) == os.path.join(libs, name)  # ldd: <venv>/fq/../fq.libs/NAME
    assert SYSTEM_LIBRARIES.fullmatch(name) or inside, f"{name} => {path}:\n{ldd}"
loaded = mapped() - before
outside = [p for p in loaded if os.path.basename(p) in bundled and not p.startswith(libs + "/")]
assert not outside, f"libraries of fq.libs/ loaded from elsewhere: {outside}"
assert os.path.join(libs, draco) in loaded, f"{draco} not loaded from fq.libs/: {sorted(loaded)}"
n = 12  # a wavy grid: the filter moves its vertices, the faces stay
V = np.array([[x, y, 0.2 * np.sin(x + 2 * y)] for y in range(n) for x in range(n)], np.float32)
cells = [v for v in range(n * n - n) if v % n < n - 1]
F = np.array([t for v in cells for t in ([v, v + 1, v + n], [v + 1, v + n + 1, v + n])], np.uint32)
moved = np.abs(fq.filter(V, F) - V).max()
assert 0 < moved < 1, moved
print(f"fq {fq.__version__} in {where}, {len(bundled)} libraries in fq.libs/, fq.filter moved {moved:.3f}")
PY
"$venv_python" -m pytest -q -p no:cacheprovider "$source/tests/python"
