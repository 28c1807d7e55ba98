// Store suite, part two (store_suite.cpp has the overview): concurrent queries and the
// scaling of query cost with the number of events.
#include "conformance/conformance.hpp"
#include "conformance/store_reference.hpp"
#include "effigi/interfaces/ieventstore.hpp"

#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <ctime>
#include <cmath>
#include <limits>
#include <thread>

namespace effigi::conform {

namespace {

/// The radius holding k events on average at n uniform events in the unit cube.
float knnRadius(std::size_t n, double k) { return float(std::cbrt(3.0 * k / (4.0 * 3.14159265358979 * double(n)))); }

/// CPU time of the calling thread: time the thread spent waiting for a core (other jobs,
/// other processes) is not counted, so load on the machine cannot fake a cost.
double seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

} // namespace

/// Four threads ask the same knn and radius queries (each starting at another place) and
/// must get the answers one thread got alone.
void checkStoreConcurrency(Target& t, IEventStore& s) {
    PCG32 rng = t.rng("concurrency");
    const std::size_t n = t.count(100000, 10000), queries = t.count(4000, 500), k = 8;
    const std::vector<Point3f> pts = makePoints(PointSet::Clustered, n, rng);
    const float r = knnRadius(n, 8.0);
    s.clear();
    s.insert(pts);
    s.build(r);
    std::vector<Point3f> q(queries);
    for (Point3f& p : q) p = Point3f(rng.nextFloat(), rng.nextFloat(), rng.nextFloat());
    std::vector<std::vector<EventNeighbour>> knnWant(queries), radWant(queries);
    std::vector<EventNeighbour> buf(k);
    for (std::size_t i = 0; i < queries; ++i) {
        knnWant[i].assign(buf.begin(), buf.begin() + std::ptrdiff_t(s.knn(q[i], k, std::numeric_limits<float>::infinity(), buf.data())));
        s.radius(q[i], r, radWant[i]);
    }
    std::atomic<std::uint64_t> bad{0};
    std::vector<std::thread> threads;
    const int nThreads = 4;
    for (int th = 0; th < nThreads; ++th)
        threads.emplace_back([&, th] {
            std::vector<EventNeighbour> out(k), got;
            for (std::size_t j = 0; j < queries; ++j) {
                const std::size_t i = (j + std::size_t(th) * queries / nThreads) % queries;
                std::size_t m = s.knn(q[i], k, std::numeric_limits<float>::infinity(), out.data());
                s.radius(q[i], r, got);
                if (!std::equal(out.begin(), out.begin() + std::ptrdiff_t(m), knnWant[i].begin(), knnWant[i].end()) ||
                    got != radWant[i])
                    ++bad;
            }
        });
    for (std::thread& th : threads) th.join();
    t.expect("concurrent queries", bad == 0, fmt::format("{} bad of {}", bad.load(), nThreads * queries),
             fmt::format("{} threads × {} knn + radius queries on {} events equal the serial answers", nThreads, queries, n));
}

/// µs per query at 10⁴, 10⁵ and 10⁶ uniform events (radius hint and radius: the one
/// holding 8 events on average, as a renderer would choose), best of five (three under
/// --quick) interleaved batches of thread CPU time; the check: cost(10⁶) / cost(10⁴) < 20 for knn and radius
/// (linear cost: 100).
void checkStoreScaling(Target& t) {
    PCG32 rng = t.rng("scaling");
    const std::size_t sizes[] = {10000, 100000, 1000000}, batch = t.count(20000, 1000);
    const int rounds = int(t.count(5, 3));
    struct Level {
        Ref<IEventStore> store;
        float r;
        double build, knn = 1e30, radius = 1e30;
    };
    std::vector<Level> levels;
    for (std::size_t n : sizes) {
        Level l{query<IEventStore>(t.create()), knnRadius(n, 8.0), 0.0};
        const std::vector<Point3f> pts = makePoints(PointSet::Uniform, n, rng);
        l.store->insert(pts);
        const auto t0 = std::chrono::steady_clock::now();  // wall time: a build may use every core
        l.store->build(l.r);
        l.build = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        levels.push_back(std::move(l));
    }
    std::vector<Point3f> q(batch);
    for (Point3f& p : q) p = Point3f(rng.nextFloat(), rng.nextFloat(), rng.nextFloat());
    std::vector<EventNeighbour> out(8), got;
    std::size_t sink = 0;  // keeps the queries from being optimised away
    for (int round = 0; round < rounds; ++round)
        for (Level& l : levels) {
            double t0 = seconds();
            for (const Point3f& p : q) sink += l.store->knn(p, 8, std::numeric_limits<float>::infinity(), out.data());
            double t1 = seconds();
            for (const Point3f& p : q) {
                l.store->radius(p, l.r, got);
                sink += got.size();
            }
            double t2 = seconds();
            l.knn = std::min(l.knn, (t1 - t0) / double(batch));
            l.radius = std::min(l.radius, (t2 - t1) / double(batch));
        }
    for (std::size_t i = 0; i < levels.size(); ++i)
        t.info(fmt::format("query cost n=1e{}", 4 + i),
               fmt::format("knn {:.2f} µs, radius {:.2f} µs", 1e6 * levels[i].knn, 1e6 * levels[i].radius),
               fmt::format("k = 8 and radius {:.4g} (8 events on average), build {:.3g} s (wall), {:.1f} bytes/event, "
                           "best of {} batches of {} ({} found)",
                           levels[i].r, levels[i].build, double(levels[i].store->memoryBytes()) / double(sizes[i]),
                           rounds, batch, sink));
    const double knnRatio = levels[2].knn / levels[0].knn, radRatio = levels[2].radius / levels[0].radius;
    t.expect("sub-linear query cost", knnRatio < 20.0 && radRatio < 20.0,
             fmt::format("knn ×{:.2f}, radius ×{:.2f}", knnRatio, radRatio),
             "cost per query at 10⁶ events over cost at 10⁴ (linear: ×100; must stay below ×20)");
}

} // namespace effigi::conform
