#!/usr/bin/env bash
# Where the time goes: effigi's own counters (effigi render --stats: rays per sample and
# rays/s by kind, thread time in tracing / shading / camera samples / film), then a
# sampling profile with perf (Debian `linux-perf`) of the same render, top functions and
# top libraries by self time.
#
#   bench/profile.sh [scene.xml] [spp]          default: the Cornell box, 64 spp
#   PERF_ARGS="--call-graph dwarf" bench/profile.sh ...   (callers too; much larger data)
#
# perf needs kernel.perf_event_paranoid <= 2 for a user's own processes (the default on
# Debian); inside containers it may need --privileged. Embree ships without symbols, so
# its time shows as addresses inside libembree3 (summed in the library table).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
SCENE=${1:-$ROOT/scenes/cornell-box/scene.xml}
SPP=${2:-64}
EFFIGI=${EFFIGI:-$ROOT/build/release/bin/effigi}
OUT=$ROOT/out/bench
mkdir -p "$OUT"
command -v perf >/dev/null || { echo "profile.sh: perf not found (apt-get install linux-perf)" >&2; exit 1; }

echo "## effigi render --stats ($SCENE, $SPP spp)"
"$EFFIGI" render "$SCENE" -o "$OUT/profile.exr" -D spp="$SPP" --no-progress --stats | grep -v '^wrote'

echo
echo "## perf: top functions by self time"
perf record ${PERF_ARGS:-} -F 2000 -o "$OUT/perf.data" -- \
    "$EFFIGI" render "$SCENE" -o "$OUT/profile.exr" -D spp="$SPP" --no-progress >/dev/null 2>"$OUT/perf.log"
perf report -i "$OUT/perf.data" --no-children --sort dso,symbol -g none --percent-limit 0.7 2>/dev/null |
    grep -v '^#' | grep '%' | grep -v 'libembree3' | sed 's/  */ /g' | cut -c1-140 | head -30
echo
echo "## perf: self time by library"
perf report -i "$OUT/perf.data" --no-children --sort dso -g none --percent-limit 0.5 2>/dev/null |
    grep -v '^#' | grep '%' | sed 's/  */ /g'
