"""Builds the smalliso package: its compiled core, smalliso._core, comes from the project's CMake
build (the module's library and python/CMakeLists.txt), configured for this interpreter."""

import os
import pathlib
import shutil
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext
from setuptools.command.sdist import sdist

HERE = pathlib.Path(__file__).resolve().parent
# What the CMake build of the core reads, relative to the repository. An sdist carries them in cpp/.
CORE_SOURCES = ("CMakeLists.txt", "itk-module.cmake", "LICENSE", "CMake", "include", "src",
                "python/CMakeLists.txt", "python/src", "python/smalliso/_version.py")


def project_root():
    """The C++ project: the sdist's copy, or the repository around this folder."""
    bundled = HERE / "cpp"
    return bundled if (bundled / "CMakeLists.txt").is_file() else HERE.parent


class BuildCore(build_ext):
    """Configures the project for the module and this package only (no tools, no tests) and
    builds the _core target. SMALLISO_CMAKE_BUILD_DIR names a build directory to use instead,
    such as one already configured by scripts/setup.sh, where only _core is brought up to date."""

    def build_extension(self, extension):
        build = pathlib.Path(os.environ.get("SMALLISO_CMAKE_BUILD_DIR") or
                             pathlib.Path(self.build_temp).resolve() / "cmake")
        if not (build / "CMakeCache.txt").is_file():
            configure = ["cmake", "-S", str(project_root()), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                         "-DBUILD_TESTING=OFF", "-DSmallIsoComponent_BUILD_APPS=OFF",
                         "-DSmallIsoComponent_BUILD_PYTHON=ON", f"-DPython3_EXECUTABLE={sys.executable}"]
            try:
                import pybind11  # pybind11's CMake files, when it came from the package index
                configure.append(f"-Dpybind11_DIR={pybind11.get_cmake_dir()}")
            except ImportError:
                pass
            if shutil.which("ninja"):
                configure += ["-G", "Ninja"]
            self.spawn(configure)
        self.spawn(["cmake", "--build", str(build), "--target", "_core", "--parallel", str(os.cpu_count() or 1)])
        built = build / "python" / "smalliso" / ("_core" + sysconfig.get_config_var("EXT_SUFFIX"))
        target = pathlib.Path(self.get_ext_fullpath(extension.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


class SourceWithCore(sdist):
    """An sdist that carries the C++ sources of the core, in cpp/."""

    def make_release_tree(self, base_dir, files):
        super().make_release_tree(base_dir, files)
        root = project_root()
        for name in CORE_SOURCES:
            source, target = root / name, pathlib.Path(base_dir) / "cpp" / name
            target.parent.mkdir(parents=True, exist_ok=True)
            if source.is_dir():
                shutil.copytree(source, target)
            else:
                shutil.copy2(source, target)


setup(ext_modules=[Extension("smalliso._core", sources=[])],
      cmdclass={"build_ext": BuildCore, "sdist": SourceWithCore})
