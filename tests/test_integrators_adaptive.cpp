// The adaptive numerical integrators `vegas` (Lepage 1978) and `adaptive` (stratification
// in rounds, after MISER): known integrals within their error bars, the VEGAS grid
// gathering at a peak, χ²/dof of its iterations near 1 on a smooth integrand, strata
// split where the variance is, VEGAS beating plain Monte Carlo on peaks, and the Cornell
// box rendered by `path` with either nested gives the same image mean as with `mean`.
// Per-pixel adaptive sampling (`adaptive` mode pixels) and its benchmark against uniform
// sampling: test_adaptive_pixels.cpp.
// Every case is seeded (deterministic); the statistical bounds are stated with the
// probability that a correct integrator fails them for a random seed.
#include "scene_text.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/iintegrator_hooks.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/render/image_metrics.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace effigi;

namespace {

using Params = std::vector<std::pair<std::string, PropertyValue>>;

/// Independent uniform values: a PCG32 stream per (pixel, sample index).
class RandomSampler final : public Implements<ISampler> {
public:
    explicit RandomSampler(std::uint64_t seed) : m_seed(seed) { startPixel(Point2i(0)); }
    int samplesPerPixel() const override { return 1 << 30; }
    void startPixel(const Point2i& p) override {
        m_key = mixBits(m_seed ^ mixBits((std::uint64_t(std::uint32_t(p.x)) << 32) | std::uint32_t(p.y)));
    }
    void startSample(std::uint64_t index) override { m_rng.seed(mixBits(m_key ^ mixBits(index + 1)), m_key); }
    float get1D() override { return m_rng.nextFloat(); }
    Point2f get2D() override {
        float x = get1D();
        return {x, get1D()};
    }
    Ref<ISampler> clone(std::uint64_t offset) const override {
        return std::make_shared<RandomSampler>(m_seed + offset);
    }

private:
    std::uint64_t m_seed, m_key = 0;
    PCG32 m_rng;
};

Ref<IIntegrator> integrator(const std::string& name, const Params& params = {}) {
    Properties p("integrator", name);
    for (const auto& [k, v] : params) p.set(k, v);
    return query<IIntegrator>(Registry::instance().create("integrator", name, p));
}

Ref<IFunction> function(const std::string& name, const Params& params = {}) {
    Properties p("function", name);
    for (const auto& [k, v] : params) p.set(k, v);
    return query<IFunction>(Registry::instance().create("function", name, p));
}

/// Forwards to a function and keeps the integrator's last report.
class Observed final : public Implements<IFunction, IIntegrationObserver> {
public:
    explicit Observed(Ref<IFunction> f) : m_f(std::move(f)) {}
    int dimension() const override { return m_f->dimension(); }
    void eval(ISampler& u, std::span<double> out) override { m_f->eval(u, out); }
    void integrated(const IntegrationReport& r) override { report = r; }
    IntegrationReport report;

private:
    Ref<IFunction> m_f;
};

/// f(x) = 1 where x₀ < 0.3, else 0, on [0,1)²: all the variance sits at x₀ = 0.3.
class Edge final : public Implements<IFunction> {
public:
    int dimension() const override { return 2; }
    void eval(ISampler& u, std::span<double> out) override {
        const float x0 = u.get1D();
        u.get1D();
        out[0] = x0 < 0.3f ? 1.0 : 0.0;
    }
};

struct Runs {
    double z = 0.0;          // pooled: Σ (m − I) / √Σ var
    double meanSquare = 0.0;  // mean of (m − I)² / var: ≈ 1 for calibrated error bars
    double rms = 0.0;         // RMS error
};

Runs repeat(const IIntegrator& integ, IFunction& f, double exact, int runs, std::uint64_t budget, std::uint64_t seed) {
    RandomSampler sampler(seed);
    double sumDiff = 0.0, sumVar = 0.0, sq = 0.0, sq2 = 0.0;
    for (int r = 0; r < runs; ++r) {
        sampler.startPixel(Point2i(r, 0));
        Estimate e = integ.integrate(f, sampler, budget);
        const double d = e.mean[0] - exact;
        sumDiff += d, sumVar += e.variance[0], sq += d * d / e.variance[0], sq2 += d * d;
    }
    return {sumDiff / std::sqrt(sumVar), sq / runs, std::sqrt(sq2 / runs)};
}

} // namespace

TEST_CASE("vegas and adaptive: known integrals within their error bars", "[integrator][vegas][adaptive]") {
    struct Case {
        std::string name;
        Ref<IFunction> f;
        double exact;
    };
    std::vector<Case> cases = {
        {"polynomial 2D", function("polynomial"), 1.0},
        {"polynomial 8D", function("polynomial", {{"dimension", std::int64_t(8)}, {"degree", std::int64_t(3)}}), 1.0},
        {"gaussian peak 1D", function("gaussian", {{"dimension", std::int64_t(1)}, {"width", 0.02}}), 0.0},
        {"gaussian peak 3D", function("gaussian", {{"dimension", std::int64_t(3)}, {"width", 0.1}}), 0.0},
        {"step 2D", function("step"), 0.0},
    };
    for (Case& c : cases)
        if (c.exact == 0.0) c.exact = (*c.f->integral())[0];
    // 40 runs of 4096 samples each. Pooled z: |z| < 4 fails a correct integrator with
    // probability 6e-5; the mean of 40 squared standardised errors (χ²₄₀/40 for exact
    // Gaussian errors) exceeds 2.2 with probability 1e-4 and lies below 0.4 with 2e-4.
    for (const std::string name : {"vegas", "adaptive"})
        for (const Case& c : cases) {
            Runs r = repeat(*integrator(name), *c.f, c.exact, 40, 4096, 2026);
            INFO(name << " on " << c.name << ": z = " << r.z << ", mean (error/σ)² = " << r.meanSquare);
            CHECK(std::abs(r.z) < 4.0);
            CHECK(r.meanSquare < 2.2);
            CHECK(r.meanSquare > 0.4);
        }
}

TEST_CASE("vegas: the grid gathers at a peak, and beats plain Monte Carlo there", "[integrator][vegas]") {
    // A Gaussian peak at 0.45, σ = 0.02: the bins there must be far narrower than the
    // uniform 1/K and than the bins in the empty tails (deterministic for the seed).
    auto f = std::make_shared<Observed>(function("gaussian", {{"dimension", std::int64_t(1)}, {"width", 0.02}}));
    RandomSampler sampler(7);
    Estimate e = integrator("vegas")->integrate(*f, sampler, 8192);
    REQUIRE(e.samples == 8192);
    REQUIRE(f->report.grid.size() == 1);
    const std::vector<double>& x = f->report.grid[0];
    REQUIRE(x.size() == 51);
    double atPeak = 1.0, inTail = 0.0;
    for (std::size_t i = 0; i + 1 < x.size(); ++i) {
        if (x[i] <= 0.45 && 0.45 < x[i + 1]) atPeak = x[i + 1] - x[i];
        if (x[i] >= 0.7) inTail = std::max(inTail, x[i + 1] - x[i]);
    }
    INFO("bin width at the peak " << atPeak << ", widest tail bin " << inTail);
    CHECK(atPeak < 0.25 / 50);
    CHECK(inTail > 2.0 / 50);
    CHECK(f->report.trainingStages >= 1);

    // RMS error over 32 runs of 4096 samples: measured 0.13× (Gaussian) and 0.07×
    // (stiff spike) of plain Monte Carlo's; the bound 0.5× leaves a margin far beyond the
    // ±13 % noise of a 32-run RMS.
    for (const auto& [name, g] :
         std::vector<std::pair<std::string, Ref<IFunction>>>{
             {"gaussian", function("gaussian", {{"dimension", std::int64_t(1)}, {"width", 0.02}})},
             {"spike", function("spike", {{"width", 2e-3}})}}) {
        const double exact = (*g->integral())[0];
        Runs vegas = repeat(*integrator("vegas"), *g, exact, 32, 4096, 11);
        Runs mean = repeat(*integrator("mean"), *g, exact, 32, 4096, 11);
        INFO(name << ": RMS error vegas " << vegas.rms << ", mean " << mean.rms);
        CHECK(vegas.rms < 0.5 * mean.rms);
    }
}

TEST_CASE("vegas: chi2/dof of the iterations is near 1 on a smooth integrand", "[integrator][vegas]") {
    // 7 estimating iterations (10, 3 training) → χ²/dof has mean 1 and standard deviation
    // √(2/6) per call; over 100 calls the mean is within 1 ± 0.23 (4 standard errors).
    auto f = std::make_shared<Observed>(function("polynomial"));
    RandomSampler sampler(3);
    auto vegas = integrator("vegas");
    double sum = 0.0;
    for (int r = 0; r < 100; ++r) {
        sampler.startPixel(Point2i(r, 1));
        vegas->integrate(*f, sampler, 4096);
        REQUIRE(f->report.stages.size() == 10);
        REQUIRE(std::isfinite(f->report.chi2PerDof));
        sum += f->report.chi2PerDof;
    }
    INFO("mean chi2/dof " << sum / 100);
    CHECK(std::abs(sum / 100 - 1.0) < 0.23);
}

TEST_CASE("adaptive: strata split where the variance is", "[integrator][adaptive]") {
    // f = [x₀ < 0.3] on [0,1)²: only strata across x₀ = 0.3 have variance, so they are
    // split (along x₀) and sampled most; strata away from it are not refined.
    auto f = std::make_shared<Observed>(std::make_shared<Edge>());
    RandomSampler sampler(5);
    Estimate e = integrator("adaptive")->integrate(*f, sampler, 8192);
    CHECK(e.mean[0] == Approx(0.3).margin(5 * std::sqrt(e.variance[0])));
    const auto& strata = f->report.strata;
    REQUIRE(strata.size() >= 8);
    double edgeWidth = 1.0, edgeDensity = 0.0, farDensity = 0.0, narrowestFar = 1.0;
    for (const auto& s : strata) {
        const double w0 = s.upper[0] - s.lower[0], volume = w0 * (s.upper[1] - s.lower[1]);
        const double density = double(s.samples) / volume;
        if (s.lower[0] <= 0.3 && 0.3 < s.upper[0]) {
            edgeWidth = std::min(edgeWidth, w0);
            edgeDensity = std::max(edgeDensity, density);
        } else if (s.upper[0] <= 0.2 || s.lower[0] >= 0.4) {
            narrowestFar = std::min(narrowestFar, w0);
            farDensity = std::max(farDensity, density);
        }
    }
    INFO("x0 width at the edge " << edgeWidth << ", narrowest far stratum " << narrowestFar << "; samples per "
                                 << "volume at the edge " << edgeDensity << ", far " << farDensity);
    CHECK(edgeWidth <= 1.0 / 64);
    CHECK(narrowestFar >= 1.0 / 16);
    CHECK(edgeDensity > 10 * farDensity);
}

TEST_CASE("adaptive: a relative error target stops early", "[integrator][adaptive]") {
    // The smooth polynomial reaches 1 % long before its budget of 16384 samples: after the
    // rounds of 256, 512 and 1024 samples (the earliest decision) and one more of 2048.
    RandomSampler sampler(9);
    auto f = function("polynomial");
    Estimate e = integrator("adaptive", {{"rel_error", 0.01}})->integrate(*f, sampler, 16384);
    INFO("samples " << e.samples << ", relative error " << std::sqrt(e.variance[0]) / e.mean[0]);
    CHECK(e.samples <= 3840);
    CHECK(std::sqrt(e.variance[0]) <= 0.01 * e.mean[0]);
    CHECK(std::abs(e.mean[0] - 1.0) < 5 * std::sqrt(e.variance[0]));
}

namespace {

struct Rendered {
    Image image;
    std::vector<float> variance;
    RenderStats stats;
    double filterFactor = 1.0;
};

Rendered renderCornell(const std::string& integratorXml, std::uint64_t seed, int spp = 64) {
    const std::string path = "<integrator type=\"path\"><integer name=\"max_depth\" value=\"$max_depth\"/>" +
                             integratorXml + "</integrator>";
    auto scene = test::loadWithIntegrator(EFFIGI_SOURCE_DIR "/scenes/cornell-box/scene.xml", path,
                                          {{"spp", std::to_string(spp)}, {"res", "32"}});
    RenderControl control;
    control.progress = false;
    control.seed = seed;
    Rendered r;
    r.stats = scene->renderer().render(*scene, control);
    r.image = scene->camera().film().develop();
    scene->renderer().varianceEstimate(r.variance);
    r.filterFactor = filterVarianceFactor(scene->camera().film().filter());
    return r;
}

/// Mean of R, G, B over the image and its standard error: the image mean is (nearly) the
/// mean of all samples, so its variance is the mean of the pixels' unfiltered variances
/// over the pixel count.
std::pair<double, double> imageMean(const Rendered& r) {
    const std::size_t pixels = std::size_t(r.image.width) * r.image.height;
    double sum = 0.0, var = 0.0;
    for (std::size_t i = 0; i < pixels; ++i)
        for (int c = 0; c < 3; ++c) {
            sum += r.image.pixels[i * r.image.channels() + c];
            var += r.variance[3 * i + c] / r.filterFactor;
        }
    const double n = 3.0 * double(pixels);
    return {sum / n, std::sqrt(var / n / double(pixels) / 3.0)};
}

} // namespace

TEST_CASE("path with a nested vegas or adaptive integrator renders the Cornell box's mean", "[integrator][render]") {
    // 32² pixels, 64 spp (256 with a relative-error target, which can stop a pixel only
    // from its fourth round on; 512 for VEGAS, whose iterations hold >= 256 samples, so
    // that its grid adapts and weighs samples by J; 128 for mode pixels, which spends half
    // of that in a pilot and allocated parts). The image means must agree within 4 combined standard
    // errors (probability 6e-5 that correct integrators fail) and within 3 % (the images'
    // noise is about 0.8 %). A film that ignored the sample weights (VEGAS's J, the strata's
    // shares) or the early stops would be off by far more.
    const Rendered ref = renderCornell("", 1);
    const auto [refMean, refError] = imageMean(ref);
    REQUIRE(ref.image.channels() >= 3);
    struct Case {
        std::string xml;
        int spp;
    };
    const std::string target = "<integrator type=\"adaptive\"><float name=\"rel_error\" value=\"0.1\"/></integrator>";
    const std::string pixels = "<integrator type=\"adaptive\"><string name=\"mode\" value=\"pixels\"/></integrator>";
    for (const Case& c : {Case{target, 256}, Case{"<integrator type=\"adaptive\"/>", 64},
                          Case{"<integrator type=\"vegas\"/>", 512}, Case{pixels, 128}}) {
        const Rendered r = renderCornell(c.xml, 2, c.spp);
        const auto [mean, error] = imageMean(r);
        const std::uint64_t budget = 32u * 32u * std::uint64_t(c.spp);
        INFO(c.xml << ": image mean " << mean << " ± " << error << ", with mean " << refMean << " ± " << refError
                   << "; " << r.stats.samples << " samples of " << budget);
        CHECK(std::abs(mean - refMean) < 4.0 * std::hypot(error, refError));
        CHECK(std::abs(mean - refMean) < 0.03 * refMean);
        if (c.xml.find("rel_error") != std::string::npos) CHECK(r.stats.samples < budget * 9 / 10);  // 70 % measured
        else if (c.xml == pixels) CHECK(std::abs(double(r.stats.samples) / double(budget) - 0.5) < 0.01);  // mean_share
        else CHECK(r.stats.samples == budget);
    }
}
