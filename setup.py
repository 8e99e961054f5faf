"""Builds the extension fulcrum._fulcrum with the project's CMake (see
pyproject.toml and docs/python.md, "Install"). Everything comes from the
machine: CMake, a C++20 compiler, pybind11 and NumPy from Debian's packages
(scripts/install-deps.sh); nothing is downloaded."""
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
        build_dir = ROOT / "build" / f"pip-py{sys.version_info.major}{sys.version_info.minor}"
        configure = ["cmake", "-S", str(ROOT), "-B", str(build_dir), "-DCMAKE_BUILD_TYPE=Release",
                     "-DFULCRUM_BUILD_PYTHON=ON", "-DFULCRUM_BUILD_TESTS=OFF", "-DFULCRUM_BUILD_APPS=OFF",
                     f"-DPython_EXECUTABLE={sys.executable}"]
        if shutil.which("ccache"):
            configure.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        subprocess.run(configure, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "_fulcrum", "-j", jobs], check=True)
        built = next((build_dir / "python" / "fulcrum").glob("_fulcrum*.so"))
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


setup(ext_modules=[Extension("fulcrum._fulcrum", sources=[])], cmdclass={"build_ext": CMakeBuild})
