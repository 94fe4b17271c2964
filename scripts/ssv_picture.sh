#!/usr/bin/env bash
# A robot's fitted SSVs drawn over its meshes from three sides (docs/ssv.md):
#   bash scripts/ssv_picture.sh OUT.png TITLE -- DESCRIPTION [fit-ssv options...]
# Runs `mbgen fit-ssv` (the built one, build/bin/mbgen) with --picture-data into a temporary
# folder, writes the fitted extras beside the PNG (OUT.ssv.yaml), and draws with
# scripts/plot_ssv_fit.gp.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
png=$1; title=$2; shift 2
[[ ${1:-} == -- ]] && shift
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"${MBGEN:-$root/build/bin/mbgen}" fit-ssv "$@" --out "${png%.png}.ssv.yaml" --picture-data "$work" --quiet
gnuplot -e "dir='$work'; png='$png'; plot_title='$title'" "$root/scripts/plot_ssv_fit.gp"
echo "ssv_picture: $png"
