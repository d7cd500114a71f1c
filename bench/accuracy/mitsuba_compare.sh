#!/usr/bin/env bash
# Independent check of igi's reference path tracer against Mitsuba 3 on the Cornell box glTF.
# Not part of CI: it installs Mitsuba 3 from PyPI into its own virtual environment.
#
# usage: bench/accuracy/mitsuba_compare.sh BUILD_DIR [SIZE] [SPP]
#   BUILD_DIR holds the built igi-path-render and igi-compare (e.g. build/native).
# Renders both at SIZE x SIZE (default 128) and SPP samples per pixel (default 256), two seeds
# each, and prints igi-compare's metrics for igi against Mitsuba next to each renderer against
# itself (two seeds): if both converge to the same image, RMSE(igi, mitsuba)^2 is about the mean
# of the two self-RMSE^2 (all three are differences of two independent noisy estimates).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
build="$(cd "${1:?usage: mitsuba_compare.sh BUILD_DIR [SIZE] [SPP]}" && pwd)"
size="${2:-128}"
spp="${3:-256}"
scene="$root/../shared/scenes/cornell/cornell_box.gltf"
work="${MITSUBA_WORK:-$build/mitsuba_compare}"
venv="$work/venv"
# shellcheck source=mitsuba_tools.sh
source "$here/mitsuba_tools.sh"

time "$venv/bin/python" "$here/mitsuba_compare.py" "$scene" "$work/mitsuba_" "$size" "$size" "$spp" 0 1
for seed in 0 1; do
  time "$path_render" "$scene" -o "$work/igi_$seed.exr" --size "${size}x${size}" --spp "$spp" --seed "$seed"
done

compare_seeds
