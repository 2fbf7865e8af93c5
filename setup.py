"""setuptools' side of `pip install .` (pyproject.toml): the `fq._fq` extension is built by
this project's CMake build, not by setuptools' compiler driver, because it links the same
static libraries as the tools (kernels, mesh I/O through Draco and assimp, optionally CUDA).

Environment:
  CMAKE_ARGS                 extra configure arguments (-DFQ_CUDA=OFF, a compiler launcher, ...)
  CMAKE_BUILD_PARALLEL_LEVEL build jobs (default: all cores)
  FQ_CMAKE_BUILD_DIR         an already configured build tree of this checkout whose module is
                             built for this Python: only its module target is brought up to
                             date there and packaged (what the wheel test does); by default
                             the project is configured in build/setuptools/cmake.<python tag>.
"""
import os
import re
import shlex
import shutil
import subprocess
import sysconfig
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent
# setuptools' own build and metadata folders, out of the source folders (build/ is also the
# default CMake build tree of scripts/build.sh: a subfolder there disturbs nothing).
BUILD_BASE = ROOT / "build" / "setuptools"


def project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(fq VERSION ([0-9.]+)", text).group(1)


class CMakeBuild(build_ext):
    """Builds the CMake target fq_python and copies the module and its type stub."""

    def run(self):
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        given = os.environ.get("FQ_CMAKE_BUILD_DIR")
        tree = Path(given).resolve() if given else BUILD_BASE / f"cmake{suffix.rsplit('.', 1)[0]}"
        if not given:
            self.configure(tree)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        subprocess.run(["cmake", "--build", str(tree), "--target", "fq_python", "-j", jobs], check=True)
        built = tree / "python" / "fq" / f"_fq{suffix}"
        if not built.exists():
            found = sorted(p.name for p in (tree / "python" / "fq").glob("_fq*"))
            sys.exit(f"setup.py: {tree} has no {built.name} for this Python ({sys.executable}); it has "
                     f"{found or 'no module'}: configure it with -DPython3_EXECUTABLE={sys.executable} "
                     "or leave FQ_CMAKE_BUILD_DIR unset")
        for ext in self.extensions:
            target = Path(self.get_ext_fullpath(ext.name))
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(built, target)
            shutil.copyfile(built.parent / "__init__.pyi", target.parent / "__init__.pyi")

    def configure(self, tree):
        """Configures `tree` the first time, and again when CMAKE_ARGS asks for changes; a
        configured tree reconfigures itself when the CMake files change."""
        extra = shlex.split(os.environ.get("CMAKE_ARGS", ""))
        args = ["cmake", "-S", str(ROOT), "-B", str(tree)]
        if not (tree / "CMakeCache.txt").exists():
            args += ["-DCMAKE_BUILD_TYPE=Release", f"-DPython3_EXECUTABLE={sys.executable}",
                     "-DFQ_BUILD_TESTS=OFF"] + (["-G", "Ninja"] if shutil.which("ninja") else [])
        elif not extra:
            return
        subprocess.run(args + extra, check=True)


BUILD_BASE.mkdir(parents=True, exist_ok=True)
setup(
    version=project_version(),
    ext_modules=[Extension("fq._fq", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": str(BUILD_BASE)}, "egg_info": {"egg_base": str(BUILD_BASE)}},
)
