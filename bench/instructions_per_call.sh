#!/usr/bin/env bash
# Instructions per call of the generated forward dynamics (ABA), inverse dynamics (RNEA) and mass
# matrix (CRBA) of iiwa14, hyq (also as hyq_snapped: its quarter turns exact) and talos, counted by
# valgrind's callgrind, beside the operation count the generator prints in the function's doc comment. Repeatable whatever the machine's
# load (instructions are counted, not timed).
#
#   bash bench/instructions_per_call.sh [BUILD_DIR]      (default: build; needs valgrind)
#
# Exit 1 if a function costs more than 4 instructions per operation (60 per sine or cosine: libm's
# sincos): straight-line code costs about 2 (the SSE instruction, its register copy or spill);
# much more means the emitted code stopped being straight-line (ctest bench.instructions_per_call).
set -euo pipefail
cd "$(dirname "$0")/.."
build=$(realpath "${1:-build}")
exe="$build/bench/mbgen_instructions"
[[ -x $exe ]] || cmake --build "$build" --target mbgen_instructions >/dev/null
calls=200
count() {  # instructions of a whole run: robot, function, calls
  valgrind --tool=callgrind --callgrind-out-file=/dev/null "$exe" "$1" "$2" "$3" 2>&1 >/dev/null |
    sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}
printf '| function | robot | operations | instructions per call | instructions per operation |\n|---|---|---|---|---|\n'
status=0
for function in forward_dynamics inverse_dynamics mass_matrix; do
  for robot in iiwa14 hyq hyq_snapped talos; do
    # The source mbgen_instructions compiles: the bench's own generation (bench/CMakeLists.txt).
    src="$build/bench/mbgen/$robot/${robot}_${function}.cpp"
    ops=$(sed -n 's|^// \([0-9]*\) operations.*|\1|p' "$src" | head -1)
    sincos=$(sed -n 's|^// [0-9]* operations.* \([0-9]*\) sin/cos.*|\1|p' "$src" | head -1)
    once=$(count "$robot" "$function" "$calls")
    twice=$(count "$robot" "$function" $((2 * calls)))
    per_call=$(((twice - once) / calls))
    printf '| %s | %s | %s | %s | %s |\n' "$function" "$robot" "$ops" "$per_call" "$(awk "BEGIN { printf \"%.2f\", $per_call / $ops }")"
    # A sine or cosine is one operation but a libm call (sincos: about 100 instructions for the pair).
    if ((per_call > 4 * (ops - sincos) + 60 * sincos)); then
      echo "instructions_per_call.sh: $robot's $function costs more than 4 instructions per operation (60 per sin or cos)" >&2
      status=1
    fi
  done
done
exit $status
