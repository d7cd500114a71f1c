#!/usr/bin/env bash
# Builds igi-render and renders the built-in Cornell box to cornell.png, printing frame time and
# Mrays/s. Usage: bash scripts/demo.sh [extra igi-render options]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh
cmake --preset native >/dev/null
cmake --build --preset native --target igi-render
./build/native/examples/render/igi-render --builtin cornell -o cornell.png "$@"
