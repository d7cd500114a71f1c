#!/usr/bin/env bash
# Builds and runs igi's whole test suite. Usage: bash scripts/test.sh [preset] (default: native)
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-native}"
bash scripts/deps.sh
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
# Under the sanitizers: a stack trace with every UBSan report (which already aborts the test:
# -fno-sanitize-recover), and no core files from aborting tests.
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}"
export ASAN_OPTIONS="${ASAN_OPTIONS:-disable_coredump=1}"
ctest --preset "$preset" -j "$(nproc)"
