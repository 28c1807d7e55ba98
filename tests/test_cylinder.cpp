// The analytic cylinder: intersection against a brute-force root search along the ray,
// the surface interaction (on the surface, outward normal, uv and dp/du, dp/dv against
// finite differences of the parametrisation), area, uniform area sampling and the
// solid-angle pdf integrating to one, and the parameter errors.
#include "shape_helpers.hpp"

#include "effigi/math/rng.hpp"
#include "effigi/math/warp_functions.hpp"

#include <algorithm>
#include <vector>

using namespace effigi;
using namespace effigi::test;

namespace {

/// A cylinder in world space described independently of the component: axis from c0
/// to c1, radius r.
struct Tube {
    Vector3d c0, c1;
    double r;
    /// (squared distance to the axis line − r², axial coordinate in [0, 1] on the tube).
    void eval(const Vector3d& p, double& g, double& z) const {
        Vector3d a = c1 - c0;
        z = glm::dot(p - c0, a) / glm::dot(a, a);
        Vector3d perp = p - c0 - z * a;
        g = glm::dot(perp, perp) - r * r;
    }
};

/// First crossing of the tube wall along the ray by a fine scan of g(t) plus bisection.
bool bruteForce(const Tube& tube, const Ray& ray, double tMax, double& tHit) {
    const int N = 4000;
    Vector3d o(ray.o), d(ray.d);
    double gPrev, zPrev;
    tube.eval(o, gPrev, zPrev);
    for (int i = 1; i <= N; ++i) {
        double t = tMax * i / N, g, z;
        tube.eval(o + t * d, g, z);
        if ((g > 0.0) != (gPrev > 0.0)) {
            double lo = tMax * (i - 1) / N, hi = t;
            for (int k = 0; k < 60; ++k) {
                double mid = 0.5 * (lo + hi), gm, zm;
                tube.eval(o + mid * d, gm, zm);
                ((gm > 0.0) == (gPrev > 0.0) ? lo : hi) = mid;
            }
            double gz, zc;
            tube.eval(o + lo * d, gz, zc);
            if (zc >= 0.0 && zc <= 1.0) {
                tHit = lo;
                return true;
            }
        }
        gPrev = g;
    }
    return false;
}

/// Tilted, moved and scaled: p0/p1/radius in object space, then a similarity.
Properties tiltedProps() {
    Properties p("shape", "cylinder");
    p.set("p0", PointValue{{0.2f, -0.1f, -0.5f}});
    p.set("p1", PointValue{{-0.3f, 0.4f, 1.f}});
    p.set("radius", 0.4);
    p.set("to_world", Transform::translate({0.5f, 0.f, 1.f}) * Transform::rotate({1.f, 0.f, 0.f}, 25.f) *
                          Transform::scale({1.5f, 1.5f, 1.5f}));
    return p;
}

Tube tiltedTube() {
    Transform t = Transform::translate({0.5f, 0.f, 1.f}) * Transform::rotate({1.f, 0.f, 0.f}, 25.f) *
                  Transform::scale({1.5f, 1.5f, 1.5f});
    return {Vector3d(t.point({0.2f, -0.1f, -0.5f})), Vector3d(t.point({-0.3f, 0.4f, 1.f})), 0.4 * 1.5};
}

} // namespace

TEST_CASE("cylinder: intersection agrees with a brute-force root search", "[shapes][cylinder]") {
    Ref<IShape> s = makeShape("cylinder", tiltedProps());
    Tube tube = tiltedTube();
    BBox3f box = s->bbox();
    Point3f mid = 0.5f * (box.min + box.max);
    PCG32 rng(41, 43);
    int hits = 0, agree = 0, compared = 0;
    for (int i = 0; i < 3000; ++i) {
        // Origins outside and inside the tube, directions uniform.
        Point3f o = mid + 3.f * (Vector3f(rng.nextFloat(), rng.nextFloat(), rng.nextFloat()) - 0.5f);
        Vector3f d = warp::squareToUniformSphere({rng.nextFloat(), rng.nextFloat()});
        Ray ray{o, d, 8.f};
        float t;
        Point2f uv;
        bool got = s->intersect(ray, t, uv);
        double tb = 0.0;  // printed below even on a miss
        bool want = bruteForce(tube, ray, 8.0, tb);
        // Skip rays that graze the wall or cross near an end circle: the scan may miss
        // or find those within its resolution.
        if (want) {
            double g, z;
            tube.eval(Vector3d(o) + tb * Vector3d(d), g, z);
            if (z < 1e-3 || z > 1.0 - 1e-3) continue;
            Vector3d a = glm::normalize(tube.c1 - tube.c0), dd(d);
            Vector3d perp = dd - glm::dot(dd, a) * a;
            if (glm::length(perp) < 0.05) continue;
        }
        ++compared;
        hits += want;
        if (got == want && (!want || std::abs(double(t) - tb) < 1e-4 * (1.0 + tb))) ++agree;
        else INFO("ray " << i << " got " << got << " t " << t << " want " << want << " t " << tb);
    }
    CHECK(hits > 500);
    CHECK(agree == compared);
}

TEST_CASE("cylinder: interaction, uv, dp/du and dp/dv", "[shapes][cylinder]") {
    Ref<IShape> s = makeShape("cylinder", tiltedProps());
    Tube tube = tiltedTube();
    Vector3d axis = tube.c1 - tube.c0;
    PCG32 rng(5, 9);
    int n = 0;
    for (int i = 0; i < 500; ++i) {
        PositionSample target = s->samplePosition({rng.nextFloat(), rng.nextFloat()});
        Point3f o = target.p + 2.f * target.n;  // from outside, toward the sampled point
        Ray ray{o, normalize(target.p - o)};
        Hit hit;
        if (!trace(*s, ray, hit)) continue;
        SurfaceInteraction si = s->interaction(ray, hit);
        ++n;
        double g, z;
        tube.eval(Vector3d(si.p), g, z);
        CHECK(std::abs(g) < 1e-4);  // on the wall
        CHECK(length(si.p - target.p) < 1e-3f);
        // Outward normal, perpendicular to the axis.
        Vector3d foot = tube.c0 + z * axis;
        CHECK(glm::dot(Vector3d(si.n), Vector3d(si.p) - foot) > 0.0);
        CHECK(std::abs(glm::dot(Vector3d(si.n), glm::normalize(axis))) < 1e-4);
        CHECK(si.uv.y == Approx(z).margin(1e-4));
        CHECK(si.uv.x == Approx(target.uv.x).margin(1e-4));
        // dp/dv is the axis; dp/du is 2π r along the circle, perpendicular to n.
        CHECK(length(Vector3d(si.dpdv) - axis) < 1e-4);
        CHECK(length(si.dpdu) == Approx(2.f * Pi * float(tube.r)).epsilon(1e-4));
        CHECK(std::abs(dot(si.dpdu, si.n)) < 1e-3f);
        // Finite differences of p(u, v) along u (moving along the surface).
        if (target.uv.x < 0.99f) {
            PositionSample next = s->samplePosition({target.uv.y, target.uv.x + 1e-3f});
            Vector3f fd = (next.p - target.p) / (next.uv.x - target.uv.x);
            CHECK(length(fd - si.dpdu) < 2e-2f * length(si.dpdu));
        }
        // Orthonormal shading frame around the normal.
        CHECK(dot(si.shading.n, si.n) == Approx(1.f));
        CHECK(std::abs(dot(si.shading.s, si.shading.n)) < 1e-5f);
        CHECK(length(si.shading.s) == Approx(1.f));
    }
    CHECK(n > 450);

    Properties fp = tiltedProps();
    fp.set("flip_normals", true);
    Ref<IShape> f = makeShape("cylinder", fp);
    PositionSample a = s->samplePosition({0.3f, 0.6f}), b = f->samplePosition({0.3f, 0.6f});
    CHECK(length(a.p - b.p) < 1e-6f);
    CHECK(dot(a.n, b.n) == Approx(-1.f));
}

TEST_CASE("cylinder: area, bounds, uniform area sampling", "[shapes][cylinder]") {
    Properties p("shape", "cylinder");
    p.set("radius", 0.5);
    p.set("to_world", Transform::scale({2.f, 2.f, 3.f}));  // scales along the axis are fine
    Ref<IShape> s = makeShape("cylinder", p);
    CHECK(s->area() == Approx(2.f * Pi * 1.f * 3.f));
    BBox3f b = s->bbox();
    CHECK(b.min.x == Approx(-1.f));
    CHECK(b.max.z == Approx(3.f));

    // Chi-square at significance level 0.001 on 8 x 8 equal-area (z, φ) cells.
    PCG32 rng(13, 17);
    const int N = 64000;
    std::vector<double> obs(64, 0.0);
    for (int i = 0; i < N; ++i) {
        PositionSample ps = s->samplePosition({rng.nextFloat(), rng.nextFloat()});
        REQUIRE(ps.pdf == Approx(1.f / s->area()));
        REQUIRE(ps.p.x * ps.p.x + ps.p.y * ps.p.y == Approx(1.f).epsilon(1e-4));
        REQUIRE(glm::all(glm::lessThanEqual(b.min, ps.p + 1e-5f)));
        REQUIRE(glm::all(glm::lessThanEqual(ps.p, b.max + 1e-5f)));
        float phi = std::atan2(ps.p.y, ps.p.x) * Inv2Pi + 0.5f;
        obs[std::size_t(std::clamp(int(ps.p.z / 3.f * 8.f), 0, 7) * 8 + std::clamp(int(phi * 8.f), 0, 7))] += 1.0;
    }
    double chi2 = 0.0, e = N / 64.0;
    for (double o : obs) chi2 += (o - e) * (o - e) / e;
    CHECK(chi2 < 103.4);  // chi-square quantile 0.999 with 63 degrees of freedom
}

TEST_CASE("cylinder: the solid-angle pdf integrates to one from inside", "[shapes][cylinder]") {
    // From a point inside the tube every wall point is visible, so ∫ pdfDirection dω over
    // the directions that hit must be 1: uniform directions, 4π·pdf where they hit.
    // Accepted within 4 standard errors (two-sided significance about 6e-5), seeded.
    Ref<IShape> s = makeShape("cylinder", tiltedProps());
    Tube tube = tiltedTube();
    Point3f ref(Vector3f(tube.c0 + 0.3 * (tube.c1 - tube.c0)));
    PCG32 rng(17, 19);
    const int N = 200000;
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < N; ++i) {
        Ray ray{ref, warp::squareToUniformSphere({rng.nextFloat(), rng.nextFloat()})};
        Hit hit;
        double x = 0.0;
        if (trace(*s, ray, hit)) x = 4.0 * double(Pi) * double(s->pdfDirection(ref, s->interaction(ray, hit)));
        sum += x;
        sum2 += x * x;
    }
    double mean = sum / N, se = std::sqrt((sum2 / N - mean * mean) / (N - 1));
    INFO("integral " << mean << " ± " << se);
    CHECK(std::abs(mean - 1.0) < 4.0 * se);
    CHECK(se < 0.05);

    // sampleDirection's pdf matches pdfDirection at the traced point.
    for (int i = 0; i < 200; ++i) {
        DirectionSample ds = s->sampleDirection(ref, {rng.nextFloat(), rng.nextFloat()});
        if (!(ds.pdf > 0.f)) continue;
        Ray ray{ref, ds.wi};
        Hit hit;
        REQUIRE(trace(*s, ray, hit));
        CHECK(hit.t == Approx(ds.dist).epsilon(1e-3));
        CHECK(s->pdfDirection(ref, s->interaction(ray, hit)) == Approx(ds.pdf).epsilon(2e-3));
    }
}

TEST_CASE("cylinder: rays leaving the wall do not hit it again at once", "[shapes][cylinder]") {
    Ref<IShape> s = makeShape("cylinder");
    Ray in{{0.f, 0.f, 0.5f}, normalize(Vector3f(1.f, 0.3f, 0.1f))};
    Hit hit;
    REQUIRE(trace(*s, in, hit));
    SurfaceInteraction si = s->interaction(in, hit);
    // Back inside, toward the opposite wall: the next hit is far, not at the origin.
    Ray back = si.spawnRay(-in.d);
    Hit h2;
    REQUIRE(trace(*s, back, h2));
    CHECK(h2.t > 1.f);
    // Outward: no hit at all (the tube is convex in cross-section).
    Hit h3;
    CHECK_FALSE(trace(*s, si.spawnRay(in.d), h3));
    // A ray along the axis never meets the wall.
    CHECK_FALSE(trace(*s, Ray{{0.f, 0.f, -1.f}, {0.f, 0.f, 1.f}}, h3));
}

TEST_CASE("cylinder: parameter errors", "[shapes][cylinder]") {
    auto bad = [](const std::string& name, PropertyValue v, const std::string& needle) {
        Properties p("shape", "cylinder");
        p.set(name, v);
        INFO(name);
        requireThrowsNaming([&] { Registry::instance().create("shape", "cylinder", p); }, needle);
    };
    bad("radius", 0.0, "radius");
    bad("p1", PointValue{{0.f, 0.f, 0.f}}, "p1");
    bad("to_world", Transform::scale({1.f, 2.f, 1.f}), "to_world");  // elliptic cross-section
    bad("to_world", Transform::rotate({0.f, 1.f, 0.f}, 30.f) * Transform::scale({1.f, 1.f, 2.f}) *
                        Transform::rotate({0.f, 1.f, 0.f}, 20.f), "to_world");  // shear
}

TEST_CASE("cylinder: t, uv, normal and dp/du agree with Mitsuba 3", "[shapes][cylinder]") {
    // Reference values printed by Mitsuba 3.9.1 (scalar_rgb, ray_intersect) for the same
    // cylinder and rays: they pin down the parametrisation (where φ = 0 lies).
    Ref<IShape> s = makeShape("cylinder", tiltedProps());
    struct Case {
        Point3f o;
        Vector3f d;
        float t;
        Point2f uv;
        Normal3f n;
        Vector3f dpdu;
    };
    const Case cases[] = {
        {{3.f, 0.2f, 1.5f}, {-1.f, 0.f, 0.f}, 1.9836351f, {0.0512036f, 0.446315f}, {0.918502f, 0.233342f, 0.319227f},
         {-0.964431f, 3.64273f, 0.112234f}},
        {{0.3f, -3.f, 1.2f}, {0.f, 1.f, 0.1f}, 2.4602754f, {0.732493f, 0.545082f}, {-0.151981f, -0.975246f, -0.160615f},
         {3.54851f, -0.725273f, 1.04608f}},
    };
    for (const Case& c : cases) {
        Ray ray{c.o, normalize(c.d)};
        Hit hit;
        REQUIRE(trace(*s, ray, hit));
        SurfaceInteraction si = s->interaction(ray, hit);
        CHECK(hit.t == Approx(c.t).epsilon(1e-5));
        CHECK(si.uv.x == Approx(c.uv.x).margin(1e-5));
        CHECK(si.uv.y == Approx(c.uv.y).margin(1e-5));
        CHECK(length(si.n - c.n) < 1e-5f);
        CHECK(length(si.dpdu - c.dpdu) < 1e-4f);
    }
    Hit miss;
    CHECK_FALSE(trace(*s, Ray{{0.4f, 0.1f, 4.f}, normalize(Vector3f(0.05f, 0.02f, -1.f))}, miss));
}
