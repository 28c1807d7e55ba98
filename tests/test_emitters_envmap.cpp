// The envmap emitter after Mitsuba 3: lat-long orientation, sampleDirect /
// pdfEnvironment / evalEnvironment agreement, the pdf integrating to 1, a chi-square test
// of its sampling, unbiased irradiance, bad input; and the Distribution2D it samples by.
// Images are written as PFM files from a seeded generator. Every Monte Carlo check is
// seeded and states its tolerance (a number of standard errors) or significance level.
#include "emitter_helpers.hpp"

#include "effigi/core/error.hpp"
#include "effigi/math/distribution2d.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/math/stats.hpp"
#include "effigi/math/warp_functions.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace effigi;
using namespace effigi::test;

namespace {

Ref<IEmitter> makeEnvmap(const TempImage& img, Params extra = {}) {
    extra.emplace_back("filename", img.path.string());
    Ref<IEmitter> e = makeEmitter("envmap", extra);
    e->preprocess(BBox3f(Point3f(-1.f), Point3f(1.f)));
    return e;
}

/// Mitsuba's lat-long direction for (u, v).
Vector3f uvToDirection(float u, float v) {
    float phi = 2.f * Pi * u, theta = Pi * v;
    return {std::sin(phi) * std::sin(theta), std::cos(theta), -std::cos(phi) * std::sin(theta)};
}

/// A seeded random image with a bright patch: smooth enough to be realistic, uneven
/// enough that a wrong density shows.
TempImage randomImage(const std::string& name, int w, int h, std::uint64_t seed) {
    PCG32 rng(seed, 3);
    std::vector<Vector3f> texels(std::size_t(w * h));
    for (auto& t : texels) t = Vector3f(rng.nextFloat(), rng.nextFloat(), rng.nextFloat()) * 0.5f;
    for (int y = 1; y < 3; ++y)
        for (int x = w / 4; x < w / 4 + 3; ++x) texels[std::size_t(y * w + x)] = Vector3f(40.f, 30.f, 20.f);
    return TempImage(name, w, h, [&](int x, int y) { return texels[std::size_t(y * w + x)]; });
}

} // namespace

// ---------------------------------------------------------------- envmap

TEST_CASE("envmap: Mitsuba's lat-long orientation, +Y up", "[emitter][envmap]") {
    // 8 × 5 black image: the top row bright (the zenith), one column a quarter of the way
    // across green (+X), the bottom row dark.
    TempImage img("orient", 8, 5, [](int x, int y) {
        if (y == 0) return Vector3f(2.f);
        if (x == 2 && y == 2) return Vector3f(0.f, 1.f, 0.f);
        return Vector3f(0.f);
    });
    auto e = makeEnvmap(img);
    CHECK(e->flags() == EmitterInfinite);
    CHECK(e->evalEnvironment(Vector3f(0.f, 1.f, 0.f), Green)[0] > 1.f);
    CHECK(e->evalEnvironment(Vector3f(0.f, -1.f, 0.f), Green)[0] == 0.f);
    // Texel x = 2 of 8 has its centre at u = 2.5/8, φ = 2π u; row 2 of 5 is the horizon.
    Vector3f green = uvToDirection(2.5f / 8.f, 0.5f);
    CHECK(e->evalEnvironment(green, Green)[0] > 0.5f);
    CHECK(e->evalEnvironment(Vector3f(-green.x, green.y, green.z), Green)[0] == 0.f);
    // to_world rotates the map: after 180° about y the green texel is on the other side.
    auto r = makeEnvmap(img, {{"to_world", Transform::rotate(Vector3f(0.f, 1.f, 0.f), 180.f)}});
    CHECK(r->evalEnvironment(Vector3f(-green.x, green.y, -green.z), Green)[0] > 0.5f);
    CHECK(r->evalEnvironment(green, Green)[0] == 0.f);
}

TEST_CASE("envmap: a constant map has the constant emitter's radiance", "[emitter][envmap]") {
    TempImage img("const", 6, 3, [](int, int) { return Vector3f(0.25f, 0.5f, 1.f); });
    auto e = makeEnvmap(img, {{"scale", 2.0}});
    auto c = makeEmitter("constant", {{"radiance", RGBValue{Vector3f(0.5f, 1.f, 2.f)}}});
    PCG32 rng(5, 5);
    for (int i = 0; i < 50; ++i) {
        Vector3f d = warp::squareToUniformSphere({rng.nextFloat(), rng.nextFloat()});
        auto lambda = SampledWavelengths::sampleVisible(rng.nextFloat());
        SampledSpectrum a = e->evalEnvironment(d, lambda), b = c->evalEnvironment(d, lambda);
        for (int k = 0; k < NSpectrumSamples; ++k) CHECK(a[k] == Approx(b[k]).epsilon(1e-4));
    }
}

TEST_CASE("envmap: sampleDirect agrees with pdfEnvironment and evalEnvironment", "[emitter][envmap]") {
    TempImage img("agree", 16, 9, [](int x, int y) { return Vector3f(float((x * 7 + y * 3) % 5), 0.5f, float(y)); });
    auto e = makeEnvmap(img);
    PCG32 rng(17, 4);
    for (int i = 0; i < 20000; ++i) {
        Point3f ref(rng.nextFloat(), rng.nextFloat(), rng.nextFloat());
        EmitterSample es = e->sampleDirect(ref, {rng.nextFloat(), rng.nextFloat()}, Green);
        if (es.pdf == 0.f) continue;
        REQUIRE(!es.delta);
        REQUIRE(std::isinf(es.dist));
        REQUIRE(std::abs(length(es.wi) - 1.f) < 1e-5f);
        REQUIRE(es.pdf == Approx(e->pdfEnvironment(ref, es.wi)).epsilon(2e-3));
        REQUIRE(es.L[0] == Approx(e->evalEnvironment(es.wi, Green)[0]).epsilon(2e-3).margin(1e-6));
    }
}

TEST_CASE("envmap: pdfEnvironment integrates to 1 over the sphere", "[emitter][envmap]") {
    auto img = randomImage("integral", 24, 12, 21);
    auto e = makeEnvmap(img);
    // Uniform directions: E[pdf · 4π] = 1. Five standard errors (false alarm < 1e-6).
    PCG32 rng(23, 6);
    const int n = 400000;
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        Vector3f d = warp::squareToUniformSphere({rng.nextFloat(), rng.nextFloat()});
        double v = e->pdfEnvironment(Point3f(0.f), d) * 4.0 * Pi;
        sum += v, sum2 += v * v;
    }
    double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
    INFO("integral " << mean << " ± " << se);
    CHECK(std::abs(mean - 1.0) <= 5.0 * se);
}

TEST_CASE("envmap: sampling follows its pdf (chi-square)", "[emitter][envmap]") {
    auto img = randomImage("chi2", 20, 10, 29);
    auto e = makeEnvmap(img);
    // Cells of a 12 × 8 grid in (u, v) that does not line up with the texels; expected
    // counts integrate the density w.r.t. du dv (pdf · 2π² sin θ) by a 96 × 96 midpoint
    // rule per cell. Significance level 1e-4 (the seed is fixed: the outcome is too).
    const int nu = 12, nv = 8, sub = 96, n = 200000;
    std::vector<double> expected(nu * nv, 0.0), observed(nu * nv, 0.0);
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            double p = 0;
            for (int b = 0; b < sub; ++b)
                for (int a = 0; a < sub; ++a) {
                    float u = (i + (a + 0.5f) / sub) / nu, v = (j + (b + 0.5f) / sub) / nv;
                    p += e->pdfEnvironment(Point3f(0.f), uvToDirection(u, v)) * 2.0 * Pi * Pi * std::sin(Pi * v);
                }
            expected[j * nu + i] = p / (double(sub) * sub * nu * nv) * n;
        }
    PCG32 rng(31, 8);
    for (int k = 0; k < n; ++k) {
        EmitterSample es = e->sampleDirect(Point3f(0.f), {rng.nextFloat(), rng.nextFloat()}, Green);
        REQUIRE(es.pdf > 0.f);
        float u = std::atan2(es.wi.x, -es.wi.z) * Inv2Pi;
        u -= std::floor(u);
        float v = std::acos(std::clamp(es.wi.y, -1.f, 1.f)) * InvPi;
        int i = std::min(int(u * nu), nu - 1), j = std::min(int(v * nv), nv - 1);
        observed[j * nu + i] += 1.0;
    }
    stats::ChiSquareResult r = stats::chiSquareTest(observed, expected);
    INFO(r.summary());
    CHECK(r.passes(1e-4));
}

TEST_CASE("envmap: light sampling estimates irradiance without bias", "[emitter][envmap]") {
    auto img = randomImage("irradiance", 16, 8, 37);
    auto e = makeEnvmap(img, {{"to_world", Transform::rotate(Vector3f(1.f, 0.f, 1.f), 35.f)}});
    // E = ∫ L cos⁺ dω for a normal n, by importance sampling and by uniform sampling of
    // evalEnvironment; the difference must be within 5 combined standard errors.
    for (Vector3f n : {Vector3f(0.f, 1.f, 0.f), normalize(Vector3f(1.f, -0.2f, 0.5f))}) {
        PCG32 rng(41, 9);
        const int count = 200000;
        double s1 = 0, q1 = 0, s2 = 0, q2 = 0;
        for (int i = 0; i < count; ++i) {
            EmitterSample es = e->sampleDirect(Point3f(0.f), {rng.nextFloat(), rng.nextFloat()}, Green);
            double a = es.pdf > 0.f ? es.L[0] * std::max(0.f, dot(n, es.wi)) / es.pdf : 0.0;
            Vector3f d = warp::squareToUniformSphere({rng.nextFloat(), rng.nextFloat()});
            double b = e->evalEnvironment(d, Green)[0] * std::max(0.f, dot(n, d)) * 4.0 * Pi;
            s1 += a, q1 += a * a, s2 += b, q2 += b * b;
        }
        double m1 = s1 / count, m2 = s2 / count;
        double se = std::sqrt((q1 / count - m1 * m1) / count + (q2 / count - m2 * m2) / count);
        INFO("importance " << m1 << ", uniform " << m2 << ", se " << se);
        CHECK(std::abs(m1 - m2) <= 5.0 * se);
        CHECK(m1 > 0.0);
    }
}

TEST_CASE("envmap: a black map emits nothing and samples nothing", "[emitter][envmap]") {
    TempImage img("black", 4, 2, [](int, int) { return Vector3f(0.f); });
    auto e = makeEnvmap(img);
    EmitterSample es = e->sampleDirect(Point3f(0.f), {0.5f, 0.5f}, Green);
    CHECK(es.pdf == 0.f);
    CHECK(e->pdfEnvironment(Point3f(0.f), Vector3f(0.f, 1.f, 0.f)) == 0.f);
    CHECK(e->evalEnvironment(Vector3f(0.f, 1.f, 0.f), Green)[0] == 0.f);
    CHECK(e->power() == 0.f);
}

TEST_CASE("envmap: bad input is a clean error", "[emitter][envmap]") {
    CHECK_THROWS_AS(makeEmitter("envmap", {{"filename", std::string("/nonexistent/sky.exr")}}), Error);
    CHECK_THROWS_AS(makeEmitter("envmap"), Error);  // no filename
    // NaN and negative texels emit nothing instead of poisoning every estimate.
    TempImage nan("nan", 4, 2, [](int x, int) { return Vector3f(x == 1 ? std::nanf("") : x == 2 ? -5.f : 1.f); });
    auto e = makeEnvmap(nan);
    for (float u : {0.f, 0.3f, 0.4f, 0.6f, 0.9f}) {
        Vector3f d = uvToDirection(u, 0.5f);
        CHECK(std::isfinite(e->evalEnvironment(d, Green)[0]));
        CHECK(std::isfinite(e->pdfEnvironment(Point3f(0.f), d)));
    }
    CHECK(e->evalEnvironment(uvToDirection(1.5f / 4.f, 0.5f), Green)[0] == 0.f);
    try {
        makeEmitter("envmap", {{"filename", std::string("/nonexistent/sky.exr")}});
        FAIL("a missing file was accepted");
    } catch (const Error& err) {
        CHECK(std::string(err.what()).find("sky.exr") != std::string::npos);
    }
    TempImage ok("ok", 4, 2, [](int, int) { return Vector3f(1.f); });
    CHECK_THROWS_AS(makeEmitter("envmap", {{"filename", ok.path.string()}, {"scale", -1.0}}), Error);
}

// ---------------------------------------------------------------- distribution

TEST_CASE("Distribution2D: sampled density equals pdf(), zero cells never drawn", "[emitter][distribution]") {
    std::vector<float> w = {0.f, 1.f, 2.f, 0.f, 0.f, 0.f, 3.f, 0.5f, 0.f};
    Distribution2D dist(w, 3, 3);
    PCG32 rng(3, 3);
    for (int i = 0; i < 10000; ++i) {
        float pdf;
        Point2f p = dist.sample({rng.nextFloat(), rng.nextFloat()}, pdf);
        REQUIRE(p.x >= 0.f);
        REQUIRE(p.x < 1.f);
        REQUIRE(p.y < 1.f);
        int cell = std::min(int(p.y * 3), 2) * 3 + std::min(int(p.x * 3), 2);
        REQUIRE(w[std::size_t(cell)] > 0.f);
        REQUIRE(pdf == dist.pdf(p));
        // Density = weight / mean weight.
        REQUIRE(pdf == Approx(w[std::size_t(cell)] / (6.5f / 9.f)));
    }
    CHECK(Distribution2D(std::vector<float>(4, 0.f), 2, 2).isZero());
}
