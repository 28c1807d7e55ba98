#pragma once
// Next-event estimation of the volumetric path tracer (volpath_core.hpp): an emitter
// sample seen from a surface point or a point inside a medium, and the transmittance of
// its shadow ray through media (exact in homogeneous media, ratio tracking with Russian
// roulette elsewhere; Novák, Selle, Jarosz 2014, "Residual ratio tracking") and across
// null surfaces, which may also change the medium. The spectral-MIS ratios of the shadow
// ray (r_u for the BSDF / phase-sampling technique, r_l for light sampling) combine the
// light sample with the path's own sampling by the balance heuristic over wavelengths and
// techniques (Miller et al. 2019; pbrt-v4 §14.2.3).
#include "mis.hpp"
#include "volpath_tracking.hpp"

#include "effigi/interfaces/isampler.hpp"

#include <cmath>
#include <limits>
#include <utility>

namespace effigi {

/// The medium a ray is in after leaving the surface si along d, coming from `current`.
inline const IMedium* mediumAfter(const SurfaceInteraction& si, const Vector3f& d, const IMedium* current) {
    if (!si.shape || !si.shape->isMediumTransition()) return current;
    return dot(d, si.n) > 0.f ? si.shape->exteriorMedium() : si.shape->interiorMedium();
}

/// One path between events.
struct VolPathState {
    SampledSpectrum L{0.f};     ///< radiance gathered so far
    SampledSpectrum beta{1.f};  ///< throughput
    SampledSpectrum rU{1.f};    ///< unidirectional density ratios per wavelength (spectral MIS)
    SampledSpectrum rL{1.f};    ///< light-sampling density ratios, valid until the next bounce
    float etaScale = 1.f;       ///< radiance scale of refraction, removed for Russian roulette
    bool specular = false;      ///< no light sample at the last bounce (delta lobe): no MIS next
    int depth = 1;              ///< the segment being traced, counted from the camera
    int nullCrossings = 0;
    Point3f prevP{0.f};         ///< the last real scattering point
    float time = 0.f;           ///< the camera ray's time (shadow rays from inside media keep it)
};

/// The sampler dimensions of one light sample, drawn whether or not it is used, so that
/// every path has the same dimension layout.
struct LightDraw {
    float uSel;
    Point2f u;
    float uTrack0, uTrack1;  ///< seed of the shadow ray's ratio tracking
};
inline LightDraw drawLight(ISampler& sampler) {
    LightDraw d;
    d.uSel = sampler.get1D();
    d.u = sampler.get2D();
    d.uTrack0 = sampler.get1D();
    d.uTrack1 = sampler.get1D();
    return d;
}

class VolPathLight {
protected:
    explicit VolPathLight(const Scene& scene) : m_scene(scene) {}

    /// Light arriving at p (on si, or inside a medium when si is null) from an emitter
    /// sample, times the scattering there: `scatter(wi)` gives (f·|cos| or phase value,
    /// density of sampling wi by the BSDF or phase function).
    template <typename Scatter>
    SampledSpectrum sampleLd(const VolPathState& s, const LightDraw& draw, const Point3f& p,
                             const SurfaceInteraction* si, const IMedium* medium, const SampledWavelengths& lambda,
                             Scatter&& scatter) const {
        float selPdf;
        const IEmitter* emitter = m_scene.sampleEmitter(draw.uSel, selPdf);
        if (!emitter) return SampledSpectrum(0.f);
        const EmitterSample es = emitter->sampleDirect(p, draw.u, lambda);
        if (!(es.pdf > 0.f) || es.L.isBlack()) return SampledSpectrum(0.f);
        const auto [f, scatterPdf] = scatter(es.wi);
        if (f.isBlack()) return SampledSpectrum(0.f);
        Ray shadow;
        if (si) {
            shadow = std::isinf(es.dist) ? si->spawnRay(es.wi) : si->spawnRayTo(es.p);
            medium = mediumAfter(*si, es.wi, medium);
        } else {
            shadow = std::isinf(es.dist) ? Ray{p, es.wi, Infinity, s.time} : Ray{p, es.p - p, 1.f - ShadowEpsilon, s.time};
        }
        SampledSpectrum rU(1.f), rL(1.f);
        PCG32 rng = trackingRng(draw.uTrack0, draw.uTrack1);
        const SampledSpectrum T = shadowTransmittance(shadow, medium, lambda, rng, rU, rL);
        if (T.isBlack()) return SampledSpectrum(0.f);
        rL *= s.rU * (selPdf * es.pdf);
        rU *= s.rU * scatterPdf;
        const float r = es.delta ? rL.average() : (rL + rU).average();
        return s.beta * f * T * es.L / r;
    }

    /// What a shadow ray keeps up to ray.tMax: the media's transmittance times the null
    /// surfaces' transmission; zero at the first opaque surface. Ratio tracking multiplies
    /// its density ratios into rU and rL.
    SampledSpectrum shadowTransmittance(Ray ray, const IMedium* medium, const SampledWavelengths& lambda, PCG32& rng,
                                        SampledSpectrum& rU, SampledSpectrum& rL) const {
        if (!medium && !m_scene.hasMedia() && !m_scene.hasNullBSDFs())
            return SampledSpectrum(m_scene.occluded(ray) ? 0.f : 1.f);
        SampledSpectrum T(1.f);
        for (int crossing = 0; crossing <= Scene::MaxNullCrossings; ++crossing) {
            SurfaceInteraction si;
            const bool hit = m_scene.intersect(ray, si);
            if (hit && (!si.bsdf || !si.bsdf->hasNull())) return SampledSpectrum(0.f);
            if (medium) {
                T *= mediumTransmittance(*medium, ray, hit ? si.t : ray.tMax, lambda, rng, rU, rL);
                if (T.isBlack()) return T;
            }
            if (!hit) return T;
            T *= si.bsdf->evalNullTransmission(si, lambda);
            if (T.isBlack()) return T;
            medium = mediumAfter(si, ray.d, medium);
            // On along the same line; t values carry over since d is the same vector.
            ray = Ray{si.offsetOrigin(ray.d), ray.d, ray.tMax - si.t, ray.time};
            if (!(ray.tMax > 0.f)) return T;
        }
        return SampledSpectrum(0.f);
    }

    /// Transmittance of one medium along ray up to tMax.
    static SampledSpectrum mediumTransmittance(const IMedium& medium, const Ray& ray, float tMax,
                                               const SampledWavelengths& lambda, PCG32& rng, SampledSpectrum& rU,
                                               SampledSpectrum& rL) {
        if (medium.isHomogeneous()) {  // exact: exp(−σt·distance)
            const MediumProperties mp = medium.at(ray.o, lambda);
            const float dist = std::isinf(tMax) ? Infinity : tMax * length(ray.d);
            return majorantTransmittance(mp.sigmaA + mp.sigmaS, dist);
        }
        SampledSpectrum T(1.f);
        const SampledSpectrum Tmaj = sampleMajorant(
            medium, ray, tMax, rng, lambda,
            [&](const Point3f&, const MediumProperties& mp, const SampledSpectrum& sigmaMaj,
                const SampledSpectrum& Tm) {
                SampledSpectrum sigmaN = sigmaMaj - mp.sigmaA - mp.sigmaS;
                for (int i = 0; i < NSpectrumSamples; ++i) sigmaN[i] = std::max(sigmaN[i], 0.f);
                const float pdf = Tm[0] * sigmaMaj[0];
                T *= Tm * sigmaN / pdf;
                rL *= Tm * sigmaMaj / pdf;
                rU *= Tm * sigmaN / pdf;
                // Russian roulette once the estimate is small: the walk ends in finite time.
                const SampledSpectrum Tr = T / (rL + rU).average();
                if (Tr.maxValue() < 0.05f) {
                    if (rng.nextFloat() < 0.75f) T = SampledSpectrum(0.f);
                    else T *= 4.f;
                }
                return !T.isBlack();
            });
        if (T.isBlack() || !(Tmaj[0] > 0.f)) return SampledSpectrum(0.f);
        T *= Tmaj / Tmaj[0];
        rL *= Tmaj / Tmaj[0];
        rU *= Tmaj / Tmaj[0];
        return T;
    }

    const Scene& m_scene;
};

} // namespace effigi
