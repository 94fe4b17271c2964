#!/usr/bin/env bash
# scripts/check_layout.sh must fail, naming the file, when the load stage includes a codegen header.
set -euo pipefail
source_dir=$1 work=$2
rm -rf "$work" && mkdir -p "$work" && cp -r "$source_dir/generator" "$work/"
echo '#include "codegen/symbolic.hpp"' >> "$work/generator/load/name_match.cpp"
if out=$(bash "$source_dir/scripts/check_layout.sh" "$work/generator"); then
  echo "check_layout.sh passed a tree where load/ includes codegen/"; exit 1
fi
grep -q "generator/load/name_match.cpp:.*stage 'load' includes 'codegen'" <<<"$out" \
  || { echo "unexpected report: $out"; exit 1; }
echo "caught: $out"
