// Camera suite, the density of directions (ICameraImportance::pdfDirection), which
// bidirectional renderers (bdpt) use for multiple importance sampling:
//  - support: every ray generateRay() produces has a positive, finite density from its
//    own lens point (a film position within rounding of the film's edge may have 0);
//  - normalisation: from a lens point the density integrates to 1 over all directions.
//    The integral is taken over the gnomonic chart (x/z, y/z) of camera space, where
//    dω = cos³θ dx dy, by uniform points over a rectangle 20 % larger than the film's
//    chart (a z-test at the suite's level: the estimate is a binomial fraction times the
//    constant density inside, so its standard error is known); for panoramas, which see
//    sideways and back, over the sphere chart (camera_chart.hpp: dω = sin y dx dy) whole.
// Cameras whose direction is a delta (orthographic) have no density: pdfDirection()
// returns 0 for them and the checks are skipped.
#include "conformance/camera_chart.hpp"
#include "conformance/conformance.hpp"
#include "conformance/histogram.hpp"
#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/icamera_importance.hpp"
#include "effigi/interfaces/ifilm.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace effigi::conform {

void checkDirectionDensity(Target& t, const ICamera& cam, const ICameraImportance& imp) {
    const Transform toLocal = cam.toWorld().inverse();
    const Vector2f full(cam.film().fullSize());
    auto ray = [&](Point2f film, Point2f lens) {
        SampledSpectrum w;
        return cam.generateRay({film, lens, 0.f}, SampledWavelengths::sampleUniform(0.37f), w);
    };
    // The point where a ray crosses the lens plane z = 0 of camera space.
    auto lensPoint = [&](const Ray& r) {
        Point3f o = toLocal.point(r.o);
        Vector3f d = toLocal.vector(r.d);
        return cam.toWorld().point(o - d * (o.z / d.z));
    };
    const Ray centre = ray(0.5f * Point2f(full), Point2f(0.5f));
    if (!(imp.pdfDirection(lensPoint(centre), centre.d) > 0.f)) {
        t.skip("direction density", "pdfDirection() is 0: the camera's direction is a delta (no density)");
        return;
    }
    PCG32 rng = t.rng("direction density");
    Tally support;
    const std::uint64_t n = t.count(200000, 20000);
    // A film position within rounding of the film's edge may map back just outside it: the
    // round trip film → unit direction → film rounds the direction by a few float ulps
    // (U = 2⁻²⁴), which at a tiny field of view is a sizeable fraction of a pixel. Such
    // positions may have density 0 (as the projection check lets them miss the film).
    constexpr double U = 0x1p-24;
    auto nearEdge = [&](Point2f film, const Ray& r, Point2f lens) {
        const float step = film.x > 0.5f * full.x ? -1.f : 1.f;  // one pixel inward
        const Ray next = ray(film + Point2f(step, 0.f), lens);
        const double perPixel = glm::length(glm::cross(glm::dvec3(r.d), glm::dvec3(next.d)));  // radians
        const double tol = 2e-3 + 64.0 * U / std::max(perPixel, 1e-30);
        const double edge = std::min({double(film.x), double(film.y), full.x - double(film.x), full.y - double(film.y)});
        return edge <= tol;
    };
    for (std::uint64_t i = 0; i < n; ++i) {
        Point2f film(rng.nextFloat() * full.x, rng.nextFloat() * full.y), lens(rng.nextFloat(), rng.nextFloat());
        Ray r = ray(film, lens);
        float pdf = imp.pdfDirection(lensPoint(r), r.d);
        const bool positive = pdf > 0.f && std::isfinite(pdf);
        support.note(positive || (pdf == 0.f && nearEdge(film, r, lens)),
                     fmt::format("film {}, {}: pdf {}", film.x, film.y, pdf));
    }
    t.expect("direction density support", support.bad == 0, fmt::format("{} of {} not positive", support.bad, n),
             support.bad ? support.first : "pdfDirection(lens point, d) of generated rays");

    // Normalisation from two lens points (the centre, and one off-centre for a thin lens).
    double worstZ = 0.0;
    std::string detail;
    const bool around = seesAround(cam);
    for (Point2f lens : {Point2f(0.5f), Point2f(0.85f, 0.2f)}) {
        const Point3f at = lensPoint(ray(0.5f * Point2f(full), lens));
        double x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL, y1 = -HUGE_VAL;
        for (Point2f c : {Point2f(0.f), Point2f(full.x, 0.f), Point2f(0.f, full.y), Point2f(full)}) {
            Vector3f d = toLocal.vector(ray(c, lens).d);
            x0 = std::min(x0, double(d.x / d.z)), x1 = std::max(x1, double(d.x / d.z));
            y0 = std::min(y0, double(d.y / d.z)), y1 = std::max(y1, double(d.y / d.z));
        }
        const double mx = 0.1 * (x1 - x0), my = 0.1 * (y1 - y0);
        x0 -= mx, x1 += mx, y0 -= my, y1 += my;
        if (around) x0 = -3.14159265358979323846, x1 = -x0, y0 = 0.0, y1 = x1;  // the sphere chart, whole
        const double area = (x1 - x0) * (y1 - y0);
        MeanVar integral;
        for (std::uint64_t i = 0; i < n; ++i) {
            double x = x0 + (x1 - x0) * rng.nextDouble(), y = y0 + (y1 - y0) * rng.nextDouble();
            const glm::dvec3 dl = around ? sphereDirection(x, y) : glm::dvec3(x, y, 1.0);
            const double jacobian = around ? std::sin(y) : std::pow(1.0 + x * x + y * y, -1.5);  // dω per chart area
            Vector3f d = normalize(cam.toWorld().vector(Vector3f(dl)));
            integral.add(area * double(imp.pdfDirection(at, d)) * jacobian);
        }
        // A floor of 1e-5 on the standard error stands for the float round-off of the
        // density (a latitude-longitude film's integrand is constant: its spread is ~1e-10).
        const double se = std::sqrt(integral.stderror() * integral.stderror() + 1e-10);
        double z = (integral.mean - 1.0) / se;
        worstZ = std::max(worstZ, std::abs(z));
        detail += fmt::format("{}lens ({}, {}): ∫ pdf dω = {:.4f} ± {:.2g}", detail.empty() ? "" : "; ", lens.x, lens.y,
                              integral.mean, integral.stderror());
    }
    double p = std::erfc(worstZ / std::sqrt(2.0));
    p = 1.0 - std::pow(1.0 - p, 2.0);  // the worst of two z-tests (Šidák)
    t.test("direction density integral", p, fmt::format("p = {:.3g}", p),
           fmt::format("{} uniform points of the {} chart per lens point; {}", n, around ? "sphere" : "gnomonic", detail));
}

} // namespace effigi::conform
