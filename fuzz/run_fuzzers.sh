#!/usr/bin/env bash
# Builds the fuzz targets with clang in BUILD_DIR and runs each for SECONDS, seeded with the
# robot descriptions of robots/, tests/data and ../shared/robots (fuzz/README.md).
#
#   run_fuzzers.sh BUILD_DIR SECONDS [TARGET...]     targets: urdf mjcf extras inspect (default all)
#
# Each target runs with -timeout=10 (an input slower than 10 s is a hang; 60 s for inspect, whose
# inputs run the whole pipeline: a loop that cannot close tries 24 assembly seeds, 0.2 s in a
# release build and ~20 s under ASan + UBSan) and -rss_limit_mb=4096,
# two at a time, with random seeds (MBGEN_FUZZ_SEED fixes it: the test suite's smoke run uses 1,
# so that it finds the same thing on every machine). A crash, hang, leak or sanitizer report leaves the input in
# BUILD_DIR/artifacts/<target>/ and fails the run; the last lines of each log give executions
# and coverage (cov: edges, ft: features). The corpus grows in BUILD_DIR/corpus/<target>/.
set -euo pipefail
if (($# < 2)); then
  echo "usage: $0 BUILD_DIR SECONDS [TARGET...]" >&2
  exit 2
fi
build_dir=$1 seconds=$2
shift 2
targets=("$@")
((${#targets[@]})) || targets=(urdf mjcf extras inspect)
source_dir=$(cd "$(dirname "$0")/.." && pwd)
shared=${MBGEN_SHARED_ROBOTS:-$source_dir/../shared/robots}

# clang and its sanitizer runtimes (the default install leaves them out); as root, installed if
# missing, otherwise named.
if [[ $(id -u) -eq 0 ]]; then
  bash "$source_dir/scripts/install_deps.sh" --fuzz
fi
for tool in clang clang++; do
  command -v "$tool" >/dev/null || { echo "$tool not found: run scripts/install_deps.sh --fuzz as root (clang libclang-rt-14-dev)" >&2; exit 1; }
done
mkdir -p "$build_dir"
cmake -S "$source_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
      -DCMAKE_CXX_COMPILER=clang++ -DMBGEN_FUZZ=ON -DMBGEN_BUILD_TESTS=OFF -DMBGEN_BUILD_BENCH=OFF \
      -DMBGEN_SHARED_ROBOTS="$shared" >"$build_dir/configure.log" 2>&1 || { cat "$build_dir/configure.log"; exit 1; }
cmake --build "$build_dir" -j"$(nproc)" --target "${targets[@]/#/fuzz_}" >"$build_dir/build.log" 2>&1 \
  || { tail -50 "$build_dir/build.log"; exit 1; }

# Seeds: every description of the project and of shared/ (files, not a folder tree: libFuzzer
# reads one level), and for inspect each URDF with its extras behind the separator.
seed_dir=$build_dir/seeds
rm -rf "$seed_dir" && mkdir -p "$seed_dir"/{urdf,mjcf,extras,inspect}
n=0
while IFS= read -r f; do cp "$f" "$seed_dir/urdf/$((n++)).urdf"; cp "$f" "$seed_dir/inspect/$n.urdf"; done \
  < <(find "$source_dir/robots" "$source_dir/tests/data" "$shared" -name '*.urdf' -size -200k | sort)
while IFS= read -r f; do cp "$f" "$seed_dir/mjcf/$((n++)).xml"; done \
  < <(find "$source_dir/tests/data" "$shared" -name '*.xml' -size -200k | sort)
while IFS= read -r f; do cp "$f" "$seed_dir/extras/$((n++)).yaml"; done \
  < <(find "$source_dir/robots" "$source_dir/tests/data" "$shared" -name '*.yaml' | sort)
for urdf in "$source_dir"/robots/mechanisms/*.urdf "$source_dir"/robots/lola/lola.urdf; do
  yaml=${urdf%.urdf}.yaml
  [[ -f $yaml ]] && { cat "$urdf"; printf '\n---extras---\n'; cat "$yaml"; } >"$seed_dir/inspect/$((n++)).pair"
done

export LSAN_OPTIONS=suppressions=$source_dir/scripts/lsan_suppressions.txt
run_one() {
  local target=$1
  mkdir -p "$build_dir/corpus/$target" "$build_dir/artifacts/$target"
  local timeout=10
  [[ $target == inspect ]] && timeout=60
  "$build_dir/fuzz/fuzz_$target" -max_total_time="$seconds" -timeout=$timeout -rss_limit_mb=4096 -max_len=262144 \
    -seed="${MBGEN_FUZZ_SEED:-0}" \
    -print_final_stats=1 -artifact_prefix="$build_dir/artifacts/$target/" \
    "$build_dir/corpus/$target" "$seed_dir/$target" >"$build_dir/fuzz_$target.log" 2>&1
}
status=0
pids=()
for target in "${targets[@]}"; do
  run_one "$target" & pids+=($!)
  if ((${#pids[@]} == 2)); then wait "${pids[0]}" || status=1; pids=("${pids[@]:1}"); fi
done
for pid in "${pids[@]}"; do wait "$pid" || status=1; done
for target in "${targets[@]}"; do
  log=$build_dir/fuzz_$target.log
  execs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*$' || echo '?')
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*$' || echo '?')
  findings=$(find "$build_dir/artifacts/$target" -type f | wc -l)
  echo "fuzz_$target: ${seconds} s, $execs executions, cov $cov edges, ft $ft, findings $findings"
  if ((findings)); then grep -E "ERROR|SUMMARY|deadly|Test unit written" "$log" | head -5; fi
done
exit $status
