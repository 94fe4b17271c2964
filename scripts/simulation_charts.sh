#!/usr/bin/env bash
# Re-makes the simulation plots of docs/ (docs/simulation.md) with mbgen_sim: the drop and the
# push of Lola (generated backend) and the four-bar's free swing. The CSVs stay in build/sim/.
#
#   bash scripts/simulation_charts.sh [BUILD_DIR]     (default build; builds mbgen_sim if needed)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
[[ -d $build ]] || cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" --target mbgen_sim -j"$(nproc)" >/dev/null
out=$build/sim
"$build/examples/mbgen_sim" drop --out "$out"
"$build/examples/mbgen_sim" push --out "$out"
"$build/examples/mbgen_sim" swing --out "$out"
cp "$out/drop_lola.png" docs/simulation_drop_lola.png
cp "$out/push_lola.png" docs/simulation_push_lola.png
cp "$out/swing_four_bar.png" docs/simulation_swing_four_bar.png
echo "docs/simulation_{drop_lola,push_lola,swing_four_bar}.png written"
