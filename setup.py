"""The compiled module chatter._chatter for pip (pyproject.toml): built by the
project's CMake build (target chatter_python) and copied into the wheel
beside the pure-Python package python/chatter/.

Environment:
  CHATTER_CMAKE_BUILD_DIR  an existing, configured CMake build tree to build
                           the target in (scripts/build.sh's build/): only
                           what changed is rebuilt. Default: a fresh tree in
                           setuptools' build_temp (the whole library, minutes).
  CMAKE_BUILD_PARALLEL_LEVEL  jobs (default: the CPU count).
"""
import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        given = os.environ.get("CHATTER_CMAKE_BUILD_DIR")
        if given:
            build = pathlib.Path(given).resolve()
            if not (build / "CMakeCache.txt").exists():
                raise RuntimeError(f"CHATTER_CMAKE_BUILD_DIR={given}: not a configured CMake build tree "
                                   "(run scripts/build.sh, or unset it to build afresh)")
        else:
            build = pathlib.Path(self.build_temp).resolve() / "cmake"
            subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                            "-DCHATTER_BUILD_TESTS=OFF", "-DCHATTER_BUILD_BENCH=OFF", "-DCHATTER_MPI=OFF",
                            "-DCHATTER_PYTHON=ON", f"-DPython_EXECUTABLE={sys.executable}"], check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        subprocess.run(["cmake", "--build", str(build), "--target", "chatter_python", "-j", jobs], check=True)
        built = sorted((build / "python" / "chatter").glob("_chatter*.so"))
        if not built:
            raise RuntimeError(f"{build}/python/chatter: the build made no _chatter module")
        dest = pathlib.Path(self.get_ext_fullpath(ext.name))
        dest.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built[0], dest)


setup(ext_modules=[CMakeExtension("chatter._chatter")], cmdclass={"build_ext": CMakeBuild})
