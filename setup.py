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

The package carries the shared libraries the module needs beyond the system's (Draco, assimp,
protobuf, ZeroMQ, OpenMP, ... and theirs) in fq.libs/ beside fq/, found through the RUNPATH
that patchelf (Debian package patchelf) sets, so that the wheel runs where they are not
installed. This is what auditwheel repair does; auditwheel is not a Debian package.
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
# The libraries a wheel leaves to the system: those of the manylinux policies (PEP 599, 600)
# that the module can link, and the dynamic loader. Every other library it loads is packaged.
SYSTEM_LIBRARIES = re.compile(
    r"(ld-linux.*|lib(c|m|dl|rt|pthread|util|nsl|resolv|gcc_s|stdc\+\+))\.so(\.[0-9]+)*")


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
            if not self.inplace:
                bundle_libraries(target, target.parent.parent / "fq.libs")

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


def bundle_libraries(module, libs):
    """Copies every non-system library that `module` loads (ldd: directly or through another)
    into `libs`; the module then finds them through its RUNPATH, and they one another through
    theirs ($ORIGIN: a RUNPATH serves only the direct needs of its own file)."""
    patchelf = shutil.which("patchelf")
    if not patchelf:
        sys.exit("setup.py: patchelf not found (Debian package patchelf): it packages the module's libraries")
    shutil.rmtree(libs, ignore_errors=True)
    libs.mkdir(parents=True)
    ldd = subprocess.run(["ldd", str(module)], check=True, capture_output=True, text=True).stdout
    for name, path in re.findall(r"^\s*(\S+) => (.+?)(?: \(0x[0-9a-f]+\))?$", ldd, re.M):
        if SYSTEM_LIBRARIES.fullmatch(name):
            continue
        if not os.path.isabs(path):
            sys.exit(f"setup.py: {module.name} needs {name}, which ldd does not find: {path}")
        shutil.copyfile(path, libs / name)
        subprocess.run([patchelf, "--set-rpath", "$ORIGIN", str(libs / name)], check=True)
    subprocess.run([patchelf, "--set-rpath", f"$ORIGIN/../{libs.name}", str(module)], check=True)


if __name__ == "__main__":  # as pip and `python setup.py` run it; the wheel test imports SYSTEM_LIBRARIES
    BUILD_BASE.mkdir(parents=True, exist_ok=True)
    setup(
        version=project_version(),
        ext_modules=[Extension("fq._fq", sources=[])],
        cmdclass={"build_ext": CMakeBuild},
        options={"build": {"build_base": str(BUILD_BASE)}, "egg_info": {"egg_base": str(BUILD_BASE)}},
    )
