# Sourced by the Mitsuba checks (mitsuba_compare.sh, mitsuba_envmap.sh) with $work, $venv and
# $build set: makes the folder, installs Mitsuba 3 and numpy from PyPI into the virtual
# environment $venv if it has none, and finds igi-path-render and igi-compare in $build as
# $path_render and $compare.
mkdir -p "$work"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet mitsuba numpy
fi
"$venv/bin/python" -c "import mitsuba; print('mitsuba', mitsuba.__version__)"
path_render="$(find "$build" -name igi-path-render -type f -perm -u+x | head -n 1)"
compare="$(find "$build" -name igi-compare -type f -perm -u+x | head -n 1)"
[ -n "$path_render" ] && [ -n "$compare" ] || { echo "build igi-path-render and igi-compare in $build first" >&2; exit 1; }
