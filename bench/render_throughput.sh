#!/usr/bin/env bash
# Times `effigi render` on the Cornell box and reports samples/s and peak memory.
# A benchmark, not a test: run it on a quiet machine, compare runs of the same build.
#   bench/render_throughput.sh [spp] [res] [repeats]
set -euo pipefail
cd "$(dirname "$0")/.."
spp=${1:-64}
res=${2:-256}
repeats=${3:-3}
bin=build/release/bin/effigi
[ -x "$bin" ] || { echo "build first: make build" >&2; exit 1; }
echo "Cornell box ${res}x${res}, ${spp} spp, $(nproc) cores, $(date -u +%Y-%m-%d)"
for i in $(seq "$repeats"); do
  "$bin" render scenes/cornell-box/scene.xml -D "spp=$spp" -D "res=$res" -o out/bench/throughput.exr --no-progress | tail -n 1
done
