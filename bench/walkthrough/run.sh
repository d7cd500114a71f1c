#!/usr/bin/env bash
# The walkthrough measurements: the forest scene written (bench/scenes/forest.py), igi-walkthrough
# over every walk and method, its JSON kept in bench/results/walkthrough.json, the charts and the
# findings table drawn from it. References are cached in WORK, so a second run only re-renders IGI.
#
#   bash bench/walkthrough/run.sh BUILD_DIR WORK_DIR [igi-walkthrough options...]
set -euo pipefail
cd "$(dirname "$0")/../.."
build="${1:?usage: run.sh BUILD_DIR WORK_DIR [options]}"
work="${2:?usage: run.sh BUILD_DIR WORK_DIR [options]}"
shift 2
mkdir -p "$work" bench/results
python3 bench/scenes/forest.py 200 "$work" >/dev/null
"$build/bench/walkthrough/igi-walkthrough" --work "$work" --forest "$work/forest_200.gltf" "$@" > bench/results/walkthrough.json
# Charts need matplotlib: Debian's python3-matplotlib (scripts/chart_python.sh installs it when missing).
if python="$(bash scripts/chart_python.sh)"; then
  "$python" bench/walkthrough/charts.py bench/results/walkthrough.json bench/results
else
  echo "run.sh: no python3-matplotlib: the JSON is in bench/results/walkthrough.json, no charts"
fi
