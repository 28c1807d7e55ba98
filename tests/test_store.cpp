// Event stores (components/store/*.cpp, IEventStore): exact answers against the
// brute-force definition (conformance/store_reference.hpp) on a few point sets, bad input,
// the empty store, rebuilding; and the store conformance suite failing a store that is
// wrong once in 10⁴ queries (in-process, like tests/test_conformance_texture.cpp).
// Every check is deterministic (seeded point sets, exact equality).
#include "app_runner.hpp"
#include "conform_session.hpp"
#include "conformance/store_reference.hpp"
#include "effigi/core/error.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ieventstore.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <mutex>
#include <set>

using namespace effigi;
using conform::BruteForce;
using conform::PointSet;

namespace {

const char* const StoreNames[] = {"kdtree", "hashgrid"};

Ref<IEventStore> makeStore(const std::string& name, const conform::ParamList& params = {}) {
    Properties p("store", name);
    for (const auto& [k, v] : params) p.set(k, v);
    Ref<IEventStore> s = query<IEventStore>(Registry::instance().create("store", name, p));
    REQUIRE(s);
    return s;
}

std::string show(const std::vector<EventNeighbour>& v) {
    std::string s;
    for (std::size_t i = 0; i < v.size() && i < 12; ++i) s += fmt::format("({}, {}) ", v[i].index, v[i].dist2);
    return s + (v.size() > 12 ? "..." : "");
}

/// Every knn and radius answer of `store` at `queries` equals brute force; returns the
/// number of answers compared.
int compareAll(const IEventStore& store, std::span<const Point3f> points, std::span<const Point3f> queries,
               float scale) {
    BruteForce ref(points);
    const float inf = std::numeric_limits<float>::infinity();
    std::vector<EventNeighbour> buf(points.size() + 3), got;
    int compared = 0;
    for (const Point3f& q : queries) {
        ref.at(q, 64);
        for (std::size_t k : {std::size_t(1), std::size_t(8), std::size_t(50), points.size() + 3})
            for (float r : {0.f, 0.03f * scale, 0.3f * scale, inf}) {
                std::size_t n = store.knn(q, k, r, buf.data());
                std::vector<EventNeighbour> have(buf.begin(), buf.begin() + std::ptrdiff_t(n)), want = ref.knn(k, r);
                INFO("knn k = " << k << ", r = " << r << " at (" << q.x << ", " << q.y << ", " << q.z << ")\n got "
                                << show(have) << "\nwant " << show(want));
                REQUIRE(have == want);
                ++compared;
            }
        for (float r : {0.f, 0.05f * scale, 10.f * scale}) {
            store.radius(q, r, got);
            INFO("radius r = " << r << " at (" << q.x << ", " << q.y << ", " << q.z << ")\n got " << show(got));
            REQUIRE(got == ref.radius(r));
            ++compared;
        }
    }
    return compared;
}

/// Query points: on events, between them, and far outside.
std::vector<Point3f> queryPoints(std::span<const Point3f> points, float scale, PCG32& rng) {
    std::vector<Point3f> q;
    for (int i = 0; i < 8 && !points.empty(); ++i) q.push_back(points[rng.nextUInt() % points.size()]);
    for (int i = 0; i < 8; ++i) q.push_back(scale * Point3f(rng.nextFloat(), rng.nextFloat(), rng.nextFloat()));
    q.push_back(Point3f(-5.f, 7.f, 3.f) * scale);
    return q;
}

} // namespace

TEST_CASE("store: exact knn and radius answers against brute force", "[store]") {
    PCG32 rng(7, 11);
    for (const char* name : StoreNames)
        for (PointSet set : {PointSet::Uniform, PointSet::Clustered, PointSet::Duplicates, PointSet::AllEqual,
                             PointSet::Coplanar, PointSet::Collinear, PointSet::Huge, PointSet::Tiny})
            for (std::size_t n : {std::size_t(1), std::size_t(37), std::size_t(3000)}) {
                INFO(name << " on " << conform::pointSetName(set) << ", n = " << n);
                std::vector<Point3f> pts = conform::makePoints(set, n, rng);
                const float scale = conform::pointSetScale(set);
                Ref<IEventStore> s = makeStore(name);
                s->insert(pts);
                s->build(n == 37 ? 0.f : 0.05f * scale);  // 0: the hash grid sizes its cells from the data
                REQUIRE(s->size() == n);
                REQUIRE(s->position(std::uint32_t(n - 1)) == pts.back());
                REQUIRE(s->memoryBytes() >= n * sizeof(Point3f));
                std::vector<Point3f> q = queryPoints(pts, scale, rng);
                CHECK(compareAll(*s, pts, q, scale) == int(q.size()) * 19);
            }
}

TEST_CASE("store: a non-finite position is a one-line error, the store unchanged", "[store]") {
    const float bad[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                         -std::numeric_limits<float>::infinity()};
    for (const char* name : StoreNames)
        for (float b : bad) {
            Ref<IEventStore> s = makeStore(name);
            const Point3f ok[] = {Point3f(0.f), Point3f(1.f)};
            s->insert(ok);
            const Point3f pts[] = {Point3f(0.5f), Point3f(0.f, b, 0.f)};
            try {
                s->insert(pts);
                FAIL("no error for " << b);
            } catch (const Error& e) {
                std::string msg = e.what();
                INFO(msg);
                CHECK(msg.find("non-finite") != std::string::npos);
                CHECK(msg.find("event 3") != std::string::npos);  // indices continue from size()
                CHECK(msg.find(name) != std::string::npos);
                CHECK(msg.find('\n') == std::string::npos);
            }
            CHECK(s->size() == 2);
        }
}

TEST_CASE("store: an empty store answers nothing, a query before build() is an error", "[store]") {
    for (const char* name : StoreNames) {
        Ref<IEventStore> s = makeStore(name);
        EventNeighbour out[4];
        std::vector<EventNeighbour> v{{1, 1.f}};
        CHECK(s->knn(Point3f(0.f), 4, 1.f, out) == 0);  // never built, nothing inserted
        s->build();
        CHECK(s->knn(Point3f(0.f), 4, std::numeric_limits<float>::infinity(), out) == 0);
        s->radius(Point3f(0.f), 1e30f, v);
        CHECK(v.empty());
        CHECK(s->memoryBytes() > 0);
        const Point3f one[] = {Point3f(1.f)};
        s->insert(one);
        CHECK_THROWS_AS(s->knn(Point3f(0.f), 1, 1.f, out), Error);
        CHECK_THROWS_AS(s->radius(Point3f(0.f), 1.f, v), Error);
        s->build();
        REQUIRE(s->knn(Point3f(0.f), 4, 10.f, out) == 1);
        CHECK(out[0] == EventNeighbour{0, 3.f});
        CHECK(s->knn(Point3f(0.f), 0, 10.f, out) == 0);
    }
}

TEST_CASE("store: rebuilding after a second insert and after clear()", "[store]") {
    PCG32 rng(3, 5);
    for (const char* name : StoreNames) {
        INFO(name);
        std::vector<Point3f> a = conform::makePoints(PointSet::Uniform, 500, rng);
        std::vector<Point3f> b = conform::makePoints(PointSet::Clustered, 700, rng);
        Ref<IEventStore> s = makeStore(name);
        s->insert(a);
        s->build(0.1f);
        s->insert(b);
        s->build(0.02f);  // a different hint: the hash grid changes its cells
        std::vector<Point3f> ab = a;
        ab.insert(ab.end(), b.begin(), b.end());
        REQUIRE(s->size() == ab.size());
        std::vector<Point3f> q = queryPoints(ab, 1.f, rng);
        compareAll(*s, ab, q, 1.f);
        s->clear();
        CHECK(s->size() == 0);
        s->insert(b);
        s->build();
        compareAll(*s, b, q, 1.f);
    }
}

TEST_CASE("store: NaN, infinite and far query points", "[store]") {
    PCG32 rng(13, 17);
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    std::vector<Point3f> pts = conform::makePoints(PointSet::Uniform, 2000, rng);
    const Point3f q[] = {Point3f(nan, 0.f, 0.f), Point3f(inf, 0.5f, 0.5f), Point3f(-inf, inf, 0.f),
                         Point3f(1e30f, -1e30f, 1e30f), Point3f(3e38f), Point3f(-2e9f, 0.5f, 0.5f)};
    for (const char* name : StoreNames) {
        INFO(name);
        Ref<IEventStore> s = makeStore(name);
        s->insert(pts);
        s->build(0.01f);
        compareAll(*s, pts, q, 1.f);
        // maxRadius NaN (nothing is within it) and negative (squared, as the definition says)
        BruteForce ref(pts);
        std::vector<EventNeighbour> buf(10);
        for (float r : {nan, -0.2f}) {
            ref.at(Point3f(0.5f));
            std::size_t n = s->knn(Point3f(0.5f), 10, r, buf.data());
            CHECK(std::vector<EventNeighbour>(buf.begin(), buf.begin() + std::ptrdiff_t(n)) == ref.knn(10, r));
        }
    }
}

// ---- the suite fails wrong stores ------------------------------------------------------
// Two realistic slips, each wrapping the kdtree (the plugin bad_neighbour_store, wrong
// once in 10⁴ queries, is caught out of tree by tests/plugins/run_plugin_tests.cmake):
// - test_store_ties: equal distances ordered by descending index (a comparison on d²
//   alone, then a reversing pass) -> knn/radius on duplicates and all-equal sets;
// - test_store_open_ball: events at exactly d² = r² left out (< instead of ≤) -> among
//   others, every query of radius 0 on an event.
namespace {

enum class StoreFault { Ties, OpenBall };

class FaultyStore final : public Implements<IEventStore> {
public:
    explicit FaultyStore(StoreFault f) : m_fault(f), m_inner(makeStore("kdtree")) {}
    void clear() override { m_inner->clear(); }
    void insert(std::span<const Point3f> p) override { m_inner->insert(p); }
    std::size_t size() const override { return m_inner->size(); }
    Point3f position(std::uint32_t i) const override { return m_inner->position(i); }
    void build(float hint) override { m_inner->build(hint); }
    std::size_t memoryBytes() const override { return m_inner->memoryBytes(); }
    std::size_t knn(const Point3f& p, std::size_t k, float r, EventNeighbour* out) const override {
        return spoil(out, m_inner->knn(p, k, r, out), r);
    }
    void radius(const Point3f& p, float r, std::vector<EventNeighbour>& out) const override {
        m_inner->radius(p, r, out);
        out.resize(spoil(out.data(), out.size(), r));
    }

private:
    std::size_t spoil(EventNeighbour* v, std::size_t n, float r) const {
        if (m_fault == StoreFault::OpenBall)
            return std::size_t(std::remove_if(v, v + n, [r2 = r * r](const EventNeighbour& e) { return e.dist2 == r2; }) - v);
        for (std::size_t i = 0, j; i < n; i = j) {  // reverse each run of equal d²
            for (j = i + 1; j < n && v[j].dist2 == v[i].dist2; ++j) {}
            std::reverse(v + i, v + j);
        }
        return n;
    }
    StoreFault m_fault;
    Ref<IEventStore> m_inner;
};

void registerFaultyStores() {
    static std::once_flag once;
    std::call_once(once, [] {
        for (auto [name, fault] : {std::pair{"test_store_ties", StoreFault::Ties},
                                   std::pair{"test_store_open_ball", StoreFault::OpenBall}}) {
            Schema s("store", name, "wrong store (tests/test_store.cpp)");
            Registry::instance().add(ComponentInfo{
                s, [fault = fault](const Properties&) -> Ref<IComponent> { return std::make_shared<FaultyStore>(fault); }, {}});
        }
    });
}

/// The checks the suite fails `name` on; every one must be an exactness check.
std::set<std::string> failedStoreChecks(const std::string& name) {
    registerFaultyStores();
    auto out = test::tempDir("conform-store");
    conform::Session s = test::runQuickSuite("store", name, out);
    std::filesystem::remove_all(out);
    INFO(test::sessionTable(s));
    for (const char* ok : {"zero points", "non-finite insert", "concurrent queries", "sub-linear query cost"})
        CHECK(test::verdictOf(s, name, ok) == conform::Verdict::Pass);
    std::set<std::string> failed = test::failedChecks(s);
    for (const std::string& c : failed) {
        INFO(c);
        CHECK((c.starts_with("knn ") || c.starts_with("radius ") || c == "many queries" ||
               c == "rebuild after insert" || c == "clear and reuse" || c == "one point"));
    }
    return failed;
}

} // namespace

TEST_CASE("store conformance: ties ordered by descending index are caught", "[store][conformance]") {
    std::set<std::string> failed = failedStoreChecks("test_store_ties");
    CHECK(failed.count("knn all equal n=10"));
    CHECK(failed.count("radius all equal n=10"));
    CHECK(failed.count("knn duplicates n=10"));
    CHECK(failed.count("knn uniform n=10"));  // at the query point 1e30 every d² is ∞: all tie
}

TEST_CASE("store conformance: an open ball (d² < r²) is caught", "[store][conformance]") {
    std::set<std::string> failed = failedStoreChecks("test_store_open_ball");
    CHECK(failed.count("radius uniform n=10"));  // radius 0 on an event
    CHECK(failed.count("knn uniform n=10"));     // maxRadius 0 on an event
    CHECK(failed.count("one point"));
}
