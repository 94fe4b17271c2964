#!/usr/bin/env bash
# The derivatives' accuracy-against-cost charts of docs/derivatives.md: runs build/bench/mbgen_derivative_accuracy
# (the build's benchmark robots) and draws one chart per robot with scripts/plot_derivative_accuracy.gp.
#   bash scripts/derivatives_chart.sh [BUILD_DIR]
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
csv=$root/docs/derivatives/accuracy.csv
mkdir -p "$root/docs/derivatives"
"$build/bench/mbgen_derivative_accuracy" > "$csv"
for robot in hyq talos lola; do
  if [ "$robot" = lola ]; then
    what="lola, closed loops (n = ny = 30): dydd/dy, dydd/dyd by differences (loops closed by Newton) and analytic"
  else
    what="$robot (n = nv): dqdd/dq, dqdd/dv by differences of the generated forward dynamics and analytic"
  fi
  gnuplot -e "csv='$csv'; robot='$robot'; png='$root/docs/derivatives/accuracy_$robot.png'; plot_title='$what'" \
    "$root/scripts/plot_derivative_accuracy.gp"
done
echo "wrote $csv and docs/derivatives/accuracy_{hyq,talos,lola}.png"
