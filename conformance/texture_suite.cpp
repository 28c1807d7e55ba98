// Texture suite: an ITexture, in each of its configurations, is checked for what the
// interface promises (include/effigi/interfaces/itexture.hpp). Lookups run at surface
// points of a small mesh with vertex and face colours (tests/data/textures/quad.ply,
// so mesh_attribute finds its attributes; the other textures read only uv), at uv
// random in [0, 1]², on the corners and edges of that square, at the texel centres of
// image textures (ITextureResolution), outside it in [−3, 4]² and at huge uv (±1e7,
// ±1e20, ±FLT_MAX), with random and extreme (360, 830 nm) wavelengths:
//  - finite: eval(), evalFloat(), evalVector() and evalFloatGradient() are finite, and
//    maxValue() and mean() are finite with mean() ≤ maxValue();
//  - non-finite uv: the same at uv = ±∞ and NaN (a degenerate hit must not poison a pixel);
//  - non-negative: eval() ≥ 0 (a texture's spectrum is a reflectance, a radiance or
//    another physical spectrum; raw data is read through evalFloat/evalVector);
//  - bounded: eval() ≤ maxValue() (documented as an upper bound over all points and
//    wavelengths: a reflectance that declares 1 must not exceed it), and evalFloat() too;
//  - constant: a texture saying isConstant() reads the same everywhere;
//  - mean: the average of evalFloat() over uv uniform in [0, 1]² against mean() (the
//    documented average over the domain), a two-sided z-test; a texture that reads the
//    mesh rather than uv (mesh_attribute: its readings change with the triangle and the
//    barycentrics, or not with uv, and it is not constant) has no uv domain, and its mean
//    over the test mesh is reported (INFO);
//  - spectral mean: where the RGB reading (evalVector) is grey, evalFloat() is the mean of
//    eval() over 360–830 nm (1e-3), as ITexture documents the scalar reading;
//  - gradient: evalFloatGradient() against central differences of evalFloat() where
//    those converge (away from jumps and kinks), 1e-2 of the texture's scale.
// The mean is the only statistical check (seeded by Target::rng, judged at the run's Šidák
// level); the others are deterministic with the tolerance they print.
#include "conformance/conformance.hpp"
#include "conformance/histogram.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/interfaces/itexture_resolution.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

namespace effigi::conform {

namespace {

struct Probe {
    SurfaceInteraction si;
    std::string where() const {
        return fmt::format("uv ({:.9g}, {:.9g}), triangle {}, barycentrics ({:.3g}, {:.3g})", si.uv.x, si.uv.y, si.prim,
                           si.primUV.x, si.primUV.y);
    }
};

/// The mesh the probes lie on; null when tests/data is out of reach (mesh_attribute
/// then reads 0, which the checks accept).
Ref<IShape> probeMesh(Registry& reg) {
    try {
        Properties p("shape", "ply");
        p.set("filename", std::string("tests/data/textures/quad.ply"));
        return query<IShape>(reg.create("shape", "ply", p));
    } catch (const std::exception&) {
        return nullptr;
    }
}

Probe probeAt(const IShape* mesh, Point2f uv, PCG32& rng) {
    Probe p;
    p.si.uv = uv;
    p.si.shape = mesh;
    p.si.prim = rng.nextUInt() & 1u;
    float b1 = rng.nextFloat(), b2 = rng.nextFloat();
    if (b1 + b2 > 1.f) b1 = 1.f - b1, b2 = 1.f - b2;
    int corner = int(rng.nextUInt() % 8u);  // now and then exactly on a corner or an edge
    if (corner < 3) b1 = corner == 1 ? 1.f : 0.f, b2 = corner == 2 ? 1.f : 0.f;
    else if (corner == 3) b2 = 1.f - b1;
    p.si.primUV = Point2f(b1, b2);
    p.si.p = Point3f(2.f * uv.x - 1.f, 2.f * uv.y - 1.f, 0.f);
    p.si.wo = Vector3f(0.f, 0.f, 1.f);
    p.si.dpdu = Vector3f(2.f, 0.f, 0.f), p.si.dpdv = Vector3f(0.f, 2.f, 0.f);
    return p;
}

bool same(const SampledSpectrum& a, const SampledSpectrum& b) {
    for (int i = 0; i < NSpectrumSamples; ++i)
        if (a[i] != b[i]) return false;
    return true;
}

bool finite(const SampledSpectrum& s) {
    for (int i = 0; i < NSpectrumSamples; ++i)
        if (!std::isfinite(s[i])) return false;
    return true;
}

/// Mean of eval() over [LambdaMin, LambdaMax] by the midpoint rule on 472 wavelengths.
double spectralMean(const ITexture& tex, const SurfaceInteraction& si) {
    constexpr int M = 118;
    double sum = 0.0;
    for (int k = 0; k < M; ++k) {
        SampledSpectrum s = tex.eval(si, SampledWavelengths::sampleUniform((float(k) + 0.5f) / M));
        for (int i = 0; i < NSpectrumSamples; ++i) sum += s[i];
    }
    return sum / (M * NSpectrumSamples);
}

void runTextureSuite(Target& t) {
    Ref<ITexture> tex = t.as<ITexture>();
    if (!tex) {
        t.expect("interface", false, "-", "component does not implement ITexture");
        return;
    }
    Ref<IShape> meshRef = probeMesh(t.registry());
    const IShape* mesh = meshRef.get();
    PCG32 rng = t.rng("probes");
    const float maxValue = tex->maxValue(), mean = tex->mean();

    // The probes with finite uv.
    std::vector<Probe> probes;
    const float edge[] = {0.f, 1e-7f, 0.25f, 0.5f, 1.f - 1e-7f, OneMinusEpsilon, 1.f};
    for (float u : edge)
        for (float v : edge) probes.push_back(probeAt(mesh, {u, v}, rng));
    if (auto res = query<ITextureResolution>(tex.get())) {
        Vector2i r = res->resolution();
        for (int y = 0; y < r.y && y < 64; ++y)
            for (int x = 0; x < r.x && x < 64; ++x)
                probes.push_back(probeAt(mesh, {(float(x) + 0.5f) / float(r.x), (float(y) + 0.5f) / float(r.y)}, rng));
    }
    for (std::uint64_t i = 0, n = t.count(20000, 4000); i < n; ++i)
        probes.push_back(probeAt(mesh, {rng.nextFloat(), rng.nextFloat()}, rng));
    for (std::uint64_t i = 0, n = t.count(4000, 1000); i < n; ++i)
        probes.push_back(probeAt(mesh, {-3.f + 7.f * rng.nextFloat(), -3.f + 7.f * rng.nextFloat()}, rng));
    const float big = std::numeric_limits<float>::max();
    const float huge[] = {1e7f + 0.3f, -1e7f, 1e20f, -1e20f, big, -big, 0.5f};
    for (float u : huge)
        for (float v : huge) probes.push_back(probeAt(mesh, {u, v}, rng));

    // finite, non-negative, bounded, constant
    Tally fin, neg, bound, cons;
    double maxSeen = 0.0;
    const SampledWavelengths fixed[] = {SampledWavelengths::constant(LambdaMin), SampledWavelengths::constant(LambdaMax)};
    const Probe& p0 = probes.front();
    const float f0 = tex->evalFloat(p0.si);
    const Vector3f v0 = tex->evalVector(p0.si);
    const SampledSpectrum s0 = tex->eval(p0.si, fixed[0]);
    const double boundTol = 1e-5 * std::abs(double(maxValue)) + 1e-30;
    for (const Probe& p : probes) {
        for (int k = 0; k < 3; ++k) {
            SampledWavelengths l = k < 2 ? fixed[k] : SampledWavelengths::sampleVisible(rng.nextFloat());
            SampledSpectrum s = tex->eval(p.si, l);
            std::string at = fmt::format("{}, λ = {:.1f} nm: eval = ({:.7g}, {:.7g}, {:.7g}, {:.7g}), maxValue {:.7g}",
                                         p.where(), l[0], s[0], s[1], s[2], s[3], maxValue);
            bool ok = finite(s);
            fin.note(ok, at);
            if (!ok) continue;
            double lo = HUGE_VAL, hi = -HUGE_VAL;
            for (int i = 0; i < NSpectrumSamples; ++i) lo = std::min(lo, double(s[i])), hi = std::max(hi, double(s[i]));
            maxSeen = std::max(maxSeen, hi);
            neg.note(lo >= 0.0, at);
            bound.note(hi <= double(maxValue) + boundTol, at);
            if (tex->isConstant() && k == 0) cons.note(same(s, s0), at + fmt::format(" (first probe: {:.7g})", s0[0]));
        }
        float f = tex->evalFloat(p.si);
        Vector3f v = tex->evalVector(p.si);
        Vector2f g = tex->evalFloatGradient(p.si);
        std::string at = fmt::format("{}: evalFloat {:.7g}, evalVector ({:.7g}, {:.7g}, {:.7g}), gradient ({:.7g}, {:.7g})",
                                     p.where(), f, v.x, v.y, v.z, g.x, g.y);
        bool ok = std::isfinite(f) && isFinite(v) && std::isfinite(g.x) && std::isfinite(g.y);
        fin.note(ok, at);
        if (ok) bound.note(double(f) <= double(maxValue) * (1.0 + 1e-4) + 1e-30, at + fmt::format(", maxValue {:.7g}", maxValue));
        if (tex->isConstant()) cons.note(f == f0 && v == v0, at);
    }
    bool declOk = std::isfinite(maxValue) && std::isfinite(mean) && mean <= maxValue * (1.f + 1e-5f);
    fin.note(declOk, fmt::format("maxValue() {:.7g}, mean() {:.7g}", maxValue, mean));
    t.expect("finite", fin.bad == 0, fin.figure(),
             fin.detail("eval, evalFloat, evalVector, evalFloatGradient finite at every probe (uv in and outside [0, 1]², "
                        "its edges, huge uv); maxValue() and mean() finite, mean() ≤ maxValue()"));
    t.expect("non-negative", neg.bad == 0, neg.figure(), neg.detail("eval() ≥ 0 at every probe and wavelength"));
    t.expect("bounded", bound.bad == 0, fmt::format("{}; largest eval {:.7g} of maxValue {:.7g}", bound.figure(), maxSeen, maxValue),
             bound.detail("eval() ≤ maxValue() (1e-5 relative) and evalFloat() ≤ maxValue() (1e-4) at every probe"));
    if (tex->isConstant()) t.expect("constant", cons.bad == 0, cons.figure(), cons.detail("isConstant(): the same readings everywhere"));

    // Non-finite uv.
    Tally nonFinite;
    const float odd[] = {std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                         std::numeric_limits<float>::quiet_NaN(), 0.5f};
    for (float u : odd)
        for (float v : odd) {
            Probe p = probeAt(mesh, {u, v}, rng);
            SampledSpectrum s = tex->eval(p.si, SampledWavelengths::sampleVisible(0.3f));
            float f = tex->evalFloat(p.si);
            Vector3f vv = tex->evalVector(p.si);
            Vector2f g = tex->evalFloatGradient(p.si);
            nonFinite.note(finite(s) && std::isfinite(f) && isFinite(vv) && std::isfinite(g.x) && std::isfinite(g.y),
                           fmt::format("{}: eval[0] {}, evalFloat {}, evalVector ({}, {}, {}), gradient ({}, {})", p.where(),
                                       s[0], f, vv.x, vv.y, vv.z, g.x, g.y));
        }
    t.expect("non-finite uv", nonFinite.bad == 0, nonFinite.figure(),
             nonFinite.detail("finite readings at uv = ±∞ and NaN"));

    // Does the texture read uv, or the mesh? The same uv at other triangles and corners,
    // and other uv at the same point of the mesh.
    bool readsMesh = false, readsUV = false;
    auto differ = [&](const SurfaceInteraction& a, const SurfaceInteraction& b) {
        return tex->evalFloat(a) != tex->evalFloat(b) || tex->evalVector(a) != tex->evalVector(b);
    };
    for (int i = 0; i < 64; ++i) {
        Point2f uv(rng.nextFloat(), rng.nextFloat());
        Probe a = probeAt(mesh, uv, rng), b = probeAt(mesh, uv, rng), c = a;
        c.si.uv = Point2f(rng.nextFloat(), rng.nextFloat());
        readsMesh = readsMesh || differ(a.si, b.si);
        readsUV = readsUV || differ(a.si, c.si);
    }
    PCG32 mrng = t.rng("mean");
    MeanVar avg;
    for (std::uint64_t i = 0, n = t.count(400000, 50000); i < n; ++i)
        avg.add(tex->evalFloat(probeAt(mesh, {mrng.nextFloat(), mrng.nextFloat()}, mrng).si));
    if (!tex->isConstant() && (readsMesh || !readsUV)) {
        t.info("mean", fmt::format("mean() {:.6g}", mean),
               fmt::format("the texture reads the mesh, not uv, so it has no uv domain: its average over the test mesh "
                           "(triangles weighted equally) is {:.6g} ± {:.2g}; mean() can only be a lobe-selection weight "
                           "here",
                           avg.mean, avg.stderror()));
    } else {
        // Slack 1e-4 of the scale: mean() is summed in float.
        double band = 1e-4 * std::max(std::abs(double(mean)), std::abs(double(maxValue)));
        double p = upperBoundPValue(std::abs(avg.mean - double(mean)), avg.stderror(), band);
        t.test("mean", p, fmt::format("p = {:.3g}", p),
               fmt::format("average of evalFloat over {} uniform uv in [0, 1]²: {:.7g} ± {:.2g}; mean() {:.7g}", avg.n,
                           avg.mean, avg.stderror(), mean));
    }

    // Spectral mean where the RGB reading is grey.
    Tally spectral;
    double worstSpec = 0.0;
    for (std::size_t i = 0; i < probes.size() && spectral.checked < 400; ++i) {
        const SurfaceInteraction& si = probes[i].si;
        Vector3f v = tex->evalVector(si);
        float scale = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
        if (!(std::abs(v.x - v.y) <= 1e-6f * scale && std::abs(v.y - v.z) <= 1e-6f * scale)) continue;
        double m = spectralMean(*tex, si), f = tex->evalFloat(si);
        double err = std::abs(m - f) / std::max({std::abs(m), std::abs(f), 1e-30});
        worstSpec = std::max(worstSpec, std::abs(m - f) <= 1e-30 ? 0.0 : err);
        spectral.note(std::abs(m - f) <= 1e-3 * std::max(std::abs(f), double(scale)) + 1e-30,
                      fmt::format("{}: grey RGB {:.7g}, evalFloat {:.7g}, mean of eval over 360–830 nm {:.7g}",
                                  probes[i].where(), v.x, f, m));
    }
    if (spectral.checked == 0) t.skip("spectral mean", "no probe has a grey RGB reading");
    else t.expect("spectral mean", spectral.bad == 0, fmt::format("{}; worst rel. error {:.2g}", spectral.figure(), worstSpec),
                  spectral.detail("where evalVector is grey, evalFloat = the mean of eval over 360–830 nm (1e-3)"));

    // Gradient against central differences where they converge.
    PCG32 grng = t.rng("gradient");
    Tally grad;
    std::uint64_t smooth = 0;
    const double scale = std::max(1e-30, double(std::max(std::abs(maxValue), std::abs(mean))));
    for (std::uint64_t i = 0, n = t.count(4000, 1000); i < n; ++i) {
        Probe p = probeAt(mesh, {0.05f + 0.9f * grng.nextFloat(), 0.05f + 0.9f * grng.nextFloat()}, grng);
        auto fd = [&](float h, int axis) {
            SurfaceInteraction a = p.si, b = p.si;
            a.uv[axis] += h, b.uv[axis] -= h;
            return (double(tex->evalFloat(a)) - double(tex->evalFloat(b))) / (double(a.uv[axis]) - double(b.uv[axis]));
        };
        Vector2f g = tex->evalFloatGradient(p.si);
        bool ok = true, conv = true;
        std::string at;
        for (int axis = 0; axis < 2; ++axis) {
            double d1 = fd(1e-3f, axis), d2 = fd(2.5e-4f, axis);
            // A jump or kink within the step: the differences do not converge there.
            double tol = 1e-2 * std::max({scale, std::abs(d1), std::abs(d2)});
            if (!(std::abs(d1 - d2) <= 0.1 * tol)) conv = false;
            ok = ok && std::abs(double(g[axis]) - d2) <= tol;
            at += fmt::format("{}∂/∂{}: gradient {:.6g}, central difference {:.6g}", axis ? "; " : "", axis ? 'v' : 'u',
                              g[axis], d2);
        }
        if (!conv) continue;
        ++smooth;
        grad.note(ok, p.where() + ": " + at);
    }
    if (smooth == 0) t.skip("gradient", "central differences converge nowhere (the texture jumps everywhere)");
    else t.expect("gradient", grad.bad == 0, grad.figure(),
                  grad.detail("evalFloatGradient against central differences of evalFloat (steps 1e-3, 2.5e-4 in uv) "
                              "where they converge; 1e-2 of the texture's scale"));
}

} // namespace

} // namespace effigi::conform

EFFIGI_CONFORMANCE_SUITE("texture",
                         "finite readings (huge and non-finite uv too), eval within [0, maxValue()], mean() against the "
                         "average over uv, evalFloat as the spectral mean, gradient against finite differences",
                         effigi::conform::runTextureSuite);
