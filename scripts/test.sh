#!/usr/bin/env bash
# Builds and runs igi's whole test suite. Usage: bash scripts/test.sh [preset] (default: native)
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-native}"
bash scripts/deps.sh
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
ctest --preset "$preset" -j "$(nproc)"
