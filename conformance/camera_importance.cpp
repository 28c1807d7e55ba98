// Camera suite, importance (conformance/camera_suite.cpp's file comment): the importance
// over the directions from a lens point (per unit area across the viewing direction for an
// orthographic camera) against the density of generateRay's directions for film positions
// uniform over the full film, by chi-square over a chart of directions (gnomonic for
// projective cameras, the sphere for panoramas: camera_chart.hpp), and its integral.
#include "conformance/camera_chart.hpp"
#include "conformance/conformance.hpp"
#include "conformance/histogram.hpp"

#include <algorithm>
#include <cmath>

namespace effigi::conform {

namespace {
constexpr double Pi64 = 3.14159265358979323846;
} // namespace

/// Importance against the density of generateRay's directions (origins), by chi-square.
void checkImportance(Target& t, const CameraSetup& s) {
    const Point2f centre = 0.5f * s.full;
    SampledSpectrum w;
    Ray r0 = rayAt(s, centre, Point2f(0.5f), w);
    CameraImportanceSample c0;
    if (!s.imp->sampleDirection(r0(0.5f * r0.tMax), Point2f(0.5f), c0)) {
        t.expect("importance chi-square", false, "-", "the middle of the central ray does not connect");
        return;
    }
    const bool delta = c0.deltaDirection, around = !delta && s.around;
    const double dist0 = glm::length(local(s, r0(0.5f * r0.tMax)));
    const double depth0 = local(s, r0(0.5f * r0.tMax)).z;
    // Panoramas clip by distance from the eye, projective cameras by depth (the clip range
    // check): the density is probed at points of the middle ray's distance or depth.
    const Ray rk = rayAt(s, Point2f(0.f), Point2f(0.5f), w);
    const double nearClip = glm::length(local(s, r0.o)), ok = glm::length(local(s, rk.o));
    const bool distanceClip = std::abs(ok - nearClip) < std::abs(local(s, rk.o).z - nearClip);
    // A second lens sample only where the lens sample moves the ray.
    std::vector<Point2f> lenses = {Point2f(0.5f)};
    if (rayAt(s, centre, Point2f(0.85f, 0.2f), w).o != r0.o) lenses.emplace_back(0.85f, 0.2f);

    // Chart: gnomonic coordinates (x/z, y/z) of the camera-space direction from the lens
    // point (dω = dx dy cos³θ), or the camera-space position across the viewing
    // direction for a delta direction (dA⊥ = J dx dy).
    glm::dvec3 tx(s.toWorld[0]), ty(s.toWorld[1]), tz = glm::normalize(glm::dvec3(s.toWorld[2]));
    const double jacobian = std::abs(glm::dot(glm::cross(tx, ty), tz));
    const int cells = int(t.count(24, 12));
    const std::uint64_t n = t.count(1000000, 40000);
    std::vector<double> pValues;
    double worstIntegral = 1.0;
    std::string detail;
    std::shared_ptr<Histogram> hist;
    std::string unresolved;
    for (Point2f lens : lenses) {
        auto chart = [&](const Ray& r, double& x, double& y) {
            if (delta) {
                glm::dvec3 o = local(s, r.o);
                x = o.x, y = o.y;
            } else if (around) {
                sphereChart(localDir(s, r.d), x, y);
            } else {
                glm::dvec3 d = localDir(s, r.d);
                x = d.x / d.z, y = d.y / d.z;
            }
        };
        Ray rc = rayAt(s, centre, lens, w);
        glm::dvec3 oc = local(s, rc.o), dc = localDir(s, rc.d);
        const glm::dvec3 lensPoint = oc - dc * (oc.z / dc.z);  // where the ray crosses z = 0
        Grid2D g;
        g.x0 = g.y0 = HUGE_VAL;
        g.x1 = g.y1 = -HUGE_VAL;
        for (Point2f corner : {Point2f(0.f), Point2f(s.full.x, 0.f), Point2f(0.f, s.full.y), s.full}) {
            double x, y;
            chart(rayAt(s, corner, lens, w), x, y);
            g.x0 = std::min(g.x0, x), g.x1 = std::max(g.x1, x), g.y0 = std::min(g.y0, y), g.y1 = std::max(g.y1, y);
        }
        // A margin of 1e-3 of the extent keeps rounded samples on the film's edge inside.
        double mx = 1e-3 * (g.x1 - g.x0), my = 1e-3 * (g.y1 - g.y0);
        g.x0 -= mx, g.x1 += mx, g.y0 -= my, g.y1 += my;
        if (around) g.x0 = -Pi64, g.x1 = Pi64, g.y0 = 0.0, g.y1 = Pi64;  // the whole sphere: corners do not bound it
        g.nx = g.ny = cells;
        g.xLabel = delta ? "x" : around ? "azimuth" : "x/z";
        g.yLabel = delta ? "y" : around ? "polar angle" : "y/z";
        // Float rays quantise the chart: directions to U per component (U (1 + x² + y²) in
        // x/z), origins to U |o|. Beyond 1e-3 of a cell the rounding itself biases the
        // counts at 10⁶ samples (a fov of 0.01° on 768 pixels: 1/4 pixel), so the test
        // is skipped there, as the BSDF suite skips lobes narrower than its cells.
        double reach = std::max({std::abs(g.x0), std::abs(g.x1), std::abs(g.y0), std::abs(g.y1)});
        double quantum = delta ? U * (glm::length(s.eye) + reach * std::max(glm::length(tx), glm::length(ty))) /
                                     (std::min(glm::length(tx), glm::length(ty)) * std::min(g.cellWidth(), g.cellHeight()))
                       : around ? 8.0 * U / std::min(g.cellWidth(), g.cellHeight())
                               : U * (1.0 + 2.0 * reach * reach) / std::min(g.cellWidth(), g.cellHeight());
        if (quantum > 1e-3) unresolved = fmt::format("float rays resolve only {:.2g} of a cell (limit 1e-3)", quantum);
        PCG32 rng = t.rng(fmt::format("importance chi-square {} {}", lens.x, lens.y));
        std::vector<double> observed(std::size_t(g.cells()), 0.0);
        double outside = 0.0;
        for (std::uint64_t i = 0; i < (unresolved.empty() ? n : 0); ++i) {
            Ray r = rayAt(s, Point2f(rng.nextFloat() * s.full.x, rng.nextFloat() * s.full.y), lens, w);
            double x, y;
            chart(r, x, y);
            int c = g.cellOf(x, y);
            if (c < 0) outside += 1.0;
            else observed[std::size_t(c)] += 1.0;
        }
        auto density = [&](double x, double y) {
            glm::dvec3 pl = delta          ? glm::dvec3(x, y, depth0)
                            : around       ? lensPoint + sphereDirection(x, y) * dist0
                            : distanceClip ? lensPoint + glm::normalize(glm::dvec3(x, y, 1.0)) * dist0
                                           : lensPoint + glm::dvec3(x, y, 1.0) * (depth0 - lensPoint.z);
            CameraImportanceSample cs;
            if (!s.imp->sampleDirection(world(s, pl), lens, cs) || !(cs.pdf > 0.f)) return 0.0;
            double we = double(cs.weight) / double(cs.pdf);
            if (delta) return we * jacobian;
            if (around) return we * double(cs.dist) * double(cs.dist) * std::sin(y);  // dω = sin θ dφ dθ
            double cos2 = 1.0 / (1.0 + x * x + y * y);
            return we * double(cs.dist) * double(cs.dist) * cos2 * std::sqrt(cos2);
        };
        // The sphere chart: to 1e-5 in all, ample beside the counts' noise (1e-6 costs a minute).
        std::vector<double> integrals = integrateCells(g, density, (around ? 1e-5 : 1e-6) / g.cells());
        FitResult fit = chiSquareFit(g, observed, outside, integrals, double(n));
        pValues.push_back(fit.chi2.pValue);
        if (std::abs(fit.densityIntegral - 1.0) >= std::abs(worstIntegral - 1.0)) worstIntegral = fit.densityIntegral;
        if (!hist || fit.chi2.pValue <= *std::min_element(pValues.begin(), pValues.end())) hist = fit.histogram;
        detail += fmt::format("{}lens {}: {}", detail.empty() ? "" : "; ", str(lens), fit.summary());
    }
    double p = combinePValues(pValues);
    if (!unresolved.empty()) t.skip("importance chi-square", unresolved);
    else t.test("importance chi-square", p, fmt::format("p = {:.3g}", p),
           fmt::format("{} film positions uniform over the full film per lens sample, {} × {} cells over the {}; {}", n,
                       cells, cells,
                       delta ? "camera-space plane across the viewing direction"
                       : around ? "sphere chart of directions (azimuth, polar angle)" : "gnomonic chart of directions",
                       detail),
           hist);
    // The cell quadrature is accurate to ~1e-4 in total; 1e-3 is the tolerance.
    t.expect("importance integral", std::abs(worstIntegral - 1.0) <= 1e-3, fmt::format("∫W_e = {:.5f}", worstIntegral),
             delta ? "importance per unit area across the viewing direction over the film (tolerance 1e-3)"
                   : "importance per solid angle from the lens point over the film (tolerance 1e-3)");
}

} // namespace effigi::conform
