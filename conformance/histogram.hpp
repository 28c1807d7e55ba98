#pragma once
// Chi-square goodness of fit of a sampling routine against its density, shared by the
// BSDF and warp suites: a grid of cells over a 2D parameterisation of the domain, the
// expected count of each cell by integrating the density over it (nested adaptive
// Simpson quadrature), the observed counts, and the images drawn when a test fails.
#include "conformance/conformance.hpp"
#include "effigi/math/stats.hpp"
#include "effigi/math/vector.hpp"

#include <functional>

namespace effigi::conform {

/// The rectangle [x0, x1] × [y0, y1] split into nx × ny equal cells; points outside
/// belong to no cell. For directions the rectangle is (φ, cos θ) ∈ [0, 2π] × [−1, 1],
/// whose area element dφ d(cos θ) is the solid angle, so a density per steradian
/// integrates over cells without a Jacobian.
struct Grid2D {
    double x0 = 0.0, x1 = 1.0, y0 = 0.0, y1 = 1.0;
    int nx = 1, ny = 1;
    std::string xLabel = "x", yLabel = "y";

    int cells() const { return nx * ny; }
    /// Cell index of (x, y), or −1 outside. The upper edges belong to the last cells.
    int cellOf(double x, double y) const;
    double cellWidth() const { return (x1 - x0) / nx; }
    double cellHeight() const { return (y1 - y0) / ny; }
};

/// The (φ, cos θ) grid over the whole sphere of directions.
Grid2D sphereGrid(int nPhi, int nCosTheta);
/// (φ, cos θ) coordinates of a unit vector.
void sphericalCoordinates(const Vector3f& w, double& phi, double& cosTheta);
/// The unit vector at (φ, cos θ).
Vector3f sphericalDirection(double phi, double cosTheta);

/// ∫ g over each cell by adaptive Simpson quadrature (outer over y, inner over x), to an
/// absolute accuracy of about `tolerance` per cell; each 1D rule is refined at least
/// minDepth and at most maxDepth times (depth 20 places a step to 1e-6 of the cell).
std::vector<double> integrateCells(const Grid2D& grid, const std::function<double(double, double)>& g,
                                   double tolerance, int minDepth = 2, int maxDepth = 20);

/// Outcome of comparing sampled counts with integrated densities.
struct FitResult {
    stats::ChiSquareResult chi2;
    double densityIntegral = 0.0;        ///< Σ of the cells' integrals
    std::shared_ptr<Histogram> histogram;
    std::string summary() const;
};

/// Chi-square test of `observed` counts (one per grid cell, plus `outside` for samples
/// that landed in no cell: absorbed, delta, out of the domain) from n draws against the
/// expectation n ∫cell pdf; the outside cell expects n (1 − Σ ∫cell pdf).
FitResult chiSquareFit(const Grid2D& grid, const std::vector<double>& observed, double outside,
                       const std::vector<double>& cellIntegrals, double n);

/// Write the observed and expected histograms as PNG images `<stem>-observed.png` and
/// `<stem>-expected.png` (same colour scale; x to the right, y up) and return their paths.
std::vector<std::string> writeHistogramImages(const Histogram& h, const std::filesystem::path& stem);

/// Bonferroni combination of k p-values of one check into one: min(1, k · min p). Keeps
/// one row per check (and one test in the Šidák count) however many sub-tests it ran.
double combinePValues(const std::vector<double>& p);

/// One-sided test of H0: mean <= bound, from an estimate with standard error se:
/// p = 1 − Φ((mean − bound) / se); with se = 0 the verdict is exact (0 or 1).
double upperBoundPValue(double mean, double se, double bound);

/// Running mean and variance (Welford).
struct MeanVar {
    double n = 0.0, mean = 0.0, m2 = 0.0;
    void add(double x) {
        n += 1.0;
        double d = x - mean;
        mean += d / n;
        m2 += d * (x - mean);
    }
    double variance() const { return n > 1.0 ? m2 / (n - 1.0) : 0.0; }
    /// Standard error of the mean.
    double stderror() const { return n > 1.0 ? std::sqrt(variance() / n) : 0.0; }
};

} // namespace effigi::conform
