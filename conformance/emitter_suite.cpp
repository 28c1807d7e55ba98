// Emitter suite: an IEmitter, in each of its configurations, is checked for what the
// interface promises (include/effigi/interfaces/iemitter.hpp):
//  - direct sampling (non-delta emitters): sampleDirect()'s directions follow
//    pdfDirect()/pdfEnvironment() (chi-square over the sphere of directions from a few
//    reference points), and each sample's L and pdf agree with eval()/evalEnvironment()
//    and pdfDirect()/pdfEnvironment() at the sampled point;
//  - delta samples (delta emitters): pdf 1 with the delta flag, a unit direction;
//  - emission: sampleEmission() gives finite values, positive pdfs wherever L > 0, unit
//    directions, and rays that start on the emitter (a surface light's shape, a point
//    light's position, outside the scene's bounding sphere for lights at infinity);
//  - power: power() against the luminance flux estimated from sampleEmission(), within
//    25 % (IEmitter documents power() as approximate: it weighs lights); an
//    environment's power depends on the scene's size and only weighs lights, so it is
//    reported (INFO) rather than judged; their emission flux is checked against their
//    radiance integrated over uniform directions instead;
//  - inverse-square law (point-like emitters): L · dist² is the same at 1e-2 … 1e4 along
//    an emitted ray, and equals the intensity sampleEmission() reports for that ray;
//  - extreme points: everything finite and non-negative seen from 1e-4 and 1e6 away.
// A surface emitter is nested in two host shapes built here (a unit square and a sphere
// of radius ½) and preprocessed with the host's bounds, as Scene does; other emitters
// are preprocessed with the scene [-1, 1]³. The emission, power, emission-flux and
// inverse-square checks are in emitter_emission.cpp.
#include "conformance/emitter_common.hpp"
#include "conformance/histogram.hpp"

#include <fmt/format.h>

namespace effigi::conform::emitter {

namespace {

std::vector<Setup> setups(Target& t) {
    Ref<IEmitter> e0 = t.as<IEmitter>();
    std::vector<Setup> out;
    if (!(e0->flags() & EmitterSurface)) {
        e0->preprocess(SceneBounds);
        std::vector<Point3f> refs{Point3f(0.3f, -0.2f, 0.5f)};
        if (!t.quick()) refs.push_back(Point3f(-0.7f, 0.4f, -0.1f));
        out.push_back({e0, {}, refs, ""});
        return out;
    }
    for (bool sphere : {false, true}) {
        Ref<IEmitter> e = query<IEmitter>(t.create());
        const std::string type = sphere ? "sphere" : "rectangle";
        Properties p("shape", type);
        if (sphere) p.set("radius", 0.5);
        else p.set("to_world", Transform::scale(Vector3f(0.5f, 0.5f, 1.f)));
        p.set("emitter", ComponentValue{"emitter", e});
        Ref<IShape> s = query<IShape>(t.registry().create("shape", type, p));
        e->preprocess(s->bbox());
        std::vector<Point3f> refs = sphere ? std::vector<Point3f>{Point3f(0.3f, 0.2f, 1.2f), Point3f(0.f, 0.f, -3.f)}
                                           : std::vector<Point3f>{Point3f(0.2f, -0.1f, 0.8f), Point3f(1.5f, 0.3f, 0.4f)};
        if (t.quick()) refs.resize(1);
        out.push_back({e, {type, s, sphere}, refs, sphere ? " on sphere" : " on square"});
    }
    return out;
}

/// The first point of the host the ray ref + s d (s > 0) meets, seen from ref.
bool hitHost(const Host& h, const Point3f& ref, const Vector3f& d, SurfaceInteraction& si) {
    const Vector3d o(ref), w(glm::normalize(Vector3d(d)));
    double s = -1.0;
    if (h.sphere) {
        double b = glm::dot(o, w), c = glm::dot(o, o) - 0.25, disc = b * b - c;
        if (disc < 0.0) return false;
        double r = std::sqrt(disc);
        s = -b - r > 0.0 ? -b - r : -b + r;
    } else if (w.z != 0.0) {
        s = -o.z / w.z;
    }
    if (!(s > 0.0)) return false;
    Vector3d p = o + s * w;
    if (!h.sphere && (std::abs(p.x) > 0.5 || std::abs(p.y) > 0.5)) return false;
    si = SurfaceInteraction();
    si.p = Point3f(p);
    si.n = h.sphere ? Normal3f(glm::normalize(p)) : Normal3f(0.f, 0.f, 1.f);
    si.shading = Frame(si.n);
    si.wo = -Vector3f(w);
    si.t = float(s);
    si.shape = h.shape.get();
    return true;
}

/// What eval()/evalEnvironment() and pdfDirect()/pdfEnvironment() say about a direct sample.
struct Expected {
    SampledSpectrum L{0.f};
    float pdf = 0.f;
};
Expected expectedAt(const Setup& s, const Point3f& ref, const EmitterSample& es, const SampledWavelengths& l) {
    Expected x;
    if (s.host.shape) {
        SurfaceInteraction si;
        si.p = es.p;
        si.n = es.n;
        si.shading = Frame(es.n);
        si.wo = -es.wi;
        si.shape = s.host.shape.get();
        x.L = s.emitter->eval(si, l);
        x.pdf = s.emitter->pdfDirect(ref, si);
    } else {
        x.L = s.emitter->evalEnvironment(es.wi, l);
        x.pdf = s.emitter->pdfEnvironment(ref, es.wi);
    }
    return x;
}

/// Chi-square of sampleDirect() against the density, and the value check of its samples.
void checkDirect(Target& t, const Setup& s) {
    const IEmitter& e = *s.emitter;
    const Grid2D grid = t.quick() ? sphereGrid(20, 10) : sphereGrid(40, 20);
    const std::uint64_t n = t.count(1000000, 100000);
    // Quadrature error far below Poisson noise. A surface's outline (great-circle arcs)
    // crosses cells at corners that a coarse first rule can miss entirely, so those cells
    // start from 2⁴ steps per dimension.
    const double tolerance = 1e-4 / grid.cells();
    const std::string name = "chi-square sampleDirect" + s.at;
    // The grid's polar axis: +y for lights at infinity, whose latitude-longitude maps put
    // their poles on ±y (Mitsuba's convention), so that the 1/sin θ of such a density is
    // singular only on the grid's poles, at cell edges that the quadrature handles,
    // rather than at a corner of four cells, where it overestimates the cells' integrals.
    const bool yUp = !s.host.shape;
    auto toGrid = [yUp](const Vector3f& w) { return yUp ? Vector3f(w.z, w.x, w.y) : w; };
    auto fromGrid = [yUp](const Vector3f& v) { return yUp ? Vector3f(v.y, v.z, v.x) : v; };
    std::vector<double> ps;
    std::string detail;
    std::shared_ptr<Histogram> worst;
    double worstP = 2.0, worstValue = 0.0;
    std::uint64_t valueChecked = 0, valueBad = 0;
    std::string valueDetail;
    for (std::size_t k = 0; k < s.refs.size(); ++k) {
        const Point3f ref = s.refs[k];
        PCG32 rng = t.rng(fmt::format("{} {}", name, k));
        std::vector<double> observed(std::size_t(grid.cells()), 0.0);
        double outside = 0.0, maxPdf = 0.0;
        for (std::uint64_t i = 0; i < n; ++i) {
            SampledWavelengths l = SampledWavelengths::sampleVisible(rng.nextFloat());
            EmitterSample es = e.sampleDirect(ref, uniform2(rng), l);
            if (!(es.pdf > 0.f) || es.delta) {
                outside += 1.0;
                continue;
            }
            maxPdf = std::max(maxPdf, double(es.pdf));
            double phi, ct;
            sphericalCoordinates(toGrid(es.wi), phi, ct);
            int c = grid.cellOf(phi, ct);
            if (c < 0) outside += 1.0;
            else observed[std::size_t(c)] += 1.0;
            if (i % 16 != 0) continue;  // the value check needs far fewer samples
            Expected x = expectedAt(s, ref, es, l);
            double err = std::max(relError(es.L, x.L), relError(es.pdf, x.pdf));
            ++valueChecked;
            worstValue = std::max(worstValue, err);
            if (!(err <= ValueTolerance)) {
                if (++valueBad == 1)
                    valueDetail = fmt::format("; first: ref ({}, {}, {}), wi ({:.4f}, {:.4f}, {:.4f}): sample L[0] = {:.5g}, "
                                              "pdf = {:.5g}; eval {:.5g}, pdf {:.5g}",
                                              ref.x, ref.y, ref.z, es.wi.x, es.wi.y, es.wi.z, es.L[0], es.pdf, x.L[0], x.pdf);
            }
        }
        if (maxPdf > MaxEmitterPdf) {
            t.skip(name, fmt::format("from ({}, {}, {}): pdf up to {:.3g} sr⁻¹, too narrow for a {}×{} histogram",
                                     ref.x, ref.y, ref.z, maxPdf, grid.nx, grid.ny));
            continue;
        }
        std::vector<double> cells = integrateCells(
            grid,
            [&](double phi, double ct) {
                Vector3f d = fromGrid(sphericalDirection(phi, ct));
                if (!s.host.shape) return double(e.pdfEnvironment(ref, d));
                SurfaceInteraction si;
                return hitHost(s.host, ref, d, si) ? double(e.pdfDirect(ref, si)) : 0.0;
            },
            tolerance, s.host.shape ? 4 : 2);
        FitResult fit = chiSquareFit(grid, observed, outside, cells, double(n));
        ps.push_back(fit.chi2.pValue);
        detail += fmt::format("{}from ({}, {}, {}): {}", detail.empty() ? "" : "; ", ref.x, ref.y, ref.z, fit.summary());
        if (fit.chi2.pValue < worstP) {
            worstP = fit.chi2.pValue;
            worst = fit.histogram;
        }
    }
    if (!ps.empty()) {
        double p = combinePValues(ps);
        t.test(name, p, fmt::format("p = {:.3g}", p), fmt::format("{} samples per point; {}", n, detail), worst);
    }
    t.expect("sample value" + s.at, valueBad == 0, fmt::format("worst rel. error {:.2g}", worstValue),
             fmt::format("{} of {} samples disagree with eval/pdf by more than {:g}{}", valueBad, valueChecked,
                         ValueTolerance, valueDetail));
}

/// A delta emitter's direct samples: pdf 1 with the delta flag (or pdf 0: no light), unit wi.
void checkDeltaSamples(Target& t, const Setup& s) {
    PCG32 rng = t.rng("delta samples");
    const std::uint64_t n = t.count(10000, 1000);
    std::uint64_t bad = 0;
    std::string first;
    for (std::uint64_t i = 0; i < n; ++i) {
        Point3f ref(4.f * rng.nextFloat() - 2.f, 4.f * rng.nextFloat() - 2.f, 4.f * rng.nextFloat() - 2.f);
        EmitterSample es = s.emitter->sampleDirect(ref, uniform2(rng), SampledWavelengths::sampleVisible(rng.nextFloat()));
        bool ok = es.pdf == 0.f || (es.pdf == 1.f && es.delta && std::abs(length(es.wi) - 1.f) <= 1e-4f && valid(es.L));
        if (!ok && bad++ == 0) first = fmt::format("ref ({}, {}, {}): pdf {}, delta {}, |wi| {}", ref.x, ref.y, ref.z, es.pdf, es.delta, length(es.wi));
    }
    t.expect("delta samples", bad == 0, fmt::format("{} bad of {}", bad, n), first);
}

/// Finite, non-negative values seen from 1e-4 and 1e6 away (front and back of a surface).
void checkExtremes(Target& t, const Setup& s) {
    const IEmitter& e = *s.emitter;
    PCG32 rng = t.rng("extreme points" + s.at);
    const Point3f light = e.sampleDirect(Point3f(0.123f, 0.456f, 0.789f), Point2f(0.5f), SampledWavelengths::constant(550.f)).p;
    std::vector<Point3f> refs;
    for (float dist : {1e-4f, 1e6f})
        for (int k = 0; k < 8; ++k) {
            Vector3f w = sphericalDirection(2.0 * Pi * rng.nextFloat(), 2.0 * rng.nextFloat() - 1.0);
            if (s.host.shape) {
                Point3f on = s.host.sphere ? Point3f(0.5f * w) : Point3f(rng.nextFloat() - 0.5f, rng.nextFloat() - 0.5f, 0.f);
                Vector3f nrm = s.host.sphere ? w : Vector3f(0.f, 0.f, 1.f);
                refs.push_back(on + (k % 2 ? -dist : dist) * nrm);
            } else {
                refs.push_back((e.flags() & EmitterDeltaPosition ? light : Point3f(0.f)) + dist * w);
            }
        }
    int checked = 0, bad = 0;
    std::string first;
    const Point2f us[] = {Point2f(0.f), Point2f(0.5f), Point2f(OneMinusEpsilon), Point2f(0.25f, 0.75f)};
    for (const Point3f& ref : refs)
        for (const Point2f& u : us) {
            SampledWavelengths l = SampledWavelengths::sampleVisible(rng.nextFloat());
            EmitterSample es = e.sampleDirect(ref, u, l);
            bool ok = valid(es.L) && std::isfinite(es.pdf) && es.pdf >= 0.f;
            if (ok && es.pdf > 0.f) ok = isFinite(es.wi) && !std::isnan(es.dist) && es.dist >= 0.f;
            if (ok && es.pdf > 0.f && !es.delta) {
                Expected x = expectedAt(s, ref, es, l);
                ok = valid(x.L) && std::isfinite(x.pdf) && x.pdf >= 0.f;
            }
            if (!e.isDelta() && !s.host.shape) {
                Vector3f d = sphericalDirection(2.0 * Pi * rng.nextFloat(), 2.0 * rng.nextFloat() - 1.0);
                float pdf = e.pdfEnvironment(ref, d);
                ok = ok && valid(e.evalEnvironment(d, l)) && std::isfinite(pdf) && pdf >= 0.f;
            }
            ++checked;
            if (!ok && bad++ == 0)
                first = fmt::format("ref ({:g}, {:g}, {:g}), u = ({}, {}): pdf {}, L[0] {}, dist {}", ref.x, ref.y, ref.z,
                                    u.x, u.y, es.pdf, es.L[0], es.dist);
        }
    t.expect("extreme points" + s.at, bad == 0, fmt::format("{} bad of {}", bad, checked),
             fmt::format("reference points 1e-4 and 1e6 from the emitter{}{}", first.empty() ? "" : "; first: ", first));
}

void runEmitterSuite(Target& t) {
    Ref<IEmitter> e = t.as<IEmitter>();
    if (!e) {
        t.expect("interface", false, "-", "component does not implement IEmitter");
        return;
    }
    for (const Setup& s : setups(t)) {
        const std::uint32_t flags = s.emitter->flags();
        if (s.emitter->isDelta()) checkDeltaSamples(t, s);
        else checkDirect(t, s);
        checkEmission(t, s);
        if (flags & EmitterDeltaPosition) checkInverseSquare(t, s);
        checkExtremes(t, s);
    }
}

} // namespace

} // namespace effigi::conform::emitter

EFFIGI_CONFORMANCE_SUITE("emitter",
                         "direct sampling against pdfs (chi-square) and eval, emission samples, power, inverse-square "
                         "law, finite values at extreme distances",
                         effigi::conform::emitter::runEmitterSuite);