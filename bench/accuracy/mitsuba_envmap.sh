#!/usr/bin/env bash
# Independent check of igi's environment light (--environment FILE) against Mitsuba 3's envmap
# emitter. Not part of CI: it installs Mitsuba 3 and numpy from PyPI into its own virtual environment.
#
# usage: bench/accuracy/mitsuba_envmap.sh BUILD_DIR [WIDTH] [HEIGHT] [SPP]
#   BUILD_DIR holds the built igi-path-render and igi-compare (e.g. build/native).
# mitsuba_envmap.py writes a small glTF scene (ground, two boxes, a camera) and a 256 x 128 sky
# (EXR and PFM: gradient, azimuthal tint, a small bright sun). Both path tracers render it at
# WIDTH x HEIGHT (default 160 x 120), SPP samples per pixel (default 512), box filter, two seeds
# each; igi-compare prints igi against Mitsuba next to each renderer against itself (if both
# converge to the same image, RMSE(igi, mitsuba)^2 is about the mean of the two self-RMSE^2).
# Orientation: Mitsuba also renders the sky turned 180 degrees about +Y and mirrored (x -> -x),
# which must be far from igi; and igi renders the PFM copy of the map, which must equal the EXR's.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="$(cd "${1:?usage: mitsuba_envmap.sh BUILD_DIR [WIDTH] [HEIGHT] [SPP]}" && pwd)"
width="${2:-160}"
height="${3:-120}"
spp="${4:-512}"
work="${MITSUBA_WORK:-$build/mitsuba_envmap}"
venv="${MITSUBA_VENV:-$work/venv}"
# shellcheck source=mitsuba_tools.sh
source "$here/mitsuba_tools.sh"

"$venv/bin/python" "$here/mitsuba_envmap.py" scene "$work"
scene="$work/envmap_scene.gltf"
time timeout 1200 "$venv/bin/python" "$here/mitsuba_envmap.py" render "$work" "$width" "$height" "$spp" identity 0 1
for seed in 0 1; do
  time timeout 1200 "$path_render" "$scene" --environment "$work/sky.exr" -o "$work/igi_$seed.exr" \
    --size "${width}x${height}" --spp "$spp" --seed "$seed"
done

compare_seeds

echo "== orientation: Mitsuba with the sky turned 180 degrees about +Y, and mirrored (x -> -x), against igi seed 0"
quick=$(( spp / 4 > 0 ? spp / 4 : 1 ))
for variant in turned mirrored; do
  timeout 1200 "$venv/bin/python" "$here/mitsuba_envmap.py" render "$work" "$width" "$height" "$quick" "$variant" 0
  echo "-- $variant ($quick spp)"
  "$compare" --json "$work/mitsuba_${variant}_0.exr" "$work/igi_0.exr"
done
echo "== igi with the PFM copy of the map against the EXR (seed 0; identical if both files read alike)"
timeout 1200 "$path_render" "$scene" --environment "$work/sky.pfm" -o "$work/igi_pfm_0.exr" \
  --size "${width}x${height}" --spp "$spp" --seed 0
"$compare" --json "$work/igi_0.exr" "$work/igi_pfm_0.exr"
echo "== the open ground alone against its analytic light (each renderer's texel convention)"
timeout 1200 "$venv/bin/python" "$here/mitsuba_envmap.py" ground "$work" "$path_render" "$spp"
