#!/usr/bin/env bash
# Builds and runs the test suite under sanitizers, in its own build tree.
#   bash tools/sanitize.sh              # AddressSanitizer + UndefinedBehaviorSanitizer, whole suite
#   bash tools/sanitize.sh thread       # ThreadSanitizer, the selection and gap tests (the TBB-parallel paths)
# Any report fails the run (halt_on_error). tools/sanitizers/ubsan.supp names the one
# third-party report suppressed and why.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
kind=${1:-address,undefined}
dir=build-sanitize-${kind//,/-}
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGMWM_SANITIZE="$kind" \
  -DGMWM_BUILD_BENCHMARKS=OFF -DGMWM_BUILD_PYTHON=OFF >/dev/null
cmake --build "$dir"
supp=$(pwd)/tools/sanitizers
export ASAN_OPTIONS=detect_leaks=1:halt_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:suppressions=$supp/ubsan.supp
export TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1
if [[ $kind == thread ]]; then
  ctest --test-dir "$dir" --output-on-failure -R "Select|Gap|Replicate|Joint" -E "InstalledPackage|Browser"
else
  ctest --test-dir "$dir" --output-on-failure -E "InstalledPackage" -j 2
fi
