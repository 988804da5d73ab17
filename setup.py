"""The pip build of the Python module (pyproject.toml): setuptools with one CMake step.

CMake configures and builds the library and the module only (no tests, apps or benchmarks), in
Release, in a build folder of its own: build-pip/ beside this file (build/ is the developers' CMake
folder and is never touched), or $LIBDEM_PIP_BUILD_DIR. The folder is kept, so a second install
rebuilds only what changed; a CMake cache made by another generator or for another source folder
or Python is started afresh. The build uses $CMAKE_BUILD_PARALLEL_LEVEL jobs if set, else every
core this process may use; $LIBDEM_CMAKE_ARGS adds configure arguments (e.g. -DLIBDEM_NATIVE=ON).

The package libdem is the extension module itself (libdem/__init__.<abi>.so, the same module as the
CMake build's build/python/libdem.<abi>.so), its type stubs libdem/__init__.pyi (python/stubgen.py,
run on the built module) and py.typed. An editable install (pip install -e .) puts the package in
<build folder>/python/libdem and a .pth file names that folder; install again after a change to
the C++ sources or the bindings.
"""

import os
import re
import shlex
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent
BUILD = Path(os.environ.get("LIBDEM_PIP_BUILD_DIR") or ROOT / "build-pip").resolve()
CMAKE_BUILD = BUILD / "cmake"
PACKAGE_PARENT = BUILD / "python"  # an editable install's package folder is PACKAGE_PARENT/libdem
STAMP = "libdem-pip-module-suffix.txt"  # in CMAKE_BUILD: the Python the cache was configured for


def version():
    text = (ROOT / "CMakeLists.txt").read_text()
    found = re.search(r"project\(\s*libdem\s+VERSION\s+([0-9.]+)", text)
    if not found:
        raise RuntimeError("CMakeLists.txt: no project(libdem VERSION x.y.z) to take the package version from")
    return found.group(1)


def cached(cache_text, name):
    found = re.search(r"^" + re.escape(name) + r":[A-Z]+=(.*)$", cache_text, re.MULTILINE)
    return found.group(1) if found else None


class CMakeBuild(build_ext):
    """Builds the module with CMake and places it, its stubs and py.typed in the package folder."""

    def build_extension(self, ext):
        cmake = shutil.which("cmake")
        if cmake is None:
            raise RuntimeError("cmake not found on PATH: scripts/install-deps installs it and the C++ dependencies")
        generator = "Ninja" if shutil.which("ninja") else "Unix Makefiles"
        ext_suffix = sysconfig.get_config_var("EXT_SUFFIX")
        self.start_afresh_if_stale(generator, ext_suffix)

        configure = [cmake, "-S", str(ROOT), "-B", str(CMAKE_BUILD), "-G", generator,
                     "-DCMAKE_BUILD_TYPE=Release", "-DLIBDEM_BUILD_TESTS=OFF", "-DLIBDEM_BUILD_APPS=OFF",
                     "-DLIBDEM_BUILD_PYTHON=ON", "-DLIBDEM_SANITIZE=OFF", "-DLIBDEM_MPI=OFF",
                     f"-DLIBDEM_PYTHON_EXECUTABLE={sys.executable}"]
        try:  # the pybind11 of the build environment (the full package index's), else the system's
            import pybind11
            configure.append(f"-Dpybind11_DIR={pybind11.get_cmake_dir()}")
        except ImportError:
            pass
        configure += shlex.split(os.environ.get("LIBDEM_CMAKE_ARGS", ""))
        build = [cmake, "--build", str(CMAKE_BUILD), "--target", "libdem_python_stubs"]
        if not os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL"):  # cmake --build reads it itself
            build += ["--parallel", str(len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count())]
        for command in (configure, build):
            print("libdem:", shlex.join(command), flush=True)
            subprocess.run(command, check=True)
            if command is configure:
                (CMAKE_BUILD / STAMP).write_text(ext_suffix + "\n")

        module = CMAKE_BUILD / "python" / ("libdem" + ext_suffix)
        stubs = CMAKE_BUILD / "python" / "libdem.pyi"
        for made in (module, stubs):
            if not made.is_file():
                raise RuntimeError(f"the CMake build made no {made}")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(module, target)
        shutil.copyfile(stubs, target.parent / "__init__.pyi")
        (target.parent / "py.typed").write_text("")

    def start_afresh_if_stale(self, generator, ext_suffix):
        """Removes a CMake cache that would make this configure fail or build for another Python."""
        cache = CMAKE_BUILD / "CMakeCache.txt"
        if not cache.is_file():
            return
        text = cache.read_text(errors="replace")
        home = cached(text, "CMAKE_HOME_DIRECTORY")
        stamp = CMAKE_BUILD / STAMP
        stale = {"generator": (cached(text, "CMAKE_GENERATOR"), generator),
                 "source folder": (home and str(Path(home).resolve()), str(ROOT)),
                 "Python module suffix": (stamp.read_text().strip() if stamp.is_file() else None, ext_suffix)}
        stale = {what: values for what, values in stale.items() if values[0] != values[1]}
        if stale:
            print(f"libdem: starting {CMAKE_BUILD} afresh: its cache has another "
                  + ", ".join(f"{what} ({old!r}, not {new!r})" for what, (old, new) in stale.items()), flush=True)
            cache.unlink()
            shutil.rmtree(CMAKE_BUILD / "CMakeFiles", ignore_errors=True)

    def copy_extensions_to_source(self):
        """An editable install: the stubs and py.typed go beside the module too."""
        package = Path(self.get_finalized_command("build_py").get_package_dir("libdem"))
        package.mkdir(parents=True, exist_ok=True)
        super().copy_extensions_to_source()
        built = Path(self.build_lib) / "libdem"
        for name in ("__init__.pyi", "py.typed"):
            shutil.copyfile(built / name, package / name)


setup(
    version=version(),
    packages=[],
    # Only an editable install reads this: its package folder, named by a .pth file.
    package_dir={"": os.path.relpath(PACKAGE_PARENT, ROOT)},
    ext_modules=[Extension("libdem.__init__", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
    # setuptools' own files stay in the build folder too, out of the source tree.
    options={"build": {"build_base": str(BUILD / "setuptools")}, "egg_info": {"egg_base": str(BUILD)}},
)
