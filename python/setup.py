"""Builds the `dwatch` wheel (python/pyproject.toml; docs/python.md, "A wheel"): setuptools with CMake.

    DWATCH_BUILD_DIR=$PWD/build /usr/bin/python3 -m build --wheel --no-isolation python/   # reuses build/
    /usr/bin/python3 -m build --wheel --no-isolation python/                          # runs CMake itself

The compiled part, `_dwatch*.so`, is what CMake builds (python/CMakeLists.txt): with DWATCH_BUILD_DIR
naming a configured build tree in which `dwatch_python` is built, the wheel takes the module from
there and builds nothing (CI builds the project once); without it, CMake configures a Release tree
in python/build/cmake and builds the module's target alone. Either way the module must have been
built for the interpreter building the wheel, which the wheel's tag names. The wheel holds the
package (python/dwatch), the module, what CMake wrote beside it (_build_info.py) and the shipped
scenarios (scenarios/*.toml and scenarios/lua/), so that `dwatch.scenario_path(...)` finds them
outside a checkout. It links Debian 12's shared libraries (Bullet, Lua, OSMesa, ...): a wheel for
Debian 12, not a manylinux one.
"""

import importlib.machinery
import os
import pathlib
import re
import shutil
import subprocess
import sys

from setuptools import setup
from setuptools.command.build_py import build_py
from setuptools.dist import Distribution

HERE = pathlib.Path(__file__).resolve().parent
SOURCE = HERE.parent  # the CMake project's root
# setuptools' files (and CMake's, when it builds): beside the build tree given, else in python/build
# (python/.gitignore), never among the sources.
WORK = pathlib.Path(os.environ["DWATCH_BUILD_DIR"]).resolve() / "python" / "wheel" if os.environ.get(
    "DWATCH_BUILD_DIR") else HERE / "build"


def project_version() -> str:
    """The version of the CMake project (CMakeLists.txt's project()), the one source of it."""
    found = re.search(r"project\(dwatch VERSION ([0-9.]+)", (SOURCE / "CMakeLists.txt").read_text())
    if not found:
        raise SystemExit("setup.py: no `project(dwatch VERSION x.y.z` in CMakeLists.txt")
    return found.group(1)


def cmake_build_dir() -> pathlib.Path:
    """The build tree holding python/dwatch/_dwatch*.so: DWATCH_BUILD_DIR's, or one CMake makes now."""
    given = os.environ.get("DWATCH_BUILD_DIR")
    if given:
        build = pathlib.Path(given)
        if not (build / "CMakeCache.txt").is_file():
            raise SystemExit(f"setup.py: DWATCH_BUILD_DIR={given} is not a CMake build tree (no CMakeCache.txt; "
                             f"a relative path is read from {HERE}, where the build runs)")
        return build.resolve()
    build = HERE / "build" / "cmake"
    configure = ["cmake", "-S", str(SOURCE), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                 f"-DPython3_EXECUTABLE={sys.executable}", "-DDWATCH_PYTHON=ON"]
    if shutil.which("ninja"):
        configure += ["-G", "Ninja"]
    subprocess.run(configure, check=True)
    subprocess.run(["cmake", "--build", str(build), "--target", "dwatch_python", "--parallel",
                    str(os.cpu_count() or 1)], check=True)
    return build


def compiled_module(build: pathlib.Path) -> pathlib.Path:
    """The module built for this interpreter (its suffix says which: .cpython-311-x86_64-linux-gnu.so)."""
    folder = build / "python" / "dwatch"
    suffix = importlib.machinery.EXTENSION_SUFFIXES[0]
    module = folder / f"_dwatch{suffix}"
    if module.is_file():
        return module
    others = sorted(p.name for p in folder.glob("_dwatch*.so"))
    if others:
        raise SystemExit(f"setup.py: {folder} holds {', '.join(others)}, built for another interpreter than this "
                         f"one ({sys.executable}, which loads _dwatch{suffix}): build the wheel with the "
                         f"interpreter the build tree was configured for, or configure one for this interpreter")
    raise SystemExit(f"setup.py: no {module.name} in {folder}: build the target dwatch_python there first "
                     f"(cmake --build {build} --target dwatch_python)")


class BuildWithCMake(build_py):
    """The pure-Python package, then the compiled module, its build info and the scenarios beside it."""

    def run(self) -> None:
        super().run()
        build = cmake_build_dir()
        package = pathlib.Path(self.build_lib) / "dwatch"
        shutil.copy2(compiled_module(build), package)
        shutil.copy2(build / "python" / "dwatch" / "_build_info.py", package)
        scenarios = package / "scenarios"
        shutil.rmtree(scenarios, ignore_errors=True)
        scenarios.mkdir()
        for toml in (SOURCE / "scenarios").glob("*.toml"):
            shutil.copy2(toml, scenarios)
        shutil.copytree(SOURCE / "scenarios" / "lua", scenarios / "lua")


class CompiledDistribution(Distribution):
    """A wheel for this interpreter and platform (cp311-cp311-linux_x86_64), not a pure one."""

    def has_ext_modules(self) -> bool:
        return True


WORK.mkdir(parents=True, exist_ok=True)
setup(
    version=project_version(),
    packages=["dwatch"],
    package_data={"dwatch": ["py.typed", "_dwatch.pyi"]},
    exclude_package_data={"dwatch": ["_build_info.py.in"]},
    cmdclass={"build_py": BuildWithCMake},
    distclass=CompiledDistribution,
    options={"build": {"build_base": str(WORK / "setuptools")}, "egg_info": {"egg_base": str(WORK)}},
)
