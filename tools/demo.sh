#!/usr/bin/env bash
# Builds the gmwm program alone (installing the missing Debian packages it needs when root),
# then runs it on the shipped six-axis example: the wavelet variance of one axis and a fit
# of AR1+WN+RW, whose HTML report it writes to build/demo/fit_report.html.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash tools/setup.sh --demo
build_dir=${GMWM_BUILD_DIR:-build}
gmwm="$build_dir/gmwm"

echo
echo "== gmwm wv data/example_imu6.csv.gz --columns gyro_x --freq 100"
"$gmwm" wv data/example_imu6.csv.gz --columns gyro_x --freq 100
echo
report="$build_dir/demo/fit_report.html"
mkdir -p "$build_dir/demo"
echo "== gmwm fit data/example_imu6.csv.gz --columns gyro_x --freq 100 --model AR1+WN+RW --report $report"
"$gmwm" fit data/example_imu6.csv.gz --columns gyro_x --freq 100 --model "AR1+WN+RW" --report "$report"
echo
echo "The fit's HTML report (interactive plots, opens offline): $report (its main plot: $report.svg)."
echo "The example was simulated from AR1(phi=0.999,sigma2=1e-8)+WN(sigma2=1e-5)+RW(gamma2=1e-10)"
echo "(see data/README.md): compare with the estimates above."
