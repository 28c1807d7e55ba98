#pragma once
// The volumetric path tracer's estimator: surfaces and participating media mixed, four
// hero wavelengths on one path, next-event estimation through media and index-matched
// boundaries (volpath_light.hpp), multiple importance sampling of light sampling against
// BSDF / phase-function sampling, and Russian roulette.
//
// Free flights are sampled by delta tracking on the hero wavelength's majorant
// (volpath_tracking.hpp); the other wavelengths ride along by spectral MIS (Miller,
// Georgiev, Jarosz 2019): besides the throughput beta a path keeps r_u, per wavelength the
// ratio of its unidirectional path density to the density the path was actually drawn
// with, and r_l, the same for the light-sampling density. An estimate divides by the
// average of r over the wavelengths: one-sample MIS with the balance heuristic over the
// wavelength that drew the distances. A chromatic medium (σt depending on λ) is thus
// rendered without bias for every wavelength of the path, and the same average combines
// light sampling with BSDF / phase sampling (balance heuristic, as pbrt-v4's volpath).
//
// A surface whose shape has media (interior / exterior) is a medium boundary: a ray
// leaving it along d is in the exterior medium when d·n > 0, else in the interior one.
// Other surfaces leave the ray's medium as it was (Mitsuba 3's rule). Null BSDFs (and the
// transparent part of mask) let rays pass straight on; such a crossing is not a bounce.
// max_depth counts segments as `path` does (Mitsuba's convention); a medium scattering
// event is a bounce like a surface one.
// Reference: Pharr, Jakob, Humphreys, pbrt-v4 (2023), §14.2 "Volumetric light transport".
#include "volpath_light.hpp"

namespace effigi {

class VolPathIntegrator : public VolPathLight {
public:
    VolPathIntegrator(const Scene& scene, int maxDepth, int rrDepth, bool hideEmitters)
        : VolPathLight(scene), m_maxDepth(maxDepth < 0 ? std::numeric_limits<int>::max() : maxDepth),
          m_rrDepth(rrDepth), m_hideEmitters(hideEmitters) {}

    /// Radiance along the camera ray `ray`, which starts in `medium` (null: vacuum).
    SampledSpectrum li(Ray ray, const IMedium* medium, SampledWavelengths& lambda, ISampler& sampler) const {
        VolPathState s;
        s.prevP = ray.o;
        s.time = ray.time;
        for (;;) {
            SurfaceInteraction si;
            const bool hit = m_scene.intersect(ray, si);
            if (medium) {
                bool scattered = false;
                if (!mediumEvent(s, ray, *medium, hit ? si.t : Infinity, lambda, sampler, scattered)) break;
                if (scattered) continue;
            }
            if (!hit) {
                escaped(s, ray, lambda);
                break;
            }
            if (!surfaceEvent(s, ray, medium, si, lambda, sampler)) break;
        }
        return s.L;
    }

private:
    /// The ray escaped: environment emission, MIS-weighted against light sampling.
    void escaped(VolPathState& s, const Ray& ray, const SampledWavelengths& lambda) const {
        if (s.depth > m_maxDepth || (s.depth == 1 && m_hideEmitters)) return;
        for (const IEmitter* env : m_scene.environments())
            addEmission(s, env->evalEnvironment(ray.d, lambda),
                        mis::environmentHitPdf(m_scene, *env, s.prevP, normalize(ray.d)));
    }

    /// Emission the path found by its own sampling, with lightPdf the density light
    /// sampling from the last scattering point would have had.
    static void addEmission(VolPathState& s, const SampledSpectrum& Le, float lightPdf) {
        if (Le.isBlack()) return;
        if (s.depth == 1 || s.specular) s.L += s.beta * Le / s.rU.average();
        else s.L += s.beta * Le / (s.rU + s.rL * lightPdf).average();
    }

    /// Delta tracking along the ray inside `medium` up to tMax: absorption ends the path
    /// (false), real scattering samples the phase function (scattered = true, ray = the
    /// new direction), reaching tMax lets the path go on to the surface or escape.
    bool mediumEvent(VolPathState& s, Ray& ray, const IMedium& medium, float tMax, SampledWavelengths& lambda,
                     ISampler& sampler, bool& scattered) const {
        PCG32 rng = trackingRng(sampler.get1D(), sampler.get1D());
        bool alive = true;
        const Vector3f wo = -normalize(ray.d);
        const SampledSpectrum Tmaj = sampleMajorant(
            medium, ray, tMax, rng, lambda,
            [&](const Point3f& p, const MediumProperties& mp, const SampledSpectrum& sigmaMaj,
                const SampledSpectrum& T) {
                // Emission of the medium at p (no light sampling of media: no MIS).
                if (s.depth <= m_maxDepth && !mp.Le.isBlack()) {
                    const float pdf = sigmaMaj[0] * T[0];
                    const SampledSpectrum rE = s.rU * sigmaMaj * T / pdf;
                    if (!rE.isBlack()) s.L += s.beta * T * mp.sigmaA * mp.Le / (pdf * rE.average());
                }
                const float pAbsorb = mp.sigmaA[0] / sigmaMaj[0], pScatter = mp.sigmaS[0] / sigmaMaj[0];
                const float u = rng.nextFloat();
                if (u < pAbsorb || (u < pAbsorb + pScatter && s.depth >= m_maxDepth)) return alive = false;
                if (u < pAbsorb + pScatter) {
                    const float pdf = T[0] * mp.sigmaS[0];
                    s.beta *= T * mp.sigmaS / pdf;
                    s.rU *= T * mp.sigmaS / pdf;
                    alive = scatterInMedium(s, ray, p, wo, medium, lambda, sampler);
                    scattered = true;
                    return false;
                }
                // A null collision: on along the same ray.
                SampledSpectrum sigmaN = sigmaMaj - mp.sigmaA - mp.sigmaS;
                for (int i = 0; i < NSpectrumSamples; ++i) sigmaN[i] = std::max(sigmaN[i], 0.f);
                const float pdf = T[0] * sigmaN[0];
                if (!(pdf > 0.f)) return alive = false;
                s.beta *= T * sigmaN / pdf;
                s.rU *= T * sigmaN / pdf;
                s.rL *= T * sigmaMaj / pdf;
                return alive = !s.beta.isBlack() && !s.rU.isBlack();
            });
        if (!alive || scattered) return alive;
        // Reached tMax: the hero wavelength's transmittance was sampled, not weighted.
        if (!(Tmaj[0] > 0.f)) return false;
        s.beta *= Tmaj / Tmaj[0];
        s.rU *= Tmaj / Tmaj[0];
        s.rL *= Tmaj / Tmaj[0];
        return !s.beta.isBlack() && !s.rU.isBlack();
    }

    /// Real scattering at p inside the medium: light sample, then a phase-function sample.
    bool scatterInMedium(VolPathState& s, Ray& ray, const Point3f& p, const Vector3f& wo, const IMedium& medium,
                         const SampledWavelengths& lambda, ISampler& sampler) const {
        if (s.beta.isBlack() || s.rU.isBlack()) return false;
        const IPhaseFunction& phase = medium.phase();
        const LightDraw draw = drawLight(sampler);
        // sample_emitters = false (Mitsuba): no light sample here, so emission found by
        // the phase sample is the only technique and takes no MIS weight.
        const bool nee = medium.sampleEmitters();
        if (nee)
            s.L += sampleLd(s, draw, p, nullptr, &medium, lambda, [&](const Vector3f& wi) {
                return std::pair(phase.eval(wo, wi, lambda), phase.pdf(wo, wi, lambda));
            });
        std::optional<PhaseSample> ps = phase.sample(wo, sampler.get2D(), lambda);
        if (!ps || !(ps->pdf > 0.f)) return false;
        s.beta *= ps->weight;
        s.rL = s.rU / ps->pdf;
        s.specular = !nee;
        s.prevP = p;
        ray = Ray{p, ps->wi, Infinity, ray.time};
        return survives(s, sampler.get1D());
    }

    /// The ray hit si: emission there, a light sample, then a BSDF sample (or a straight
    /// crossing of a null surface). False when the path ends.
    bool surfaceEvent(VolPathState& s, Ray& ray, const IMedium*& medium, const SurfaceInteraction& si,
                      SampledWavelengths& lambda, ISampler& sampler) const {
        if (si.emitter && s.depth <= m_maxDepth && !(s.depth == 1 && m_hideEmitters))
            addEmission(s, si.emitter->eval(si, lambda), mis::emitterHitPdf(m_scene, s.prevP, si));
        if (!si.bsdf) return false;
        const IBSDF& bsdf = *si.bsdf;
        const bool scatters = s.depth < m_maxDepth;
        if (!scatters && !bsdf.hasNull()) return false;
        const Vector3f wo = si.toLocal(si.wo);
        const LightDraw draw = drawLight(sampler);  // drawn always: one dimension layout
        if (scatters && !bsdf.isPureSpecular())
            s.L += sampleLd(s, draw, si.p, &si, medium, lambda, [&](const Vector3f& wiWorld) {
                const Vector3f wi = si.toLocal(wiWorld);
                return std::pair(bsdf.f(si, wo, wi, lambda, TransportMode::Radiance) * std::abs(wi.z),
                                 bsdf.pdf(si, wo, wi, lambda, TransportMode::Radiance));
            });
        const float uc = sampler.get1D();
        const Point2f u = sampler.get2D();
        std::optional<BSDFSample> bs = bsdf.sample(si, wo, uc, u, lambda, TransportMode::Radiance);
        if (!bs || !(bs->pdf > 0.f) || bs->f.isBlack()) return false;
        s.beta *= bs->f * (std::abs(bs->wi.z) / bs->pdf);
        if (bs->flags & BSDFNull) {
            // Straight on, into the medium beyond: not a bounce (depth and MIS state stay).
            if (++s.nullCrossings > Scene::MaxNullCrossings) return false;
            medium = mediumAfter(si, ray.d, medium);
            ray = si.spawnRay(ray.d);
            return true;
        }
        if (!scatters) return false;
        const Vector3f wi = si.toWorld(bs->wi);
        s.rL = s.rU / bs->pdf;
        s.specular = bs->isSpecular();
        s.prevP = si.p;
        if (bs->isTransmission()) s.etaScale *= sqr(bs->eta);
        medium = mediumAfter(si, wi, medium);
        ray = si.spawnRay(wi);
        return survives(s, sampler.get1D());
    }

    /// After a bounce: Russian roulette on the throughput in MIS terms (beta / average
    /// r_u) with the radiance scale of refraction removed, from rr_depth on, then the next
    /// segment. False: the path ends.
    bool survives(VolPathState& s, float u) const {
        if (s.depth >= m_rrDepth) {
            const float q = std::min((s.beta / s.rU.average()).maxValue() * s.etaScale, 0.95f);
            if (!(u < q)) return false;
            s.beta *= 1.f / q;
        }
        ++s.depth;
        return true;
    }

    int m_maxDepth, m_rrDepth;
    bool m_hideEmitters;
};

} // namespace effigi
