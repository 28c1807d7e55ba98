#!/usr/bin/env bash
# Strong scaling of `mpirun -np N effigi render` on the Cornell box at a fixed wall time:
# samples/s for 1, 2 and 4 ranks of one thread each (and one process of all the cores'
# threads, for comparison), the bytes each rank sends per reduction, the time spent in the
# reductions, and the image mean of each run against the single process's. Then the load
# balance a static split of the image into tiles would have had: the same spp rendered in
# four horizontal strips (crop windows), one thread each.
#   bench/mpi_scaling.sh [seconds] [res] [max ranks]
# A benchmark, not a test: run it on a quiet machine. Needs a build with EFFIGI_MPI.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-10}
res=${2:-256}
maxranks=${3:-4}
bin=$PWD/build/release/bin/effigi
[ -x "$bin" ] || { echo "build first: make build" >&2; exit 1; }
command -v mpirun >/dev/null || { echo "mpirun missing: apt-get install openmpi-bin libopenmpi-dev" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
out=out/bench/mpi
mkdir -p "$out"
scene=scenes/cornell-box/scene.xml

mean() {  # image mean of R, G, B of an EXR
  oiiotool "$1" --printstats 2>/dev/null | awk '/Stats Avg/ {print $3, $4, $5; exit}'
}
# "<samples> <seconds>" from effigi's report line, "<MiB> <s>" from its MPI line.
samples() { sed -n 's/.*, \([0-9]*\) samples in \([0-9.]*\) s .*/\1 \2/p' "$1"; }
traffic() { sed -n 's/.*reductions into rank 0 of \([0-9.]*\) MiB per rank, \([0-9.]*\) s in all/\1 \2/p' "$1"; }

echo "Cornell box ${res}x${res}, --time ${seconds} s, $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg), $(date -u +%Y-%m-%d)"
# cpu/wall: the cores the run had on average (processes and threads together): below the
# threads asked for, the machine was busy with something else.
printf '%-26s %10s %8s %9s %9s %9s %9s %s\n' configuration samples seconds "M samp/s" cpu/wall "MiB/rank" \
  "reduce s" "image mean R G B"
run() {  # name, then the command
  local name=$1; shift
  /usr/bin/time -f '%U %S %e' -o "$out/$name.time" "$@" > "$out/$name.log" 2>&1
  local n s mib= rs= user sys wall
  read -r n s < <(samples "$out/$name.log")
  read -r mib rs < <(traffic "$out/$name.log") || true
  read -r user sys wall < "$out/$name.time"
  printf '%-26s %10s %8s %9.3f %9.2f %9s %9s %s\n' "$name" "$n" "$s" "$(echo "$n / $s / 1000000" | bc -l)" \
    "$(echo "($user + $sys) / $wall" | bc -l)" "${mib:--}" "${rs:--}" "$(mean "$out/$name.exr")"
}
common=("$scene" -D "res=$res" --time "$seconds" --no-progress)
run "1 process, 1 thread" "$bin" render "${common[@]}" -t 1 -o "$out/1 process, 1 thread.exr"
run "1 process, $(nproc) threads" "$bin" render "${common[@]}" -o "$out/1 process, $(nproc) threads.exr"
for n in 1 2 4 8; do
  [ "$n" -le "$maxranks" ] || break
  run "mpirun -np $n, 1 thread" mpirun --oversubscribe -np "$n" "$bin" render "${common[@]}" -t 1 \
    -o "$out/mpirun -np $n, 1 thread.exr"
done
# The same with checkpoints every second: each one reduces the film and the renderer's
# per-pixel error statistics.
run "mpirun -np 2, checkpoints" mpirun --oversubscribe -np 2 "$bin" render "${common[@]}" -t 1 \
  --checkpoint "$out/ckpt" --checkpoint-every 1s -o "$out/mpirun -np 2, checkpoints.exr"
rm -rf "$out/ckpt"

# Tiles instead of passes: four strips of the image, the same spp each, one thread.
strip_spp=$(( seconds > 4 ? 16 : 4 ))
echo
echo "Static tiles: four horizontal strips of ${res}x$((res / 4)) at ${strip_spp} spp, one thread each"
sed -e "s|<integer name=\"height\" value=\"\$res\"/>|&<integer name=\"crop_offset_y\" value=\"\$y\"/><integer name=\"crop_height\" value=\"$((res / 4))\"/>|" \
    -e "s|<scene version=\"3.0.0\">|&<path value=\"$PWD/scenes/cornell-box\"/>|" "$scene" > "$out/strip.xml"
for k in 0 1 2 3; do
  "$bin" render "$out/strip.xml" -D "res=$res" -D "y=$((k * res / 4))" -D "spp=$strip_spp" -t 1 --no-progress \
    -o "$out/strip$k.exr" > "$out/strip$k.log" 2>&1
  read -r n s < <(samples "$out/strip$k.log")
  echo "strip $k (rows $((k * res / 4))-$(((k + 1) * res / 4 - 1))): $s s"
done
