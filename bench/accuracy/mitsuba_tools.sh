# Sourced by the Mitsuba checks (mitsuba_compare.sh, mitsuba_envmap.sh) with $work, $venv and
# $build set: makes the folder, installs Mitsuba 3 and numpy from PyPI into the virtual
# environment $venv if it has none, and finds igi-path-render and igi-compare in $build as
# $path_render and $compare; defines compare_seeds.
mkdir -p "$work"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet mitsuba numpy
fi
"$venv/bin/python" -c "import mitsuba; print('mitsuba', mitsuba.__version__)"
path_render="$(find "$build" -name igi-path-render -type f -perm -u+x | head -n 1)"
compare="$(find "$build" -name igi-compare -type f -perm -u+x | head -n 1)"
[ -n "$path_render" ] && [ -n "$compare" ] || { echo "build igi-path-render and igi-compare in $build first" >&2; exit 1; }

# Prints igi against Mitsuba for seeds 0 and 1 ($work/igi_N.exr, $work/mitsuba_N.exr), each renderer
# against itself (the noise two estimates of one image differ by), and mitsuba_stats.py's means.
compare_seeds() {
  echo "== igi vs mitsuba (seed 0 each, then seed 1 each)"
  "$compare" --json "$work/mitsuba_0.exr" "$work/igi_0.exr"
  "$compare" --json "$work/mitsuba_1.exr" "$work/igi_1.exr"
  echo "== mitsuba vs mitsuba (noise of two Mitsuba estimates)"
  "$compare" --json "$work/mitsuba_0.exr" "$work/mitsuba_1.exr"
  echo "== igi vs igi (noise of two igi estimates)"
  "$compare" --json "$work/igi_0.exr" "$work/igi_1.exr"
  echo "== means and low-pass (igi - mitsuba in units of its standard error; about 1 if they agree)"
  "$venv/bin/python" "$here/mitsuba_stats.py" "$work"
}
