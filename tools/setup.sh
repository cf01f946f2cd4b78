#!/usr/bin/env bash
# Installs the Debian packages gmwm needs (when missing) and builds it into build/.
#   bash tools/setup.sh            # everything: program, libraries, tests, benchmarks, Python module
#   bash tools/setup.sh --demo     # only what tools/demo.sh runs: the gmwm program and its libraries
# As root it installs what is missing; not root and something missing: prints the apt-get
# line to run, exits 1.
# Environment: GMWM_BUILD_DIR (default build), GMWM_BUILD_TYPE (default Release),
#              GMWM_JOBS (default: number of cores).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

demo=0
if [[ ${1:-} == --demo ]]; then demo=1; fi

# What building the program needs. libjs-vega: the Vega modules the HTML report (--report)
# inlines, so that the demo's report (and every --report the README suggests) works from the
# first command (issue 46: the demo's build said "configured without Vega").
packages=(cmake ninja-build g++ libeigen3-dev libtbb-dev libnlopt-cxx-dev libnlopt-dev
          libboost-dev libboost-math-dev libboost-random-dev libspdlog-dev zlib1g-dev libssl-dev libcli11-dev
          nlohmann-json3-dev libtinyxml2-dev libyaml-cpp-dev libsqlite3-dev libbz2-dev liblz4-dev
          libzstd-dev libcpp-httplib-dev pkg-config libjs-vega)
# What the tests, the benchmarks and the Python module need besides.
# chromium: the HTML report's headless browser test (tests/cli/html_report_browser_test.cc); python3-rosbag and
# python3-sensor-msgs: ROS's own writer of the ROS 1 test bags; python3-matplotlib: the
# plots of docs/python.md, whose cells the suite runs (python/tests/test_docs_python.py);
# python3-distributed: the fleet's Dask runner and its LocalCluster test
# (python/tests/test_fleet_dask.py); python3-pandas: FleetResult.to_dataframe(); nodejs and
# npm: the web app's browser test (tests/browser: playwright-core from the npm registry, pinned
# by its package-lock.json, driving Debian's chromium); mypy: the Python package's type check
# (Repository.PythonPackageTypeChecksUnderMypyStrict); clang-format: the layout check
# (Repository.EveryCppFileIsLaidOutAsClangFormatSays); python3-venv, python3-pip,
# python3-setuptools and python3-wheel: pip install . and pip wheel . into fresh virtual
# environments, offline (python/tests/test_packaging.py); python3-nbconvert and
# python3-ipykernel: the notebook examples/gmwm_tour.ipynb, executed by the suite
# (python/tests/test_notebook.py).
if ((!demo)); then
  packages+=(libgtest-dev libgmock-dev libbenchmark-dev pybind11-dev python3-dev python3-numpy python3-pytest
             python3-rosbag python3-sensor-msgs python3-matplotlib python3-distributed python3-pandas
             chromium nodejs npm mypy clang-format python3-venv python3-pip python3-setuptools python3-wheel
             python3-nbconvert python3-ipykernel)
fi

# A package whose program another distribution already installed counts as present:
# NodeSource's nodejs ships its own npm and conflicts with Debian's npm package (apt-get then
# stops on "held broken packages"), so nodejs and npm are checked by their commands.
declare -A provided_by_command=([nodejs]=node [npm]=npm)

missing=()
for p in "${packages[@]}"; do
  if [[ -n ${provided_by_command[$p]:-} ]] && command -v "${provided_by_command[$p]}" >/dev/null 2>&1; then
    continue
  fi
  if ! dpkg -s "$p" >/dev/null 2>&1 || \
     ! dpkg -s "$p" 2>/dev/null | grep -q '^Status: install ok installed'; then
    missing+=("$p")
  fi
done

if ((${#missing[@]})); then
  if [[ $(id -u) -ne 0 ]]; then
    echo "gmwm setup: missing Debian packages; run as root:" >&2
    echo "  apt-get update && apt-get install -y --no-install-recommends ${missing[*]}" >&2
    exit 1
  fi
  echo "gmwm setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

build_dir=${GMWM_BUILD_DIR:-build}
build_type=${GMWM_BUILD_TYPE:-Release}
jobs=${GMWM_JOBS:-$(nproc 2>/dev/null || echo 2)}

generator=()
if [[ ! -f "$build_dir/CMakeCache.txt" ]] && command -v ninja >/dev/null 2>&1; then
  generator=(-G Ninja)
fi

if ((demo)); then
  # The program alone: the tests, benchmarks and Python module are not configured (their
  # packages may be missing) nor built. A later full setup turns them back on.
  cmake -S . -B "$build_dir" "${generator[@]}" -DCMAKE_BUILD_TYPE="$build_type" \
        -DGMWM_BUILD_TESTS=OFF -DGMWM_BUILD_BENCHMARKS=OFF -DGMWM_BUILD_PYTHON=OFF
  cmake --build "$build_dir" --parallel "$jobs" --target gmwm
  exit 0
fi
cmake -S . -B "$build_dir" "${generator[@]}" -DCMAKE_BUILD_TYPE="$build_type" \
      -DGMWM_BUILD_TESTS=ON -DGMWM_BUILD_BENCHMARKS=ON -DGMWM_BUILD_PYTHON=ON
cmake --build "$build_dir" --parallel "$jobs"

# The web app's browser test (tests/browser): playwright-core from the npm registry at the
# versions its package-lock.json pins, into tests/browser/node_modules (not tracked).
# Installed again when the installed version is not the pinned one.
browser_pinned() {
  node -e 'const l = require("./tests/browser/package-lock.json").packages["node_modules/playwright-core"];
           const i = require("./tests/browser/node_modules/playwright-core/package.json");
           process.exit(l && i.version === l.version ? 0 : 1)' 2>/dev/null
}
# Without the registry the rest of the set-up still stands: the browser test then skips, or
# fails under GMWM_REQUIRE_BROWSER=1 (.ci/run) naming what is missing.
if [[ -f tests/browser/package-lock.json ]] && command -v npm >/dev/null 2>&1 && ! browser_pinned; then
  if ! npm ci --prefix tests/browser --no-audit --no-fund --loglevel=error; then
    echo "gmwm setup: warning: npm could not install the browser test's playwright-core (tests/browser);" \
         "the browser test will say so" >&2
  fi
fi

# `import gmwm` from the system Python (Debian's python3, which has python3-numpy): a .pth
# file naming the build tree's python folder (python/CMakeLists.txt puts the module there).
if [[ -x /usr/bin/python3 && -d "$build_dir/python/gmwm" ]]; then
  python_dir=$(cd "$build_dir/python" && pwd)
  site=$(/usr/bin/python3 -c 'import site; print(site.getsitepackages()[0])')
  if [[ $(id -u) -eq 0 ]]; then
    mkdir -p "$site" && echo "$python_dir" > "$site/gmwm-build.pth"
  else
    echo "gmwm setup: to import gmwm from Python, export PYTHONPATH=$python_dir" >&2
  fi
fi
