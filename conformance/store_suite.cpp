// Store suite: an IEventStore, in each configuration, answers exactly what the brute-force
// definition (store_reference.hpp) answers — the same (index, d²) lists, bit for bit:
//  - "knn <set> n=<n>" / "radius <set> n=<n>": point sets uniform, clustered, coplanar,
//    collinear, exact duplicates, all equal, huge (1e6) and tiny (1e-6) coordinates, at 10
//    and 10⁶ events (5·10⁴ under --quick, fewer queries, and answers holding every event
//    only on small sets); knn with k = 1, 8, 100, n + 1
//    and maxRadius 0, tiny, finite, ∞; radius 0, tiny, finite, large (every event); query
//    points on events, between them, outside and far outside (1e30: every d² is ∞);
//    build()'s radius hint the finite radius, or 0 on every other set;
//  - "one point", "zero points", "rebuild after insert", "clear and reuse",
//    "non-finite insert" (an effigi::Error);
//  - "many queries": 10⁵ random knn and radius queries at and near events, against brute
//    force on 192 events (clustered, with duplicates); about 8.5·10⁴ answers are
//    non-empty, so a store wrong once in 10⁴ answers escapes with probability
//    (1 − 10⁻⁴)^85000 ≈ 2·10⁻⁴ (the row gives the count and the probability);
//  - "concurrent queries": four threads asking the same queries get the serial answers;
//  - "query cost": µs per knn (k = 8) and radius query at 10⁴, 10⁵, 10⁶ uniform events
//    (info), and "sub-linear query cost": the ratio 10⁶ / 10⁴ below 20 (linear: 100),
//    the best of five interleaved batches so that load on the machine cannot fail it.
// All checks are deterministic (seeded sets and queries, exact comparison).
#include "conformance/conformance.hpp"
#include "conformance/store_reference.hpp"
#include "effigi/interfaces/ieventstore.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

namespace effigi::conform {

namespace {

constexpr float Inf = std::numeric_limits<float>::infinity();

std::string show(const Point3f& q) { return fmt::format("({:g}, {:g}, {:g})", q.x, q.y, q.z); }
/// n [(index, d²) ...] from entry `from` on (the first difference), five entries at most.
std::string show(std::span<const EventNeighbour> v, std::size_t from = 0) {
    from = std::min(from, v.size());
    std::string s = fmt::format("{} [{}", v.size(), from ? fmt::format("#{}: ", from) : "");
    for (std::size_t i = from; i < v.size() && i < from + 5; ++i)
        s += fmt::format("{}({}, {:g})", i > from ? " " : "", v[i].index, v[i].dist2);
    return s + (v.size() > from + 5 ? " ...]" : "]");
}
std::string showBoth(std::span<const EventNeighbour> got, std::span<const EventNeighbour> want) {
    std::size_t i = 0;
    while (i < got.size() && i < want.size() && got[i] == want[i]) ++i;
    const std::size_t from = i > 1 ? i - 1 : 0;
    return fmt::format("got {}, brute force {}", show(got, from), show(want, from));
}

/// Compares one store with brute force at query points; buffers kept between calls.
class Comparer {
public:
    Comparer(const IEventStore& s, std::span<const Point3f> points) : m_store(s), m_ref(points) {}

    /// The query sets of one point set at q: knn over ks × radii, radius over radii.
    void at(const Point3f& q, std::span<const std::size_t> ks, std::span<const float> knnRadii,
            std::span<const float> radii, Tally& knnTally, Tally& radiusTally) {
        std::size_t depth = 0;
        for (std::size_t k : ks) depth = std::max(depth, k);
        m_ref.at(q, std::min(depth, std::size_t(128)));
        for (std::size_t k : ks)
            for (float r : knnRadii) knn(q, k, r, knnTally);
        for (float r : radii) radius(q, r, radiusTally);
    }
    bool knn(const Point3f& q, std::size_t k, float r, Tally& tally) {
        if (m_buf.size() < k) m_buf.resize(k);
        std::size_t n = m_store.knn(q, k, r, m_buf.data());
        std::vector<EventNeighbour> want = m_ref.knn(k, r);
        const bool ok = n <= k && std::equal(m_buf.begin(), m_buf.begin() + std::ptrdiff_t(n), want.begin(), want.end());
        note(tally, ok, [&] {
            return fmt::format("knn(k = {}, r = {:g}) at {}: {}", k, r, show(q), showBoth({m_buf.data(), std::min(n, k)}, want));
        });
        return !want.empty();
    }
    bool radius(const Point3f& q, float r, Tally& tally) {
        m_store.radius(q, r, m_got);
        std::vector<EventNeighbour> want = m_ref.radius(r);
        note(tally, m_got == want,
             [&] { return fmt::format("radius({:g}) at {}: {}", r, show(q), showBoth(m_got, want)); });
        return !want.empty();
    }
    BruteForce& reference() { return m_ref; }

private:
    /// Describes a probe only when it is the first bad one (formatting every one is slow).
    template <typename Describe> static void note(Tally& tally, bool ok, Describe&& describe) {
        tally.note(ok, ok || tally.bad ? std::string() : describe());
    }

    const IEventStore& m_store;
    BruteForce m_ref;
    std::vector<EventNeighbour> m_buf, m_got;
};

/// Query points of a set: on events, in its bounding box, outside it, far outside.
std::vector<Point3f> queryPoints(std::span<const Point3f> pts, float scale, std::size_t each, PCG32& rng) {
    Point3f lo(scale), hi(-scale);
    for (const Point3f& p : pts) lo = glm::min(lo, p), hi = glm::max(hi, p);
    std::vector<Point3f> q;
    for (std::size_t i = 0; i < each && !pts.empty(); ++i) q.push_back(pts[rng.nextUInt() % pts.size()]);
    for (std::size_t i = 0; i < each; ++i)
        q.push_back(lo + (hi - lo) * Point3f(rng.nextFloat(), rng.nextFloat(), rng.nextFloat()));
    q.push_back(hi + (hi - lo + scale) * Point3f(3.f, 0.5f, 2.f));
    q.push_back(Point3f(1e30f, -1e30f, 1e30f));
    return q;
}

void loadStore(IEventStore& s, std::span<const Point3f> pts, float hint) {
    s.clear();
    s.insert(pts);
    s.build(hint);
}

/// Every query kind on one point set: the rows "knn <set> n=<n>" and "radius <set> n=<n>".
void checkSet(Target& t, IEventStore& s, PointSet set, std::size_t n, std::size_t queriesEach, bool hint) {
    PCG32 rng = t.rng(fmt::format("set {} {}", pointSetName(set), n));
    const std::vector<Point3f> pts = makePoints(set, n, rng);
    const float scale = pointSetScale(set), tiny = 1e-3f * scale,
                finite = scale * std::min(0.5f, std::cbrt(12.f / float(std::max<std::size_t>(n, 1))));
    loadStore(s, pts, hint ? finite : 0.f);
    Comparer cmp(s, pts);
    Tally knnT, radT;
    const std::size_t ks[] = {1, 8, 100, n + 1}, ksSmall[] = {1, 8, 100};
    const float knnR[] = {0.f, tiny, finite, Inf}, radR[] = {0.f, tiny, finite, 10.f * scale}, radRSmall[] = {0.f, tiny, finite};
    const std::vector<Point3f> q = queryPoints(pts, scale, queriesEach, rng);
    for (std::size_t i = 0; i < q.size(); ++i) {
        // Answers holding every event cost O(n log n): at one point only on large sets.
        const bool all = n <= 1000 || (i == 0 && !t.quick());
        cmp.at(q[i], all ? std::span<const std::size_t>(ks) : ksSmall, knnR, all ? std::span<const float>(radR) : radRSmall,
               knnT, radT);
    }
    const std::string at = fmt::format("{} n={}", pointSetName(set), n);
    t.expect("knn " + at, knnT.bad == 0, knnT.figure(), knnT.detail("every answer equals brute force"));
    t.expect("radius " + at, radT.bad == 0, radT.figure(), radT.detail("every answer equals brute force"));
}

void checkEdges(Target& t, IEventStore& s) {
    PCG32 rng = t.rng("edges");
    s.clear();
    s.build(0.f);
    EventNeighbour out[4];
    std::vector<EventNeighbour> v{{7, 1.f}};
    const std::size_t found = s.knn(Point3f(0.f), 4, Inf, out);
    s.radius(Point3f(0.f), Inf, v);
    t.expect("zero points", s.size() == 0 && found == 0 && v.empty(), fmt::format("{} + {} found", found, v.size()),
             "an empty store answers nothing");

    const std::vector<Point3f> a = makePoints(PointSet::Uniform, 1000, rng), b = makePoints(PointSet::Clustered, 3000, rng);
    std::vector<Point3f> ab = a;
    ab.insert(ab.end(), b.begin(), b.end());
    const std::size_t ks[] = {1, 8, 100, 5000};
    const float knnR[] = {0.f, 0.02f, Inf}, radR[] = {0.f, 0.02f, 0.1f};
    auto compare = [&](const std::string& check, std::span<const Point3f> pts) {
        Comparer cmp(s, pts);
        Tally k, r;
        for (const Point3f& q : queryPoints(pts, 1.f, 8, rng)) cmp.at(q, ks, knnR, radR, k, r);
        k.checked += r.checked;
        k.bad += r.bad;
        if (k.first.empty()) k.first = r.first;
        t.expect(check, k.bad == 0 && s.size() == pts.size(), k.figure(), k.detail("every answer equals brute force"));
    };
    loadStore(s, a, 0.05f);
    s.insert(b);
    s.build(0.01f);
    compare("rebuild after insert", ab);
    loadStore(s, b, 0.f);
    compare("clear and reuse", b);
    const Point3f single[] = {Point3f(0.25f, -0.5f, 2.f)};
    loadStore(s, single, 0.f);
    compare("one point", single);

    s.clear();
    const Point3f bad[] = {Point3f(0.f), Point3f(std::numeric_limits<float>::quiet_NaN(), 0.f, 0.f)};
    std::string what;
    try {
        s.insert(bad);
    } catch (const Error& e) {
        what = e.what();
    }
    t.expect("non-finite insert", !what.empty(), what.empty() ? "accepted" : "effigi::Error",
             what.empty() ? "a NaN position was accepted" : what);
}

/// 10⁵ queries of random kind near events of a small set (under --quick too: they are
/// what catches a rare fault).
void checkManyQueries(Target& t, IEventStore& s) {
    PCG32 rng = t.rng("many queries");
    std::vector<Point3f> pts = makePoints(PointSet::Clustered, 160, rng), dup = makePoints(PointSet::Duplicates, 32, rng);
    for (Point3f& p : dup) p = 0.2f + 0.6f * p;
    pts.insert(pts.end(), dup.begin(), dup.end());
    loadStore(s, pts, 0.05f);
    Comparer cmp(s, pts);
    Tally tally;
    std::uint64_t nonEmpty = 0;
    const std::uint64_t queries = 100000;
    for (std::uint64_t i = 0; i < queries; ++i) {
        // On an event, or near one: most answers are non-empty, so a wrong one shows.
        Point3f q = pts[rng.nextUInt() % pts.size()];
        if (i % 4 != 0) q += 0.1f * Point3f(rng.nextFloat() - 0.5f, rng.nextFloat() - 0.5f, rng.nextFloat() - 0.5f);
        const float r = 0.01f + 0.1f * rng.nextFloat();
        if (i % 2 == 0) {
            const std::size_t k = 1 + rng.nextUInt() % 24;
            cmp.reference().at(q, k);
            nonEmpty += cmp.knn(q, k, (i % 8 == 0) ? r : Inf, tally);
        } else {
            cmp.reference().at(q, 0);
            nonEmpty += cmp.radius(q, r, tally);
        }
    }
    // A store wrong on a fraction f of non-empty answers escapes with (1 − f)^nonEmpty.
    t.expect("many queries", tally.bad == 0, tally.figure(),
             tally.detail(fmt::format("{} non-empty answers: a fault in 1 of 10⁴ escapes with probability {:.1e}",
                                      nonEmpty, std::pow(1.0 - 1e-4, double(nonEmpty)))));
}

} // namespace

void checkStoreConcurrency(Target& t, IEventStore& s);
void checkStoreScaling(Target& t);

namespace {

void runStoreSuite(Target& t) {
    Ref<IEventStore> store = t.as<IEventStore>();
    if (!store) {
        t.expect("interface", false, "-", "component does not implement IEventStore");
        return;
    }
    const std::size_t large = t.count(1000000, 50000), each = t.count(10, 3);
    // build()'s hint: the finite radius on every other set, 0 (the store's own choice) on
    // the others (clustered, collinear, all equal, tiny).
    int i = 0;
    for (PointSet set : {PointSet::Uniform, PointSet::Clustered, PointSet::Coplanar, PointSet::Collinear,
                         PointSet::Duplicates, PointSet::AllEqual, PointSet::Huge, PointSet::Tiny}) {
        checkSet(t, *store, set, 10, 10, i % 2 == 0);
        checkSet(t, *store, set, large, each, i++ % 2 == 0);
    }
    checkEdges(t, *store);
    checkManyQueries(t, *store);
    checkStoreConcurrency(t, *store);
    checkStoreScaling(t);
    store->clear();
}

} // namespace

} // namespace effigi::conform

EFFIGI_CONFORMANCE_SUITE("store",
                         "exact (index, d²) answers of knn and radius queries against brute force on degenerate and "
                         "large point sets, thread-safe queries, sub-linear query cost",
                         effigi::conform::runStoreSuite, effigi::conform::RangeEnds::Probed);
