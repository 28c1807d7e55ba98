// Warp suite: sample() against pdf() by chi-square, pdf() integrating to 1 over the
// domain, inverse(sample(u)) = u where an inverse exists, points inside the domain, and
// finite results for inputs on the boundary of the square.
#include "conformance/histogram.hpp"
#include "effigi/interfaces/iwarp.hpp"

#include <fmt/format.h>

namespace effigi::conform {

namespace {

struct DomainMap {
    WarpDomain domain;
    Grid2D grid;

    bool sphere() const { return domain.kind == WarpDomain::Kind::Sphere; }
    void coords(const Vector3f& p, double& x, double& y) const {
        if (sphere()) sphericalCoordinates(p, x, y);
        else {
            x = p.x;
            y = p.y;
        }
    }
    Vector3f point(double x, double y) const {
        return sphere() ? sphericalDirection(x, y) : Vector3f(float(x), float(y), 0.f);
    }
    /// Where a sampled point violates the domain, or "".
    std::string violation(const Vector3f& p) const {
        if (!isFinite(p)) return "not finite";
        if (sphere()) return std::abs(length(p) - 1.f) <= 1e-4f ? "" : fmt::format("|p| = {} (not a unit vector)", length(p));
        if (p.z != 0.f) return fmt::format("z = {} (planar points have z = 0)", p.z);
        if (p.x < domain.lower.x || p.y < domain.lower.y || p.x > domain.upper.x || p.y > domain.upper.y)
            return "outside the domain's bounds";
        return "";
    }
};

std::string str(const Vector3f& p) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", p.x, p.y, p.z); }

void checkDistribution(Target& t, const IWarp& w, const DomainMap& m) {
    PCG32 rng = t.rng("chi-square");
    const std::uint64_t n = t.count(1000000, 100000);
    std::vector<double> observed(std::size_t(m.grid.cells()), 0.0);
    double outside = 0.0;
    for (std::uint64_t i = 0; i < n; ++i) {
        Vector3f p = w.sample(Point2f(rng.nextFloat(), rng.nextFloat()));
        double x, y;
        m.coords(p, x, y);
        int c = isFinite(p) ? m.grid.cellOf(x, y) : -1;
        if (c < 0) outside += 1.0;
        else observed[std::size_t(c)] += 1.0;
    }
    std::vector<double> cells = integrateCells(
        m.grid, [&](double x, double y) { return double(w.pdf(m.point(x, y))); }, 1e-6 / m.grid.cells());
    FitResult fit = chiSquareFit(m.grid, observed, outside, cells, double(n));
    t.test("chi-square", fit.chi2.pValue, fmt::format("p = {:.3g}", fit.chi2.pValue),
           fmt::format("{} samples over {}; {}", n, m.domain.description, fit.summary()), fit.histogram);
    // The cell quadrature is accurate to ~1e-4 in total; 1e-3 is the tolerance.
    double integral = fit.densityIntegral;
    t.expect("pdf integral", std::abs(integral - 1.0) <= 1e-3, fmt::format("∫pdf = {:.5f}", integral),
             fmt::format("over the {}×{} cells covering the domain (tolerance 1e-3)", m.grid.nx, m.grid.ny));
}

void checkDomain(Target& t, const IWarp& w, const DomainMap& m) {
    PCG32 rng = t.rng("in domain");
    const std::uint64_t n = t.count(100000, 20000);
    std::uint64_t bad = 0;
    std::string first;
    for (std::uint64_t i = 0; i < n; ++i) {
        Point2f u(rng.nextFloat(), rng.nextFloat());
        Vector3f p = w.sample(u);
        std::string v = m.violation(p);
        float pdf = w.pdf(p);
        if (v.empty() && !(pdf > 0.f && std::isfinite(pdf))) v = fmt::format("pdf = {} at a sampled point", pdf);
        if (!v.empty() && bad++ == 0) first = fmt::format("u = ({}, {}) -> {}: {}", u.x, u.y, str(p), v);
    }
    t.expect("in domain", bad == 0, fmt::format("{} bad of {}", bad, n),
             bad ? "first: " + first : "sampled points lie in " + m.domain.description + " with a positive, finite pdf");
}

void checkBoundary(Target& t, const IWarp& w, const DomainMap& m) {
    const float edges[] = {0.f, 1e-7f, 0.5f, 1.f - 1e-7f, OneMinusEpsilon};
    std::uint64_t bad = 0, checked = 0;
    std::string first;
    auto note = [&](const std::string& s) {
        if (bad++ == 0) first = s;
    };
    for (float a : edges)
        for (float b : edges) {
            ++checked;
            Point2f u(a, b);
            Vector3f p = w.sample(u);
            std::string v = m.violation(p);
            float pdf = w.pdf(p);
            if (!v.empty()) note(fmt::format("sample({}, {}) = {}: {}", a, b, str(p), v));
            else if (!(pdf >= 0.f) || !std::isfinite(pdf)) note(fmt::format("pdf(sample({}, {})) = {}", a, b, pdf));
            else if (w.hasInverse()) {
                Point2f back = w.inverse(p);
                if (!(back.x >= 0.f && back.x <= 1.f && back.y >= 0.f && back.y <= 1.f))
                    note(fmt::format("inverse(sample({}, {})) = ({}, {}) outside [0,1]²", a, b, back.x, back.y));
            }
        }
    t.expect("boundary", bad == 0, fmt::format("{} bad of {}", bad, checked),
             bad ? "first: " + first : "u in {0, 1e-7, 0.5, 1−1e-7, 1−ε}²: finite points, pdf and inverse");
}

void checkInverse(Target& t, const IWarp& w) {
    if (!w.hasInverse()) {
        t.skip("inverse", "the warp has no inverse (hasInverse() is false)");
        return;
    }
    PCG32 rng = t.rng("inverse");
    const std::uint64_t n = t.count(200000, 20000);
    // Float maps lose a few ulps each way; 1e-3 of the unit square is a thousand times
    // that and far below any real mistake (a wrong quadrant, a swapped coordinate).
    constexpr float Tolerance = 1e-3f;
    double worst = 0.0;
    std::uint64_t bad = 0, seams = 0;
    std::string first;
    for (std::uint64_t i = 0; i < n; ++i) {
        Point2f u(rng.nextFloat(), rng.nextFloat());
        Vector3f p = w.sample(u);
        Point2f back = w.inverse(p);
        float err = std::max(std::abs(back.x - u.x), std::abs(back.y - u.y));
        if (!(err <= Tolerance)) {
            // Where the map is not one-to-one (a seam of φ, a pole) another input gives the
            // same point; that input is an inverse too.
            Vector3f again = w.sample(back);
            if (isFinite(again) && length(again - p) <= 1e-4f) {
                ++seams;
                continue;
            }
            if (bad++ == 0)
                first = fmt::format("u = ({}, {}) -> {} -> ({}, {})", u.x, u.y, str(p), back.x, back.y);
        }
        worst = std::max(worst, std::isnan(err) ? 1e9 : double(err));
    }
    t.expect("inverse", bad == 0, fmt::format("max |u' − u| = {:.2g}", worst),
             fmt::format("{} inputs, {} bad (tolerance {}), {} on seams where another input maps to the same point{}", n,
                         bad, Tolerance, seams, bad ? "; first: " + first : ""));
}

void runWarpSuite(Target& t) {
    Ref<IWarp> w = t.as<IWarp>();
    if (!w) {
        t.expect("interface", false, "-", "component does not implement IWarp");
        return;
    }
    if (w->inputDimension() != 2) {
        t.skip("warp", fmt::format("input dimension {}: the suite checks 2D warps", w->inputDimension()));
        return;
    }
    DomainMap m{w->domain(), {}};
    if (m.sphere()) {
        m.grid = t.quick() ? sphereGrid(20, 10) : sphereGrid(40, 20);
    } else {
        if (!(m.domain.upper.x > m.domain.lower.x && m.domain.upper.y > m.domain.lower.y)) {
            t.expect("domain", false, "-", "planar domain with an empty bounding box");
            return;
        }
        int k = t.quick() ? 20 : 40;
        m.grid = Grid2D{m.domain.lower.x, m.domain.upper.x, m.domain.lower.y, m.domain.upper.y, k, k, "x", "y"};
    }
    checkDistribution(t, *w, m);
    checkDomain(t, *w, m);
    checkBoundary(t, *w, m);
    checkInverse(t, *w);
}

} // namespace

} // namespace effigi::conform

EFFIGI_CONFORMANCE_SUITE("warp", "chi-square of sample() against pdf(), pdf integral, inverse, domain, boundary inputs",
                         effigi::conform::runWarpSuite);
