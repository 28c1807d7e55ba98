// Grids, cell integrals, the chi-square fit with its outside cell, and histogram images.
#include "conformance/histogram.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace effigi::conform {

int Grid2D::cellOf(double x, double y) const {
    if (!(x >= x0 && x <= x1 && y >= y0 && y <= y1)) return -1;
    int i = std::min(nx - 1, int((x - x0) / (x1 - x0) * nx));
    int j = std::min(ny - 1, int((y - y0) / (y1 - y0) * ny));
    return j * nx + i;
}

Grid2D sphereGrid(int nPhi, int nCosTheta) {
    Grid2D g;
    g.x0 = 0.0;
    g.x1 = 2.0 * std::numbers::pi;
    g.y0 = -1.0;
    g.y1 = 1.0;
    g.nx = nPhi;
    g.ny = nCosTheta;
    g.xLabel = "phi";
    g.yLabel = "cos theta";
    return g;
}

void sphericalCoordinates(const Vector3f& w, double& phi, double& cosTheta) {
    cosTheta = std::clamp(double(w.z), -1.0, 1.0);
    phi = std::atan2(double(w.y), double(w.x));
    if (phi < 0.0) phi += 2.0 * std::numbers::pi;
}

Vector3f sphericalDirection(double phi, double cosTheta) {
    double s = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
    return Vector3f(float(s * std::cos(phi)), float(s * std::sin(phi)), float(cosTheta));
}

namespace {

/// Adaptive Simpson on [a, b] given f at a, the midpoint and b and the whole-interval
/// estimate; Richardson-corrected result (Lyness 1969, "Notes on the adaptive Simpson
/// quadrature routine", J. ACM 16(3)). `budget` caps the evaluations: past it intervals
/// are accepted as they are, so a noisy or pathological density cannot stall the run.
template <typename F>
double simpson(F& f, double a, double b, double fa, double fm, double fb, double whole, double eps, int depth,
               int minDepth, int maxDepth, int& budget) {
    double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
    double flm = f(lm), frm = f(rm);
    budget -= 2;
    double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
    double right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    double delta = left + right - whole;
    if (depth >= maxDepth || budget <= 0 || (depth >= minDepth && std::abs(delta) <= 15.0 * eps) ||
        !std::isfinite(delta))
        return left + right + delta / 15.0;
    return simpson(f, a, m, fa, flm, fm, left, 0.5 * eps, depth + 1, minDepth, maxDepth, budget) +
           simpson(f, m, b, fm, frm, fb, right, 0.5 * eps, depth + 1, minDepth, maxDepth, budget);
}

template <typename F>
double adaptiveSimpson(F&& f, double a, double b, double eps, int minDepth, int maxDepth, int budget) {
    double fa = f(a), fm = f(0.5 * (a + b)), fb = f(b);
    double whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    return simpson(f, a, b, fa, fm, fb, whole, eps, 0, minDepth, maxDepth, budget);
}

} // namespace

std::vector<double> integrateCells(const Grid2D& grid, const std::function<double(double, double)>& g,
                                   double tolerance, int minDepth, int maxDepth) {
    // Evaluations per 1D integral: a few hundred for smooth densities, a few thousand
    // along a discontinuity or a narrow peak; the cap only stops runaway refinement.
    constexpr int Budget = 4000;
    std::vector<double> out(std::size_t(grid.cells()), 0.0);
    const double w = grid.cellWidth(), h = grid.cellHeight();
    for (int j = 0; j < grid.ny; ++j) {
        double ya = grid.y0 + j * h, yb = ya + h;
        for (int i = 0; i < grid.nx; ++i) {
            double xa = grid.x0 + i * w, xb = xa + w;
            // The inner integral's error is multiplied by the outer interval's length.
            auto inner = [&](double y) {
                return adaptiveSimpson([&](double x) { return g(x, y); }, xa, xb, 0.5 * tolerance / h, minDepth,
                                       maxDepth, Budget);
            };
            out[std::size_t(j * grid.nx + i)] =
                adaptiveSimpson(inner, ya, yb, 0.5 * tolerance, minDepth, maxDepth, Budget);
        }
    }
    return out;
}

std::string FitResult::summary() const {
    return fmt::format("chi2 = {:.1f}, dof = {}, {} cells ({} pooled), integral of pdf = {:.5f}{}", chi2.statistic,
                       chi2.dof, chi2.cells, chi2.pooledCells, densityIntegral,
                       chi2.impossibleSample ? ", samples where the pdf integrates to 0" : "");
}

FitResult chiSquareFit(const Grid2D& grid, const std::vector<double>& observed, double outside,
                       const std::vector<double>& cellIntegrals, double n) {
    FitResult r;
    auto h = std::make_shared<Histogram>();
    h->nx = grid.nx;
    h->ny = grid.ny;
    h->xLabel = grid.xLabel;
    h->yLabel = grid.yLabel;
    h->observed = observed;
    h->expected.resize(cellIntegrals.size());
    for (std::size_t i = 0; i < cellIntegrals.size(); ++i) {
        r.densityIntegral += cellIntegrals[i];
        h->expected[i] = std::max(0.0, cellIntegrals[i]) * n;
    }
    h->outsideObserved = outside;
    h->outsideExpected = std::max(0.0, 1.0 - r.densityIntegral) * n;
    // A density integrating to more than one predicts more samples than were drawn: the
    // statistic sees it through the inflated cells, but say so outright.
    std::vector<double> obs = h->observed, exp = h->expected;
    obs.push_back(h->outsideObserved);
    exp.push_back(h->outsideExpected);
    r.chi2 = stats::chiSquareTest(obs, exp);
    r.histogram = std::move(h);
    return r;
}

double combinePValues(const std::vector<double>& p) {
    if (p.empty()) return 1.0;
    double lo = 1.0;
    for (double x : p) lo = std::min(lo, std::isnan(x) ? 0.0 : x);
    return std::min(1.0, lo * double(p.size()));
}

double upperBoundPValue(double mean, double se, double bound) {
    if (!std::isfinite(mean)) return 0.0;
    if (!(se > 0.0)) return mean <= bound ? 1.0 : 0.0;
    return 1.0 - stats::normalCdf((mean - bound) / se);
}

namespace {

/// Colour ramp from dark blue through magenta and orange to pale yellow (own choice,
/// monotone in lightness so that counts read as brightness in grey-scale print too).
std::array<unsigned char, 3> ramp(double t) {
    static const double stops[5][3] = {
        {0.02, 0.02, 0.08}, {0.30, 0.07, 0.45}, {0.78, 0.22, 0.35}, {0.98, 0.58, 0.15}, {0.99, 0.98, 0.70}};
    t = std::clamp(t, 0.0, 1.0) * 4.0;
    int k = std::min(3, int(t));
    double f = t - k;
    std::array<unsigned char, 3> c;
    for (int i = 0; i < 3; ++i)
        c[std::size_t(i)] = static_cast<unsigned char>(255.0 * ((1 - f) * stops[k][i] + f * stops[k + 1][i]) + 0.5);
    return c;
}

void writePng(const std::filesystem::path& file, const std::vector<double>& cells, int nx, int ny, double scale) {
    const int px = std::clamp(640 / std::max(nx, 1), 1, 16), py = std::clamp(480 / std::max(ny, 1), 1, 16);
    const int w = nx * px, hgt = ny * py;
    std::vector<unsigned char> pixels(std::size_t(w) * std::size_t(hgt) * 3);
    for (int y = 0; y < hgt; ++y) {
        int j = ny - 1 - y / py;  // image rows go down, cells' y goes up
        for (int x = 0; x < w; ++x) {
            int i = x / px;
            auto c = ramp(scale > 0.0 ? cells[std::size_t(j * nx + i)] / scale : 0.0);
            std::copy(c.begin(), c.end(), pixels.begin() + (std::ptrdiff_t(y) * w + x) * 3);
        }
    }
    auto out = OIIO::ImageOutput::create(file.string());
    if (!out) fail("cannot create an image writer for {}", file.string());
    OIIO::ImageSpec spec(w, hgt, 3, OIIO::TypeDesc::UINT8);
    if (!out->open(file.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) || !out->close())
        fail("cannot write {}: {}", file.string(), out->geterror());
}

} // namespace

std::vector<std::string> writeHistogramImages(const Histogram& h, const std::filesystem::path& stem) {
    std::filesystem::create_directories(stem.parent_path().empty() ? std::filesystem::path(".") : stem.parent_path());
    double scale = 0.0;
    for (double v : h.observed) scale = std::max(scale, v);
    for (double v : h.expected) scale = std::max(scale, v);
    std::vector<std::string> files;
    for (const char* which : {"observed", "expected"}) {
        std::filesystem::path file = stem;
        file += std::string("-") + which + ".png";
        writePng(file, which[0] == 'o' ? h.observed : h.expected, h.nx, h.ny, scale);
        files.push_back(file.string());
    }
    return files;
}

} // namespace effigi::conform
