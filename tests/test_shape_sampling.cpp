// The sampling contracts every shape keeps: uniform area sampling with pdf 1/area;
// sampleDirection's pdf equal to pdfDirection; pdfDirection integrating to one over the
// directions that see the shape.
#include "shape_helpers.hpp"

#include "effigi/math/rng.hpp"
#include "effigi/math/warp_functions.hpp"

#include <algorithm>
#include <vector>

using namespace effigi;
using namespace effigi::test;

namespace {

/// Wilson–Hilferty approximation of the chi-square quantile with k degrees of freedom;
/// z is the standard normal quantile (3.090 for a significance level of 0.001).
double chi2Critical(int k, double z = 3.090) {
    double a = 2.0 / (9.0 * k);
    return k * std::pow(1.0 - a + z * std::sqrt(a), 3.0);
}

double chi2(const std::vector<double>& observed, const std::vector<double>& expected) {
    double c = 0.0;
    for (std::size_t i = 0; i < observed.size(); ++i) {
        double d = observed[i] - expected[i];
        c += d * d / expected[i];
    }
    return c;
}

/// sampleDirection's pdf must equal pdfDirection at the point found by tracing the
/// sampled direction (so MIS weights computed either way agree).
void checkDirectionPdfs(const IShape& s, const Point3f& ref, bool expectFirstHit, int minChecked = 1500) {
    PCG32 rng(3, 5);
    int checked = 0;
    for (int i = 0; i < 2000; ++i) {
        DirectionSample ds = s.sampleDirection(ref, {rng.nextFloat(), rng.nextFloat()});
        if (!(ds.pdf > 0.f)) continue;
        CHECK(length(ds.wi) == Approx(1.f));
        CHECK(length(ds.p - ref) == Approx(ds.dist).epsilon(1e-4));
        Ray ray{ref, ds.wi};
        Hit hit;
        if (!trace(s, ray, hit)) continue;  // grazing directions may round past the edge
        if (expectFirstHit) CHECK(hit.t == Approx(ds.dist).epsilon(1e-3));
        if (std::abs(hit.t - ds.dist) > 1e-3f * ds.dist) continue;
        SurfaceInteraction si = s.interaction(ray, hit);
        // On an edge of the cube the trace may report the neighbouring face.
        if (dot(si.n, ds.n) < 0.99f) continue;
        INFO(s.typeName() << " p " << ds.p.x << " " << ds.p.y << " " << ds.p.z);
        CHECK(s.pdfDirection(ref, si) == Approx(ds.pdf).epsilon(2e-3));
        ++checked;
    }
    CHECK(checked > minChecked);
}

/// Monte Carlo estimate of ∫ pdfDirection dω over the directions from ref that hit s:
/// uniform directions, 4π·pdf where they hit. Must be `expected` within 4 standard errors
/// (two-sided significance about 6e-5), seeded. That is 1 when every sampled point is
/// visible from ref; for area sampling of a shape that hides part of itself, the
/// visible fraction of its area.
void checkPdfIntegral(const IShape& s, const Point3f& ref, double expected = 1.0) {
    PCG32 rng(17, 19);
    const int N = 200000;
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < N; ++i) {
        Vector3f d = warp::squareToUniformSphere({rng.nextFloat(), rng.nextFloat()});
        Ray ray{ref, d};
        Hit hit;
        double x = 0.0;
        if (trace(s, ray, hit)) x = 4.0 * double(Pi) * double(s.pdfDirection(ref, s.interaction(ray, hit)));
        sum += x;
        sum2 += x * x;
    }
    double mean = sum / N, var = (sum2 / N - mean * mean) / (N - 1);
    INFO("integral " << mean << " ± " << std::sqrt(var));
    CHECK(std::abs(mean - expected) < 4.0 * std::sqrt(var));
    CHECK(std::sqrt(var) < 0.05);  // the test has power
}

} // namespace

TEST_CASE("samplePosition is uniform by area with pdf 1/area", "[shapes][sampling]") {
    // Chi-square tests at significance level 0.001 on equal-expectation cells.
    PCG32 rng(7, 11);
    const int N = 96000;

    SECTION("scaled cube (faces of different areas)") {
        Properties p("shape", "cube");
        p.set("to_world", Transform::scale({1.f, 2.f, 3.f}));
        Ref<IShape> c = makeShape("cube", p);
        const Vector3f ext(1.f, 2.f, 3.f);
        // 6 faces x 4 x 4 cells, expected count ∝ cell area.
        std::vector<double> obs(96, 0.0), exp(96, 0.0);
        for (int axis = 0; axis < 3; ++axis) {
            float faceArea = 4.f * ext[(axis + 1) % 3] * ext[(axis + 2) % 3];
            for (int side = 0; side < 2; ++side)
                for (int k = 0; k < 16; ++k) exp[std::size_t((axis * 2 + side) * 16 + k)] = N * faceArea / 16.f / c->area();
        }
        for (int i = 0; i < N; ++i) {
            PositionSample ps = c->samplePosition({rng.nextFloat(), rng.nextFloat()});
            REQUIRE(ps.pdf == Approx(1.f / c->area()));
            Vector3f q = ps.p / ext;  // back to [-1,1]³
            int axis = std::abs(ps.n.x) > 0.5f ? 0 : std::abs(ps.n.y) > 0.5f ? 1 : 2;
            REQUIRE(q[axis] * ps.n[axis] == Approx(1.f));
            int side = ps.n[axis] > 0.f;
            auto cell = [](float x) { return std::clamp(int((x + 1.f) * 2.f), 0, 3); };
            int a = cell(q[(axis + 1) % 3]), b = cell(q[(axis + 2) % 3]);
            obs[std::size_t((axis * 2 + side) * 16 + a * 4 + b)] += 1.0;
        }
        CHECK(chi2(obs, exp) < chi2Critical(95));
    }
    SECTION("sphere and disk") {
        for (const char* type : {"sphere", "disk"}) {
            INFO(type);
            Ref<IShape> s = makeShape(type);
            // Equal-area cells: (z, φ) on the sphere (Archimedes), (r², φ) on the disk.
            std::vector<double> obs(64, 0.0), exp(64, N / 64.0);
            for (int i = 0; i < N; ++i) {
                PositionSample ps = s->samplePosition({rng.nextFloat(), rng.nextFloat()});
                REQUIRE(ps.pdf == Approx(1.f / s->area()));
                float a = std::string(type) == "sphere" ? (ps.p.z + 1.f) / 2.f : dot(ps.p, ps.p);
                float phi = std::atan2(ps.p.y, ps.p.x) * Inv2Pi + 0.5f;
                obs[std::size_t(std::clamp(int(a * 8.f), 0, 7) * 8 + std::clamp(int(phi * 8.f), 0, 7))] += 1.0;
            }
            CHECK(chi2(obs, exp) < chi2Critical(63));
        }
    }
}

TEST_CASE("sampleDirection pdf equals pdfDirection", "[shapes][sampling]") {
    Properties rp("shape", "rectangle");
    rp.set("to_world", Transform::rotate({0.70710678f, 0.70710678f, 0.f}, 30.f) * Transform::scale({1.f, 0.5f, 1.f}));
    checkDirectionPdfs(*makeShape("rectangle", rp), {0.4f, -0.7f, 1.3f}, true);
    // From here only the +z face of the cube is visible: 1/6 of the samples are first hits.
    checkDirectionPdfs(*makeShape("cube"), {0.4f, -0.7f, 3.f}, false, 250);
    checkDirectionPdfs(*makeShape("disk"), {0.4f, -0.7f, -0.5f}, true);

    Properties sp("shape", "sphere");
    sp.set("center", PointValue{{0.f, 0.f, 1.f}});
    sp.set("radius", 0.5);
    Ref<IShape> sphere = makeShape("sphere", sp);
    checkDirectionPdfs(*sphere, {0.3f, 0.2f, -3.f}, true);   // outside: cone sampling
    checkDirectionPdfs(*sphere, {0.1f, 0.f, 0.8f}, true);     // inside: area sampling

    // Cone sampling is uniform in the cone: (1 − cos θ)/(1 − cos θmax) and φ uniform
    // (chi-square at significance level 0.001 on 10 x 10 cells).
    Point3f ref(0.3f, 0.2f, -3.f);
    Vector3f axis = normalize(Point3f(0.f, 0.f, 1.f) - ref);
    float d = length(Point3f(0.f, 0.f, 1.f) - ref);
    float cosMax = std::sqrt(1.f - 0.25f / (d * d));
    Vector3f s, t;
    coordinateSystem(axis, s, t);
    PCG32 rng(23, 29);
    const int N = 50000;
    std::vector<double> obs(100, 0.0), exp(100, N / 100.0);
    for (int i = 0; i < N; ++i) {
        DirectionSample ds = sphere->sampleDirection(ref, {rng.nextFloat(), rng.nextFloat()});
        REQUIRE(ds.pdf == Approx(1.f / (2.f * Pi * (1.f - cosMax))).epsilon(1e-3));
        double c = (1.0 - double(dot(ds.wi, axis))) / (1.0 - double(cosMax));
        double phi = std::atan2(dot(ds.wi, t), dot(ds.wi, s)) * Inv2Pi + 0.5;
        obs[std::size_t(std::clamp(int(c * 10), 0, 9) * 10 + std::clamp(int(phi * 10), 0, 9))] += 1.0;
    }
    CHECK(chi2(obs, exp) < chi2Critical(99));
}

TEST_CASE("pdfDirection integrates to one over the shape's directions", "[shapes][sampling]") {
    checkPdfIntegral(*makeShape("rectangle"), {0.3f, -0.2f, 1.5f});
    checkPdfIntegral(*makeShape("disk"), {0.5f, 0.5f, -0.7f});
    checkPdfIntegral(*makeShape("cube"), {2.f, 1.5f, 3.f}, 0.5);  // the +x, +y, +z faces are visible
    Properties sp("shape", "sphere");
    sp.set("center", PointValue{{0.f, 0.f, 1.f}});
    Ref<IShape> sphere = makeShape("sphere", sp);
    checkPdfIntegral(*sphere, {0.5f, 0.5f, -2.f});  // outside: cone sampling
    checkPdfIntegral(*sphere, {0.2f, 0.f, 1.3f});   // inside: area sampling
}
