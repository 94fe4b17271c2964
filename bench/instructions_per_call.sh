#!/usr/bin/env bash
# Instructions per call of the generated forward dynamics (ABA) of iiwa14, hyq and talos, counted
# by valgrind's callgrind, beside the operation count the generator prints in the function's doc
# comment. Repeatable whatever the machine's load (instructions are counted, not timed).
#
#   bash bench/instructions_per_call.sh [BUILD_DIR]      (default: build; needs valgrind)
#
# Exit 1 if a function costs more than 4 instructions per operation: straight-line code costs
# about 2 (the SSE instruction, its register copy or spill); much more means the emitted code
# stopped being straight-line (ctest bench.instructions_per_call).
set -euo pipefail
cd "$(dirname "$0")/.."
build=$(realpath "${1:-build}")
exe="$build/bench/mbgen_instructions"
[[ -x $exe ]] || cmake --build "$build" --target mbgen_instructions >/dev/null
calls=200
count() {  # instructions of a whole run
  valgrind --tool=callgrind --callgrind-out-file=/dev/null "$exe" "$1" "$2" 2>&1 >/dev/null |
    sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}
printf '| robot | operations | instructions per call | instructions per operation |\n|---|---|---|---|\n'
status=0
for robot in iiwa14 hyq talos; do
  # The source mbgen_instructions compiles: the bench's own generation (bench/CMakeLists.txt).
  src="$build/bench/mbgen/$robot/${robot}_forward_dynamics.cpp"
  ops=$(sed -n 's|^// \([0-9]*\) operations.*|\1|p' "$src" | head -1)
  once=$(count "$robot" "$calls")
  twice=$(count "$robot" $((2 * calls)))
  per_call=$(((twice - once) / calls))
  printf '| %s | %s | %s | %s |\n' "$robot" "$ops" "$per_call" "$(awk "BEGIN { printf \"%.2f\", $per_call / $ops }")"
  if ((per_call > 4 * ops)); then
    echo "instructions_per_call.sh: $robot's forward_dynamics costs more than 4 instructions per operation" >&2
    status=1
  fi
done
exit $status
