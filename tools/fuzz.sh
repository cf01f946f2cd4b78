#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz/fuzz_targets.h) with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer into build-fuzz/, and runs them on their corpora.
#   bash tools/fuzz.sh                      # every target, 600 s each, one after the other
#   bash tools/fuzz.sh delimited 1800       # one target, 30 minutes
# New interesting inputs are added to tests/fuzz/corpus/<target>/ (replayed by the normal
# suite); a crash input is written there too (crash-*), and the run fails.
# Needs Debian clang and libfuzzer-14-dev (apt-get install clang libfuzzer-14-dev).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
targets=(delimited model_syntax kalibr_yaml gazebo_sdf export_source binary_logs ulog rosbag1 mcap cdr)
seconds=${2:-600}
if [[ $# -ge 1 ]]; then targets=("$1"); fi

CXX=clang++ CC=clang cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGMWM_FUZZ=ON \
  -DGMWM_BUILD_TESTS=OFF -DGMWM_BUILD_BENCHMARKS=OFF -DGMWM_BUILD_PYTHON=OFF >/dev/null
cmake --build build-fuzz --target "${targets[@]/#/fuzz_}"

for t in "${targets[@]}"; do
  corpus=tests/fuzz/corpus/$t
  mkdir -p "$corpus"
  echo "fuzz_$t: ${seconds} s on $corpus"
  # Leak checking stays on (detect_leaks=1); -max_len bounds one input at 64 kB. The binary
  # readers' targets have a dictionary (tests/fuzz/dict/) and a mutator that drives their
  # size fields to extremes (tests/fuzz/size_fields.h).
  dict=()
  if [[ -f tests/fuzz/dict/$t.dict ]]; then dict=(-dict="tests/fuzz/dict/$t.dict"); fi
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "build-fuzz/fuzz_$t" -max_total_time="$seconds" -max_len=65536 -timeout=10 -rss_limit_mb=2048 \
    "${dict[@]}" -artifact_prefix="$corpus/" "$corpus" 2>&1 | tail -n 3
done
