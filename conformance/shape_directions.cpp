// The shape suite's direction sampling (see shape_suite.cpp for the whole suite): from
// reference points outside the bounding sphere (1.6 R and, without --quick, 3 R from the
// centre) and inside it (0.05 R from the centre), sampleDirection() is checked for
//  - direction samples on surface: each sampled point lies on a crossing of the ray from
//    the reference along wi (or a short ray along wi hits it, for points the long ray
//    misses by rounding: grazing, or at a rim);
//  - direction pdf: its pdf equals pdfDirection() where a renderer would ask, at the
//    crossing it lies on (at the sampled point where that is ill-conditioned);
//  - direction E[1/pdf]: E[1/pdf] equals the solid angle the samples can reach, measured
//    by casting rays toward uniform points of the bounding box's surface;
//  - chi-square sampleDirection: for strategies of the shape's own, the sampled directions
//    against pdfDirection() integrated over the cells of a grid by ray casting.
// A shape may sample every point of its surface (IShape's default strategy: the density
// of a direction is then Σ pdfDirection over its crossings) or only the points the
// reference sees (a sphere's cone: pdfDirection at the first crossing); the suite takes
// the second when no sample lay behind a nearer crossing. Statistical checks are seeded by
// Target::rng and judged at the run's Šidák level.
#include "conformance/histogram.hpp"
#include "conformance/shape_common.hpp"

namespace effigi::conform::shape {

namespace {

/// The directions a reference point is checked over: the cone around the bounding
/// sphere from outside it, the whole sphere of directions from inside.
struct Cone {
    Frame frame;
    double cosMax = -1.0;
    Vector3f direction(double phi, double c) const {
        double sn = std::sqrt(std::max(0.0, 1.0 - c * c));
        return frame.toWorld(Vector3f(float(sn * std::cos(phi)), float(sn * std::sin(phi)), float(c)));
    }
    void coordinates(const Vector3f& w, double& phi, double& c) const {
        sphericalCoordinates(frame.toLocal(w), phi, c);
    }
};

/// The crossing of the ray ref → wi nearest the sampled point, if one is within the
/// tolerance: the point's own, plus the rounding of the ray (its direction to u, its
/// origin to u |ref|) magnified by 1 / |cos θ| across a surface the ray meets obliquely.
int matchCrossing(const Setup& s, const std::vector<SurfaceInteraction>& xs, const DirectionSample& ds, const Point3f& ref) {
    double best = HUGE_VAL;
    int at = -1;
    for (std::size_t k = 0; k < xs.size(); ++k) {
        double e = glm::length(Vector3d(xs[k].p) - Vector3d(ds.p));
        if (e < best) best = e, at = int(k);
    }
    if (at < 0) return -1;
    double cosT = std::max(1e-3, double(absDot(xs[std::size_t(at)].n, ds.wi)));
    double ray = 8.0 * 0x1p-24 * (double(ds.dist) + double(maxAbsComponent(ref)));
    return best <= s.tolerance(ds.p) + ray / cosT ? at : -1;
}

struct RefResult {
    double pMean = 1.0, pChi = 1.0;
    bool meanRun = false, chiRun = false;
    std::string text;
    std::shared_ptr<Histogram> histogram;
};

RefResult checkReference(Target& t, const Setup& s, const Point3f& ref, int index, Tally& onSurface, Tally& pdfs) {
    const IShape& shape = *s.shape;
    const double Rb = 1.001 * s.radius;
    Vector3d toC = Vector3d(s.centre) - Vector3d(ref);
    double D = glm::length(toC);
    Cone cone;
    if (D > Rb) cone.frame = Frame(Vector3f(toC / D)), cone.cosMax = std::sqrt(std::max(0.0, 1.0 - (Rb / D) * (Rb / D)));
    else cone.frame = Frame(normalize(Vector3f(0.2f, 0.3f, 0.93f)));
    Grid2D grid;
    grid.x1 = 2.0 * std::numbers::pi;
    grid.y0 = cone.cosMax;
    grid.nx = grid.ny = int(t.count(24, 12));
    grid.xLabel = "phi", grid.yLabel = "cos theta (about the axis to the centre)";
    const double cellSolidAngle = grid.cellWidth() * grid.cellHeight();

    PCG32 rng = t.rng(fmt::format("direction sampling {}", index));
    const std::uint64_t n = t.count(100000, 10000);
    std::vector<double> observed(std::size_t(grid.cells()), 0.0);
    double outside = 0.0;
    std::uint64_t hidden = 0, narrow = 0;
    bool ownStrategy = false;  // sampleDirection() differs from IShape's default
    MeanVar inv;
    for (std::uint64_t i = 0; i < n; ++i) {
        const Point2f u = uniform2(rng);
        DirectionSample ds = shape.sampleDirection(ref, u);
        if (i < 16 && !ownStrategy) {
            DirectionSample base = shape.IShape::sampleDirection(ref, u);
            ownStrategy = base.p != ds.p || base.pdf != ds.pdf || base.wi != ds.wi;
        }
        if (!(ds.pdf > 0.f) || !std::isfinite(ds.pdf)) {
            outside += 1.0, inv.add(0.0);
            continue;
        }
        inv.add(1.0 / double(ds.pdf));
        if (double(ds.pdf) * cellSolidAngle > 1.0) ++narrow;
        double phi, c;
        cone.coordinates(ds.wi, phi, c);
        int cell = grid.cellOf(phi, c);
        if (cell < 0) outside += 1.0;
        else observed[std::size_t(cell)] += 1.0;
        std::vector<SurfaceInteraction> xs = traceAll(s, Ray{ref, ds.wi, Infinity});
        int m = matchCrossing(s, xs, ds, ref);
        std::string at = fmt::format("ref {}: sample {} (dist {:.7g}, wi {}, pdf {:.7g})", str(ref), str(ds.p), ds.dist,
                                     str(ds.wi), ds.pdf);
        if (m < 0 && onSurface.bad == 0) {
            std::string list;
            for (const SurfaceInteraction& x : xs) list += fmt::format(" {}", str(x.p));
            at += fmt::format(": no crossing of the ray there; crossings:{}", list.empty() ? " none" : list);
        }
        // A long ray grazing the surface, or passing the rim of an open surface, may miss
        // the point by its rounding: a short ray from 1e-4 R before the point (or 256u·|p|)
        // along wi must then hit it.
        const double cosS = std::abs(double(dot(ds.n, ds.wi)));
        bool near = m >= 0 || crossingAt(s, ds.p, ds.n, ds.wi).has_value();
        if (near || cosS >= 0.02) onSurface.note(near, at);
        if (m > 0) ++hidden;
        // pdfDirection() where a renderer would ask: at the crossing, if the crossing is the
        // sample's own point of the surface (same normal to 1e-3 rad, not grazing, where a
        // density ∝ 1 / |cos θ| is ill-conditioned); else at the sample's own point.
        SurfaceInteraction x;
        x.p = ds.p, x.n = ds.n, x.shading = Frame(ds.n), x.wo = -ds.wi, x.shape = &shape;
        double angle = 0.0;
        if (m >= 0) {
            Vector3d a(xs[std::size_t(m)].n), b(ds.n);
            angle = std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
        }
        bool crossing = m >= 0 && cosS >= 0.05 && angle <= 1e-3;
        if (crossing) x = xs[std::size_t(m)];
        float back = shape.pdfDirection(ref, x);
        double err = std::abs(double(back) - double(ds.pdf)) / std::max(double(back), double(ds.pdf));
        // The density goes as 1 / |cos θ|: the normals' difference enters magnified by it.
        double tol = 1e-3 + ((crossing ? angle : 0.0) + 1e-6) / cosS;
        pdfs.worst = std::max(pdfs.worst, err / tol);
        pdfs.note(err <= tol, at + fmt::format(": pdfDirection {:.7g} at the {} (|cos θ| {:.3g})", back,
                                               crossing ? "crossing" : "sampled point", cosS));
    }
    const bool all = hidden > 0;
    RefResult r;
    r.text = fmt::format("ref {} ({} crossings sampled{})", str(ref), all ? "all" : "visible",
                         ownStrategy ? "" : ", IShape's default strategy");
    // The solid angle the samples can reach, counted with multiplicity when every
    // crossing is sampled.
    // Directions toward uniform points of the bounding box's surface reach every point of
    // the shape, thin ones too, with a density known in closed form.
    PCG32 crng = t.rng(fmt::format("direction solid angle {}", index));
    const BoxSurface K(shape.bbox());
    MeanVar omega;
    std::uint64_t crossings = 0;
    for (std::uint64_t i = 0, m = K.S > 0.0 ? t.count(100000, 10000) : 0; i < m; ++i) {
        int axis;
        bool upper;
        Vector3d w = K.sample(crng, axis, upper) - Vector3d(ref);
        double len = glm::length(w), pdf = len > 0.0 ? K.directionPdf(Vector3d(ref), w / len) : 0.0;
        if (!(pdf > 0.0) || !std::isfinite(pdf)) {
            omega.add(0.0);
            continue;
        }
        std::size_t k = traceAll(s, Ray{ref, Vector3f(w / len), Infinity}).size();
        crossings += k;
        omega.add(double(all ? k : std::min<std::size_t>(k, 1)) / pdf);
    }
    if (crossings >= 1000) {
        r.meanRun = true;
        r.pMean = agreementPValue(inv.mean, inv.stderror(), omega.mean, omega.stderror(),
                                  std::max(0.0, s.areaSlack) * omega.mean);
        r.text += fmt::format(": E[1/pdf] {:.6g} ± {:.2g}, solid angle {:.6g} ± {:.2g}", inv.mean, inv.stderror(),
                              omega.mean, omega.stderror());
    } else {
        r.text += fmt::format(": E[1/pdf] not compared, {} directions crossed the shape {} times (< 1000)", omega.n,
                              crossings);
    }
    // The chi-square: for strategies of the shape's own (the default one is area sampling,
    // checked by "sampling density" and "direction pdf").
    if (!ownStrategy) return r;
    if (!s.approximate.empty()) {
        r.text += fmt::format("; chi-square skipped: {}", s.approximate);
        return r;
    }
    if (narrow * 100 > n) {
        r.text += fmt::format("; chi-square skipped: {} of {} samples have a density above 1 per cell, too narrow for "
                              "the {}×{} grid", narrow, n, grid.nx, grid.ny);
        return r;
    }
    auto density = [&](double phi, double c) {
        Ray ray{ref, cone.direction(phi, c), Infinity};
        if (!all) {
            Hit h;
            return s.accel->intersect(ray, h) ? double(shape.pdfDirection(ref, shape.interaction(ray, h))) : 0.0;
        }
        double sum = 0.0;
        for (const SurfaceInteraction& x : traceAll(s, ray)) sum += double(shape.pdfDirection(ref, x));
        return sum;
    };
    std::vector<double> cells = integrateCells(grid, density, 1e-4 / grid.cells(), 2, 16);
    FitResult fit = chiSquareFit(grid, observed, outside, cells, double(n));
    r.chiRun = true;
    r.pChi = fit.chi2.pValue;
    r.histogram = fit.histogram;
    r.text += fmt::format("; {}", fit.summary());
    return r;
}

} // namespace

void checkDirections(Target& t, const Setup& s) {
    auto at = [&](double dist, Vector3d dir) { return Point3f(Vector3d(s.centre) + dist * s.radius * glm::normalize(dir)); };
    std::vector<Point3f> refs = {at(1.6, {1.3, 0.4, 0.9}), at(0.05, {0.3, -0.8, 0.5})};
    if (!t.quick()) refs.push_back(at(3.0, {-0.5, -1.1, -0.7}));
    Tally onSurface, pdfs;
    std::vector<double> pMean, pChi;
    std::string text;
    std::shared_ptr<Histogram> worst;
    double worstP = 2.0;
    for (std::size_t i = 0; i < refs.size(); ++i) {
        RefResult r = checkReference(t, s, refs[i], int(i), onSurface, pdfs);
        if (r.meanRun) pMean.push_back(r.pMean);
        if (r.chiRun) pChi.push_back(r.pChi);
        if (r.chiRun && r.pChi < worstP) worstP = r.pChi, worst = r.histogram;
        text += fmt::format("{}{}", text.empty() ? "" : "; ", r.text);
    }
    judge(t, s, "direction samples on surface", onSurface.bad == 0, onSurface.figure(),
          onSurface.detail("each sampleDirection() point lies on a crossing of the ray from the reference along wi "
                           "(1e-5 R + 64u·|p| + the ray's rounding / |cos θ|), or else a ray from 1e-4 R before "
                           "it along wi hits it there (or, at a rim, one aimed 1e-5 R + 256u·|p| beside it); grazing "
                           "samples (|cos θ| < 0.02) count only if they do"));
    judge(t, s, "direction pdf", pdfs.bad == 0, fmt::format("{}; worst {:.2g} of tolerance", pdfs.figure(), pdfs.worst),
          pdfs.detail("pdf of each sample = pdfDirection() at the crossing it lies on (at the sampled point itself "
                      "where the crossing grazes, |cos θ| < 0.05, or its normal differs by over 1e-3 rad), within "
                      "1e-3 + (angle between the normals + 1e-6) / |cos θ| relative"));
    if (pMean.empty()) {
        t.skip("direction E[1/pdf]", text);
    } else if (!s.approximate.empty()) {
        // Discrete samples (sdfgrid's crossing points) misrepresent what a near reference sees.
        t.info("direction E[1/pdf]", fmt::format("p = {:.3g}", combinePValues(pMean)), fmt::format("{}; not judged: {}", text, s.approximate));
    } else {
        double p = combinePValues(pMean);
        t.test("direction E[1/pdf]", p, fmt::format("p = {:.3g}", p), text);
    }
    if (pChi.empty()) {
        t.skip("chi-square sampleDirection", text);
    } else {
        double pc = combinePValues(pChi);
        t.test("chi-square sampleDirection", pc, fmt::format("p = {:.3g}", pc), text, worst);
    }
}

} // namespace effigi::conform::shape
