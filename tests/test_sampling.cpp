// Sampling: the independent sampler (range, determinism, uniformity), the mean-sample
// integrator (accuracy, honest error estimate, coverage), the warp functions of
// math/warp_functions.hpp (normalisation, inverses, distribution), and the statistics
// helpers of math/stats.hpp the other statistical tests rely on.
//
// Every statistical test is seeded, so it either always passes or always fails; the
// significance level it was designed with is stated next to it.
#include "mc_mean.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifunction.hpp"
#include "effigi/interfaces/iintegrator.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/math/stats.hpp"
#include "effigi/math/warp_functions.hpp"

#include <catch2/catch.hpp>

#include <set>

using namespace effigi;
using effigi::test::mcMean;

namespace {

constexpr double Alpha = 0.01;  // significance level of every chi-square test here

Ref<ISampler> makeSampler(std::int64_t seed = 0, std::int64_t spp = 4) {
    Properties p("sampler", "independent");
    p.set("seed", seed);
    p.set("sample_count", spp);
    Ref<ISampler> s = query<ISampler>(Registry::instance().create("sampler", "independent", p));
    REQUIRE(s);
    return s;
}

Ref<IIntegrator> makeMean() {
    Properties p("integrator", "mean");
    Ref<IIntegrator> i = query<IIntegrator>(Registry::instance().create("integrator", "mean", p));
    REQUIRE(i);
    return i;
}

/// f(u) = u² on [0,1): ∫ = 1/3, Var f = 1/5 − 1/9 = 4/45.
class Square final : public Implements<IFunction> {
public:
    int dimension() const override { return 1; }
    void eval(ISampler& s, std::span<double> out) override {
        double x = s.get1D();
        out[0] = x * x;
    }
    std::optional<std::vector<double>> integral() const override { return std::vector<double>{1.0 / 3.0}; }
};

/// Several channels at once, with a huge offset on one (tests Welford's stability).
class Channels final : public Implements<IFunction> {
public:
    explicit Channels(int n) : m_n(n) {}
    int dimension() const override { return 1; }
    int channels() const override { return m_n; }
    void eval(ISampler& s, std::span<double> out) override {
        double x = s.get1D();
        for (int c = 0; c < m_n; ++c) out[std::size_t(c)] = (c == 0 ? 1e8 : 0.0) + double(c + 1) * x;
    }

private:
    int m_n;
};

/// Histogram of n values in [0,1) into k equal bins.
std::vector<double> histogram1D(const std::vector<float>& values, int k) {
    std::vector<double> h(std::size_t(k), 0.0);
    for (float v : values) h[std::size_t(std::min(int(v * float(k)), k - 1))] += 1.0;
    return h;
}

} // namespace

// ---------------------------------------------------------------------------------------
// stats.hpp

TEST_CASE("chi-square CDF and normal quantile match tabulated values", "[sampling]") {
    // Tabulated critical values (e.g. NIST/SEMATECH e-Handbook, table 1.3.6.7.4).
    CHECK(stats::chi2Cdf(3.841459, 1) == Approx(0.95).epsilon(1e-6));
    CHECK(stats::chi2Cdf(18.307038, 10) == Approx(0.95).epsilon(1e-6));
    CHECK(stats::chi2Survival(23.209251, 10) == Approx(0.01).epsilon(1e-5));
    CHECK(stats::chi2Survival(135.806723, 100) == Approx(0.01).epsilon(1e-5));
    CHECK(stats::chi2Cdf(2.0, 2) == Approx(1.0 - std::exp(-1.0)).epsilon(1e-12));  // exponential
    CHECK(stats::regularizedGammaP(3.0, 0.0) == 0.0);
    CHECK(stats::regularizedGammaQ(3.0, 1e6) == 0.0);
    CHECK(stats::normalQuantile(0.975) == Approx(1.959963985).epsilon(1e-9));
    CHECK(stats::normalQuantile(0.5) == Approx(0.0).margin(1e-12));
    CHECK(stats::normalQuantile(1e-10) == Approx(-6.361340902).epsilon(1e-8));
    CHECK(stats::normalCdf(stats::normalQuantile(0.3)) == Approx(0.3).epsilon(1e-12));
}

TEST_CASE("chi-square test pools sparse cells and rejects impossible samples", "[sampling]") {
    std::vector<double> expected{100, 100, 100, 1, 1, 1, 2, 0};
    std::vector<double> observed{100, 100, 100, 2, 0, 1, 2, 0};
    auto r = stats::chiSquareTest(observed, expected);
    CHECK(r.pooledCells == 4);
    CHECK(r.cells == 4);  // three big cells + one pool of expected 5
    CHECK(r.statistic == Approx(0.0));
    CHECK(r.passes(Alpha));

    observed.back() = 1;  // a sample where the expected count is zero
    CHECK_FALSE(stats::chiSquareTest(observed, expected).passes(Alpha));

    // A clearly wrong distribution is rejected.
    std::vector<double> e2(10, 1000.0), o2(10, 1000.0);
    o2[0] = 1200;
    o2[1] = 800;
    CHECK_FALSE(stats::chiSquareTest(o2, e2).passes(Alpha));
}

// ---------------------------------------------------------------------------------------
// independent sampler

TEST_CASE("independent sampler: values in the half-open unit interval, parameters", "[sampling]") {
    auto s = makeSampler(7, 16);
    CHECK(s->samplesPerPixel() == 16);
    float lo = 1.f, hi = 0.f;
    for (int px = 0; px < 8; ++px) {
        s->startPixel({px, 3 * px});
        for (std::uint64_t i = 0; i < 64; ++i) {
            s->startSample(i);
            for (int d = 0; d < 16; ++d) {
                float v = s->get1D();
                Point2f v2 = s->get2D();
                lo = std::min({lo, v, v2.x, v2.y});
                hi = std::max({hi, v, v2.x, v2.y});
            }
        }
    }
    CHECK(lo >= 0.f);
    CHECK(hi < 1.f);

    Properties bad("sampler", "independent");
    bad.set("sample_count", std::int64_t(0));
    CHECK_THROWS_AS(Registry::instance().create("sampler", "independent", bad), Error);
}

TEST_CASE("independent sampler is deterministic per (pixel, index, seed)", "[sampling]") {
    auto draw = [](ISampler& s, Point2i px, std::uint64_t i) {
        s.startPixel(px);
        s.startSample(i);
        std::vector<float> v;
        for (int d = 0; d < 8; ++d) v.push_back(s.get1D());
        return v;
    };
    auto a = makeSampler(3), b = makeSampler(3);
    // Same inputs, any order of calls, any object: the same numbers.
    auto ref = draw(*a, {5, 9}, 17);
    draw(*b, {1, 1}, 2);
    CHECK(draw(*b, {5, 9}, 17) == ref);
    CHECK(draw(*a, {5, 9}, 17) == ref);
    // A clone with offset 0 is a copy; other inputs give other numbers.
    CHECK(draw(*a->clone(0), {5, 9}, 17) == ref);
    CHECK(draw(*a->clone(1), {5, 9}, 17) != ref);
    CHECK(draw(*a, {9, 5}, 17) != ref);
    CHECK(draw(*a, {5, 9}, 18) != ref);
    CHECK(draw(*makeSampler(4), {5, 9}, 17) != ref);

    // No two of many (pixel, index) pairs start alike.
    std::set<std::vector<float>> seen;
    for (int x = 0; x < 16; ++x)
        for (std::uint64_t i = 0; i < 16; ++i) seen.insert(draw(*a, {x, 0}, i));
    CHECK(seen.size() == 256);
}

TEST_CASE("independent sampler is uniform in 1D and 2D, also across sample indices", "[sampling]") {
    // Chi-square at significance 0.01 each.
    auto s = makeSampler(11);
    std::vector<float> values, firstOfSample;
    std::vector<double> grid(16 * 16, 0.0);
    for (int px = 0; px < 50; ++px) {
        s->startPixel({px, px / 7});
        for (std::uint64_t i = 0; i < 200; ++i) {
            s->startSample(i);
            firstOfSample.push_back(s->get1D());
            for (int d = 0; d < 4; ++d) values.push_back(s->get1D());
            Point2f p = s->get2D();
            grid[std::size_t(int(p.y * 16.f) * 16 + int(p.x * 16.f))] += 1.0;
        }
    }
    auto h = histogram1D(values, 100);
    auto r1 = stats::chiSquareTest(h, std::vector<double>(100, double(values.size()) / 100.0));
    INFO("1D: " << r1.summary());
    CHECK(r1.passes(Alpha));

    auto r2 = stats::chiSquareTest(grid, std::vector<double>(256, 10000.0 / 256.0));
    INFO("2D: " << r2.summary());
    CHECK(r2.passes(Alpha));

    // Consecutive sample indices must not be correlated: pairs (first value of sample i,
    // first value of sample i+1) fill the unit square uniformly.
    std::vector<double> pairs(10 * 10, 0.0);
    double nPairs = 0;
    for (std::size_t k = 0; k + 1 < firstOfSample.size(); k += 2) {
        int a = std::min(int(firstOfSample[k] * 10.f), 9), b = std::min(int(firstOfSample[k + 1] * 10.f), 9);
        pairs[std::size_t(a * 10 + b)] += 1.0;
        nPairs += 1.0;
    }
    auto r3 = stats::chiSquareTest(pairs, std::vector<double>(100, nPairs / 100.0));
    INFO("pairs: " << r3.summary());
    CHECK(r3.passes(Alpha));
}

// ---------------------------------------------------------------------------------------
// mean integrator

TEST_CASE("mean integrator: ∫x² = 1/3 within its own error estimate", "[sampling]") {
    auto mean = makeMean();
    auto s = makeSampler(1);
    s->startPixel({0, 0});
    Square f;
    const std::uint64_t n = 20000;
    Estimate e = mean->integrate(f, *s, n);
    REQUIRE(e.channels == 1);
    CHECK(e.samples == n);
    double sigma = std::sqrt(e.variance[0]);
    CHECK(std::abs(e.mean[0] - 1.0 / 3.0) < 4.0 * sigma);
    // The variance of the mean estimates (4/45)/n; its own relative error is ~1%.
    CHECK(e.variance[0] == Approx(4.0 / 45.0 / double(n)).epsilon(0.05));

    // One sample: no variance estimate.
    Estimate one = mean->integrate(f, *s, 1);
    CHECK(std::isinf(one.variance[0]));
}

TEST_CASE("mean integrator: the 95% interval covers the truth about 95% of the time", "[sampling]") {
    // 200 seeded repetitions; Binomial(200, 0.95) lies in [180, 198] with probability
    // ≈ 0.997, and the seeds make the outcome fixed.
    auto mean = makeMean();
    Square f;
    int covered = 0;
    const double z = stats::normalQuantile(0.975);
    for (int rep = 0; rep < 200; ++rep) {
        auto s = makeSampler(rep);
        s->startPixel({rep, 0});
        Estimate e = mean->integrate(f, *s, 1000);
        if (std::abs(e.mean[0] - 1.0 / 3.0) <= z * std::sqrt(e.variance[0])) ++covered;
    }
    INFO("covered " << covered << " of 200");
    CHECK(covered >= 180);
    CHECK(covered <= 198);
}

TEST_CASE("mean integrator: several channels, large offsets, channel limit", "[sampling]") {
    auto mean = makeMean();
    auto s = makeSampler(2);
    s->startPixel({3, 4});
    Channels f(3);
    const std::uint64_t n = 50000;
    Estimate e = mean->integrate(f, *s, n);
    REQUIRE(e.channels == 3);
    for (int c = 0; c < 3; ++c) {
        double k = c + 1;
        // ∫ (offset + k x) = offset + k/2, Var = k²/12: Welford keeps it despite the 1e8 offset.
        double offset = c == 0 ? 1e8 : 0.0;
        CHECK(std::abs(e.mean[c] - (offset + k / 2)) < 5.0 * std::sqrt(e.variance[c]));
        CHECK(e.variance[c] == Approx(k * k / 12.0 / double(n)).epsilon(0.05));
    }
    Channels tooMany(Estimate::MaxChannels + 1);
    CHECK_THROWS_AS(mean->integrate(tooMany, *s, 10), Error);
}

// ---------------------------------------------------------------------------------------
// warp functions

TEST_CASE("warp pdfs integrate to one", "[sampling]") {
    const int n = 400000;
    // Direction pdfs: ∫_S² p dω = E[p(ω) / (1/4π)] for ω uniform on the sphere.
    auto overSphere = [&](auto pdf, std::uint64_t seed) {
        return mcMean([&](Point2f u) { return double(pdf(warp::squareToUniformSphere(u))) * 4.0 * Pi; }, n, seed);
    };
    const float cosMax = 0.7f;
    std::vector<std::pair<std::string, std::pair<double, double>>> cases = {
        {"cosine hemisphere", overSphere([](Vector3f v) { return warp::squareToCosineHemispherePdf(v); }, 1)},
        {"uniform hemisphere", overSphere([](Vector3f v) { return warp::squareToUniformHemispherePdf(v); }, 2)},
        {"uniform sphere", overSphere([](Vector3f v) { return warp::squareToUniformSpherePdf(v); }, 3)},
        {"cone", overSphere([&](Vector3f v) { return warp::squareToUniformConePdf(v, cosMax); }, 4)},
        // Disk: ∫ p dA over [-1,1]² = E[4 p].
        {"disk", mcMean([](Point2f u) { return 4.0 * warp::squareToUniformDiskPdf(2.f * u - 1.f); }, n, 5)},
        // Wavelengths: ∫ p dλ over [360, 830] = E[470 p].
        {"visible wavelength", mcMean([](Point2f u) { return 470.0 * warp::visibleWavelengthPdf(360.f + 470.f * u.x); },
                                      n, 6)},
    };
    for (const auto& [name, est] : cases) {
        INFO(name << ": " << est.first << " ± " << est.second);
        CHECK(std::abs(est.first - 1.0) < std::max(5.0 * est.second, 1e-5));
        CHECK(std::abs(est.first - 1.0) < 0.01);
    }
}

TEST_CASE("warps land in their domain and invert", "[sampling]") {
    PCG32 rng(42, 7);
    double worst[4] = {0, 0, 0, 0};
    for (int i = 0; i < 100000; ++i) {
        Point2f u(rng.nextFloat(), rng.nextFloat());
        Point2f d = warp::squareToUniformDiskConcentric(u);
        REQUIRE(dot(d, d) <= 1.f + 1e-6f);
        worst[0] = std::max(worst[0], double(glm::length(warp::uniformDiskToSquareConcentric(d) - u)));

        Vector3f h = warp::squareToCosineHemisphere(u);
        REQUIRE(h.z >= 0.f);
        REQUIRE(length(h) == Approx(1.f).epsilon(1e-5));
        worst[1] = std::max(worst[1], double(glm::length(warp::cosineHemisphereToSquare(h) - u)));

        Vector3f s = warp::squareToUniformSphere(u);
        REQUIRE(length(s) == Approx(1.f).epsilon(1e-5));
        worst[2] = std::max(worst[2], double(glm::length(warp::uniformSphereToSquare(s) - u)));

        Vector3f c = warp::squareToUniformCone(u, 0.7f);
        REQUIRE(c.z >= 0.7f - 1e-6f);
        REQUIRE(length(c) == Approx(1.f).epsilon(1e-5));

        Point2f b = warp::squareToUniformTriangle(u);
        REQUIRE(b.x >= 0.f);
        REQUIRE(b.y >= 0.f);
        REQUIRE(b.x + b.y <= 1.f + 1e-6f);
        if (u.x > 1e-4f)  // near u.x = 0 the map squeezes u.y into a point
            worst[3] = std::max(worst[3], double(glm::length(warp::uniformTriangleToSquare(b) - u)));
    }
    INFO("disk " << worst[0] << ", cosine " << worst[1] << ", sphere " << worst[2] << ", triangle " << worst[3]);
    for (double w : worst) CHECK(w < 1e-3);
}

TEST_CASE("warped samples follow their pdf (chi-square)", "[sampling]") {
    // Bins over (cos θ, φ), where dω = d cos θ dφ; expected counts are exact integrals of
    // the pdf over each bin. Significance 0.01 per distribution.
    const int nz = 20, nphi = 40, n = 200000;
    std::uint64_t seed = 1234;
    auto test = [&](const char* name, auto sample, auto binProbability, double zLo) {
        PCG32 rng(++seed, 5);
        std::vector<double> obs(std::size_t(nz * nphi), 0.0), exp(obs.size(), 0.0);
        for (int i = 0; i < n; ++i) {
            Vector3f v = sample(Point2f(rng.nextFloat(), rng.nextFloat()));
            double phi = std::atan2(v.y, v.x);
            if (phi < 0) phi += 2 * M_PI;
            int iz = std::clamp(int((v.z - zLo) / (1.0 - zLo) * nz), 0, nz - 1);
            int ip = std::clamp(int(phi / (2 * M_PI) * nphi), 0, nphi - 1);
            obs[std::size_t(iz * nphi + ip)] += 1.0;
        }
        for (int iz = 0; iz < nz; ++iz) {
            double z0 = zLo + (1.0 - zLo) * iz / nz, z1 = zLo + (1.0 - zLo) * (iz + 1) / nz;
            for (int ip = 0; ip < nphi; ++ip) exp[std::size_t(iz * nphi + ip)] = n * binProbability(z0, z1) / nphi;
        }
        auto r = stats::chiSquareTest(obs, exp);
        INFO(name << ": " << r.summary());
        CHECK(r.passes(Alpha));
    };
    // Cosine: ∫ z/π dz dφ over a ring = (z1² − z0²)/2 · 2π/π.
    test("cosine hemisphere", [](Point2f u) { return warp::squareToCosineHemisphere(u); },
         [](double z0, double z1) { return z1 * z1 - z0 * z0; }, 0.0);
    test("uniform sphere", [](Point2f u) { return warp::squareToUniformSphere(u); },
         [](double z0, double z1) { return (z1 - z0) / 2.0; }, -1.0);
    test("cone", [](Point2f u) { return warp::squareToUniformCone(u, 0.3f); },
         [](double z0, double z1) { return (z1 - z0) / 0.7; }, 0.3);
}

TEST_CASE("triangle warp is uniform over the triangle", "[sampling]") {
    // 10×10 cells of the (b0, b1) square: cells below the diagonal hold 1/50 of the
    // samples, the ones it cuts 1/100, the rest none. Significance 0.01.
    const int k = 10, n = 100000;
    PCG32 rng(99, 3);
    std::vector<double> obs(std::size_t(k * k), 0.0), exp(obs.size(), 0.0);
    for (int i = 0; i < n; ++i) {
        Point2f b = warp::squareToUniformTriangle(Point2f(rng.nextFloat(), rng.nextFloat()));
        int i0 = std::min(int(b.x * k), k - 1), i1 = std::min(int(b.y * k), k - 1);
        obs[std::size_t(i0 * k + i1)] += 1.0;
    }
    for (int i0 = 0; i0 < k; ++i0)
        for (int i1 = 0; i1 < k; ++i1)
            exp[std::size_t(i0 * k + i1)] = i0 + i1 < k - 1 ? n / 50.0 : i0 + i1 == k - 1 ? n / 100.0 : 0.0;
    auto r = stats::chiSquareTest(obs, exp);
    INFO(r.summary());
    CHECK(r.passes(Alpha));
}
