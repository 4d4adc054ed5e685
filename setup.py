# Builds the extension ndfmip._ndfmip with CMake (target ndfmip_python) against a static
# library, so the installed package is one self-contained file plus its Python sources.
# Set CMAKE_BUILD_PARALLEL_LEVEL to choose the build's jobs (default: every core).
import os
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


class CMakeBuild(build_ext):
    def build_extension(self, ext: Extension) -> None:
        build = Path(self.build_temp).resolve() / "cmake"
        configure = ["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                     "-DNDFMIP_PYTHON=ON", "-DNDFMIP_BUILD_CLI=OFF", "-DNDFMIP_BUILD_TESTS=OFF",
                     "-DNDFMIP_BUILD_BENCH=OFF", "-DNDFMIP_GPU=OFF", "-DBUILD_SHARED_LIBS=OFF",
                     f"-DPython3_EXECUTABLE={sys.executable}"]
        if shutil.which("ninja") and not (build / "CMakeCache.txt").exists():
            configure += ["-G", "Ninja"]
        if shutil.which("ccache"):
            configure.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        subprocess.run(configure, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        subprocess.run(["cmake", "--build", str(build), "--target", "ndfmip_python", "--parallel", jobs], check=True)
        built = next((build / "python" / "ndfmip").glob("_ndfmip*.so"))
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


setup(ext_modules=[Extension("ndfmip._ndfmip", sources=[])], cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": "build-python"}, "egg_info": {"egg_base": "build-python"}})
