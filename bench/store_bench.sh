#!/bin/sh
# Event stores (issue 13): builds bench/store_bench.cpp against the release build (which
# must hold the store modules: cmake --build build/release --target effigi-store-kdtree
# effigi-store-hashgrid) and prints the table of bench/RESULTS.md: each store on 10^7
# uniform and 10^6 clustered events, each run in its own process (peak RSS per run).
#   bench/store_bench.sh [queries]      (default 100000 knn and as many radius queries)
set -e
cd "$(dirname "$0")/.."
B=build/release
mkdir -p $B/bench
c++ -O3 -DNDEBUG -DFMT_SHARED -std=c++20 -fno-math-errno -Iinclude -I. bench/store_bench.cpp -o $B/bench/store_bench \
    -L$B/lib -leffigi -lfmt -ltbb -Wl,-rpath,"$PWD/$B/lib"
Q=${1:-100000}
echo "| store | set | events | build s (wall) | knn k=50 µs/query (thread CPU) | radius µs/query (thread CPU; events found) | bytes/event (memoryBytes) | peak RSS MiB | radius |"
echo "|---|---|---|---|---|---|---|---|---|"
uptime
for store in kdtree hashgrid; do
  $B/bench/store_bench $store uniform 1e7 "$Q"
  $B/bench/store_bench $store clustered 1e6 "$Q"
done
uptime
