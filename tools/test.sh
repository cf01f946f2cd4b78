#!/usr/bin/env bash
# Builds gmwm (installing missing Debian packages when root) and runs the whole test
# suite with ctest. Exits non-zero when anything fails.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash tools/setup.sh
build_dir=${GMWM_BUILD_DIR:-build}
jobs=${GMWM_TEST_JOBS:-$(nproc 2>/dev/null || echo 2)}

set +e
ctest --test-dir "$build_dir" --output-on-failure --parallel "$jobs" 2>&1 | tee "$build_dir/ctest.log"
rc=${PIPESTATUS[0]}
set -e
summary=$(grep -E 'tests passed|tests failed' "$build_dir/ctest.log" | tail -n 1 || true)
echo "gmwm tests: ${summary:-no ctest summary line}"
exit "$rc"
