#!/usr/bin/env bash
# The pages and pictures of docs/view.md: the narrow turning walk (configurations "both" and "qp")
# and Lola's drop, as `mbgen view` pages in docs/view/, each with a PNG taken by headless Chromium
# at a chosen frame (page.html#frame=K). Needs the build (build/bin/mbgen, build/examples/) and
# Chromium (scripts/install_deps.sh --browser).
#   bash scripts/view_snapshots.sh [OUT_DIR]     (default docs/view)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
out=${1:-$root/docs/view}
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
lola=("$root/robots/lola/lola.urdf" --extras "$root/robots/lola/lola.yaml" --floating)
mbgen=${MBGEN:-$root/build/bin/mbgen}

"$root/build/examples/mbgen_walk" --out "$work" --no-plot >/dev/null
"$root/build/examples/mbgen_sim" drop --out "$work" --no-plot >/dev/null

# snapshot PAGE PNG FRAME: the page at that frame, 1000 x 750.
snapshot() {
  chromium --headless --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader --window-size=1000,750 \
    --virtual-time-budget=15000 --screenshot="$2" "file://$1#frame=$3" >/dev/null 2>&1
  echo "view_snapshots: $2"
}
# closest_frame PAGE: the frame with the smallest near-pair distance (the walk's closest moment).
closest_frame() {
  /usr/bin/python3 - "$1" <<'PY'
import json, re, sys
scene = json.loads(re.search(r'id="mbgen-scene">(.*?)</script>', open(sys.argv[1], encoding="utf-8").read(), re.S).group(1))
best = min(range(len(scene["frames"]["t"])), key=lambda k: min([n[1] for n in scene["frames"]["near"][k]] or [1e9]))
print(best)
PY
}
for config in both qp; do
  page="$out/walk_narrow_turn_$config.html"
  "$mbgen" view "${lola[@]}" --trajectory "$work/walk_narrow_turn_${config}_poses.csv" --fps 15 --near 0.03 --out "$page" --quiet
  snapshot "$page" "$out/walk_narrow_turn_$config.png" "$(closest_frame "$page")"
done
page="$out/drop_lola.html"
"$mbgen" view "${lola[@]}" --trajectory "$work/drop_lola_poses.csv" --fps 30 --out "$page" --quiet
snapshot "$page" "$out/drop_lola.png" 45
