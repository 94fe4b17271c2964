#!/usr/bin/env bash
# Install test (issue 3): installs the build tree into a fresh prefix, then configures, builds and
# runs tests/consumer (find_package(mbgen) + mbgen_add_robot) against that prefix alone.
#
#   run_consumer_test.sh BUILD_DIR WORK_DIR [CMAKE_BUILD_TYPE]
set -euo pipefail
if (($# < 2)); then
  echo "usage: $0 BUILD_DIR WORK_DIR [CMAKE_BUILD_TYPE]" >&2
  exit 2
fi
build_dir=$1 work_dir=$2 build_type=${3:-Release}
source_dir=$(cd "$(dirname "$0")" && pwd)
prefix=$work_dir/prefix

rm -rf "$work_dir"
mkdir -p "$work_dir"
cmake --install "$build_dir" --prefix "$prefix" >"$work_dir/install.log"
for installed in bin/mbgen share/mbgen/templates/cpp/header.fmt share/mbgen/templates/c/header.fmt \
                 include/mbgen/mbgen.hpp lib/cmake/mbgen/mbgenConfig.cmake \
                 lib/cmake/mbgen/mbgenConfigVersion.cmake lib/cmake/mbgen/mbgen_add_robot.cmake; do
  if [[ ! -e $prefix/$installed ]]; then
    echo "FAIL: cmake --install did not install $installed (log: $work_dir/install.log)" >&2
    exit 1
  fi
done

# Only the fresh prefix may provide mbgen: no package registry, no MBGEN_EXECUTABLE from outside.
cmake -S "$source_dir" -B "$work_dir/build" -DCMAKE_BUILD_TYPE="$build_type" \
      -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -UMBGEN_EXECUTABLE \
      >"$work_dir/configure.log" || { cat "$work_dir/configure.log"; exit 1; }
if ! grep -q "mbgen generator: $prefix/bin/mbgen" "$work_dir/configure.log"; then
  echo "FAIL: the consumer did not pick the installed generator:" >&2
  grep "mbgen generator" "$work_dir/configure.log" >&2 || true
  exit 1
fi
cmake --build "$work_dir/build" -j2 >"$work_dir/build.log" || { cat "$work_dir/build.log"; exit 1; }
"$work_dir/build/consumer"
"$work_dir/build/consumer_c"

# The Python package, when the build made it: importable from the prefix alone, running the
# installed mbgen command.
if [[ -d $prefix/lib/python3/dist-packages/mbgen ]]; then
  # MBGEN_SANITIZED_PYTHON: in the whole sanitized build, ASan's runtime preloaded for python3
  # alone (cmake/mbgen_sanitizers.cmake); unset elsewhere.
  # shellcheck disable=SC2086
  env PYTHONPATH=$prefix/lib/python3/dist-packages MBGEN_EXECUTABLE= ${MBGEN_SANITIZED_PYTHON:-} /usr/bin/python3 - "$prefix" "$source_dir/../data/tiny_arm.urdf" <<'PY'
import os, sys
import mbgen
prefix, urdf = sys.argv[1], sys.argv[2]
assert mbgen.__file__.startswith(prefix), mbgen.__file__
assert os.path.samefile(mbgen.executable(), os.path.join(prefix, "bin", "mbgen")), mbgen.executable()
robot = mbgen.load(urdf, base="fixed")
assert mbgen.inspect(urdf, base="fixed")["nv"] == robot.nv
print(f"python: mbgen from {os.path.dirname(mbgen.__file__)}, {robot.name} nv {robot.nv}")
PY
fi
