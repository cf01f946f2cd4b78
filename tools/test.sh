#!/usr/bin/env bash
# Builds gmwm (installing missing Debian packages when root) and runs the whole test
# suite with ctest, then a short pass under AddressSanitizer + UndefinedBehaviorSanitizer
# in its own build tree (tools/sanitize.sh quick; GMWM_SKIP_SANITIZERS=1 leaves it out).
# Exits non-zero when anything fails.
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
if [[ ${GMWM_SKIP_SANITIZERS:-0} != 1 ]]; then
  set +e
  bash tools/sanitize.sh quick 2>&1 | tee "$build_dir/sanitize.log"
  src=${PIPESTATUS[0]}
  set -e
  [[ $src == 0 ]] || rc=1
  echo "gmwm tests: ${summary:-no ctest summary line}"
  tail -n 1 "$build_dir/sanitize.log"
else
  echo "gmwm tests: ${summary:-no ctest summary line}"
fi
exit "$rc"
