// Phase suite, distribution: sample() against pdf() by chi-square, and pdf() integrating
// to 1 over the sphere.
//
// A (φ, cos θ) grid about a fixed axis cannot see the lobe of a strongly peaked phase
// function: Henyey–Greenstein with g = 0.99 keeps half its mass within 1° of the
// forward direction, inside one band of a uniform cos θ grid. The grid here is about the
// forward axis −wo, and its cos θ band edges are quantiles of cos θ in a pilot run of
// sample() (independent of the tested samples, so the grid is fixed given the pilot and
// the test keeps its level), which spreads the samples evenly over the bands however
// narrow the lobe. Each band's cells are integrated by adaptive quadrature in (φ, cos θ),
// whose area element is the solid angle.
#include "conformance/histogram.hpp"
#include "conformance/media_common.hpp"
#include "effigi/math/frame.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace effigi::conform::media {

namespace {

constexpr double TwoPi = 2.0 * std::numbers::pi;

/// (φ, μ = cos θ) about the forward axis −wo, in double.
struct Chart {
    Frame frame;
    explicit Chart(const Vector3f& wo) : frame(normalize(-wo)) {}

    bool coords(const Vector3f& wi, double& phi, double& mu) const {
        Vector3d w(wi);
        const double l = std::sqrt(dot(w, w));
        if (!(l > 0.0) || !std::isfinite(l)) return false;
        w /= l;
        mu = std::clamp(dot(w, Vector3d(frame.n)), -1.0, 1.0);
        phi = std::atan2(dot(w, Vector3d(frame.t)), dot(w, Vector3d(frame.s)));
        if (phi < 0.0) phi += TwoPi;
        return true;
    }
    Vector3f direction(double phi, double mu) const {
        const double s = std::sqrt(std::max(0.0, (1.0 - mu) * (1.0 + mu)));
        return Vector3f(Vector3d(frame.s) * (s * std::cos(phi)) + Vector3d(frame.t) * (s * std::sin(phi)) +
                        Vector3d(frame.n) * mu);
    }
};

/// Band edges −1 = e0 < e1 < ... < e_bands = 1 at the pilot's cos θ quantiles.
std::vector<double> bandEdges(const IPhaseFunction& p, const Vector3f& wo, const SampledWavelengths& lambda,
                              const Chart& chart, PCG32& rng, int bands, std::uint64_t pilot) {
    std::vector<double> mus;
    for (std::uint64_t i = 0; i < pilot; ++i) {
        auto s = p.sample(wo, Point2f(rng.nextFloat(), rng.nextFloat()), lambda);
        double phi, mu;
        if (s && chart.coords(s->wi, phi, mu)) mus.push_back(mu);
    }
    std::sort(mus.begin(), mus.end());
    std::vector<double> edges(std::size_t(bands) + 1);
    edges.front() = -1.0;
    edges.back() = 1.0;
    // Strictly increasing, whatever the pilot gave (a sampler stuck on one direction).
    constexpr double Gap = 1e-9;
    for (int k = 1; k < bands; ++k) {
        double q = mus.empty() ? -1.0 + 2.0 * k / bands : mus[std::size_t(k) * mus.size() / std::size_t(bands)];
        edges[std::size_t(k)] = std::clamp(q, edges[std::size_t(k) - 1] + Gap, 1.0 - (bands - k) * Gap);
    }
    return edges;
}

} // namespace

void checkPhaseDistribution(Target& t, const IPhaseFunction& p) {
    const int nx = t.quick() ? 20 : 40, bands = t.quick() ? 10 : 20;
    const std::uint64_t n = t.count(1000000, 100000), pilot = t.count(40000, 10000);
    // Cell quadrature to 1e-4 of an average cell's probability: far below the Poisson
    // noise of its expected count.
    const double tolerance = 1e-4 / (nx * bands);
    double worstIntegral = 0.0;
    std::string integralDetail;
    for (const Vector3f& wo : conditioningDirections(t)) {
        const std::string name = "chi-square wo = " + vec(wo);
        PCG32 rng = t.rng(name);
        const SampledWavelengths lambda = SampledWavelengths::sampleUniform(rng.nextFloat());
        const Chart chart(wo);
        const std::vector<double> edges = bandEdges(p, wo, lambda, chart, rng, bands, pilot);

        std::vector<double> observed(std::size_t(nx * bands), 0.0);
        double outside = 0.0;
        for (std::uint64_t i = 0; i < n; ++i) {
            auto s = p.sample(wo, Point2f(rng.nextFloat(), rng.nextFloat()), lambda);
            double phi, mu;
            if (!s || !(s->pdf > 0.f) || !chart.coords(s->wi, phi, mu)) {
                outside += 1.0;
                continue;
            }
            int band = int(std::upper_bound(edges.begin(), edges.end(), mu) - edges.begin()) - 1;
            band = std::clamp(band, 0, bands - 1);
            int cell = std::min(nx - 1, int(phi / TwoPi * nx));
            observed[std::size_t(band * nx + cell)] += 1.0;
        }
        std::vector<double> cells;
        cells.reserve(observed.size());
        for (int k = 0; k < bands; ++k) {
            Grid2D band{0.0, TwoPi, edges[std::size_t(k)], edges[std::size_t(k) + 1], nx, 1, "phi", "cos theta"};
            auto row = integrateCells(
                band, [&](double phi, double mu) { return double(p.pdf(wo, chart.direction(phi, mu), lambda)); },
                tolerance);
            cells.insert(cells.end(), row.begin(), row.end());
        }
        const Grid2D grid{0.0, TwoPi, 0.0, 1.0, nx, bands, "phi", "cos theta quantile band"};
        FitResult fit = chiSquareFit(grid, observed, outside, cells, double(n));
        t.test(name, fit.chi2.pValue, fmt::format("p = {:.3g}", fit.chi2.pValue),
               fmt::format("{} samples, cos θ about −wo in {} bands at quantiles of a pilot run ({:.6g} … {:.6g}); {}",
                           n, bands, edges[1], edges[std::size_t(bands) - 1], fit.summary()),
               fit.histogram);
        const double err = std::abs(fit.densityIntegral - 1.0);
        if (!(err <= worstIntegral)) {
            worstIntegral = std::isnan(err) ? 1e9 : err;
            integralDetail = fmt::format("worst at wo = {}: ∫pdf = {:.6f}", vec(wo), fit.densityIntegral);
        }
    }
    // The quadrature is accurate to ~1e-4 in total; 1e-3 is the tolerance.
    t.expect("pdf integral", worstIntegral <= 1e-3, fmt::format("max |∫pdf − 1| = {:.2g}", worstIntegral),
             integralDetail + " (cell quadrature over the sphere, tolerance 1e-3)");
}

} // namespace effigi::conform::media
