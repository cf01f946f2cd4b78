#!/usr/bin/env bash
# Builds and runs the test suite under sanitizers, in its own build tree.
#   bash tools/sanitize.sh              # AddressSanitizer + UndefinedBehaviorSanitizer, whole suite
#   bash tools/sanitize.sh quick        # the same sanitizers, the short pass tools/test.sh runs:
#                                       # engine, readers, fuzz-corpus replay, and the hostile
#                                       # inputs and output safety run against the sanitized
#                                       # program (the slow statistical suites left out)
#   bash tools/sanitize.sh thread       # ThreadSanitizer, the selection and gap tests (the TBB-parallel paths)
# Any report fails the run (halt_on_error). tools/sanitizers/ubsan.supp names the one
# third-party report suppressed and why. Under TSan the parallel loops run on std::threads
# instead of oneTBB (gmwm/engine/parallel.h says why); nothing is suppressed.
# Compiled at -O1 with line tables (-g1): the level AddressSanitizer's documentation
# recommends, reports keep file:line, and a translation unit compiles in ~40% of -O2 -g's
# time (engine/src/joint_fit.cc: 43 s against 109 s with ASan+UBSan on this machine kind).
# UBSan's null and alignment checks are left out but in the readers (GMWM_SANITIZE_LEAN in
# CMakeLists.txt says why: they double the compile time; -DGMWM_SANITIZE_LEAN=OFF keeps them).
# The CLI tests of the quick pass are the ordinary build's test_cli (GMWM_BUILD_DIR, default
# build/, which tools/test.sh has just built) pointed at the sanitized program through
# $GMWM_CLI: what runs under the sanitizers is the program that reads the hostile files.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
mode=${1:-address,undefined}
kind=$mode
[[ $mode == quick ]] && kind=address,undefined
dir=build-sanitize-${kind//,/-}
jobs=${GMWM_JOBS:-$(nproc 2>/dev/null || echo 2)}
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DGMWM_SANITIZE="$kind" -DGMWM_BUILD_BENCHMARKS=OFF -DGMWM_BUILD_PYTHON=OFF >/dev/null
supp=$(pwd)/tools/sanitizers
export ASAN_OPTIONS=detect_leaks=1:halt_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:suppressions=$supp/ubsan.supp
export TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1
if [[ $mode == quick ]]; then
  main_build=${GMWM_BUILD_DIR:-build}
  targets=(gmwm test_engine test_stability test_io test_fuzz test_serve)
  cli_tests=$main_build/test_cli
  if [[ ! -x $cli_tests ]]; then
    targets+=(test_cli)
    cli_tests=$dir/test_cli
  fi
  cmake --build "$dir" --parallel "$jobs" --target "${targets[@]}"
  # The five runs in two lanes of about equal length when there are two cores (on an idle
  # 2-core machine, one after another: engine 256 s, readers 102 s, fuzz corpus 28 s; CLI
  # hostile inputs 250 s, web app 172 s), each into its own log, printed in order afterwards.
  logs=$(mktemp -d)
  lanes=()
  # Background jobs of a script ignore SIGINT: on an interrupt or exit the lanes (and the test
  # programs they run) are stopped, not left running into deleted logs.
  trap '((${#lanes[@]} == 0)) || kill -- "${lanes[@]}" 2>/dev/null || true; rm -rf "$logs"' EXIT
  trap 'exit 130' INT TERM
  run() {
    local name=$1
    shift
    local status=0
    "$@" >"$logs/$name.log" 2>&1 || status=$?
    echo "$status" >"$logs/$name.rc"
  }
  cli=$(pwd)/$dir/gmwm
  lane_library() {
    for t in test_engine test_stability test_io test_fuzz; do run "$t" "$dir/$t" --gtest_brief=1; done
  }
  lane_program() {
    run cli env GMWM_CLI="$cli" "$cli_tests" --gtest_brief=1 \
      --gtest_filter='Corpus/Hostile.*:GmwmCliOutputSafety.*:StabilityCommand.*'
    # The web app's hostile requests (traversal, limits, malformed bodies, a hundred clients,
    # dropped connections, cancellation, the guard's rules, the bounds, the hostile corpus of
    # crafted requests), served by the sanitized library.
    run serve env GMWM_CLI="$cli" "$dir/test_serve" --gtest_brief=1 \
      --gtest_filter='ServeServerTest.*:ServeGuardTest.*:ServeLimitsTest.*:Corpus/ServeHostileRequests.*:ServeAppTest.Refuses*:ServeAppTest.AJsonBody*:ServeAppTest.AnUpload*:ServeAppTest.TwoTabs*:ServeAppTest.Cancelling*'
  }
  if ((jobs >= 2)); then
    set -m  # each lane its own process group, so that the trap's kill reaches its test program
    lane_library &
    lanes+=("-$!")
    lane_program &
    lanes+=("-$!")
    set +m
    wait
    lanes=()
  else
    lane_library
    lane_program
  fi
  rc=0
  for name in test_engine test_stability test_io test_fuzz cli serve; do
    cat "$logs/$name.log" 2>/dev/null || echo "sanitizer pass: no log for $name"
    [[ $(cat "$logs/$name.rc" 2>/dev/null) == 0 ]] || { echo "sanitizer pass: $name FAILED"; rc=1; }
  done
  echo "gmwm sanitizer pass (ASan+UBSan: engine, stability, readers, fuzz corpus, hostile inputs, output safety, stability command, web app): $([[ $rc == 0 ]] && echo clean || echo FAILED)"
  exit $rc
fi
cmake --build "$dir" --parallel "$jobs"
if [[ $kind == thread ]]; then
  ctest --test-dir "$dir" --output-on-failure -R "Select|Gap|Replicate|Joint" -E "InstalledPackage|Browser"
else
  ctest --test-dir "$dir" --output-on-failure -E "InstalledPackage" -j 2
fi
