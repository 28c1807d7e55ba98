#!/usr/bin/env bash
# Error against run time for every renderer on one chart (issue 13): `effigi converge` on
# the Cornell box (against the committed 2048-spp Mitsuba 3 reference) and on the caustic
# scene (against a long sppm render, a; a second one with another seed, b, bounds a's own
# noise: relMSE(a, b) estimates var_a + var_b ≥ var_a).
#
#   bench/converge_renderers.sh [seconds per renderer] [reference iterations]
#
# Writes out/bench/converge-{cornell,caustic}/ (convergence.csv / .svg, report.html) and
# copies the two charts to docs/images/. Biased renderers (photonmap, irradiancecache)
# flatten at their bias floor; the consistent ones (path, ptracer, sppm) keep falling.
set -euo pipefail
cd "$(dirname "$0")/.."
T=${1:-60}
REF_N=${2:-1000}
EFFIGI=build/release/bin/effigi
OUT=out/bench
mkdir -p "$OUT" docs/images

echo "== Cornell box, ${T} s per renderer"
$EFFIGI converge scenes/cornell-box/scene.xml --reference tests/data/cornell/mitsuba-reference.exr \
    --renderer path,ptracer,photonmap,sppm,irradiancecache,radiosity --time "$T" --no-progress \
    --out "$OUT/converge-cornell"
cp "$OUT/converge-cornell/convergence.svg" docs/images/convergence-renderers-cornell.svg

if [ ! -f "$OUT/caustic-ref-a.exr" ] || [ ! -f "$OUT/caustic-ref-b.exr" ]; then
    echo "== caustic reference: sppm, 2 × ${REF_N} iterations"
    for s in a:1 b:2; do
        $EFFIGI render scenes/caustic/sppm.xml -o "$OUT/caustic-ref-${s%%:*}.exr" --spp "$REF_N" \
            --seed "${s##*:}" --no-progress
    done
fi
# relMSE(a, b) with the mean of the two as the reference value: mean (a − b)² / (m² + 0.01).
A="$OUT/caustic-ref-a.exr"; B="$OUT/caustic-ref-b.exr"
stats=$(oiiotool "$A" --ch R,G,B "$B" --ch R,G,B --sub --dup --mul "$A" --ch R,G,B "$B" --ch R,G,B --add --mulc 0.5 \
        --dup --mul --addc 0.01 --div --printstats | grep "Stats Avg")
echo "$stats" | awk '{ m = ($3 + $4 + $5) / 3; printf "caustic reference a: relMSE(a, b) = %.4g bounds its own noise (sppm bias not included)\n", m }'

echo "== caustic scene, ${T} s per renderer"
$EFFIGI converge scenes/caustic/scene.xml --reference "$A" \
    --renderer path,ptracer,photonmap,sppm,irradiancecache --time "$T" --no-progress \
    --out "$OUT/converge-caustic"
cp "$OUT/converge-caustic/convergence.svg" docs/images/convergence-renderers-caustic.svg
