#!/usr/bin/env bash
# Installs the Debian 12 packages igi builds, tests and runs with; skips those already present.
set -euo pipefail
packages=(
  g++ cmake ninja-build pkg-config git
  libglm-dev libtinygltf-dev libtinyexr-dev libstb-dev nlohmann-json3-dev
  libembree-dev libtbb-dev libcli11-dev
  catch2 libbenchmark-dev
  libopenmpi-dev openmpi-bin
  libsdl2-dev xvfb xauth
  doxygen
  python3-dev python3-venv pybind11-dev python3-numpy python3-pytest
)
missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "igi: installing ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
