#!/usr/bin/env bash
# Rewrites generated/<robot>/ for every robot shipped in robots/ (robots/<group>/<name>.urdf with
# its extras <name>.yaml), the committed output that CI compares byte for byte.
#
#   bash scripts/regenerate.sh                 # update generated/ (builds mbgen first if needed)
#   bash scripts/regenerate.sh --check         # compare instead; exit 1 on any difference
#   bash scripts/regenerate.sh --mbgen PATH    # use this mbgen instead of build/bin/mbgen
#
# Inputs are given to mbgen by repository-relative paths from the repository root, so the output
# does not depend on where the checkout lives. Each robot gets its extras' base and mbgen's default
# scalars; the C++ namespace and file prefix are the extras' `robot:` name.
set -euo pipefail
cd "$(dirname "$0")/.."

mode=update
mbgen=
while (($#)); do
  case $1 in
    --check) mode=check ;;
    --mbgen) mbgen=$2; shift ;;
    -h|--help) sed -n '2,11p' "$0"; exit 0 ;;
    *) echo "regenerate.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
if [[ -z $mbgen ]]; then
  mbgen=build/bin/mbgen
  [[ -d build ]] || cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build --target mbgen -j"$(nproc)" >/dev/null
fi
mbgen=$(realpath "$mbgen")

fresh=$(mktemp -d)
trap 'rm -rf "$fresh"' EXIT
for description in robots/*/*.urdf; do
  name=$(basename "${description%.urdf}")
  extras=${description%.urdf}.yaml
  if [[ ! -f $extras ]]; then
    echo "regenerate.sh: $description has no extras file $extras (every shipped robot needs one)" >&2
    exit 1
  fi
  "$mbgen" generate "$description" --extras "$extras" --out "$fresh/$name" --quiet
done

if [[ $mode == update ]]; then
  cp generated/README.md "$fresh/" 2>/dev/null || true
  rm -rf generated
  mv "$fresh" generated
  chmod 755 generated
  trap - EXIT
  echo "generated/: $(find generated -type f | wc -l) files for $(find generated -mindepth 1 -type d | wc -l) robots"
  exit 0
fi

if ! diff_output=$(diff -r -x README.md generated "$fresh" 2>&1); then
  echo "generated/ is out of date: mbgen's output for robots/ differs from the committed files:" >&2
  diff -rq -x README.md generated "$fresh" | sed "s|$fresh|<fresh output>|g" >&2 || true
  echo "$diff_output" | sed "s|$fresh|<fresh output>|g" | head -40 >&2
  echo "Run 'bash scripts/regenerate.sh' from the repository root and commit generated/." >&2
  exit 1
fi
echo "generated/ is up to date ($(find generated -type f | wc -l) files)"
