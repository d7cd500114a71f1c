#!/usr/bin/env bash
# Builds igi's libFuzzer harnesses with clang (ASan + UBSan) and runs each for a set time.
# Usage: bash scripts/fuzz.sh [SECONDS_PER_HARNESS] [HARNESS...]   (default 300 s, both harnesses)
#   harnesses: igi_fuzz_gltf (the glTF loader), igi_fuzz_scene_render (loader + every backend + a frame)
# The corpus grows in build/fuzz/corpus/<harness> across runs; crashing inputs land in
# build/fuzz/findings/<harness>/. Prints executions and findings per harness; exits 1 on findings.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-300}"
shift || true
harnesses=("$@")
[ ${#harnesses[@]} -gt 0 ] || harnesses=(igi_fuzz_gltf igi_fuzz_scene_render)

bash scripts/deps.sh
# Debian 12: clang 14 is the default clang; libFuzzer comes in libclang-rt-14-dev (pulled in by clang).
missing=()
for package in clang libclang-rt-14-dev; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
fi

build=build/fuzz
# AVX2, not native: lanes.hpp refuses clang with AVX-512 (libstdc++'s simd masks miscompile there).
CXX=clang++ cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Debug -DIGI_BUILD_FUZZERS=ON \
  -DIGI_BUILD_TESTS=OFF -DIGI_BUILD_BENCH=OFF -DIGI_BUILD_EXAMPLES=OFF -DIGI_ISA=avx2 >/dev/null
cmake --build "$build" -j 2 --target "${harnesses[@]}"

seeds="$build/seeds"
rm -rf "$seeds"
python3 fuzz/make_seeds.py "$seeds" >/dev/null

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:allocator_may_return_null=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
status=0
summary=""
for harness in "${harnesses[@]}"; do
  corpus="$build/corpus/$harness"
  findings="$build/findings/$harness"
  mkdir -p "$corpus" "$findings"
  log="$build/$harness.log"
  start="$build/$harness.start"  # findings of earlier runs stay in the folder; only newer ones count
  touch "$start"
  echo "== $harness: fuzzing for $seconds s (log: $log)"
  # -timeout 30: a tiny frame takes milliseconds, so 30 s on one input is a hang, not slowness.
  # -rss_limit_mb 2048 (libFuzzer's default, named here): the harnesses cap igi's memory budget at 1 GiB.
  # -max_len 65536: room for the Cornell seeds (9 KiB) to grow; larger inputs only slow mutation.
  "$build/fuzz/$harness" "$corpus" "$seeds" -max_total_time="$seconds" -timeout=30 -rss_limit_mb=2048 \
    -max_len=65536 -print_final_stats=1 -artifact_prefix="$findings/" >"$log" 2>&1 || true
  executions=$(grep -m1 -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  found=$(find "$findings" -type f -newer "$start" | wc -l)
  line="$harness: $executions executions in $seconds s, corpus $(ls "$corpus" | wc -l) files, $found findings"
  echo "$line"
  summary+="$line"$'\n'
  if [ "$found" -gt 0 ]; then
    status=1
    find "$findings" -type f -newer "$start" -printf '  %p (%s bytes)\n'
    grep -m3 -E 'ERROR: |runtime error|invariant broken|uncaught exception|deadly signal' "$log" | sed 's/^/  /' || true
  fi
done
echo "== summary"
printf '%s' "$summary"
exit $status
