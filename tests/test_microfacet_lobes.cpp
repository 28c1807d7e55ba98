// A chi-square test of near-specular lobes of the rough BSDFs (α = 1e-4, η = 1.0001) in a
// chart zoomed onto the lobe, which effigi-conform's whole-sphere histogram cannot
// resolve (its pdf reaches 1e7–3e8 sr⁻¹ there). Seeded; the significance level is stated.
#include "bsdf_helpers.hpp"

#include "effigi/math/frame.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/math/stats.hpp"
#include "effigi/render/microfacet.hpp"

#include <catch2/catch.hpp>

using namespace effigi;
using namespace effigi::test;

namespace {

const SurfaceInteraction NoSi{};  // the BSDFs under test ignore the interaction

/// Chi-square test of sample() against pdf() in the gnomonic chart (x, y) = (wi·t1, wi·t2)
/// / (wi·c) about the lobe's centre c, on a grid fitted to the lobe; the density there is
/// pdf(wi) (wi·c)³. Samples outside the window, in another lobe or absorbed go to one more
/// cell expecting n (1 − Σ ∫cell). Cell integrals by 4×4 Gauss–Legendre on 4×4 sub-cells.
stats::ChiSquareResult zoomedChiSquare(const IBSDF& b, const Vector3f& wo, const Vector3f& centre, PCG32& rng,
                                       int n = 200000, int cells = 16) {
    Frame frame(centre);
    auto chart = [&](const Vector3f& wi, double& x, double& y) {
        Vector3d l = Vector3d(frame.toLocal(wi));
        if (!(l.z > 0.0)) return false;
        x = l.x / l.z;
        y = l.y / l.z;
        return true;
    };
    std::vector<Vector3f> samples;
    std::vector<double> extent;
    for (int i = 0; i < n; ++i) {
        SampledWavelengths l = SampledWavelengths::constant(550.f);
        auto bs = b.sample(NoSi, wo, rng.nextFloat(), {rng.nextFloat(), rng.nextFloat()}, l, TransportMode::Radiance);
        if (!bs) continue;
        samples.push_back(bs->wi);
        double x, y;
        if (chart(bs->wi, x, y) && std::max(std::abs(x), std::abs(y)) < 0.1)
            extent.push_back(std::max(std::abs(x), std::abs(y)));
    }
    // The window holds about 95 % of the samples within 0.1 rad of the centre (the lobe;
    // the other lobe and far tails lie beyond).
    std::sort(extent.begin(), extent.end());
    REQUIRE(extent.size() > 1000);
    double w = extent[std::size_t(0.95 * double(extent.size()))];
    std::vector<double> observed(std::size_t(cells * cells + 1), 0.0), expected(observed.size(), 0.0);
    for (const Vector3f& wi : samples) {
        double x, y;
        std::size_t c = observed.size() - 1;
        if (chart(wi, x, y) && std::abs(x) < w && std::abs(y) < w)
            c = std::size_t(std::min(cells - 1, int((y + w) / (2 * w) * cells))) * cells +
                std::size_t(std::min(cells - 1, int((x + w) / (2 * w) * cells)));
        observed[c] += 1.0;
    }
    observed.back() += double(n - int(samples.size()));
    const double gx[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
    const double gw[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
    const int sub = 4;
    double h = 2 * w / (cells * sub), total = 0.0;
    for (int cy = 0; cy < cells; ++cy)
        for (int cx = 0; cx < cells; ++cx) {
            double sum = 0.0;
            for (int sy = 0; sy < sub; ++sy)
                for (int sx = 0; sx < sub; ++sx)
                    for (int i = 0; i < 4; ++i)
                        for (int j = 0; j < 4; ++j) {
                            double x = -w + (cx * sub + sx + 0.5 + 0.5 * gx[i]) * h;
                            double y = -w + (cy * sub + sy + 0.5 + 0.5 * gx[j]) * h;
                            double r2 = 1.0 + x * x + y * y;
                            Vector3f wi = normalize(frame.toWorld(Vector3f(float(x), float(y), 1.f)));
                            SampledWavelengths l = SampledWavelengths::constant(550.f);
                            double p = b.pdf(NoSi, wo, wi, l, TransportMode::Radiance);
                            sum += gw[i] * gw[j] * 0.25 * h * h * p / (r2 * std::sqrt(r2));
                        }
            expected[std::size_t(cy * cells + cx)] = sum * n;
            total += sum;
        }
    expected.back() = std::max(0.0, 1.0 - total) * n;
    return stats::chiSquareTest(observed, expected);
}

} // namespace

TEST_CASE("near-specular lobes follow pdf() in a chart zoomed onto them (chi-square)", "[microfacet][bsdf]") {
    // effigi-conform skips lobes narrower than its whole-sphere histogram (pdf > 1000
    // sr⁻¹); here each lobe gets its own 16 × 16 grid. 200k samples per test, 8 tests,
    // each at significance 1e-3 (Bonferroni: 0.8 % for the family).
    PCG32 rng(42, 7);
    struct Case {
        std::string what;
        Ref<IBSDF> b;
        Vector3f wo, centre;
    };
    std::vector<Case> cases;
    for (const char* dist : {"ggx", "beckmann"}) {
        Vector3f wo = directionFromCos(0.5f);
        cases.push_back({std::string(dist) + " roughconductor 1e-4",
                         makeBSDF("roughconductor", {{"distribution", std::string(dist)}, {"alpha", 1e-4}}), wo,
                         reflectLocal(wo)});
        Ref<IBSDF> glass = makeBSDF("roughdielectric", {{"distribution", std::string(dist)}, {"alpha", 1e-4}});
        cases.push_back({std::string(dist) + " roughdielectric 1e-4 reflection", glass, directionFromCos(0.3f), reflectLocal(directionFromCos(0.3f))});
        Vector3f wt = directionFromCos(0.8f, 0.7f, -1.f);
        cases.push_back({std::string(dist) + " roughdielectric 1e-4 refraction from inside", glass, wt,
                         smoothRefraction(wt, 1.5046f / 1.000277f)});
        Ref<IBSDF> matched = makeBSDF("roughdielectric", {{"distribution", std::string(dist)}, {"alpha", 0.3},
                                                          {"int_ior", 1.0001}, {"ext_ior", 1.0}});
        cases.push_back({std::string(dist) + " roughdielectric 0.3, eta 1.0001, refraction", matched, directionFromCos(0.6f),
                         smoothRefraction(directionFromCos(0.6f), 1.0001f)});
    }
    for (const Case& c : cases) {
        stats::ChiSquareResult r = zoomedChiSquare(*c.b, c.wo, c.centre, rng);
        INFO(c.what << ": " << r.summary());
        CHECK(r.passes(1e-3));
        CHECK(r.cells > 100);  // the grid did resolve the lobe
    }
}

