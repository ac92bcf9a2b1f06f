"""Builds the module qmaps._engine with the project's CMake for `pip install` (pyproject.toml).
The engine is built in <build_temp>/cmake, or in QMAPS_CMAKE_BUILD_DIR when set (an existing
build folder is built as it is configured, which rebuilds nothing that is up to date)."""
import glob
import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = pathlib.Path(os.environ.get("QMAPS_CMAKE_BUILD_DIR") or
                             pathlib.Path(self.build_temp) / "cmake").resolve()
        if not (build / "CMakeCache.txt").is_file():
            subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                            "-DQMAPS_BUILD_TESTS=OFF", "-DQMAPS_BUILD_BENCHMARKS=OFF",
                            f"-DPython3_EXECUTABLE={sys.executable}"], check=True)
        subprocess.run(["cmake", "--build", str(build), "--target", "qmaps_python", "-j",
                        str(os.cpu_count() or 1)], check=True)
        built = glob.glob(str(build / "python" / "qmaps" / "_engine*.so"))
        if not built:
            raise RuntimeError(f"{build}: the build made no python/qmaps/_engine*.so")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], target)


# setuptools' own folders under build/pip, beside a CMake build in build/.
setup(ext_modules=[Extension("qmaps._engine", sources=[])], cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": "build/pip"}})
