"""Builds the Python package effigi for `pip install ./python` (pyproject.toml).

The compiled modules come from the project's CMake build, not from setuptools: the target
effigi_python is built in build/release (configured with the release preset if it is not
yet; another build folder through EFFIGI_BUILD_DIR), and its two modules are copied into
the wheel. They link libeffigi of that build by absolute path (their RPATH), and libeffigi
finds its component modules beside itself, so the build folder must stay where it is.
"""
import os
import pathlib
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent


def project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(effigi VERSION ([0-9.]+)", text).group(1)


class CMakeBuild(build_ext):
    """Builds effigi_python with CMake and copies the modules it wrote (no compiler here)."""

    def run(self):
        build = pathlib.Path(os.environ.get("EFFIGI_BUILD_DIR", ROOT / "build" / "release")).resolve()
        if not (build / "CMakeCache.txt").is_file():
            # A fresh checkout: configure for this interpreter.
            python = f"-DPython_EXECUTABLE={sys.executable}"
            if "EFFIGI_BUILD_DIR" in os.environ:
                cmd = ["cmake", "-S", str(ROOT), "-B", str(build), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release", python]
            else:
                cmd = ["cmake", "--preset", "release", python]
            subprocess.run(cmd, cwd=ROOT, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 2)
        try:
            subprocess.run(["cmake", "--build", str(build), "--target", "effigi_python", "-j", jobs], check=True)
        except subprocess.CalledProcessError:
            sys.exit(f"effigi: building the target effigi_python in {build} failed. It exists only where CMake found "
                     "pybind11 (pybind11-dev) and Python's headers (python3-dev): see 'Python module effigi' in the "
                     "output of `cmake --preset release`.")
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        for ext in self.extensions:
            name = ext.name.split(".")[-1]
            built = build / "python" / "effigi" / f"{name}{suffix}"
            if not built.is_file():
                sys.exit(f"effigi: {built} is missing: {build} builds the module for another Python than "
                         f"{sys.executable}. Reconfigure it for this one: cmake {build} -DPython_EXECUTABLE={sys.executable}")
            target = pathlib.Path(self.get_ext_fullpath(ext.name))
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(built, target)


setup(
    version=project_version(),
    packages=["effigi"],
    ext_modules=[Extension("effigi._effigi", sources=[]), Extension("effigi._conform", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)
