#!/usr/bin/env bash
# scripts/check_layout.sh must fail, naming the file, on an upward include planted in a copy of the
# tree: the load stage including a codegen header, and the algorithm layer a simulator header.
set -euo pipefail
source_dir=$1 work=$2
plant() {  # plant WHAT: copies both trees and plants one violation
  rm -rf "$work" && mkdir -p "$work/runtime" && cp -r "$source_dir/generator" "$work/" && cp -r "$source_dir/runtime/include/mbgen" "$work/runtime/"
  case $1 in
    generator) echo '#include "codegen/symbolic.hpp"' >> "$work/generator/load/name_match.cpp" ;;
    runtime) sed -i '0,/^#include "mbgen/s||#include "mbgen/sim/contact.hpp"\n&|' "$work/runtime/mbgen/algorithm/crba.hpp" ;;
  esac
}
bash "$source_dir/scripts/check_layout.sh" "$source_dir/generator" "$source_dir/runtime/include/mbgen" >/dev/null \
  || { echo "check_layout.sh fails on the tree itself"; exit 1; }
expect() {  # expect WHAT PATTERN
  plant "$1"
  if out=$(bash "$source_dir/scripts/check_layout.sh" "$work/generator" "$work/runtime/mbgen"); then
    echo "check_layout.sh passed a tree with a planted upward include ($1)"; exit 1
  fi
  grep -q "$2" <<<"$out" || { echo "unexpected report ($1): $out"; exit 1; }
  echo "caught: $out"
}
expect generator "generator/load/name_match.cpp:.*stage 'load' includes 'codegen'"
expect runtime "runtime/include/mbgen/algorithm/crba.hpp:.*layer 'algorithm' includes 'sim'"
