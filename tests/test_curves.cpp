// The curve shapes linearcurve and bsplinecurve: ray hits against independent brute-force
// references (a distance-function scan along the ray), the special cases (a straight
// constant-radius curve is a capsule, coincident points a sphere), back-face culling,
// uv, the file reader's errors, and an end-to-end comparison with Mitsuba 3.
#include "shape_helpers.hpp"

#include "effigi/interfaces/ifilm.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/xml/loader.hpp"
#include "image_helpers.hpp"

#include <fstream>
#include <functional>
#include <unistd.h>

using namespace effigi;
using namespace effigi::test;

namespace {

std::filesystem::path tempDir() {
    auto d = std::filesystem::temp_directory_path() / ("effigi_test_curves_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
}

std::string writeFile(const std::string& name, const std::string& text) {
    auto p = tempDir() / name;
    std::ofstream(p) << text;
    return p.string();
}

Ref<IShape> makeCurve(const std::string& type, const std::string& file, Transform toWorld = {}) {
    Properties p("shape", type);
    p.set("filename", file);
    p.set("to_world", toWorld);
    return makeShape(type, p);
}

struct Pt {
    Vector3d p;
    double r;
};

/// Signed distance-like function of the swept sphere of the linear polyline (convex in s
/// per segment: ternary search finds the exact minimum).
double sweptSpheres(const std::vector<Pt>& pts, const Vector3d& q) {
    double best = 1e300;
    for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
        auto f = [&](double s) {
            return glm::length(q - ((1 - s) * pts[i].p + s * pts[i + 1].p)) - ((1 - s) * pts[i].r + s * pts[i + 1].r);
        };
        double lo = 0, hi = 1;
        for (int k = 0; k < 40; ++k) {
            double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
            (f(m1) < f(m2) ? hi : lo) = (f(m1) < f(m2) ? m2 : m1);
        }
        best = std::min(best, f(0.5 * (lo + hi)));
    }
    return best;
}

/// Distance to a uniform cubic B-spline's centre line minus a constant radius; dense
/// samples then golden-section refinement around the best one.
double bsplineTube(const std::vector<Vector3d>& P, double r, const Vector3d& q) {
    auto c = [&](double v) {
        int i = std::min(int(v), int(P.size()) - 4);
        double t = v - i, w = 1 - t;
        return (w * w * w * P[i] + (3 * t * t * t - 6 * t * t + 4) * P[i + 1] +
                (-3 * t * t * t + 3 * t * t + 3 * t + 1) * P[i + 2] + t * t * t * P[i + 3]) / 6.0;
    };
    double vmax = double(P.size() - 3), bestV = 0, best = 1e300;
    for (int k = 0; k <= 150; ++k) {
        double v = vmax * k / 150, d = glm::length(q - c(v));
        if (d < best) best = d, bestV = v;
    }
    double lo = std::max(0.0, bestV - vmax / 150), hi = std::min(vmax, bestV + vmax / 150);
    for (int k = 0; k < 50; ++k) {
        double m1 = lo + (hi - lo) * 0.382, m2 = lo + (hi - lo) * 0.618;
        if (glm::length(q - c(m1)) < glm::length(q - c(m2))) hi = m2;
        else lo = m1;
    }
    return glm::length(q - c(0.5 * (lo + hi))) - r;
}

/// First zero crossing of F along the ray (from outside), by a fine scan plus bisection.
bool scan(const std::function<double(const Vector3d&)>& F, const Ray& ray, double tMax, double& tHit) {
    const int N = 3000;
    Vector3d o(ray.o), d(ray.d);
    if (F(o) <= 0) return false;
    for (int i = 1; i <= N; ++i) {
        double t = tMax * i / N;
        if (F(o + t * d) <= 0) {
            double lo = tMax * (i - 1) / N, hi = t;
            for (int k = 0; k < 60; ++k) {
                double m = 0.5 * (lo + hi);
                (F(o + m * d) > 0 ? lo : hi) = m;
            }
            tHit = lo;
            return true;
        }
    }
    return false;
}

/// Rays from a sphere of radius R around `centre` toward random points near the curve.
Ray randomRay(PCG32& rng, const Vector3d& centre, double R, const Vector3d& target, double spread) {
    Vector3d dir(rng.nextDouble() * 2 - 1, rng.nextDouble() * 2 - 1, rng.nextDouble() * 2 - 1);
    Vector3d o = centre + R * glm::normalize(dir + Vector3d(1e-9));
    Vector3d aim = target + spread * Vector3d(rng.nextDouble() - 0.5, rng.nextDouble() - 0.5, rng.nextDouble() - 0.5);
    return Ray{Point3f(o), Vector3f(glm::normalize(aim - o)), Infinity};
}

/// Compares the shape with the reference F on random rays. Rays whose minimum of F
/// along the ray lies within `graze` of zero (silhouettes) are not judged.
/// Rays passing within avoidR of a point in `avoid` are skipped (open spline ends, which
/// F does not model).
void compareHits(const IShape& shape, const std::function<double(const Vector3d&)>& F, const Vector3d& centre,
                 double R, double spread, double tTol, int n, std::uint64_t seed,
                 const std::vector<Vector3d>& avoid = {}, double avoidR = 0) {
    PCG32 rng(seed, 7);
    int hits = 0, judged = 0, skipped = 0;
    for (int i = 0; i < n; ++i) {
        Ray ray = randomRay(rng, centre, R, centre, spread);
        bool nearEnd = false;
        for (const Vector3d& a : avoid) {
            Vector3d w = a - Vector3d(ray.o), d(ray.d);
            nearEnd = nearEnd || glm::length(w - glm::dot(w, d) * d) < avoidR;
        }
        if (nearEnd) {
            ++skipped;
            continue;
        }
        double tRef = 0;
        bool ref = scan(F, ray, 2.5 * R, tRef);
        Hit h;
        bool got = trace(shape, ray, h);
        if (got != ref) {
            // A disagreement is acceptable only for a ray that grazes the surface.
            double minF = 1e300;
            for (int k = 0; k <= 3000; ++k) minF = std::min(minF, std::abs(F(Vector3d(ray.o) + 2.5 * R * k / 3000 * Vector3d(ray.d))));
            INFO("ray " << i << " effigi " << got << " reference " << ref << " min|F| " << minF);
            CHECK(minF < tTol * 20);
            continue;
        }
        ++judged;
        if (!got) continue;
        ++hits;
        INFO("ray " << i << " t " << h.t << " reference " << tRef << " o " << ray.o.x << "," << ray.o.y << "," << ray.o.z << " d " << ray.d.x << "," << ray.d.y << "," << ray.d.z << " piece " << h.uv.x << " s " << h.uv.y);
        // Hit point on the reference surface and no earlier crossing.
        CHECK(std::abs(F(Vector3d(ray.o) + double(h.t) * Vector3d(ray.d))) < tTol);
        CHECK(double(h.t) < tRef + 50 * tTol);
        SurfaceInteraction si = shape.interaction(ray, h);
        CHECK(std::abs(glm::length(si.n) - 1.f) < 1e-4f);
        CHECK(dot(si.n, ray.d) < 1e-3f);  // front faces only
        CHECK(si.uv.x >= 0.f);
        CHECK(si.uv.x < 1.f);
        CHECK(si.uv.y >= 0.f);
        CHECK(si.uv.y <= 1.f);
    }
    CHECK(hits > n / 5);  // the rays do exercise the surface
    CHECK(judged > (n - skipped) * 9 / 10);
    CHECK(skipped < n / 2);
}

} // namespace

TEST_CASE("linearcurve: straight constant radius is a capsule, hits match a brute-force scan", "[shape][curves]") {
    std::vector<Pt> pts{{{-1, 0.2, 0.1}, 0.3}, {{1, 0.2, 0.1}, 0.3}};
    auto shape = makeCurve("linearcurve", writeFile("capsule.txt", "-1 0.2 0.1 0.3\n1 0.2 0.1 0.3\n"));
    compareHits(*shape, [&](const Vector3d& q) { return sweptSpheres(pts, q); }, {0, 0.2, 0.1}, 3.0, 1.0, 1e-5,
                120, 1);

    // On the cylinder part: uv.y is the axial fraction, uv.x Mitsuba's angle (frame: the z
    // axis made perpendicular to the curve, and z × axis), the normal is radial.
    Ray ray{Point3f(0.5f, -3.f, 0.1f), Vector3f(0, 1, 0), Infinity};
    Hit h;
    REQUIRE(trace(*shape, ray, h));
    CHECK(h.t == Approx(3.f + 0.2f - 0.3f).margin(1e-5));  // enters at y = 0.2 - 0.3
    SurfaceInteraction si = shape->interaction(ray, h);
    CHECK(si.uv.y == Approx(0.75f).margin(1e-5));
    Vector3f n = si.n;
    CHECK(n.y == Approx(-1.f).margin(1e-5));
    float u = std::atan2(n.z, dot(n, cross(Vector3f(0, 0, 1), Vector3f(1, 0, 0)))) / (2.f * Pi);
    if (u < 0) u += 1;
    CHECK(si.uv.x == Approx(u).margin(1e-5));
    CHECK(si.uv.x == Approx(0.5f).margin(1e-5));  // -y direction: angle π
}

TEST_CASE("linearcurve: tapered polyline with joints, coincident points form a sphere", "[shape][curves]") {
    std::vector<Pt> pts{{{-1, 0, 0}, 0.1}, {{-0.2, 0.6, 0.1}, 0.35}, {{0.4, -0.3, 0}, 0.2}, {{1, 0.3, -0.2}, 0.02}};
    std::string text;
    for (const Pt& p : pts) text += fmt::format("{} {} {} {}\n", p.p.x, p.p.y, p.p.z, p.r);
    auto shape = makeCurve("linearcurve", writeFile("tapered.txt", text));
    compareHits(*shape, [&](const Vector3d& q) { return sweptSpheres(pts, q); }, {0, 0.1, 0}, 3.0, 1.2, 1e-5, 120,
                2);

    // Two coincident points: a sphere of the larger radius.
    auto sphere = makeCurve("linearcurve", writeFile("sphere.txt", "0.5 0 0 0.25\n0.5 0 0 0.25\n"));
    Ray ray{Point3f(0.5f, 0.1f, 5.f), Vector3f(0, 0, -1), Infinity};
    Hit h;
    REQUIRE(trace(*sphere, ray, h));
    CHECK(h.t == Approx(5.0 - std::sqrt(0.25 * 0.25 - 0.01)).epsilon(1e-6));
    SurfaceInteraction si = sphere->interaction(ray, h);
    CHECK(glm::length(si.n - normalize(si.p - Point3f(0.5f, 0, 0))) < 1e-4f);
    CHECK(std::isfinite(si.uv.x));
    CHECK(std::isfinite(si.uv.y));
    CHECK(isFinite(si.dpdu));
    CHECK(isFinite(si.shading.s));
}

TEST_CASE("linearcurve: back faces are culled, misses and to_world", "[shape][curves]") {
    auto file = writeFile("straight.txt", "0 0 0 0.5\n2 0 0 0.5\n");
    auto shape = makeCurve("linearcurve", file);
    Hit h;
    // From inside the tube: nothing (Mitsuba's documented back-face culling).
    CHECK_FALSE(trace(*shape, Ray{Point3f(1, 0, 0), Vector3f(0, 1, 0), Infinity}, h));
    // Parallel to the axis just outside the radius, and short rays.
    CHECK_FALSE(trace(*shape, Ray{Point3f(-3, 0.5001f, 0), Vector3f(1, 0, 0), Infinity}, h));
    CHECK(trace(*shape, Ray{Point3f(-3, 0.4999f, 0), Vector3f(1, 0, 0), Infinity}, h));
    CHECK_FALSE(trace(*shape, Ray{Point3f(1, -3, 0), Vector3f(0, 1, 0), 2.4f}, h));
    // to_world moves the points but not the radius: a non-uniform scale along the axis.
    auto scaled = makeCurve("linearcurve", file, Transform::scale(Vector3f(3, 1, 1)));
    REQUIRE(trace(*scaled, Ray{Point3f(5.5f, -3, 0), Vector3f(0, 1, 0), Infinity}, h));
    CHECK(h.t == Approx(2.5f).margin(1e-5));
    CHECK(scaled->bbox().max.x == Approx(6.5f).margin(1e-3));
}

TEST_CASE("bsplinecurve: constant radius tube matches a brute-force distance scan", "[shape][curves]") {
    std::vector<Vector3d> P{{-1.5, 0, 0}, {-1, 0.8, 0.2}, {-0.3, -0.6, 0}, {0.3, 0.7, -0.3}, {1, -0.5, 0.2}, {1.6, 0.2, 0}};
    double r = 0.15;
    std::string text;
    for (const auto& p : P) text += fmt::format("{} {} {} {}\n", p.x, p.y, p.z, r);
    auto shape = makeCurve("bsplinecurve", writeFile("spline.txt", text));
    // The traced surface is within 1e-3 r of the spline tube (curve_common.hpp): judge at 2e-3 r.
    // Rays aim at the middle so that the open ends (not modelled by F) are rarely involved.
    Vector3d end0 = (P[0] + 4.0 * P[1] + P[2]) / 6.0, end1 = (P[3] + 4.0 * P[4] + P[5]) / 6.0;
    compareHits(*shape, [&](const Vector3d& q) { return bsplineTube(P, r, q); }, {0, 0.05, 0}, 3.0, 0.5,
                2e-3 * r, 80, 3, {end0, end1}, 2.5 * r);
}

TEST_CASE("bsplinecurve: ends are open, cut perpendicular to the curve", "[shape][curves]") {
    // Straight spline along x with equally spaced points: the curve runs from x = 0 to 1
    // (B-spline end points are (P0 + 4 P1 + P2) / 6).
    auto shape = makeCurve("bsplinecurve", writeFile("open.txt", "-1 0 0 0.2\n0 0 0 0.2\n1 0 0 0.2\n2 0 0 0.2\n"));
    Hit h;
    // Looking into the open end along the axis: through the tube, nothing is hit.
    CHECK_FALSE(trace(*shape, Ray{Point3f(-3, 0.05f, 0), Vector3f(1, 0, 0), Infinity}, h));
    // From the side, just inside and just outside the end plane.
    CHECK(trace(*shape, Ray{Point3f(0.01f, -2, 0), Vector3f(0, 1, 0), Infinity}, h));
    CHECK(h.t == Approx(1.8f).margin(1e-4));
    CHECK_FALSE(trace(*shape, Ray{Point3f(-0.01f, -2, 0), Vector3f(0, 1, 0), Infinity}, h));
    CHECK_FALSE(trace(*shape, Ray{Point3f(1.01f, -2, 0), Vector3f(0, 1, 0), Infinity}, h));
    REQUIRE(trace(*shape, Ray{Point3f(0.25f, -2, 0), Vector3f(0, 1, 0), Infinity}, h));
    SurfaceInteraction si = shape->interaction(Ray{Point3f(0.25f, -2, 0), Vector3f(0, 1, 0), Infinity}, h);
    CHECK(si.uv.y == Approx(0.25f).margin(1e-4));
}

TEST_CASE("curves: bad files give one line naming file:line and the cause", "[shape][curves]") {
    auto bad = [](const std::string& type, const std::string& name, const std::string& text, const std::string& needle) {
        std::string f = writeFile(name, text);
        requireThrowsNaming([&] { makeCurve(type, f); }, name + needle);
    };
    bad("linearcurve", "letters.txt", "0 0 0 1\n0 0 x 1\n", ":2: expected 4 numbers");
    bad("linearcurve", "short.txt", "0 0 0 1\n1 1 1\n", ":2: expected 4 numbers");
    bad("linearcurve", "trailing.txt", "0 0 0 1\n1 1 1 1 junk\n", ":2: unexpected text");
    bad("linearcurve", "negative.txt", "0 0 0 1\n1 1 1 -1\n", ":2: radius must be");
    bad("linearcurve", "nan.txt", "0 0 0 1\n1 nan 1 1\n", ":2: control point position is not finite");
    bad("linearcurve", "single.txt", "0 0 0 1\n1 1 1 1\n\n\n5 5 5 1\n", ":5: linear curve needs at least 2");
    bad("bsplinecurve", "three.txt", "0 0 0 1\n1 1 1 1\n2 2 2 1\n", ":1: B-spline curve needs at least 4");
    bad("linearcurve", "empty.txt", "\n  \n", ": linear curve file contains no control points");
    Properties p("shape", "linearcurve");
    p.set("filename", (tempDir() / "does_not_exist.txt").string());
    CHECK_THROWS_AS(makeShape("linearcurve", p), Error);
}

namespace {
/// Grey values of the scene rendered with the given seed.
std::vector<double> renderGrey(const std::string& file, std::uint64_t seed, int& w, int& h) {
    xml::ParseOptions opt;
    opt.defines = {{"spp", "64"}};
    auto scene = loadSceneFile(file, opt);
    RenderControl control;
    control.progress = false;
    control.seed = seed;
    RenderStats stats = scene->renderer().render(*scene, control);
    CHECK(stats.rejectedSamples == 0);
    Image img = scene->camera().film().develop();
    w = img.width, h = img.height;
    std::vector<double> g;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) g.push_back((img.at(x, y, 0) + img.at(x, y, 1) + img.at(x, y, 2)) / 3.0);
    return g;
}
} // namespace

TEST_CASE("curves: images agree with Mitsuba 3 (scalar_spectral, 1024 spp)", "[render][curves]") {
    for (std::string kind : {"linearcurve", "bsplinecurve"}) {
        std::string file = EFFIGI_SOURCE_DIR "/tests/data/curves/" + kind + ".xml";
        int w, h;
        std::vector<double> a = renderGrey(file, 1, w, h), b = renderGrey(file, 2, w, h);
        ExrImage ref = readExr(EFFIGI_SOURCE_DIR "/tests/data/curves/" + kind + "-mitsuba.exr");
        REQUIRE(ref.spec.width == w);
        REQUIRE(ref.spec.height == h);
        // Pixels where the reference shows the curve (darker than the white sky); the
        // noise of our mean from the difference of two independently seeded renders.
        double sumA = 0, sumB = 0, sumR = 0, diff2 = 0, sumAll = 0, sumRefAll = 0;
        int n = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                std::size_t i = std::size_t(y) * w + x;
                double r = (ref.at(x, y, 0) + ref.at(x, y, 1) + ref.at(x, y, 2)) / 3.0;
                sumAll += 0.5 * (a[i] + b[i]), sumRefAll += r;
                if (r > 0.9) continue;
                sumA += a[i], sumB += b[i], sumR += r, diff2 += (a[i] - b[i]) * (a[i] - b[i]), ++n;
            }
        REQUIRE(n > 50);
        double ours = 0.5 * (sumA + sumB) / n, theirs = sumR / n;
        double stderr_ = std::sqrt(diff2 / 2.0 / n / n / 2.0);  // of the two-render mean
        // Tolerance: 1 % systematic (sphere- vs circle-sweep of a varying radius, see
        // bsplinecurve.cpp) plus 4 standard errors (two-sided false-alarm probability
        // 6e-5; the renders are seeded, so the outcome is deterministic).
        double rel = (ours - theirs) / theirs, tol = 0.01 + 4.0 * stderr_ / theirs;
        INFO(kind << ": curve pixels effigi " << ours << " ± " << stderr_ << ", mitsuba " << theirs << ", tolerance "
                  << tol);
        CHECK(std::abs(rel) < tol);
        CHECK(tol < 0.03);
        CHECK(std::abs(sumAll - sumRefAll) / sumRefAll < 0.005);  // whole image (mostly sky): coverage
    }
}
