"""The Python module's build for pip (pyproject.toml): CMake configures and builds the target
pldamp_python of this repository, and the extension it makes goes into the wheel beside
python/pldamp.

    pip install --no-build-isolation .

PLDAMP_BUILD_DIR: the CMake build directory (default build-pip/cmake; an existing one, such as
build/, is reused as it is configured); PLDAMP_CMAKE_ARGS: more arguments for a new one
(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache, say).
"""

import glob
import os
import re
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE = os.path.dirname(os.path.abspath(__file__))
SCRATCH = os.path.join(SOURCE, "build-pip")


def version():
    with open(os.path.join(SOURCE, "CMakeLists.txt"), encoding="utf-8") as cmake:
        return re.search(r"project\(pldamp VERSION ([0-9.]+)", cmake.read()).group(1)


class CMakeExtension(Extension):
    def __init__(self):
        super().__init__("pldamp._pldamp", sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = os.environ.get("PLDAMP_BUILD_DIR", os.path.join(SCRATCH, "cmake"))
        if not os.path.exists(os.path.join(build, "CMakeCache.txt")):
            arguments = ["-DCMAKE_BUILD_TYPE=Release", "-DPython_EXECUTABLE=" + sys.executable,
                         "-DPLDAMP_BUILD_TESTS=OFF", "-DPLDAMP_BUILD_BENCHMARKS=OFF"]
            arguments += os.environ.get("PLDAMP_CMAKE_ARGS", "").split()
            subprocess.run(["cmake", "-S", SOURCE, "-B", build, *arguments], check=True)
        subprocess.run(["cmake", "--build", build, "--target", "pldamp_python", "-j",
                        str(os.cpu_count() or 1)], check=True)
        built = glob.glob(os.path.join(build, "python", "pldamp", "_pldamp*.so"))
        if len(built) != 1:
            sys.exit("the CMake build made no _pldamp extension in %s (Python development "
                     "files, numpy and pybind11 are needed)" % build)
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(built[0], target)


os.makedirs(SCRATCH, exist_ok=True)
setup(
    version=version(),
    packages=["pldamp"],
    package_dir={"": "python"},
    package_data={"pldamp": ["__init__.pyi", "py.typed"]},
    ext_modules=[CMakeExtension()],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": os.path.join(SCRATCH, "setuptools")},
             "egg_info": {"egg_base": SCRATCH}},
)
