#!/usr/bin/env bash
# Bidirectional and Metropolis renderers against path tracing (issue 14): error against
# run time with `effigi converge`, one chart per scene.
#  - door: the camera's room is lit only through a 4 cm gap from the lamp's room
#    (scenes/door, after Veach's thesis fig. 10.3); reference: a long bdpt render, a,
#    and a second with another seed, b, whose relMSE(a, b) bounds a's own noise.
#  - cornell-box: against the committed 2048-spp Mitsuba 3 reference.
#
#   bench/bdpt_converge.sh [seconds per renderer] [reference spp] [renderers]
#
# Writes out/bench/converge-{door,cornell-bdpt}/ and copies the charts to docs/images/.
set -euo pipefail
cd "$(dirname "$0")/.."
T=${1:-60}
REF_SPP=${2:-1024}
RENDERERS=${3:-path,bdpt,pssmlt}
RES=128
EFFIGI=build/release/bin/effigi
OUT=out/bench
mkdir -p "$OUT" docs/images

if [ ! -f "$OUT/door-ref-a.exr" ] || [ ! -f "$OUT/door-ref-b.exr" ]; then
    echo "== door reference: bdpt, 2 × ${REF_SPP} spp at ${RES}²"
    for s in a:1 b:2; do
        $EFFIGI render scenes/door/scene.xml -D renderer=bdpt -D res=$RES -o "$OUT/door-ref-${s%%:*}.exr" \
            --spp "$REF_SPP" --seed "${s##*:}" --no-progress
    done
fi
A="$OUT/door-ref-a.exr"; B="$OUT/door-ref-b.exr"
stats=$(oiiotool "$A" --ch R,G,B "$B" --ch R,G,B --sub --dup --mul "$A" --ch R,G,B "$B" --ch R,G,B --add --mulc 0.5 \
        --dup --mul --addc 0.01 --div --printstats | grep "Stats Avg")
echo "$stats" | awk '{ m = ($3 + $4 + $5) / 3; printf "door reference a: relMSE(a, b) = %.4g bounds its own noise\n", m }'

echo "== door, ${T} s per renderer"
$EFFIGI converge scenes/door/scene.xml -D res=$RES --reference "$A" --renderer "$RENDERERS" --time "$T" \
    --no-progress --out "$OUT/converge-door"
cp "$OUT/converge-door/convergence.svg" docs/images/convergence-door.svg

echo "== Cornell box, ${T} s per renderer"
$EFFIGI converge scenes/cornell-box/scene.xml --reference tests/data/cornell/mitsuba-reference.exr \
    --renderer "$RENDERERS" --time "$T" --no-progress --out "$OUT/converge-cornell-bdpt"
cp "$OUT/converge-cornell-bdpt/convergence.svg" docs/images/convergence-cornell-bdpt.svg
