#!/usr/bin/env bash
# Quick start, step 2: build everything (tests, generated robots, benchmarks) and run the whole
# test suite with ctest, except the tests labelled `slow` (fuzz.smoke: `ctest -L slow` runs them).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh --browser  # Chromium: the tests of mbgen view load its pages
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
ctest --test-dir build -j"$(nproc)" --output-on-failure -LE slow
