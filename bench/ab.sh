#!/usr/bin/env bash
# A/B speed of two effigi builds on one scene: the builds alternate run by run (so a slow
# spell of a shared machine hits both), and the median samples/s ratio B / A is printed.
# This is how the per-change rows of bench/RESULTS.md (2026-11-29) were measured: copy the
# old build's bin/effigi, lib/ and share/ to a folder (bin/effigi finds its modules
# relative to itself), rebuild, compare.
#
#   bench/ab.sh OLD/bin/effigi build/release/bin/effigi [scene.xml] [pairs] [threads] [spp]
#   defaults: the Cornell box, 5 pairs, 1 thread, 32 spp
set -euo pipefail
A=$1 B=$2
SCENE=${3:-$(dirname "$0")/../scenes/cornell-box/scene.xml}
PAIRS=${4:-5} THREADS=${5:-1} SPP=${6:-32}
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
rate() {  # samples/s of one render, in M
    "$1" render "$SCENE" -o "$OUT/$2.exr" --no-progress --stats -t "$THREADS" -D spp="$SPP" |
        sed -n 's/.*: \([0-9.]*\) M samples\/s.*/\1/p'
}
a=() b=()
for _ in $(seq "$PAIRS"); do
    a+=("$(rate "$A" a)")
    b+=("$(rate "$B" b)")
done
python3 - "${a[*]}" "${b[*]}" <<'PY'
import statistics, sys
a = [float(x) for x in sys.argv[1].split()]
b = [float(x) for x in sys.argv[2].split()]
print("A M samples/s:", " ".join(f"{x:.3f}" for x in sorted(a)))
print("B M samples/s:", " ".join(f"{x:.3f}" for x in sorted(b)))
print(f"median B / A: {statistics.median(b) / statistics.median(a):.3f}")
PY
