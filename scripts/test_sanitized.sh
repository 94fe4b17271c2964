#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer (docs/reliability.md):
# a separate build tree, build-sanitize/, with MBGEN_SANITIZE=ON (generator, tests and generated
# code instrumented; the benchmarks left out: they time, they do not check). Any sanitizer
# report fails its test (-fno-sanitize-recover, halt_on_error). Takes about 3x the normal suite.
#
#   bash scripts/test_sanitized.sh [ctest arguments...]   e.g. -R Generated
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh --fuzz  # the suite here includes fuzz.smoke (clang)
# -O1 -g1: what ASan's authors recommend (fast enough, line numbers in reports); -O2 -g on the
# larger robots' generated functions takes far longer to compile and finds nothing more.
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
      -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1" -DMBGEN_SANITIZE=ON -DMBGEN_BUILD_BENCH=OFF >/dev/null
cmake --build build-sanitize -j"$(nproc)"
export ASAN_OPTIONS=abort_on_error=1:detect_stack_use_after_return=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/scripts/lsan_suppressions.txt
ctest --test-dir build-sanitize -j"$(nproc)" --output-on-failure "$@"
