// Medium suite: an IMedium, in each of its configurations, against the promises of
// include/effigi/interfaces/imedium.hpp, and the transmittance estimators of
// include/effigi/render/transmittance.hpp on it.
//  - finite: at() gives finite σa, σs and Le at random points (and at ±1e6), at random
//    and extreme (360, 830 nm) wavelengths;
//  - albedo: σa ≥ 0 and σs ≥ 0, so σt ≥ 0 and the albedo σs/σt lies in [0, 1];
//  - emission: Le ≥ 0, and Le = 0 where isEmissive() is false;
//  - homogeneous: a medium saying isHomogeneous() has the same coefficients everywhere;
//  - majorant: along random rays (directions of length ½ to 2), the pieces majorant()
//    returns start where asked, advance, end by tMax (also infinite), and bound σt
//    (to 1e-6 relative, for the rounding of σa + σs) at points inside them;
//  - delta tracking, ratio tracking, estimators agree: medium_transmittance.cpp.
#include "conformance/media_common.hpp"

#include <cmath>

namespace effigi::conform::media {

namespace {

Point3f randomPoint(PCG32& rng, float extent) {
    return Point3f(extent * (2.f * rng.nextFloat() - 1.f), extent * (2.f * rng.nextFloat() - 1.f),
                   extent * (2.f * rng.nextFloat() - 1.f));
}

void checkCoefficients(Target& t, const IMedium& m) {
    PCG32 rng = t.rng("coefficients");
    const int n = int(t.count(20000, 4000));
    Tally finite, albedo, emission, constant;
    double maxAlbedo = 0.0;
    const SampledWavelengths fixed = SampledWavelengths::sampleUniform(0.5f);
    const MediumProperties first = m.at(Point3f(0.f), fixed);
    for (int i = 0; i < n; ++i) {
        const Point3f p = i % 100 == 0 ? randomPoint(rng, 1e6f) : randomPoint(rng, 10.f);
        const SampledWavelengths l = probeWavelengths(rng, std::size_t(i));
        const MediumProperties mp = m.at(p, l);
        const std::string at = fmt::format("p = ({:.4g}, {:.4g}, {:.4g}), λ0 = {:.1f} nm: σa {}, σs {}, Le {}", p.x, p.y,
                                           p.z, l[0], spec(mp.sigmaA), spec(mp.sigmaS), spec(mp.Le));
        finite.note(mp.sigmaA.isFinite() && mp.sigmaS.isFinite() && mp.Le.isFinite(), at);
        albedo.note(nonNegative(mp.sigmaA) && nonNegative(mp.sigmaS), at);
        emission.note(nonNegative(mp.Le) && (m.isEmissive() || mp.Le.isBlack()), at);
        for (int k = 0; k < NSpectrumSamples; ++k) {
            const double st = double(mp.sigmaA[k]) + double(mp.sigmaS[k]);
            if (st > 0.0) maxAlbedo = std::max(maxAlbedo, double(mp.sigmaS[k]) / st);
        }
        if (m.isHomogeneous()) {
            const MediumProperties here = m.at(p, fixed);
            bool same = true;
            for (int k = 0; k < NSpectrumSamples; ++k)
                same = same && here.sigmaA[k] == first.sigmaA[k] && here.sigmaS[k] == first.sigmaS[k];
            constant.note(same, fmt::format("at p = ({:.4g}, {:.4g}, {:.4g}): σa {}, σs {}; at the origin σa {}, σs {}",
                                            p.x, p.y, p.z, spec(here.sigmaA), spec(here.sigmaS), spec(first.sigmaA),
                                            spec(first.sigmaS)));
        }
    }
    t.expect("finite", finite.bad == 0, finite.figure(), finite.detail("σa, σs and Le finite"));
    t.expect("albedo", albedo.bad == 0, fmt::format("max albedo {:.4g}", maxAlbedo),
             albedo.detail("σa ≥ 0 and σs ≥ 0: albedo σs/σt in [0, 1]"));
    t.expect("emission", emission.bad == 0, emission.figure(),
             emission.detail(m.isEmissive() ? "Le ≥ 0" : "not emissive: Le = 0"));
    if (m.isHomogeneous())
        t.expect("homogeneous", constant.bad == 0, constant.figure(), constant.detail("the same σa, σs everywhere"));
    else
        t.skip("homogeneous", "the medium is not homogeneous");
}

void checkMajorants(Target& t, const IMedium& m) {
    PCG32 rng = t.rng("majorant");
    const int rays = int(t.count(2000, 400));
    constexpr int MaxPieces = 100000;
    Tally tally;
    for (int r = 0; r < rays; ++r) {
        const float speed = 0.5f + 1.5f * rng.nextFloat();
        const Vector3f dir = speed * uniformDirection(rng);
        const Ray ray{randomPoint(rng, 10.f), dir, Infinity};
        const float tMax = r % 4 == 3 ? Infinity : std::pow(10.f, 6.f * rng.nextFloat() - 3.f);
        const SampledWavelengths l = probeWavelengths(rng, std::size_t(r));
        float tNow = 0.f;
        std::string bad;
        for (int piece = 0; piece < MaxPieces && bad.empty() && tNow < tMax; ++piece) {
            const MajorantSegment seg = m.majorant(ray, tNow, tMax, l);
            if (seg.tMin != tNow || !(seg.tMax > tNow) || seg.tMax > tMax)
                bad = fmt::format("asked from t = {} to {}, got [{}, {}]", tNow, tMax, seg.tMin, seg.tMax);
            else if (!seg.sigmaMaj.isFinite() || !nonNegative(seg.sigmaMaj))
                bad = fmt::format("σ_maj = {} on [{}, {}]", spec(seg.sigmaMaj), seg.tMin, seg.tMax);
            for (int j = 0; j < 4 && bad.empty(); ++j) {
                const float hi = std::isfinite(seg.tMax) ? seg.tMax : seg.tMin + 1e3f;
                const float s = seg.tMin + (hi - seg.tMin) * rng.nextFloat();
                const SampledSpectrum st = m.at(ray(s), l).sigmaT();
                for (int k = 0; k < NSpectrumSamples; ++k)
                    if (!(st[k] <= seg.sigmaMaj[k] * (1.f + 1e-6f) + 1e-30f))
                        bad = fmt::format("σt = {} above σ_maj = {} at t = {} of [{}, {}]", spec(st),
                                          spec(seg.sigmaMaj), s, seg.tMin, seg.tMax);
            }
            tNow = seg.tMax;
            if (piece + 1 == MaxPieces && tNow < tMax) bad = fmt::format("{} pieces do not reach tMax = {}", MaxPieces, tMax);
        }
        tally.note(bad.empty(), fmt::format("ray {}: {}", r, bad));
    }
    t.expect("majorant", tally.bad == 0, tally.figure(),
             tally.detail("pieces start where asked, advance to tMax and bound σt (1e-6 relative)"));
}

void runMediumSuite(Target& t) {
    Ref<IMedium> m = t.as<IMedium>();
    if (!m) {
        t.expect("interface", false, "-", "component does not implement IMedium");
        return;
    }
    checkCoefficients(t, *m);
    checkMajorants(t, *m);
    checkTransmittance(t, *m);
    t.info("phase", m->phase().typeName().empty() ? "-" : m->phase().typeName(), "the medium's phase function");
}

} // namespace

} // namespace effigi::conform::media

EFFIGI_CONFORMANCE_SUITE("medium",
                         "finite coefficients, albedo in [0, 1], majorants; delta and ratio tracking against exp(−σt d)",
                         effigi::conform::media::runMediumSuite);
