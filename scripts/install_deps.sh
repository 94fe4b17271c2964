#!/usr/bin/env bash
# Installs the Debian packages mbgen needs to build, test and benchmark (run as root).
# Does nothing when they are all present; otherwise updates the package lists once and installs.
#
#   install_deps.sh          what the build and the test suite need
#   install_deps.sh --fuzz   and clang with its sanitizer runtimes, for the fuzz targets
#                            (fuzz/run_fuzzers.sh asks for them; the suite's default run does not
#                            build them, so CI does not download a second compiler)
#   install_deps.sh --browser  and Debian's Chromium, which the tests of `mbgen view`'s pages load
#                            headless (scripts/test.sh asks for it; the Quick start's build does not)
#   install_deps.sh --ccache   and ccache, which scripts/test_sanitized.sh compiles through (its
#                            whole run is hours of compiling; a repeat recompiles what changed)
# npm (the build installs three.js with it, for `mbgen view`) comes with Node.js: Debian's nodejs
# and npm are installed only when no npm is on the PATH (a Node.js from elsewhere brings its own,
# and Debian's npm package would conflict with it).
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libeigen3-dev liburdfdom-dev libyaml-cpp-dev libfmt-dev libcli11-dev nlohmann-json3-dev
  libtinyxml2-dev libconsole-bridge-dev libssl-dev libassimp-dev libqhull-dev libsdformat-dev
  libgtest-dev libbenchmark-dev liborocos-kdl-dev libfcl-dev libmujoco-dev coinor-libipopt-dev
  gcc-arm-none-eabi libstdc++-arm-none-eabi-newlib
  gnuplot-nox python3 valgrind
  python3-dev pybind11-dev python3-numpy python3-matplotlib
)
for option in "$@"; do
  case "$option" in
    --fuzz) packages+=(clang libclang-rt-14-dev) ;;
    --browser) packages+=(chromium) ;;
    --ccache) packages+=(ccache) ;;
    *) echo "usage: $0 [--fuzz] [--browser] [--ccache]" >&2; exit 2 ;;
  esac
done
command -v npm >/dev/null || packages+=(nodejs npm)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "mbgen: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq "${missing[@]}" >/dev/null
fi
