"""`pip install .`: the extension woven._woven built by the project's CMake (target woven_python)
for the interpreter pip runs, in build/pip (or WOVEN_CMAKE_BUILD_DIR, an existing build folder to
reuse), then copied into the wheel beside python/woven/__init__.py. pyproject.toml holds the
rest; docs/PYTHON.md the commands."""
import os
import re
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))


def version():
    text = open(os.path.join(ROOT, "CMakeLists.txt")).read()
    return re.search(r"project\(woven VERSION ([0-9.]+)", text).group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = os.environ.get("WOVEN_CMAKE_BUILD_DIR") or os.path.join(ROOT, "build", "pip")
        if not os.path.exists(os.path.join(build, "CMakeCache.txt")):
            subprocess.run(["cmake", "-S", ROOT, "-B", build, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release", "-DWOVEN_TESTS=OFF",
                            f"-DPYTHON_EXECUTABLE={sys.executable}"], check=True)
        jobs = os.environ.get("WOVEN_BUILD_JOBS", str(os.cpu_count() or 1))
        subprocess.run(["cmake", "--build", build, "--target", "woven_python", "-j", jobs], check=True)
        built = [f for f in os.listdir(os.path.join(build, "python", "woven")) if f.startswith("_woven") and f.endswith(".so")]
        if len(built) != 1:
            raise RuntimeError(f"woven: expected one _woven*.so in {build}/python/woven, found {built}")
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(os.path.join(build, "python", "woven", built[0]), target)


setup(version=version(), ext_modules=[Extension("woven._woven", sources=[])], cmdclass={"build_ext": CMakeBuild})
