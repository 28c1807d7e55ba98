// Event stores (issue 13): build time, knn (k = 50) and radius query cost, memory, for one
// store on one point set, one line of Markdown per run (run each in its own process, so
// that the peak RSS is that run's). Not a test: it measures, nothing fails.
//
//   bench/store_bench.sh                      # builds this file, runs the table of RESULTS.md
//   build/release/bench/store_bench kdtree uniform 10000000 [queries]
//
// Queries: uniform sets at uniform random points of the unit cube; clustered sets at
// events jittered by 0.01 (where a renderer asks: on the surfaces). The radius of the
// radius queries, also passed to build() as the hint, is the median distance of the 50th
// neighbour over 1000 such query points, so both kinds of query find about 50 events.
// Times: queries in CPU time of the one querying thread; build in wall time, as the store
// does it (kdtree: on every core).
#include "conformance/store_reference.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ieventstore.hpp"

#include <fmt/format.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <limits>
#include <string>
#include <thread>

using namespace effigi;

namespace {

double now() {
    using namespace std::chrono;
    return duration<double>(steady_clock::now().time_since_epoch()).count();
}

/// CPU time of this thread: queries are timed by it, so a busy machine (time spent
/// waiting for a core) does not inflate them.
double threadCpu() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

Ref<IEventStore> makeStore(const std::string& name) {
    Properties p("store", name);
    return query<IEventStore>(Registry::instance().create("store", name, p));
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: store_bench <store> <uniform|clustered> <points> [queries]\n");
        return 2;
    }
    const std::string name = argv[1], setName = argv[2];
    const std::size_t n = std::size_t(std::stod(argv[3])), queries = argc > 4 ? std::size_t(std::stod(argv[4])) : 100000;
    const conform::PointSet set = setName == "clustered" ? conform::PointSet::Clustered : conform::PointSet::Uniform;
    PCG32 rng(2026, 13);
    std::vector<Point3f> pts = conform::makePoints(set, n, rng);
    std::vector<Point3f> q(queries);
    for (Point3f& p : q)
        p = set == conform::PointSet::Uniform
                ? Point3f(rng.nextFloat(), rng.nextFloat(), rng.nextFloat())
                : pts[rng.nextUInt() % n] + 0.01f * Point3f(rng.nextFloat() - 0.5f, rng.nextFloat() - 0.5f, rng.nextFloat() - 0.5f);

    Ref<IEventStore> store = makeStore(name);
    store->insert(pts);
    // The radius holding ~50 events where queries are made, from a first build.
    store->build(0.f);
    const float inf = std::numeric_limits<float>::infinity();
    std::vector<EventNeighbour> out(50), got;
    std::vector<float> d50;
    for (std::size_t i = 0; i < 1000 && i < queries; ++i)
        if (store->knn(q[i], 50, inf, out.data()) == 50) d50.push_back(std::sqrt(out[49].dist2));
    std::nth_element(d50.begin(), d50.begin() + std::ptrdiff_t(d50.size() / 2), d50.end());
    const float r = d50[d50.size() / 2];

    double t0 = now();
    store->build(r);
    const double build = now() - t0;
    std::size_t found = 0;
    t0 = threadCpu();
    for (const Point3f& p : q) found += store->knn(p, 50, inf, out.data());
    const double knn = (threadCpu() - t0) / double(queries);
    std::size_t inBall = 0;
    t0 = threadCpu();
    for (const Point3f& p : q) {
        store->radius(p, r, got);
        inBall += got.size();
    }
    const double radius = (threadCpu() - t0) / double(queries);
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    std::printf("| %s | %s | %s | %.3f | %.2f | %.2f (%.1f found) | %.1f | %.0f | %.4g |\n", name.c_str(), setName.c_str(),
                fmt::format("{:.0e}", double(n)).c_str(), build, 1e6 * knn, 1e6 * radius, double(inBall) / double(queries),
                double(store->memoryBytes()) / double(n), double(ru.ru_maxrss) / 1024.0, r);
    (void)found;
    return 0;
}
