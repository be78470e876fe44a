"""Builds gfmd's C++ core with CMake for the Python package (setuptools drives it; see pyproject.toml).

The extension gfmd._core, the gfmd program (gfmd/bin/gfmd, started by the console script
`gfmd`) and the plotting helpers (gfmd/share/gfmd/scripts) come from one CMake build in
setuptools' build_temp. CMake is started by argument vector (no shell). GFMD_CMAKE_ARGS adds
arguments (split on spaces), GFMD_BUILD_JOBS sets the parallelism (default: all cores).
GFMD_BUILD_DIR names a CMake build directory configured already (scripts/setup.sh passes
its build/): only the package's targets are built there, nothing is configured again.
"""
import os
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        jobs = os.environ.get("GFMD_BUILD_JOBS", str(os.cpu_count() or 1))
        given = os.environ.get("GFMD_BUILD_DIR", "")
        if given:
            build = Path(given).resolve()
            if not (build / "CMakeCache.txt").is_file():
                raise RuntimeError(f"GFMD_BUILD_DIR={given} is not a configured CMake build directory")
        else:
            build = Path(self.build_temp).resolve() / "cmake"
            build.mkdir(parents=True, exist_ok=True)
            configure = ["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                         "-DGFMD_BUILD_TESTS=OFF", f"-DGFMD_PYTHON={sys.executable}"]
            try:  # pybind11 from pip (isolated builds); Debian's pybind11-dev has only its CMake files
                import pybind11

                configure.append(f"-Dpybind11_DIR={pybind11.get_cmake_dir()}")
            except ImportError:
                pass
            configure += [a for a in os.environ.get("GFMD_CMAKE_ARGS", "").split(" ") if a]
            subprocess.run(configure, check=True)
        subprocess.run(["cmake", "--build", str(build), "-j", jobs, "--target", "gfmd_python", "gfmd"], check=True)
        target = Path(self.get_ext_fullpath(ext.name)).resolve()
        package = target.parent
        package.mkdir(parents=True, exist_ok=True)
        cores = sorted((build / "python" / "gfmd").glob("_core*.so"))
        if not cores:
            raise RuntimeError("the CMake build made no gfmd/_core*.so (are pybind11-dev and python3-dev installed?)")
        shutil.copy2(cores[0], target)
        (package / "bin").mkdir(exist_ok=True)
        shutil.copy2((build / "gfmd").resolve(), package / "bin" / "gfmd")
        scripts = package / "share" / "gfmd" / "scripts"
        scripts.mkdir(parents=True, exist_ok=True)
        for f in (build / "share" / "gfmd" / "scripts").iterdir():
            shutil.copy2(f, scripts / f.name)


setup(ext_modules=[CMakeExtension("gfmd._core")], cmdclass={"build_ext": CMakeBuild}, zip_safe=False)
