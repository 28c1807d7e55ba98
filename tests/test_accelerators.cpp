// The project's own accelerators, bvh (binned SAH) and kdtree (SAH), against bruteforce:
// on a random scene of triangles and spheres every closest hit and any-hit answer must
// be identical — the three share the watertight triangle test, so even the float t
// agrees to the bit — in the default and in extreme parameters; the empty scene and a
// single triangle. And the accelerator suite of effigi-conform fails accelerators that
// are wrong in one way each: one blind to grazing hits (|cos θ| < 1e-2), one with cracks
// along edges, one whose t is 1e-3 too far; every check it fails starts with
// "closest hit" or "any hit" and names the scene where the fault shows.
//
// All scenes and rays are seeded; nothing here depends on timing.
#include "conformance/accelerator_builder.hpp"  // SuiteMesh
#include "conform_session.hpp"
#include "conformance/conformance.hpp"

#include "app_runner.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iintersect.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/math/rng.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <mutex>

using namespace effigi;
using effigi::test::sessionTable;
using effigi::test::verdictOf;

namespace {

Ref<IIntersect> makeAccel(const std::string& name, const std::vector<std::pair<std::string, PropertyValue>>& params = {}) {
    Properties p("accelerator", name);
    for (const auto& [k, v] : params) p.set(k, v);
    Ref<IIntersect> a = query<IIntersect>(Registry::instance().create("accelerator", name, p));
    REQUIRE(a);
    return a;
}

Vector3f randomDirection(PCG32& rng) {
    float z = 1.f - 2.f * rng.nextFloat(), phi = 2.f * Pi * rng.nextFloat(), r = std::sqrt(std::max(0.f, 1.f - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
}

struct Scene {
    std::vector<Ref<IShape>> owned;
    std::vector<const IShape*> shapes;
    void add(Ref<IShape> s) { shapes.push_back(s.get()), owned.push_back(std::move(s)); }
};

/// 300 random triangles in two meshes and two spheres in [-1, 1]³.
Scene randomScene(std::uint64_t seed) {
    PCG32 rng(seed, 7);
    Scene s;
    TriangleMesh m[2];
    for (int i = 0; i < 300; ++i) {
        Point3f c(rng.nextFloat() * 2 - 1, rng.nextFloat() * 2 - 1, rng.nextFloat() * 2 - 1);
        float size = 0.02f + 0.3f * rng.nextFloat();
        auto base = std::uint32_t(m[i % 2].positions.size());
        for (int k = 0; k < 3; ++k) m[i % 2].positions.push_back(c + size * randomDirection(rng));
        m[i % 2].indices.insert(m[i % 2].indices.end(), {base, base + 1, base + 2});
    }
    for (auto& mesh : m) s.add(std::make_shared<conform::SuiteMesh>(std::move(mesh)));
    for (int i = 0; i < 2; ++i) {
        Properties p("shape", "sphere");
        p.set("center", PointValue{Point3f(rng.nextFloat() - 0.5f, rng.nextFloat() - 0.5f, rng.nextFloat() - 0.5f)});
        p.set("radius", 0.1 + 0.2 * rng.nextFloat());
        s.add(query<IShape>(Registry::instance().create("shape", "sphere", p)));
    }
    return s;
}

/// Every answer of `accel` equals bruteforce's on 4000 random rays (30 % with finite tMax).
void requireSameAsBruteforce(IIntersect& accel, const Scene& scene, std::uint64_t seed) {
    Ref<IIntersect> ref = makeAccel("bruteforce");
    ref->build(scene.shapes);
    accel.build(scene.shapes);
    PCG32 rng(seed, 11);
    int hits = 0;
    for (int i = 0; i < 4000; ++i) {
        Ray r{Point3f(rng.nextFloat() * 3 - 1.5f, rng.nextFloat() * 3 - 1.5f, rng.nextFloat() * 3 - 1.5f),
              randomDirection(rng) * (0.5f + rng.nextFloat()), Infinity};
        if (rng.nextFloat() < 0.3f) r.tMax = 2.f * rng.nextFloat();
        Hit a, b;
        bool ha = ref->intersect(r, a), hb = accel.intersect(r, b);
        INFO("ray " << i);
        REQUIRE(ha == hb);
        if (ha) {
            ++hits;
            CHECK(a.shape == b.shape);
            CHECK(a.prim == b.prim);
            CHECK(a.t == b.t);  // the same float test on the same triangle
            CHECK(a.uv == b.uv);
        }
        CHECK(ref->occluded(r) == accel.occluded(r));
    }
    CHECK(hits > 400);  // the rays do meet the scene (564 of them)
    BBox3f x = ref->bbox(), y = accel.bbox();
    CHECK(glm::all(glm::lessThanEqual(y.min, x.min)));
    CHECK(glm::all(glm::greaterThanEqual(y.max, x.max)));
}

} // namespace

TEST_CASE("accelerators: bvh and kdtree give bruteforce's answers on a random scene", "[accelerator]") {
    Scene scene = randomScene(2026);
    for (const auto& [name, params] :
         std::vector<std::pair<std::string, std::vector<std::pair<std::string, PropertyValue>>>>{
             {"bvh", {}},
             {"bvh", {{"max_leaf", std::int64_t(1)}, {"bins", std::int64_t(2)}}},
             {"bvh", {{"max_leaf", std::int64_t(64)}}},
             {"kdtree", {}},
             {"kdtree", {{"max_depth", std::int64_t(1)}}},
             {"kdtree", {{"empty_bonus", 0.9}, {"intersection_cost", 100.0}}},
         }) {
        INFO(name << " with " << params.size() << " parameters set");
        Ref<IIntersect> a = makeAccel(name, params);
        requireSameAsBruteforce(*a, scene, 99);
    }
}

TEST_CASE("accelerators: empty scene and a single triangle", "[accelerator]") {
    for (const char* name : {"bvh", "kdtree"}) {
        INFO(name);
        Ref<IIntersect> empty = makeAccel(name);
        empty->build({});
        Hit h;
        h.t = 42.f;
        CHECK_FALSE(empty->intersect(Ray{Point3f(0.f), Vector3f(0.f, 0.f, 1.f)}, h));
        CHECK(h.t == 42.f);  // untouched on a miss
        CHECK_FALSE(empty->occluded(Ray{Point3f(0.f), Vector3f(0.f, 0.f, 1.f)}));
        CHECK_FALSE(empty->bbox().valid());

        TriangleMesh m;
        m.positions = {{0, 0, 2}, {1, 0, 2}, {0, 1, 2}};
        m.indices = {0, 1, 2};
        Scene s;
        s.add(std::make_shared<conform::SuiteMesh>(std::move(m)));
        Ref<IIntersect> one = makeAccel(name);
        one->build(s.shapes);
        Ray r{Point3f(0.25f, 0.25f, 0.f), Vector3f(0.f, 0.f, 1.f)};
        REQUIRE(one->intersect(r, h));
        CHECK(h.t == 2.f);
        CHECK(h.shape == 0);
        CHECK(h.prim == 0);
        CHECK(h.uv.x == Approx(0.25f));
        CHECK(h.uv.y == Approx(0.25f));
        CHECK(one->occluded(r));
        r.tMax = 1.9f;  // stops short
        CHECK_FALSE(one->intersect(r, h));
        CHECK_FALSE(one->occluded(r));
        CHECK_FALSE(one->occluded(Ray{Point3f(0.75f, 0.75f, 0.f), Vector3f(0.f, 0.f, 1.f)}));  // beside it
        CHECK_FALSE(one->occluded(Ray{Point3f(0.25f, 0.25f, 0.f), Vector3f(0.f, 0.f, -1.f)}));  // away from it
        // Along the axes, with zero direction components, and from the triangle's plane.
        CHECK(one->occluded(Ray{Point3f(0.25f, 0.25f, 3.f), Vector3f(0.f, 0.f, -1.f)}));
        CHECK_FALSE(one->occluded(Ray{Point3f(-1.f, 0.25f, 2.f), Vector3f(1.f, 0.f, 0.f)}));  // in its plane: edge on
    }
}

TEST_CASE("accelerators: parameters out of range are one-line errors", "[accelerator]") {
    for (auto [name, param] : {std::pair{"bvh", "max_leaf"}, std::pair{"bvh", "bins"}, std::pair{"kdtree", "max_depth"}}) {
        Properties p("accelerator", name);
        p.set(param, std::int64_t(-1));
        try {
            Registry::instance().create("accelerator", name, p);
            FAIL("no error for " << name << " " << param << " = -1");
        } catch (const Error& e) {
            CHECK_THAT(e.what(), Catch::Contains(param));
            CHECK(std::string(e.what()).find('\n') == std::string::npos);
        }
    }
}

// ---- the suite catches wrong accelerators ----------------------------------------------

namespace {

/// The bvh with one fault added after the fact (so that the suite's large mesh is quick):
/// a closest hit that grazes its triangle (|cos θ| < 1e-2) or lies within 1e-4 (in
/// barycentrics) of an edge is dropped — reported as a miss, by occluded() too — or the
/// hit distance is reported 1e-3 too far.
class FaultyAccel final : public Implements<IIntersect> {
public:
    enum Fault { GrazingBlind, Cracks, LateT };
    explicit FaultyAccel(Fault f) : m_fault(f), m_inner(makeAccel("bvh")) {}
    void build(std::span<const IShape* const> shapes) override {
        m_shapes.assign(shapes.begin(), shapes.end());
        m_inner->build(shapes);
    }
    bool intersect(const Ray& ray, Hit& hit) const override {
        Hit h;
        if (!m_inner->intersect(ray, h) || dropped(ray, h)) return false;
        if (m_fault == LateT) h.t *= 1.001f;
        hit = h;
        return true;
    }
    bool occluded(const Ray& ray) const override {
        if (m_fault == LateT) return m_inner->occluded(ray);
        Hit h;
        return m_inner->intersect(ray, h) && !dropped(ray, h);
    }
    BBox3f bbox() const override { return m_inner->bbox(); }

private:
    bool dropped(const Ray& ray, const Hit& h) const {
        const TriangleMesh* mesh = m_shapes[h.shape]->mesh();
        if (!mesh) return false;
        Point3f p0, p1, p2;
        mesh->triangle(h.prim, p0, p1, p2);
        if (m_fault == GrazingBlind) return std::abs(dot(normalize(ray.d), normalize(cross(p1 - p0, p2 - p0)))) < 1e-2f;
        if (m_fault == Cracks) return std::min({h.uv.x, h.uv.y, 1.f - h.uv.x - h.uv.y}) < 1e-4f;
        return false;
    }

    Fault m_fault;
    Ref<IIntersect> m_inner;
    std::vector<const IShape*> m_shapes;
};

void registerFaulty() {
    static std::once_flag once;
    std::call_once(once, [] {
        for (auto [name, fault] : {std::pair{"test_grazing_blind", FaultyAccel::GrazingBlind},
                                   std::pair{"test_cracks", FaultyAccel::Cracks}, std::pair{"test_late_t", FaultyAccel::LateT}}) {
            Schema s("accelerator", name, "test accelerator (tests/test_accelerators.cpp)");
            Registry::instance().add(ComponentInfo{
                s, [fault = fault](const Properties&) -> Ref<IComponent> { return std::make_shared<FaultyAccel>(fault); }, {}});
        }
    });
}

} // namespace

TEST_CASE("accelerators: the conformance suite fails wrong accelerators by the right checks", "[accelerator][conformance]") {
    registerFaulty();
    auto out = test::tempDir("conform-accel");
    auto run = [&](const std::string& name) { return test::runQuickSuite("accelerator", name, out); };
    using conform::Verdict;
    {
        conform::Session s = run("test_grazing_blind");
        INFO(sessionTable(s));
        CHECK(verdictOf(s, "test_grazing_blind", "closest hit grazing") == Verdict::Fail);
        CHECK(verdictOf(s, "test_grazing_blind", "any hit grazing") == Verdict::Fail);
        // Random rays graze now and then too (|cos θ| < 1e-2 for 1 % of them), so other
        // scenes may fail as well, but only ever by hit checks.
        for (const conform::Row* r : s.find("test_grazing_blind", ""))
            if (r->verdict == Verdict::Fail) CHECK((r->check.rfind("closest hit", 0) == 0 || r->check.rfind("any hit", 0) == 0));
    }
    {
        conform::Session s = run("test_cracks");
        INFO(sessionTable(s));
        CHECK(verdictOf(s, "test_cracks", "closest hit edges and vertices") == Verdict::Fail);
    }
    {
        conform::Session s = run("test_late_t");
        INFO(sessionTable(s));
        CHECK(verdictOf(s, "test_late_t", "closest hit soup") == Verdict::Fail);
        CHECK(verdictOf(s, "test_late_t", "closest hit cornell") == Verdict::Fail);
        // Its any-hit answers are bruteforce's.
        CHECK(verdictOf(s, "test_late_t", "any hit soup") == Verdict::Pass);
        CHECK(verdictOf(s, "test_late_t", "any hit cornell") == Verdict::Pass);
    }
    std::filesystem::remove_all(out);
}
