"""pip's way into the project's CMake: `pip install --no-build-isolation .` configures the
project for this interpreter with only the Python module on (no tests, benchmarks or MPI),
builds its one target and installs the module and its type stubs. The C++ build is the CMake
one, unchanged: this file only drives it (docs/python.md, "Installing with pip").

SPHRAY_CMAKE_ARGS adds arguments to the configure step (for example -DCMAKE_CXX_COMPILER=...);
the build runs on every core unless CMAKE_BUILD_PARALLEL_LEVEL says otherwise.
"""

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(sphray VERSION ([0-9.]+)", text).group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = Path(self.build_temp).resolve() / "cmake"
        build.mkdir(parents=True, exist_ok=True)
        configure = ["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                     f"-DPython_EXECUTABLE={sys.executable}", "-DSPHRAY_PYTHON=ON",
                     "-DSPHRAY_BUILD_TESTS=OFF", "-DSPHRAY_BUILD_BENCH=OFF", "-DSPHRAY_MPI=OFF",
                     "-DSPHRAY_WERROR=OFF"]
        configure += shlex.split(os.environ.get("SPHRAY_CMAKE_ARGS", ""))
        subprocess.run(configure, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        subprocess.run(["cmake", "--build", str(build), "--target", "sphray_python",
                        "--parallel", jobs], check=True)
        module = next((build / "python").glob("sphray*.so"))
        target = Path(self.get_ext_fullpath(ext.name)).resolve()
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(module, target)
        shutil.copy2(ROOT / "python" / "sphray.pyi", target.parent / "sphray.pyi")


# setuptools' own files (build/pip/lib..., build/pip/sphray.egg-info) stay under build/, which
# git ignores, beside the CMake presets' trees.
Path(ROOT / "build" / "pip").mkdir(parents=True, exist_ok=True)
setup(version=project_version(),
      packages=[],
      py_modules=[],
      ext_modules=[Extension("sphray", sources=[])],
      cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": "build/pip"}, "egg_info": {"egg_base": "build/pip"}},
      zip_safe=False)
