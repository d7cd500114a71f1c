#!/usr/bin/env bash
# Runs igi's whole benchmark suite, the source of every number bench/README.md quotes: builds the
# bench targets (Release, native preset), runs them, writes bench/results/*.json, draws PNG
# charts (Debian's python3-matplotlib) and rewrites the generated tables in
# bench/README.md (between <!-- bench:NAME --> and <!-- /bench:NAME -->; the hand-written text
# around them stays).
#
#   bash bench/run_all.sh [--smoke] [--build-dir DIR] [--no-build] [--frames N]
#
#   --smoke        tiny images, one frame: checks that every benchmark runs (a few seconds);
#                  results go to a temporary folder, README and bench/results are left alone
#   --build-dir    where to configure and build (default build/native, the preset's folder)
#   --no-build     use the binaries already in the build folder
#   --frames N     timed frames per configuration (default 3; medians are reported)
#
# The walkthroughs (bench/walkthrough/run.sh: per frame error, brightness, flicker and frame time
# side by side, every method) cache their path-traced references in $IGI_WALK_WORK (default
# build-dir/walkthrough-references): the first full run renders them (most of its time), later
# ones only IGI's frames.
#
# Needs the Debian packages of scripts/deps.sh, and python3-matplotlib for the charts (charts are
# skipped with a message if it cannot). The suite itself took 944-951 s on 2 cores at load average
# 12-15 (other builds running, about a quarter of the cores for it); an idle machine needs less.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/.." && pwd)"
smoke=0
build=1
frames=3
build_dir="$root/build/native"
while [[ $# -gt 0 ]]; do
  case "$1" in
    --smoke) smoke=1 ;;
    --no-build) build=0 ;;
    --build-dir) build_dir="$(realpath -m "$2")"; shift ;;
    --frames) frames="$2"; shift ;;
    -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
    *) echo "run_all.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
[[ "$frames" =~ ^[1-9][0-9]*$ ]] || { echo "run_all.sh: --frames needs a positive whole number, got '$frames'" >&2; exit 2; }

total_start=$(date +%s)
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
targets=(pipeline_bench scaling_bench shading_bench occlusion16_bench filters_bench temporal_bench igi-walkthrough)

if [[ $build == 1 ]]; then
  if [[ ! -f "$build_dir/CMakeCache.txt" ]]; then
    cmake --preset native -B "$build_dir" >/dev/null
  else
    cmake "$build_dir" >/dev/null  # picks up bench folders added since the last configure
  fi
  known="$(cmake --build "$build_dir" --target help)"
  for target in "${targets[@]}"; do
    if grep -q "^$target:" <<<"$known"; then
      cmake --build "$build_dir" -j 2 --target "$target"
    else
      echo "run_all.sh: no target $target in this tree: skipped"
    fi
  done
fi

start=$(date +%s)  # the suite's own time starts after the build
if [[ $smoke == 1 ]]; then
  results="$(mktemp -d)"
  trap 'rm -rf "$results"' EXIT
  extra=(--smoke)
else
  results="$here/results"
  mkdir -p "$results"
  extra=("--frames=$frames")
fi

bin() { echo "$build_dir/bench/$1/$2"; }
# run NAME PROGRAM ARGS...: one benchmark process whose JSON goes to $results/NAME.json.
run() {
  local name="$1" program="$2"
  shift 2
  if [[ ! -x "$program" ]]; then
    echo "run_all.sh: $program is not built: $name skipped"
    return 0
  fi
  echo "== $name: $(basename "$program") $*"
  local t0=$(date +%s)
  "$program" "$@" --benchmark_format=console --benchmark_out="$results/$name.json" --benchmark_out_format=json
  echo "== $name: $(( $(date +%s) - t0 )) s"
}

pipeline="$(bin pipeline pipeline_bench)"
scaling="$(bin scaling scaling_bench)"
run efficiency "$pipeline" "${extra[@]}" --benchmark_filter='^efficiency/'
run table1 "$pipeline" "${extra[@]}" --benchmark_filter='^table1/'
run table3 "$pipeline" "${extra[@]}" --benchmark_filter='^table3/'
run fps "$pipeline" "${extra[@]}" --benchmark_filter='^fps/'
run threads "$pipeline" "${extra[@]}" --benchmark_filter='^threads/'
run width "$pipeline" "${extra[@]}" --benchmark_filter='^width/'
# One process per scene size, so each one's peak memory is its own.
if [[ -x "$scaling" ]]; then
  rm -f "$results"/size_*.json  # the list of sizes may have changed since the last run
  i=0
  while read -r size; do
    [[ -n "$size" ]] || continue
    run "size_$i" "$scaling" "${extra[@]}" --benchmark_filter="^${size}/iterations:"
    i=$((i + 1))
  done < <("$scaling" "${extra[@]}" --benchmark_list_tests | sed 's|/iterations:.*||')
fi
run shading "$(bin shading shading_bench)" "${extra[@]}"
# How EmbreeBackend<16> traces coherent shadow packets around Embree's looping kernel (medians of 5;
# the smoke run times each way once, briefly).
if [[ $smoke == 1 ]]; then
  run occlusion16 "$(bin backends occlusion16_bench)" --benchmark_min_time=0.01
else
  run occlusion16 "$(bin backends occlusion16_bench)" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
    --benchmark_min_time=0.2
fi

# The filters alone on one tile, one thread: ns per pixel of each filter and à-trous stage (medians of 5).
if [[ $smoke == 1 ]]; then
  run filters_bench "$(bin filters filters_bench)" --benchmark_min_time=0.001
else
  run filters_bench "$(bin filters filters_bench)" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
fi

# Temporal reuse alone on a 640 x 480 frame, one thread: ns per pixel in each of its modes (medians of 5).
if [[ $smoke == 1 ]]; then
  run temporal_bench "$(bin temporal temporal_bench)" --benchmark_min_time=0.001
else
  run temporal_bench "$(bin temporal temporal_bench)" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
fi

# The walkthroughs: error and frame time of each method frame by frame while things move.
walkthrough="$(bin walkthrough igi-walkthrough)"
if [[ ! -x "$walkthrough" ]]; then
  echo "run_all.sh: $walkthrough is not built: walkthroughs skipped"
elif [[ $smoke == 1 ]]; then
  echo "== walkthrough (smoke): one walk, 32x24, 2 frames, 4-spp references"
  "$walkthrough" --work "$results/walkthrough-work" --walks window --size 32x24 --frames 2 --reference-spp 4 \
    > "$results/walkthrough.json"
else
  walk_work="${IGI_WALK_WORK:-$build_dir/walkthrough-references}"
  echo "== walkthrough: references cached in $walk_work"
  t0=$(date +%s)
  bash "$here/walkthrough/run.sh" "$build_dir" "$walk_work"
  echo "== walkthrough: $(( $(date +%s) - t0 )) s"
fi

seconds=$(( $(date +%s) - start ))
load_after=$(cut -d' ' -f1-3 /proc/loadavg)
cat > "$results/machine.json" <<EOF
{"date": "$(date -u +%Y-%m-%dT%H:%MZ)", "seconds": $seconds, "cores": $(nproc), "load_before": "$load_before",
 "load_after": "$load_after", "frames": $frames, "smoke": $smoke,
 "note": "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//; s/"//g')"}
EOF

# Charts need matplotlib: Debian's python3-matplotlib (scripts/chart_python.sh installs it when missing).
charts=--charts
if ! python="$(bash "$here/../scripts/chart_python.sh")"; then
  echo "run_all.sh: no python3-matplotlib: no charts"
  charts=""
  python=python3
fi
if [[ $smoke == 1 ]]; then
  # The report runs on a copy of the README, so the smoke run checks it without touching the real one.
  cp "$here/README.md" "$results/README.md"
  "$python" "$here/report.py" "$results" "$results/README.md" $charts
  echo "run_all.sh: smoke run passed in $seconds s"
else
  "$python" "$here/report.py" "$results" "$here/README.md" $charts
  echo "run_all.sh: suite ran in $seconds s, $(( $(date +%s) - total_start )) s with build and report" \
    "(load average $load_before before, $load_after after)"
fi
