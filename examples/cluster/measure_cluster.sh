#!/bin/sh
# Measures the tile farm on this machine: 1 rank alone, 1 worker (-np 2) and 2 workers (-np 3),
# one thread per rank, and writes igi-cluster's JSON statistics into OUT (default ./cluster-measure).
# Usage: measure_cluster.sh BUILD_DIR [OUT] [extra igi-cluster options...]
set -eu
build=$1
out=${2:-cluster-measure}
shift; [ $# -gt 0 ] && shift
exe="$build/examples/cluster/igi-cluster"
mkdir -p "$out"
root=""
[ "$(id -u)" = 0 ] && root="--allow-run-as-root"
scene=${IGI_MEASURE_SCENE:---builtin cornell}
frames=${IGI_MEASURE_FRAMES:-12}
uptime > "$out/load.txt"
for np in 1 2 3; do
  # shellcheck disable=SC2086
  mpirun --oversubscribe $root -np $np "$exe" $scene --size 640x480 --threads 1 --frames "$frames" \
    --stats json -o "$out/np$np.png" "$@" | tail -n 1 > "$out/np$np.json"
  uptime >> "$out/load.txt"
done
echo "wrote $out/np1.json np2.json np3.json and load.txt"
