"""Builds volguide's Python module and CLI with CMake for `pip install .` (docs/python.md).

The extension volguide._core and the `volguide` executable (installed as volguide/bin/volguide, run by
the `volguide` console script) come from one CMake build: a build directory of its own under
setuptools' build_temp, or VOLGUIDE_CMAKE_BUILD_DIR (an existing build directory, reused as it is
configured, e.g. the project's build/, so that the install only relinks what changed).
VOLGUIDE_CMAKE_JOBS: parallel build jobs (default: the CPU count).
"""
import os
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE_DIR = os.path.dirname(os.path.abspath(__file__))
# What the package needs: the module and the CLI, without tests, benchmarks or the Open PGL peer.
CMAKE_OPTIONS = ["-DCMAKE_BUILD_TYPE=Release", "-DVOLGUIDE_BUILD_PYTHON=ON", "-DVOLGUIDE_BUILD_TESTS=OFF",
                 "-DVOLGUIDE_BUILD_BENCH=OFF", "-DVOLGUIDE_WITH_OPENPGL=OFF"]


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build_dir = os.environ.get("VOLGUIDE_CMAKE_BUILD_DIR") or os.path.join(os.path.abspath(self.build_temp), "cmake")
        if not os.path.exists(os.path.join(build_dir, "CMakeCache.txt")):
            # The interpreter pip runs is the one the module is for (a venv's python resolves to its base).
            subprocess.check_call(["cmake", "-S", SOURCE_DIR, "-B", build_dir, *CMAKE_OPTIONS,
                                   "-DPython3_EXECUTABLE=" + sys.executable])
        jobs = os.environ.get("VOLGUIDE_CMAKE_JOBS", str(os.cpu_count() or 1))
        subprocess.check_call(["cmake", "--build", build_dir, "-j", jobs, "--target", "volguide_python", "volguide_cli"])
        self.install_outputs(build_dir, ext)

    def install_outputs(self, build_dir, ext):
        package_dir = os.path.join(build_dir, "python", "volguide")
        core = [f for f in os.listdir(package_dir) if f.startswith("_core") and f.endswith(".so")]
        if len(core) != 1:
            raise RuntimeError(f"expected one _core extension in {package_dir}, found {core}")
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(os.path.join(package_dir, core[0]), target)
        bin_dir = os.path.join(os.path.dirname(target), "bin")
        os.makedirs(bin_dir, exist_ok=True)
        shutil.copy2(os.path.join(build_dir, "volguide"), os.path.join(bin_dir, "volguide"))


# setuptools' own build folder apart from the project's build/ (the default would nest in it).
setup(ext_modules=[Extension("volguide._core", sources=[])], cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": "build-pip"}, "egg_info": {"egg_base": "build-pip"}})
