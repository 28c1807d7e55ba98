// Near-delta lobes (pdf above MaxHistogramPdf, e.g. GGX α = 1e-4): a (φ, cos θ) grid over
// the whole sphere puts such a lobe into one cell, so sample() is instead compared with
// pdf() on a chart centred on the lobe. The chart's coordinates are the azimuth φ' about
// the lobe's centre c and y = √(1 − c·wi) (proportional to the angle from c, so cells
// are finer where the lobe peaks); its area element is dω = 2y dy dφ'. 1 − c·wi is
// computed as |c × wi|² / (1 + c·wi), which keeps its relative precision at the small
// angles where 1 − c·wi in float would be all rounding error.
//
// One chart per side of the surface that holds a narrow lobe (reflection, transmission):
// its centre is the pilot sample of highest density on that side, its radius covers the
// pilot samples whose density is at least 1e-3 of that peak (97 % of a GGX lobe's mass,
// > 99.9 % of a Beckmann lobe's). Samples outside the chart, absorbed or in delta lobes
// form the outside cell, whose expected count is 1 − ∫chart pdf.
#include "conformance/bsdf_common.hpp"
#include "conformance/histogram.hpp"

#include <algorithm>
#include <array>

namespace effigi::conform::bsdf {

namespace {

struct Chart {
    Vector3d c, t1, t2;  // centre and a frame about it
    double yMax = 0.0;

    /// (φ', y) of a direction, false if it lies in the hemisphere opposite c.
    bool coordinates(const Vector3f& wf, double& phi, double& y) const {
        Vector3d w = glm::normalize(Vector3d(wf));
        double cosT = glm::dot(c, w);
        if (!(cosT > 0.0)) return false;
        Vector3d x = glm::cross(c, w);
        y = std::sqrt(glm::dot(x, x) / (1.0 + cosT));
        phi = std::atan2(glm::dot(w, t2), glm::dot(w, t1));
        if (phi < 0.0) phi += 2.0 * Pi;
        return true;
    }
    Vector3f direction(double phi, double y) const {
        double s = y * y, cosT = 1.0 - s, sinT = std::sqrt(std::max(0.0, s * (2.0 - s)));
        return Vector3f(glm::normalize(cosT * c + sinT * (std::cos(phi) * t1 + std::sin(phi) * t2)));
    }
};

Chart makeChart(const Vector3f& centre) {
    Chart ch;
    ch.c = glm::normalize(Vector3d(centre));
    Vector3d a = std::abs(ch.c.z) < 0.9 ? Vector3d(0, 0, 1) : Vector3d(1, 0, 0);
    ch.t1 = glm::normalize(glm::cross(a, ch.c));
    ch.t2 = glm::cross(ch.c, ch.t1);
    return ch;
}

struct Draw {
    Vector3f wi;
    double pdf;
};

std::optional<Draw> draw(const IBSDF& b, const SurfaceInteraction& si, const Vector3f& wo, PCG32& rng, float lambda) {
    SampledWavelengths l = SampledWavelengths::constant(lambda);
    auto bs = b.sample(si, wo, rng.nextFloat(), Point2f(rng.nextFloat(), rng.nextFloat()), l, TransportMode::Radiance);
    if (!bs || !(bs->pdf > 0.f) || bs->isSpecular()) return std::nullopt;
    return Draw{bs->wi, double(bs->pdf)};
}

} // namespace

void checkNarrowLobes(Target& t, const IBSDF& b, const SurfaceInteraction& si, const Vector3f& wo,
                      const std::string& name, std::uint64_t n) {
    const float lambda = 550.f;
    // Pilot samples (their own stream): where the lobes are and how wide.
    std::array<std::vector<Draw>, 2> side;  // 0: wi on wo's side, 1: the other side
    const std::uint64_t pilotCount = std::max<std::uint64_t>(n / 10, 20000);
    PCG32 pilot = t.rng(name + " pilot");
    for (std::uint64_t i = 0; i < pilotCount; ++i)
        if (auto d = draw(b, si, wo, pilot, lambda)) side[d->wi.z * wo.z > 0.f ? 0 : 1].push_back(*d);
    bool any = false;
    for (int s = 0; s < 2; ++s) {
        auto& draws = side[std::size_t(s)];
        if (draws.size() < pilotCount / 100) continue;  // under 1 % of the samples: nothing to chart
        const Draw& peak = *std::max_element(draws.begin(), draws.end(),
                                             [](const Draw& a, const Draw& c) { return a.pdf < c.pdf; });
        if (!(peak.pdf > MaxHistogramPdf)) continue;  // a wide lobe on this side: the sphere grid's business
        Chart chart = makeChart(peak.wi);
        for (const Draw& d : draws) {
            double phi, y;
            if (d.pdf >= 1e-3 * peak.pdf && chart.coordinates(d.wi, phi, y)) chart.yMax = std::max(chart.yMax, y);
        }
        chart.yMax = std::min(1.0, 1.2 * chart.yMax);
        if (!(chart.yMax > 0.0)) continue;
        any = true;

        Grid2D grid;
        grid.x1 = 2.0 * Pi;
        grid.y1 = chart.yMax;
        grid.nx = t.quick() ? 12 : 24;
        grid.ny = t.quick() ? 8 : 16;
        grid.xLabel = "phi about the lobe";
        grid.yLabel = "sqrt(1 - cos)";
        const std::string check = name + (s == 0 ? " (lobe chart, same side)" : " (lobe chart, other side)");
        PCG32 rng = t.rng(check);
        std::vector<double> observed(std::size_t(grid.cells()), 0.0);
        double outside = 0.0;
        for (std::uint64_t i = 0; i < n; ++i) {
            auto d = draw(b, si, wo, rng, lambda);
            double phi, y;
            int c = d && chart.coordinates(d->wi, phi, y) ? grid.cellOf(phi, y) : -1;
            if (c < 0) outside += 1.0;
            else observed[std::size_t(c)] += 1.0;
        }
        SampledWavelengths l = SampledWavelengths::constant(lambda);
        std::vector<double> cells = integrateCells(
            grid,
            [&](double phi, double y) {
                return double(b.pdf(si, wo, chart.direction(phi, y), l, TransportMode::Radiance)) * 2.0 * y;
            },
            1e-4 / grid.cells());
        FitResult fit = chiSquareFit(grid, observed, outside, cells, double(n));
        t.test(check, fit.chi2.pValue, fmt::format("p = {:.3g}", fit.chi2.pValue),
               fmt::format("{} samples; peak pdf {:.3g} sr⁻¹ at {}, chart radius {:.3g} rad; {}", n, peak.pdf,
                           vec(peak.wi), 2.0 * std::asin(std::min(1.0, chart.yMax / std::sqrt(2.0))), fit.summary()),
               fit.histogram);
    }
    if (!any)
        t.skip(name, "pdf above the sphere grid's resolution, but no lobe holding 1 % of the samples to chart");
}

} // namespace effigi::conform::bsdf
