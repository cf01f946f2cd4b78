#!/usr/bin/env bash
# Runs every benchmark on the shared IMU recordings (the folder named by $GMWM_SHARED_DATA; a default folder beside the clone when unset) and writes their
# output into a dated detail file, tools/bench/results/<date>-run-all.md (tools/bench/RESULTS.md is the
# one-page summary that links to the detail files; add the new figures there by hand). Needs a built
# tree (bash tools/setup.sh).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
build=${GMWM_BUILD_DIR:-build}
data=${GMWM_SHARED_DATA:-$(pwd)/../shared/data}
export GMWM_SHARED_DATA=$data
out=tools/bench/results/$(date -u +%Y-%m-%d)-run-all.md
{
  echo "# Benchmark results"
  echo
  echo "Machine: $(nproc) cores, $(free -g | awk '/Mem:/{print $2}') GB; $(date -u +%Y-%m-%d). Reference times: R GMWM 3.0.0 on this machine kind (quoted per section)."
  echo
  echo "[Back to the summary](../RESULTS.md)"
  echo
  echo "## End-to-end \`gmwm wv\` on adis_16405_imu1.csv.gz (6 x 1,000,000, gzip)"
  echo
  best=1e9
  for i in 1 2 3 4 5; do
    s=$(date +%s.%N); "$build/gmwm" wv "$data/adis_16405_imu1.csv.gz" --freq 100 --quiet --json /tmp/gmwm_bench_wv.json; e=$(date +%s.%N)
    best=$(echo "$e - $s" | bc -l | awk -v b="$best" '{print ($1 < b) ? $1 : b}')
  done
  printf 'best of 5: %.3f s wall (reference R: 3.46 s for the WV alone, parsing excluded)\n\n' "$best"
  echo "## Speed (bench_speed)"
  echo
  "$build/bench_speed"
  echo
  echo "## Nested fits on real data (bench_nested)"
  echo
  "$build/bench_nested" || true
  echo
  echo "## Published simulation study WN + GM + DR (bench_simulation_study)"
  echo
  "$build/bench_simulation_study" || true
  echo
  echo "## Model selection (bench_select)"
  echo
  "$build/bench_select" || true
  echo
  echo "## Robust WV (bench_robust)"
  echo
  "$build/bench_robust" || true
  echo
  echo "## WVIC optimism: analytic vs bootstrap vs Monte-Carlo truth (bench_optimism)"
  echo
  "$build/bench_optimism" || true
  echo
  echo "## Bootstrap refits: from the fit alone against an added placement start (bench_bootstrap_refit_starts)"
  echo
  "$build/bench_bootstrap_refit_starts" || true
  echo
  echo "## Representability on real data (bench_representation)"
  echo
  "$build/bench_representation" || true
  echo
  echo "## Noise figures on real recordings (bench_noise_figures)"
  echo
  "$build/bench_noise_figures" || true
  echo
  echo "## B's floor rule against an oracle (bench_floor_choice)"
  echo
  "$build/bench_floor_choice" 400 || true
  echo
  echo "## Replicates with gaps: the shared-theta test's level (bench_shared_theta_level)"
  echo
  for missing in 0.05 0.2; do "$build/bench_shared_theta_level" 1 3 14 1000 39 "$missing" || true; done
  echo
  echo "## Long gaps: the windows pooled or the segments as replicates (bench_segments)"
  echo
  "$build/bench_segments" 400 18 || true
  echo
  echo "## Robust goodness of fit (bench_robust_gof)"
  echo
  "$build/bench_robust_gof" || true
  echo
  echo "## Model selection accuracy: WVIC vs BIC (bench_selection_accuracy)"
  echo
  "$build/bench_selection_accuracy" || true
  echo
  echo "## Sim-to-real gap on real recordings (gap_real.py)"
  echo
  python3 tools/bench/gap_real.py "$build/gmwm" || true
  echo
  echo "## The ADIS units with 5% removed (gaps_real.py, gaps_real_robust.py)"
  echo
  python3 tools/bench/gaps_real.py "$build/gmwm" || true
  echo
  python3 tools/bench/gaps_real_robust.py "$build/gmwm" || true
  echo
  echo "## Sim-to-real gap diagnosis (bench_gap)"
  echo
  "$build/bench_gap" || true
} > "$out"
echo "wrote $out"
