#!/usr/bin/env bash
# Accuracy benchmark: IGI (VPLs, interleaving, filter, anti-aliasing, clamp) and the reference path
# tracer against a converged path-traced reference, on the built-in Cornell box and Sponza_lit at
# 640x480. Writes bench/results/accuracy_<scene>.csv and accuracy_<scene>_{time,vpls}.png.
#
# usage: bench/accuracy/sweep.sh [BUILD_DIR] [SCENE...]
#   BUILD_DIR  default build/accuracy (configured with the native preset if it is not yet)
#   SCENE      cornell and/or sponza_lit (default both; Sponza_lit is skipped with a message
#              when the shared scenes folder is missing)
# Environment (see sweep.py): IGI_ACCURACY_REF_SPP_CORNELL, IGI_ACCURACY_REF_SPP_SPONZA_LIT,
# IGI_ACCURACY_FRAMES, IGI_ACCURACY_THREADS, IGI_ACCURACY_SIZE, IGI_ACCURACY_RERUN=1,
# IGI_SCENES_DIR. Renders and references are cached in BUILD_DIR/sweep; a second run only
# compares and draws. Runtime on the shared 2-core machine: see bench/README.md.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
build="${1:-$root/build/accuracy}"
shift || true
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(cornell sponza_lit)
export IGI_SCENES_DIR="${IGI_SCENES_DIR:-$root/../shared/scenes}"

chosen=()
for scene in "${scenes[@]}"; do
  if [ "$scene" = sponza_lit ] && [ ! -f "$IGI_SCENES_DIR/sponza/Sponza_lit.gltf" ]; then
    echo "sweep: skipping sponza_lit: $IGI_SCENES_DIR/sponza/Sponza_lit.gltf is missing (set IGI_SCENES_DIR)"
    continue
  fi
  chosen+=("$scene")
done
[ ${#chosen[@]} -gt 0 ] || { echo "sweep: no scene to run" >&2; exit 1; }

# Python with matplotlib and numpy: Debian's (scripts/chart_python.sh installs them when missing).
python="$(bash "$root/scripts/chart_python.sh")" || { echo "sweep: charts need python3-matplotlib" >&2; exit 1; }

# Only the two programs the sweep runs.
[ -f "$build/CMakeCache.txt" ] || (cd "$root" && cmake --preset native -B "$build")
cmake --build "$build" -j 2 --target igi-render igi-compare

echo "sweep: $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, $(uptime)"
time "$python" "$here/sweep.py" "$build" "$build/sweep" "$root/bench/results" "${chosen[@]}"
echo "sweep: done $(date -u '+%Y-%m-%d %H:%M UTC'), $(uptime)"
