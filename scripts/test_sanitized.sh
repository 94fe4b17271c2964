#!/usr/bin/env bash
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer (docs/reliability.md): a
# separate build tree, build-sanitize/, with MBGEN_SANITIZE=ON (generator, tests and generated
# code instrumented; the benchmarks left out: they time, they do not check). Any sanitizer report
# fails its test (-fno-sanitize-recover, halt_on_error).
#
#   bash scripts/test_sanitized.sh [ctest arguments...]            the whole suite (about 2 h on 2 cores
#                                                                  from an empty compiler cache)
#   bash scripts/test_sanitized.sh -R test_generated          (one ctest test per executable: sanitized.<executable>)
#   bash scripts/test_sanitized.sh --subset [ctest arguments...]   the runtime's numerics and the
#                                                                  examples' short runs (label
#                                                                  sanitized_subset), and only their build
#
# The ordinary build already runs that subset instrumented (MBGEN_SANITIZE_SUBSET, so CI does on
# every stop); --subset here differs in instrumenting the generated libraries too.
set -euo pipefail
cd "$(dirname "$0")/.."
subset=false
if [[ ${1:-} == --subset ]]; then
  subset=true
  shift
fi
# The whole suite includes fuzz.smoke, which needs clang; the subset does not.
if $subset; then bash scripts/install_deps.sh --ccache; else bash scripts/install_deps.sh --fuzz --browser --ccache; fi
# Through ccache: the whole build is about 1,500 instrumented compilations (over an hour on 2 cores, longer
# than the tests), and the run is repeated before each issue touching runtime/ or generator/ is
# resolved, mostly over unchanged files. A clean clone at the same path as the last one finds
# them in the cache (the tests' compile definitions hold the clone's path).
export CCACHE_MAXSIZE=${CCACHE_MAXSIZE:-30G}
# The test files share a precompiled header (-include): ccache caches those compilations only so.
export CCACHE_SLOPPINESS=${CCACHE_SLOPPINESS:-pch_defines,time_macros,include_file_mtime,include_file_ctime}
# -O1 -g1: what ASan's authors recommend (fast enough, line numbers in reports); -O2 -g on the
# larger robots' generated functions takes far longer to compile and finds nothing more.
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
      -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1" -DMBGEN_SANITIZE=ON -DMBGEN_BUILD_BENCH=OFF \
      -DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache >/dev/null
export ASAN_OPTIONS=abort_on_error=1:detect_stack_use_after_return=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/scripts/lsan_suppressions.txt
if $subset; then
  cmake --build build-sanitize -j"$(nproc)" --target mbgen_sanitized_subset
  ctest --test-dir build-sanitize -j"$(nproc)" --output-on-failure -L sanitized_subset "$@"
else
  cmake --build build-sanitize -j"$(nproc)"
  ctest --test-dir build-sanitize -j"$(nproc)" --output-on-failure "$@"
fi
