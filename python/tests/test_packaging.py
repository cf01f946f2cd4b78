"""pip installs gmwm (issue 46, item 1): `pip install .` into a fresh virtual environment,
offline, gives the package and the gmwm program; `pip wheel .` gives a wheel that installs
into a second fresh environment; one version everywhere.

The build backend (setup.py) reuses the build tree the suite runs from (GMWM_BUILD_DIR: the
folder of GMWM_CLI_PATH), which is up to date, so nothing is compiled a second time. The
environments see the system's packages (--system-site-packages): Debian's numpy, setuptools
and wheel, as nothing may be downloaded. Run by its own ctest entry (Python.PipInstall), beside
the rest of the Python suite.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import zipfile
from pathlib import Path
from typing import Dict, List

import pytest

SOURCE = Path(os.environ.get("GMWM_SOURCE_DIR", Path(__file__).resolve().parents[2]))
CLI = os.environ.get("GMWM_CLI_PATH")
EXAMPLE = SOURCE / "data" / "example_imu6.csv.gz"
FIT_ARGS = ["fit", str(EXAMPLE), "--columns", "gyro_x", "--freq", "100", "--model", "AR1+WN+RW",
            "--quiet", "--json", "-"]

pytestmark = pytest.mark.skipif(CLI is None, reason="GMWM_CLI_PATH is not set: the build tree to package is unknown")


def clean_env(**extra: str) -> Dict[str, str]:
    """The environment without the suite's PYTHONPATH (the build tree's package): what is
    imported must be what pip installed."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "LD_LIBRARY_PATH")}
    env.update(extra)
    return env


def run(cmd: List[str], cwd: Path, **extra: str) -> subprocess.CompletedProcess[str]:
    done = subprocess.run(cmd, cwd=cwd, env=clean_env(**extra), capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, f"{' '.join(cmd)} exited {done.returncode}:\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}"
    return done


def fit_json(program: str | Path, cwd: Path) -> Dict[str, object]:
    """The fit's JSON without its "run" object (timings, host, argv)."""
    doc = json.loads(run([str(program), *FIT_ARGS], cwd=cwd).stdout)
    doc.pop("run")
    return dict(doc)


def venv(path: Path) -> Path:
    # The interpreter the module was built for (Debian's, where numpy lives).
    run([sys.executable, "-m", "venv", "--system-site-packages", str(path)], cwd=path.parent)
    return path / "bin"


def project_version() -> str:
    m = re.search(r"project\(\s*gmwm\s+VERSION\s+([0-9.]+)", (SOURCE / "CMakeLists.txt").read_text())
    assert m, "CMakeLists.txt names the project's version"
    return m.group(1)


PROBE = """
import json, gmwm, gmwm._gmwm
maps = [l.split()[-1] for l in open('/proc/self/maps') if 'libgmwm_engine' in l]
fit = gmwm.fit(gmwm.read({path!r}, columns=['gyro_x'], freq=100.0), 'AR1+WN+RW')
print(json.dumps({{'file': gmwm.__file__, 'module': gmwm._gmwm.__file__, 'engine': maps[0],
                  'version': gmwm.__version__, 'model': fit.model}}))
"""


def probe(bin_dir: Path, cwd: Path) -> Dict[str, str]:
    out = run([str(bin_dir / "python"), "-c", PROBE.format(path=str(EXAMPLE))], cwd=cwd).stdout
    return dict(json.loads(out.strip().splitlines()[-1]))


@pytest.fixture(scope="module")
def build_env() -> Dict[str, str]:
    return {"GMWM_BUILD_DIR": str(Path(str(CLI)).resolve().parent)}


@pytest.fixture(scope="module")
def installed(tmp_path_factory: pytest.TempPathFactory, build_env: Dict[str, str]) -> Path:
    """A fresh environment into which `pip install .` put gmwm: its bin/."""
    env_bin = venv(tmp_path_factory.mktemp("pip") / "env")
    run([str(env_bin / "pip"), "install", "--no-build-isolation", "--no-index", "--no-deps", str(SOURCE)],
        cwd=env_bin, **build_env)
    return env_bin


def test_pip_install_dot_puts_the_package_and_the_program_into_a_fresh_environment(tmp_path: Path,
                                                                                    installed: Path) -> None:
    env_bin = installed
    found = probe(env_bin, tmp_path)
    env_root = str(env_bin.parent.resolve())
    # The package, its compiled module and the libraries it loads are the environment's own.
    for key in ("file", "module", "engine"):
        assert str(Path(found[key]).resolve()).startswith(env_root), f"{key} {found[key]} is outside {env_root}"
    assert found["version"] == project_version()
    # The program: in the environment's bin/, runs without LD_LIBRARY_PATH, and writes the
    # same JSON as the build tree's program on the same data.
    installed = fit_json(env_bin / "gmwm", tmp_path)
    assert installed == fit_json(str(CLI), tmp_path)
    assert installed["columns"][0]["model"] == found["model"]  # type: ignore[index]
    assert run([str(env_bin / "gmwm"), "--version"], cwd=tmp_path).stdout.strip() == project_version()
    # Nothing of the build is left in the sources.
    assert not list(SOURCE.glob("*.egg-info")) and not (SOURCE / "python" / "gmwm.egg-info").exists()


def test_pip_wheel_makes_a_wheel_that_installs_into_a_second_fresh_environment(tmp_path: Path,
                                                                               build_env: Dict[str, str]) -> None:
    builder = venv(tmp_path / "builder")
    wheels = tmp_path / "wheels"
    run([str(builder / "pip"), "wheel", "--no-build-isolation", "--no-index", "--no-deps", "-w", str(wheels),
         str(SOURCE)], cwd=tmp_path, **build_env)
    (wheel,) = wheels.glob("*.whl")
    tag = f"cp{sys.version_info.major}{sys.version_info.minor}"
    assert wheel.name.startswith(f"gmwm-{project_version()}-{tag}-{tag}-linux_"), wheel.name
    with zipfile.ZipFile(wheel) as z:
        names = z.namelist()
        program = z.getinfo(f"gmwm-{project_version()}.data/data/bin/gmwm")
        assert program.external_attr >> 16 & 0o111, "the program is executable in the wheel"
    assert any(re.match(r"gmwm/_gmwm\..*\.so$", n) for n in names)
    assert any(re.search(r"\.data/data/lib/libgmwm_engine\.so\.\d+$", n) for n in names)

    user = venv(tmp_path / "user")
    run([str(user / "pip"), "install", "--no-index", "--no-deps", str(wheel)], cwd=tmp_path)
    found = probe(user, tmp_path)
    assert str(Path(found["engine"]).resolve()).startswith(str((tmp_path / "user").resolve()))
    assert fit_json(user / "gmwm", tmp_path) == fit_json(str(CLI), tmp_path)
    # pip uninstall takes every file back: the program and the libraries too.
    run([str(user / "pip"), "uninstall", "-y", "gmwm"], cwd=tmp_path)
    assert not (user / "gmwm").exists()
    assert not list((tmp_path / "user" / "lib").glob("libgmwm_*"))


def test_the_installed_program_runs_a_fleet_on_a_dask_cluster_with_the_environments_python(tmp_path: Path,
                                                                                            installed: Path) -> None:
    # gmwm fleet --scheduler starts a Python bridge: from an environment, the environment's
    # python3 (which sees the gmwm pip put there), not the one the build tree was made with.
    distributed = pytest.importorskip("distributed", reason="python3-distributed is not installed")
    rows = ["path,unit,model,units"]
    for k in (1, 2):
        run([str(installed / "gmwm"), "simulate", "--model", "WN(sigma2=1e-4)+RW(gamma2=1e-10)", "--n", "4096",
             "--freq", "100", "--names", "gyro_x", "--seed", str(k), "--output", f"u{k}.csv", "--quiet"], cwd=tmp_path)
        rows.append(f'u{k}.csv,SN{k},IMU-X,"gyro=rad/s"')
    (tmp_path / "fleet.csv").write_text("\n".join(rows) + "\n")
    fleet = [str(installed / "gmwm"), "fleet", "fleet.csv", "--model", "WN+RW", "--no-cache", "--quiet"]
    run([*fleet, "--json", "local.json"], cwd=tmp_path)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None) as cluster:
        run([*fleet, "--scheduler", cluster.scheduler_address, "--json", "dask.json"], cwd=tmp_path)
    local, remote = (json.loads((tmp_path / f).read_text()) for f in ("local.json", "dask.json"))
    for doc in (local, remote):
        doc.pop("run")
        for row in doc["rows"]:
            row.pop("seconds")
    assert remote == local and all(r["status"] == "ok" for r in remote["rows"])


def test_a_build_tree_of_other_sources_is_refused_naming_both(tmp_path: Path) -> None:
    # GMWM_BUILD_DIR left pointing at another checkout's tree would pack that checkout's
    # program and module under these sources' name.
    foreign = tmp_path / "other-build"
    foreign.mkdir()
    (foreign / "CMakeCache.txt").write_text(f"CMAKE_HOME_DIRECTORY:INTERNAL={tmp_path / 'other-checkout'}\n")
    done = subprocess.run([sys.executable, "-B", "-c", "import setup; setup.configure(setup.BUILD_DIR)"], cwd=SOURCE,
                          env=clean_env(GMWM_BUILD_DIR=str(foreign)), capture_output=True, text=True, timeout=120)
    assert done.returncode != 0
    assert f"the build tree {foreign} was configured from {tmp_path / 'other-checkout'}, not from {SOURCE.resolve()}" \
        in done.stderr
