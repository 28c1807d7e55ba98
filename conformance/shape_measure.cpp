// The shape suite's measurements of the surface by ray casting (see shape_suite.cpp for
// the whole suite):
//  - intersections: every crossing of random lines with the shape lies on the line and
//    inside bbox(), with a unit normal, an orthonormal shading frame, finite uv and
//    wo = −d;
//  - area: area() against the closed form of the configuration (sphere, disk, cylinder,
//    rectangle, cube), and against Cauchy–Crofton: isotropic uniform lines meeting a
//    convex body K (here the bounding box) cross a surface of area A inside it on average
//    2A / S(K) times, S(K) the area of K's surface (L. A. Santaló, "Integral Geometry and
//    Geometric Probability", 1976, §14); such lines enter K at a uniform point of its
//    surface in a cosine-weighted direction;
//  - sampling density: E[f(x)/pdf(x)] over samplePosition() against ∫ f dA by the same
//    lines, for f = 1 (the pdf integrates to 1 over the surface) and f = the indicator
//    of each of 8 octants around the centre (the samples are spread as the area is):
//    each a z-test of two independent means, Bonferroni-combined.
// Below 1000 crossings the statistical rows are skipped: too thin a shape for the lines.
// Statistical checks are seeded by Target::rng and judged at the run's Šidák level.
#include "conformance/histogram.hpp"
#include "conformance/shape_common.hpp"

#include "effigi/math/warp_functions.hpp"

namespace effigi::conform::shape {

double agreementPValue(double a, double seA, double b, double seB, double band) {
    return upperBoundPValue(std::abs(a - b), std::sqrt(seA * seA + seB * seB), band);
}

namespace {

/// Which of the 8 octants around the centre (shifted off any symmetry plane) p is in.
int octant(const Setup& s, const Point3f& p) {
    Vector3d q = Vector3d(p) - Vector3d(s.centre) - s.radius * Vector3d(0.0123, -0.0317, 0.0219);
    return (q.x > 0.0 ? 1 : 0) | (q.y > 0.0 ? 2 : 0) | (q.z > 0.0 ? 4 : 0);
}

bool frameOk(const SurfaceInteraction& si) {
    const Frame& f = si.shading;
    auto unit = [](const Vector3f& v) { return std::abs(length(v) - 1.f) <= 1e-4f; };
    return unit(si.n) && unit(f.s) && unit(f.t) && unit(f.n) && std::abs(dot(f.s, f.t)) <= 1e-4f &&
           std::abs(dot(f.s, f.n)) <= 1e-4f && std::abs(dot(f.t, f.n)) <= 1e-4f;
}

} // namespace

void checkArea(Target& t, const Setup& s, std::optional<double> analytic) {
    const IShape& shape = *s.shape;
    const double area = shape.area();
    const BBox3f box = shape.bbox();
    if (analytic)
        t.expect("area analytic", std::abs(area - *analytic) <= 1e-5 * *analytic,
                 fmt::format("area() {:.7g}, closed form {:.7g}", area, *analytic),
                 "the configuration's geometry in closed form (1e-5 relative)");
    else t.skip("area analytic", "no closed form for this shape (a mesh from a file, curves, a grid, an instance)");

    // Isotropic uniform lines meeting the bounding box K: a point uniform by area on its
    // surface and a cosine-weighted direction into it. They meet K with measure π S / 2
    // (S its surface area) and cross the surface on average 2A / S times.
    const BoxSurface K(box);
    const double perCrossing = 0.5 * K.S;
    PCG32 rng = t.rng("area by ray casting");
    MeanVar lines[9];
    Tally hits;
    for (std::uint64_t i = 0, n = K.S > 0.0 ? t.count(40000, 8000) : 0; i < n; ++i) {
        int axis;
        bool upper;
        Vector3d q = K.sample(rng, axis, upper);
        Vector3f inward(0.f);
        inward[axis] = upper ? -1.f : 1.f;
        Vector3f d = Frame(inward).toWorld(warp::squareToCosineHemisphere(uniform2(rng)));
        Vector3d o = q - 1e-3 * s.radius * Vector3d(d);
        Ray ray{Point3f(o), d, Infinity};
        int count[9] = {0};
        for (const SurfaceInteraction& si : traceAll(s, ray)) {
            double off = glm::length(glm::cross(Vector3d(si.p) - Vector3d(ray.o), Vector3d(d)));
            double tol = s.tolerance(si.p) + 64.0 * 0x1p-24 * glm::length(o);
            bool ok = isFinite(si.p) && off <= tol && frameOk(si) && std::isfinite(si.uv.x) && std::isfinite(si.uv.y) &&
                      glm::length(si.wo + d) <= 1e-5f && si.t > 0.f;
            for (int a = 0; ok && a < 3; ++a)
                ok = double(si.p[a]) >= double(box.min[a]) - tol && double(si.p[a]) <= double(box.max[a]) + tol;
            hits.note(ok, fmt::format("line {} + s {}: hit {} ({:.3g} R off the line), n {}, |s| {}, t {}, uv ({}, {})",
                                      str(ray.o), str(d), str(si.p), off / s.radius, str(si.n), length(si.shading.s),
                                      si.t, si.uv.x, si.uv.y));
            if (!isFinite(si.p)) continue;
            ++count[octant(s, si.p)];
            ++count[8];
        }
        for (int k = 0; k < 9; ++k) lines[k].add(perCrossing * count[k]);
    }
    t.expect("intersections", hits.bad == 0, hits.figure(),
             hits.detail("every crossing of random lines: on the line and inside bbox() (1e-5 R + rounding), unit "
                         "normal, orthonormal shading frame, finite uv, wo = −d, t > 0"));

    const double cast = lines[8].mean, castSe = lines[8].stderror();
    const double crossings = lines[8].n * cast / perCrossing;
    const std::string castText =
        fmt::format("ray casting {:.6g} ± {:.2g} ({} lines, {:.0f} crossings)", cast, castSe, lines[8].n, crossings);
    // Below 1000 crossings the estimate is too rough (and too skewed) for a z-test; the
    // count area() predicts decides too, so that a shape the lines miss cannot pass.
    const bool measurable = std::max(crossings, lines[8].n * area / perCrossing) >= 1000.0;
    const std::string tooFew = fmt::format("the shape is too thin for the lines to measure: {}", castText);
    if (!measurable) {
        t.skip("area by ray casting", tooFew);
    } else if (s.areaSlack < 0.0) {
        t.info("area by ray casting", fmt::format("area() {:.6g}", area),
               fmt::format("{}; not compared: {}", castText, s.approximate));
    } else {
        double p = agreementPValue(area, 0.0, cast, castSe, s.areaSlack * area);
        t.test("area by ray casting", p, fmt::format("p = {:.3g}", p),
               fmt::format("area() {:.6g} against {} (Cauchy–Crofton; slack {:g} relative{}{})", area, castText,
                           s.areaSlack, s.approximate.empty() ? "" : ": ", s.approximate));
    }
    if (!s.samples) return;
    if (!measurable) {
        t.skip("sampling density", tooFew);
        return;
    }

    // E[f/pdf] over samplePosition() for the same 9 functions.
    PCG32 srng = t.rng("sampling density");
    MeanVar samples[9];
    for (std::uint64_t i = 0, n = t.count(200000, 40000); i < n; ++i) {
        PositionSample ps = shape.samplePosition(uniform2(srng));
        double w = ps.pdf > 0.f && std::isfinite(ps.pdf) && isFinite(ps.p) ? 1.0 / double(ps.pdf) : 0.0;
        int k = w > 0.0 ? octant(s, ps.p) : -1;
        for (int j = 0; j < 8; ++j) samples[j].add(j == k ? w : 0.0);
        samples[8].add(w);
    }
    std::vector<double> ps;
    double worstZ = 0.0;
    std::string worst;
    const double band = std::max(0.0, s.areaSlack) * area;
    for (int k = 0; k < 9; ++k) {
        ps.push_back(agreementPValue(samples[k].mean, samples[k].stderror(), lines[k].mean, lines[k].stderror(), band));
        double se = std::hypot(samples[k].stderror(), lines[k].stderror());
        double z = se > 0.0 ? std::abs(samples[k].mean - lines[k].mean) / se : 0.0;
        if (z >= worstZ)
            worstZ = z, worst = fmt::format("{}: E[f/pdf] {:.6g} ± {:.2g}, ray casting {:.6g} ± {:.2g}",
                                           k == 8 ? std::string("whole surface") : fmt::format("octant {}", k),
                                           samples[k].mean, samples[k].stderror(), lines[k].mean, lines[k].stderror());
    }
    double p = combinePValues(ps);
    std::string detail = fmt::format("E[f/pdf] of {} samples against ∫f dA by ray casting, f = 1 and the 8 octants "
                                     "(Bonferroni); largest |z| {:.2f} at {}",
                                     samples[8].n, worstZ, worst);
    // Discrete samples (sdfgrid's crossing points) stand for the area only on average.
    if (s.approximate.empty()) t.test("sampling density", p, fmt::format("p = {:.3g}", p), detail);
    else t.info("sampling density", fmt::format("p = {:.3g}", p), fmt::format("{}; not judged: {}", detail, s.approximate));
}

} // namespace effigi::conform::shape
