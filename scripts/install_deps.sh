#!/usr/bin/env bash
# Installs the Debian packages mbgen needs to build, test and benchmark (run as root).
# Does nothing when they are all present; otherwise updates the package lists once and installs.
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libeigen3-dev liburdfdom-dev libyaml-cpp-dev libfmt-dev libcli11-dev nlohmann-json3-dev
  libtinyxml2-dev libconsole-bridge-dev libssl-dev libassimp-dev libqhull-dev
  libgtest-dev libbenchmark-dev liborocos-kdl-dev libfcl-dev libmujoco-dev
  gcc-arm-none-eabi libstdc++-arm-none-eabi-newlib
  gnuplot-nox python3 valgrind
  clang libclang-rt-14-dev
)
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
