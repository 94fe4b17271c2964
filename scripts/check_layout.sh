#!/usr/bin/env bash
# The generator's stages depend downward only (generator/README.md): a file of a stage includes
# headers of its own stage or of earlier ones, never of a later one. Prints each violation as
# file:line and exits 1 if there is any. Takes the generator folder as an optional argument (the
# test plants a violation in a copy to show the check can fail).
set -euo pipefail
cd "${1:-$(dirname "$0")/../generator}"
stages=(mesh load model collision codegen cli)
rank() { local i; for i in "${!stages[@]}"; do [[ ${stages[$i]} == "$1" ]] && echo "$i" && return; done; echo -1; }
bad=0
for stage in "${stages[@]}"; do
  [[ -d $stage ]] || { echo "check_layout: generator/$stage is missing"; exit 1; }
  mine=$(rank "$stage")
  while IFS=: read -r file line include; do
    used=${include#*\"}; used=${used%%/*}
    r=$(rank "$used")
    if ((r > mine)); then
      echo "generator/$file:$line: stage '$stage' includes '$used', a later stage: ${include}"
      bad=1
    fi
  done < <(grep -Hn '^#include "[a-z_]*/' "$stage"/*.hpp "$stage"/*.cpp 2>/dev/null || true)
done
for folder in */; do
  [[ $(rank "${folder%/}") -ge 0 ]] || { echo "check_layout: generator/$folder is not a stage (${stages[*]})"; bad=1; }
done
exit $bad
