#!/usr/bin/env bash
# Quick start, step 1: install what is missing, build mbgen, generate C++ for the default robot,
# compile it into the demo and run the demo (it prints what the generated code computed and how
# it compares with the generic runtime).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target mbgen mbgen_demo
./build/examples/mbgen_demo
