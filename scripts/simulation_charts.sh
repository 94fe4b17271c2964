#!/usr/bin/env bash
# Re-makes the simulation plots of docs/ (docs/simulation.md) with mbgen_sim: the drop and the
# push of Lola (generated backend), Lola falling to the ground after a 10 N s push (every link
# touching the ground, generic backend), the four-bar's free swing, and Cassie's drop beside
# MuJoCo's (mbgen_sim_vs_mujoco, when built). The CSVs stay in build/sim/.
#
#   bash scripts/simulation_charts.sh [BUILD_DIR]     (default build; builds mbgen_sim if needed)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
[[ -d $build ]] || cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" --target mbgen_sim -j"$(nproc)" >/dev/null
cmake --build "$build" --target mbgen_sim_vs_mujoco -j"$(nproc)" >/dev/null 2>&1 || true
out=$build/sim
"$build/examples/mbgen_sim" drop --out "$out"
"$build/examples/mbgen_sim" push --out "$out"
"$build/examples/mbgen_sim" swing --out "$out"
"$build/examples/mbgen_sim" push --impulse 10 --duration 5 --whole-body-contact --out "$out/fall"
cp "$out/drop_lola.png" docs/simulation_drop_lola.png
cp "$out/push_lola.png" docs/simulation_push_lola.png
cp "$out/swing_four_bar.png" docs/simulation_swing_four_bar.png
cp "$out/fall/push_lola.png" docs/simulation_fall_lola.png
echo "docs/simulation_{drop_lola,push_lola,fall_lola,swing_four_bar}.png written"
if [[ -x $build/examples/mbgen_sim_vs_mujoco ]]; then
  "$build/examples/mbgen_sim_vs_mujoco" --duration 1 --csv "$out/cassie_pelvis.csv"
  gnuplot -e "csv='$out/cassie_pelvis.csv'; png='docs/simulation_cassie_vs_mujoco.png'; plot_title='Cassie dropped from 5 cm, passive, joint ranges on both sides: pelvis height'" \
    scripts/plot_sim_vs_mujoco.gp
  echo "docs/simulation_cassie_vs_mujoco.png written"
fi
