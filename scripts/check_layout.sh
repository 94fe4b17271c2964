#!/usr/bin/env bash
# Includes run downward only, in the generator and in the runtime. Prints each violation as
# file:line and exits 1 if there is any.
#   generator/ (generator/README.md): stages mesh < load < model < collision < codegen < view < cli; a
#     file of a stage includes headers of its own stage or of earlier ones, never of a later one.
#   runtime/include/mbgen/ (runtime/README.md): layers spatial < core (the headers directly in
#     mbgen/: index, model, data, joint limits, contact model) < algorithm < collision < sim <
#     control < python (what the Python modules share: pybind11 on top of the rest); mbgen.hpp,
#     the umbrella header, is exempt.
# Usage: check_layout.sh [GENERATOR_DIR [RUNTIME_INCLUDE_DIR]] (the test plants violations in copies
# to show the check can fail).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
generator=$(cd "${1:-$root/generator}" && pwd)
runtime=$(cd "${2:-$root/runtime/include/mbgen}" && pwd)
bad=0

# rank NAME LIST...: NAME's position in LIST, or -1.
rank() { local name=$1 i=0; shift; for s in "$@"; do [[ $s == "$name" ]] && echo $i && return; i=$((i + 1)); done; echo -1; }

stages=(mesh load model collision codegen view cli)
cd "$generator"
for stage in "${stages[@]}"; do
  [[ -d $stage ]] || { echo "check_layout: generator/$stage is missing"; exit 1; }
  mine=$(rank "$stage" "${stages[@]}")
  while IFS=: read -r file line include; do
    used=${include#*\"}; used=${used%%/*}
    if (($(rank "$used" "${stages[@]}") > mine)); then
      echo "generator/$file:$line: stage '$stage' includes '$used', a later stage: ${include}"
      bad=1
    fi
  done < <(grep -Hn '^#include "[a-z_]*/' "$stage"/*.hpp "$stage"/*.cpp 2>/dev/null || true)
done
for folder in */; do
  [[ $(rank "${folder%/}" "${stages[@]}") -ge 0 ]] || { echo "check_layout: generator/$folder is not a stage (${stages[*]})"; bad=1; }
done

layers=(spatial core algorithm collision sim control python)
layer_of() { local d; d=$(dirname "$1"); [[ $d == . ]] && echo core || echo "$d"; }
cd "$runtime"
while IFS= read -r header; do
  header=${header#./}
  [[ $header == mbgen.hpp ]] && continue
  mine=$(rank "$(layer_of "$header")" "${layers[@]}")
  ((mine >= 0)) || { echo "check_layout: runtime/include/mbgen/$header is in no layer (${layers[*]})"; bad=1; continue; }
  while IFS=: read -r line include; do
    used=${include#*\"mbgen/}; used=${used%\"*}
    layer=$(layer_of "$used")
    if (($(rank "$layer" "${layers[@]}") > mine)); then
      echo "runtime/include/mbgen/$header:$line: layer '$(layer_of "$header")' includes '$layer', a higher layer: ${include}"
      bad=1
    fi
  done < <(grep -n '^#include "mbgen/' "$header" || true)
done < <(find . -name '*.hpp' | sort)
exit $bad
