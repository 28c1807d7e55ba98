// BSDF suite: the distribution checks (sample() against pdf() by chi-square; pdf()
// integrating to the fraction of samples that are neither absorbed nor delta) and the
// suite's registration. The value and physics checks are in bsdf_values.cpp and
// bsdf_physics.cpp.
#include "conformance/bsdf_common.hpp"
#include "conformance/histogram.hpp"

namespace effigi::conform::bsdf {

void checkDistribution(Target& t, const IBSDF& b) {
    if (b.isPureSpecular()) return;  // nothing to histogram: the 'delta' check covers it
    const SurfaceInteraction si = probePoint();
    const std::vector<float> cosines =
        // From below at −0.8 a dielectric of η = 1.5 both reflects and refracts (at −0.6 it
        // reflects totally).
        t.quick() ? std::vector<float>{0.6f, -0.8f} : std::vector<float>{0.9f, 0.5f, 0.1f, -0.6f, -0.8f};
    const Grid2D grid = t.quick() ? sphereGrid(20, 10) : sphereGrid(40, 20);
    const std::uint64_t n = t.count(1000000, 100000);
    // Cell quadrature to 1e-4 of an average cell's probability: its error in an expected
    // count is then far below that count's Poisson noise.
    const double tolerance = 1e-4 / grid.cells();
    const float lambda = 550.f;
    double worstIntegral = 0.0, worstGap = 0.0, maxFraction = 0.0;
    bool integralOk = true, anyChecked = false;
    std::string integralDetail;
    for (float cosTheta : cosines) {
        const Vector3f wo = direction(cosTheta, 0.4f);
        const std::string name = fmt::format("chi-square cos θo = {}", cosTheta);
        PCG32 rng = t.rng(name);
        std::vector<double> observed(std::size_t(grid.cells()), 0.0);
        double outside = 0.0, maxPdf = 0.0;
        for (std::uint64_t i = 0; i < n; ++i) {
            SampledWavelengths l = SampledWavelengths::constant(lambda);
            auto bs = b.sample(si, wo, rng.nextFloat(), Point2f(rng.nextFloat(), rng.nextFloat()), l,
                               TransportMode::Radiance);
            if (!bs || !(bs->pdf > 0.f) || bs->isSpecular()) {
                outside += 1.0;
                continue;
            }
            maxPdf = std::max(maxPdf, double(bs->pdf));
            double phi, ct;
            sphericalCoordinates(bs->wi, phi, ct);
            int c = grid.cellOf(phi, ct);
            if (c < 0) outside += 1.0;
            else observed[std::size_t(c)] += 1.0;
        }
        if (maxPdf > MaxHistogramPdf) {  // too narrow for the sphere grid: a chart on the lobe
            checkNarrowLobes(t, b, si, wo, name, n);
            continue;
        }
        SampledWavelengths l = SampledWavelengths::constant(lambda);
        std::vector<double> cells = integrateCells(
            grid,
            [&](double phi, double ct) {
                return double(b.pdf(si, wo, sphericalDirection(phi, ct), l, TransportMode::Radiance));
            },
            tolerance);
        FitResult fit = chiSquareFit(grid, observed, outside, cells, double(n));
        t.test(name, fit.chi2.pValue, fmt::format("p = {:.3g}", fit.chi2.pValue),
               fmt::format("{} samples; {}", n, fit.summary()), fit.histogram);

        // pdf() must integrate to the fraction of samples it describes: those neither
        // absorbed nor in a delta lobe (1 for a BSDF that samples without loss). The
        // fraction's binomial noise allows 5 standard deviations; the quadrature 1e-3.
        double fraction = (double(n) - outside) / double(n);
        double gap = std::abs(fit.densityIntegral - fraction);
        double allowed = 1e-3 + 5.0 * std::sqrt(fraction * (1.0 - fraction) / double(n));
        anyChecked = true;
        if (fit.densityIntegral > worstIntegral) {
            worstIntegral = fit.densityIntegral;
            maxFraction = fraction;
        }
        worstGap = std::max(worstGap, gap);
        if (!(fit.densityIntegral <= 1.0 + 1e-3) || !(gap <= allowed)) {
            integralOk = false;
            if (integralDetail.empty())
                integralDetail = fmt::format("; at cos θo = {}: ∫pdf = {:.5f} but {:.5f} of the samples are "
                                             "non-delta (allowed gap {:.2g})",
                                             cosTheta, fit.densityIntegral, fraction, allowed);
        }
    }
    if (anyChecked)
        t.expect("pdf integral", integralOk, fmt::format("max ∫pdf {:.5f}", worstIntegral),
                 fmt::format("sampled fraction {:.5f} there; worst |∫pdf − fraction| = {:.2g}{}", maxFraction,
                             worstGap, integralDetail));
}

namespace {

void runBsdfSuite(Target& t) {
    Ref<IBSDF> b = t.as<IBSDF>();
    if (!b) {
        t.expect("interface", false, "-", "component does not implement IBSDF");
        return;
    }
    checkNonNegative(t, *b);
    checkStability(t, *b);
    checkSampleWeight(t, *b);
    checkReciprocity(t, *b);
    checkEnergy(t, *b);
    checkDelta(t, *b);
    // The chi-square tests are the costly part: --quick runs them on the declared
    // configurations only, the full run on the range ends too.
    if (!(t.quick() && t.rangeEnd())) checkDistribution(t, *b);
}

} // namespace

} // namespace effigi::conform::bsdf

EFFIGI_CONFORMANCE_SUITE("bsdf",
                         "non-negativity, stability, sample weight, reciprocity, energy conservation, delta lobes, "
                         "chi-square of sample() against pdf(), pdf integral",
                         effigi::conform::bsdf::runBsdfSuite, effigi::conform::RangeEnds::Probed);
