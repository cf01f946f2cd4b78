"""The build backend's one step: build the C++ tree with CMake and lay out what it installs.

setuptools (pyproject.toml) runs this for `pip install .` and `pip wheel .`. What goes into
the wheel is what `cmake --install` puts under a prefix, so CMake's install rules stay the one
description of the installed layout:

    PREFIX/lib/pythonX.Y/site-packages/gmwm/   the package and its compiled module (_gmwm)
    PREFIX/bin/gmwm                            the program
    PREFIX/LIBDIR/libgmwm_*.so.MAJOR           the shared libraries both run against
    PREFIX/share/man/man1/gmwm.1               the manual page

Every prefix pip installs into (a virtual environment, --user, /usr/local) keeps these
relative places, so the RPATHs CMake writes ($ORIGIN/../LIBDIR for the program,
$ORIGIN/../../../../LIBDIR for the module) find the libraries there.

The build tree: GMWM_BUILD_DIR (relative to this folder), else build/, the tree
tools/setup.sh makes. An existing tree is reused (an up-to-date one builds nothing, so the
wheel costs seconds); a missing one is configured for the program and the module alone.
GMWM_JOBS sets the parallel build jobs (default: every core).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path
from typing import Dict, List, NoReturn, Optional, Tuple

from setuptools import setup
from setuptools.command.build_py import build_py
from setuptools.dist import Distribution

# After setuptools: its own copy of distutils.
from distutils.command.install_data import install_data  # noqa: E402

ROOT = Path(__file__).resolve().parent
BUILD_DIR = (ROOT / os.environ.get("GMWM_BUILD_DIR", "build")).resolve()
# Where setuptools works and where the install is staged: inside the build tree, so that a
# pip build leaves nothing in the sources.
WHEEL_DIR = BUILD_DIR / "wheel"
STAGE_DIR = WHEEL_DIR / "stage"


def fail(message: str) -> NoReturn:
    raise SystemExit(f"gmwm setup.py: {message}")


def project_version() -> str:
    """The version: the CMake project's, its one place."""
    text = (ROOT / "CMakeLists.txt").read_text(encoding="utf-8")
    m = re.search(r"project\(\s*gmwm\s+VERSION\s+([0-9]+\.[0-9]+\.[0-9]+)", text)
    if not m:
        fail("CMakeLists.txt has no project(gmwm VERSION MAJOR.MINOR.PATCH ...)")
    return m.group(1)


def cmake_cache(build_dir: Path) -> Dict[str, str]:
    cache: Dict[str, str] = {}
    path = build_dir / "CMakeCache.txt"
    if not path.exists():
        return cache
    for line in path.read_text(encoding="utf-8", errors="replace").splitlines():
        m = re.match(r"^([A-Za-z0-9_]+):[A-Z]+=(.*)$", line)
        if m:
            cache[m.group(1)] = m.group(2)
    return cache


def run(cmd: List[str]) -> None:
    print("gmwm setup.py:", " ".join(cmd), flush=True)
    try:
        subprocess.run(cmd, check=True)
    except FileNotFoundError:
        fail(f"{cmd[0]} is not installed (Debian: apt-get install cmake g++; tools/setup.sh lists the rest)")
    except subprocess.CalledProcessError as e:
        fail(f"`{' '.join(cmd)}` failed with exit status {e.returncode}")


def configure(build_dir: Path) -> None:
    """A tree without the Python module (or no tree): configure it with the module on."""
    cache = cmake_cache(build_dir)
    home = cache.get("CMAKE_HOME_DIRECTORY")
    if home is not None and Path(home).resolve() != ROOT:
        # Another checkout's tree: its program and module are not these sources'.
        fail(f"the build tree {build_dir} was configured from {home}, not from {ROOT}: set GMWM_BUILD_DIR to a "
             "tree of these sources (or to a new folder)")
    if cache.get("GMWM_BUILD_PYTHON") == "ON":
        return
    args = ["cmake", "-S", str(ROOT), "-B", str(build_dir), "-DGMWM_BUILD_PYTHON=ON",
            f"-DPython3_EXECUTABLE={sys.executable}"]
    if not cache:
        # A new tree: the program and the module alone (tools/setup.sh turns the tests on later).
        args += ["-DCMAKE_BUILD_TYPE=Release", "-DGMWM_BUILD_TESTS=OFF", "-DGMWM_BUILD_BENCHMARKS=OFF"]
        if shutil.which("ninja"):
            args += ["-G", "Ninja"]
    try:
        run(args)
    except SystemExit as e:
        fail(f"{str(e).removeprefix('gmwm setup.py: ')}; the module needs Debian's pybind11-dev, python3-dev and python3-numpy besides the program's "
             "packages (bash tools/setup.sh installs them all)")


def check_interpreter(stage: Path) -> None:
    """The compiled module must be for the interpreter pip runs: same ABI suffix."""
    suffix = sysconfig.get_config_var("EXT_SUFFIX")
    modules = list(stage.glob("lib/python*/*-packages/gmwm/_gmwm*"))
    if not modules:
        fail(f"cmake --install put no compiled module under {stage}/lib/python*/")
    if not any(m.name == "_gmwm" + suffix for m in modules):
        fail(f"the build tree {BUILD_DIR} holds {modules[0].name}, not _gmwm{suffix} for "
             f"{sys.executable}: run pip with the Python the tree was built for, or set "
             "GMWM_BUILD_DIR to another folder")


_staged: Optional[Path] = None


def staged() -> Path:
    """Builds the program and the module in the build tree and installs them under STAGE_DIR."""
    global _staged
    if _staged is not None:
        return _staged
    configure(BUILD_DIR)
    jobs = os.environ.get("GMWM_JOBS") or str(os.cpu_count() or 2)
    # What cmake --install takes: the program (and the libraries it links), the module, and
    # the manual page the program writes about itself.
    run(["cmake", "--build", str(BUILD_DIR), "--target", "gmwm", "_gmwm", "gmwm_man_and_completion", "--parallel", jobs])
    shutil.rmtree(STAGE_DIR, ignore_errors=True)
    run(["cmake", "--install", str(BUILD_DIR), "--prefix", str(STAGE_DIR)])
    check_interpreter(STAGE_DIR)
    _staged = STAGE_DIR
    return STAGE_DIR


def staged_package(stage: Path) -> Path:
    return next(stage.glob("lib/python*/*-packages/gmwm"))


def staged_data(stage: Path) -> List[Tuple[str, List[str]]]:
    """The files installed beside the package, by their folder relative to the prefix: the
    program, the libraries under their SONAME (what the loader asks for; a wheel cannot hold
    the symbolic links), the manual page and the licence."""
    major = project_version().split(".")[0]
    libs = sorted(p for p in stage.rglob(f"libgmwm_*.so.{major}") if "python" not in p.parts)
    if not libs:
        fail(f"cmake --install put no libgmwm_*.so.{major} under {stage}")
    data: Dict[str, List[str]] = {}
    for p in [stage / "bin" / "gmwm", *libs, stage / "share" / "man" / "man1" / "gmwm.1",
              stage / "share" / "doc" / "gmwm" / "LICENSE"]:
        if not p.exists():
            fail(f"cmake --install did not install {p.relative_to(stage)}")
        data.setdefault(str(p.parent.relative_to(stage)), []).append(str(p))
    return sorted(data.items())


class BuildPy(build_py):
    """The package as CMake installs it: the Python modules, the stub and _gmwm."""

    def run(self) -> None:
        package = staged_package(staged())
        target = Path(self.build_lib) / "gmwm"
        shutil.rmtree(target, ignore_errors=True)
        shutil.copytree(package, target)


class InstallData(install_data):
    """The program, libraries, manual page and licence, into the prefix (the wheel's .data)."""

    def finalize_options(self) -> None:
        super().finalize_options()
        self.data_files = staged_data(staged())


class GmwmDistribution(Distribution):
    # A compiled module (a platform wheel: cpXY-cpXY-linux_ARCH) with files beside the package.
    def has_ext_modules(self) -> bool:
        return True

    def has_data_files(self) -> bool:
        return True


if __name__ == "__main__":  # setuptools runs this file as __main__; a test imports it
    WHEEL_DIR.mkdir(parents=True, exist_ok=True)
    setup(
        version=project_version(),
        packages=["gmwm"],
        package_dir={"gmwm": "python/gmwm"},
        distclass=GmwmDistribution,
        cmdclass={"build_py": BuildPy, "install_data": InstallData},
        options={
            "build": {"build_base": str(WHEEL_DIR / "setuptools")},
            "egg_info": {"egg_base": str(WHEEL_DIR)},
        },
    )
