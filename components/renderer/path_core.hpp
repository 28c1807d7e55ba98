#pragma once
// The path tracer's estimator one segment at a time, shared by the one-path-at-a-time
// loop (PathIntegrator::li, the readable reference) and the wavefront mode
// (path_wavefront.hpp), which advances thousands of paths together and traces their rays
// in batches. Both run exactly these steps in the same order and draw the same sampler
// dimensions, so they are the same estimator; only when rays are traced differs.
//
// A path samples four hero wavelengths, adds emission found by BSDF sampling and by light
// sampling, weighted by multiple importance sampling with the power heuristic (Veach &
// Guibas 1995), and is ended by Russian roulette after rr_depth. Pass-through surfaces
// (BSDFNull lobes: null, the transparent part of mask) are not scattering events, as in
// Mitsuba 3's volpath: a null sample continues the ray straight on without counting a
// segment or playing Russian roulette, and emission found beyond it is MIS-weighted with
// the density of the last real bounce (a null crossing does not change the direction, so
// that density and its point stay valid); shadow rays cross such surfaces weighted by
// evalNullTransmission (Scene::transmittance). Scenes without them take the plain
// occlusion test.
// Reference: Kajiya 1986, "The Rendering Equation"; Veach 1997, PhD thesis, ch. 9.
#include "mis.hpp"

#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/render/scene.hpp"

#include <limits>
#include <optional>

namespace effigi {

/// One path between two segments: everything the next segment needs from the earlier ones.
struct PathState {
    Ray ray;                       ///< the segment to trace next
    SampledSpectrum L{0.f};        ///< radiance gathered so far
    SampledSpectrum beta{1.f};     ///< path throughput
    float prevPdf = 1.f;           ///< density of the last BSDF sample (MIS of emission hit next)
    float etaScale = 1.f;          ///< radiance scale of refraction, removed for Russian roulette
    Point3f prevP{0.f};            ///< where that sample was taken
    bool specular = false;         ///< the last bounce was a delta lobe (no MIS)
    int depth = 1;                 ///< segments traced so far, `ray` included
    int nullCrossings = 0;

    PathState() = default;
    explicit PathState(const Ray& r) : ray(r), prevP(r.o) {}
};

/// Next-event estimation's shadow ray and what it adds to L if nothing blocks it.
struct ShadowRay {
    Ray ray;
    SampledSpectrum contribution;
};

class PathIntegrator {
public:
    PathIntegrator(const Scene& scene, int maxDepth, int rrDepth, bool hideEmitters)
        : m_scene(scene), m_maxDepth(maxDepth < 0 ? std::numeric_limits<int>::max() : maxDepth),
          m_rrDepth(rrDepth), m_hideEmitters(hideEmitters) {}

    /// The readable reference: one path, each ray traced as soon as it is known.
    SampledSpectrum li(const Ray& ray, SampledWavelengths& lambda, ISampler& sampler) const {
        PathState s(ray);
        SurfaceInteraction si;
        if (!m_scene.intersect(s.ray, si)) {
            miss(s, lambda);
            return s.L;
        }
        return liFromHit(s, si, lambda, sampler);
    }

    /// li() from the state `s` whose segment s.ray is already known to hit `si` (callers
    /// that need the first hit before the path goes on: irradiancecache's gather rays).
    SampledSpectrum liFromHit(PathState s, SurfaceInteraction si, SampledWavelengths& lambda, ISampler& sampler) const {
        std::optional<ShadowRay> shadow;
        for (;;) {
            bool more = scatter(s, si, lambda, sampler, shadow);
            if (shadow) s.L += shadow->contribution * shadowTransmittance(shadow->ray, lambda);
            if (!more) break;
            if (!m_scene.intersect(s.ray, si)) {
                miss(s, lambda);
                break;
            }
        }
        return s.L;
    }

    /// The segment escaped: environment emission; the path ends.
    void miss(PathState& s, const SampledWavelengths& lambda) const {
        // Emission counts on segments 1..max_depth only: max_depth 0 is black (Mitsuba).
        if (s.depth > m_maxDepth || (s.depth == 1 && m_hideEmitters)) return;
        for (const IEmitter* env : m_scene.environments()) {
            float w = 1.f;
            if (s.depth > 1 && !s.specular)
                w = mis::powerHeuristic(s.prevPdf, mis::environmentHitPdf(m_scene, *env, s.prevP, s.ray.d));
            s.L += s.beta * env->evalEnvironment(s.ray.d, lambda) * w;
        }
    }

    /// The segment hit si: emission there, a light sample (its shadow ray, not yet traced,
    /// in `shadow`), then a BSDF sample that becomes s.ray. False when the path ends.
    bool scatter(PathState& s, const SurfaceInteraction& si, SampledWavelengths& lambda, ISampler& sampler,
                 std::optional<ShadowRay>& shadow) const {
        shadow.reset();
        if (si.emitter && s.depth <= m_maxDepth && !(s.depth == 1 && m_hideEmitters)) {
            SampledSpectrum Le = si.emitter->eval(si, lambda);
            if (!Le.isBlack()) {
                float w = 1.f;
                if (s.depth > 1 && !s.specular)
                    w = mis::powerHeuristic(s.prevPdf, mis::emitterHitPdf(m_scene, s.prevP, si));
                s.L += s.beta * Le * w;
            }
        }
        if (!si.bsdf) return false;
        const IBSDF& bsdf = *si.bsdf;
        // At the last segment only a pass-through may still go on.
        const bool scatters = s.depth < m_maxDepth;
        if (!scatters && !bsdf.hasNull()) return false;
        const Vector3f wo = si.toLocal(si.wo);
        // Always draw the light-sampling dimensions so every path uses the same layout.
        const float uLight = sampler.get1D();
        const Point2f uLight2 = sampler.get2D();
        if (scatters && !bsdf.isPureSpecular()) shadow = sampleLight(s, si, bsdf, wo, uLight, uLight2, lambda);

        const float uc = sampler.get1D();
        const Point2f u = sampler.get2D();
        std::optional<BSDFSample> bs = bsdf.sample(si, wo, uc, u, lambda, TransportMode::Radiance);
        if (!bs || bs->pdf <= 0.f || bs->f.isBlack()) return false;
        if (bs->flags & BSDFNull) {
            // Straight on along the same line: not a bounce, so depth, the MIS state
            // (prevPdf, prevP, specular) and Russian roulette are left as they were.
            if (++s.nullCrossings > Scene::MaxNullCrossings) return false;
            s.beta *= bs->f * (std::abs(bs->wi.z) / bs->pdf);
            s.ray = si.spawnRay(s.ray.d);
            return true;
        }
        if (!scatters) return false;
        s.beta *= bs->f * (std::abs(bs->wi.z) / bs->pdf);
        s.specular = bs->isSpecular();
        s.prevPdf = bs->pdf;
        s.prevP = si.p;
        if (bs->isTransmission()) s.etaScale *= sqr(bs->eta);
        s.ray = si.spawnRay(si.toWorld(bs->wi));

        // Russian roulette on the throughput with the radiance scale of refraction
        // removed, so paths inside glass are not killed for being "bright".
        if (s.depth >= m_rrDepth) {
            float q = std::min(s.beta.maxValue() * s.etaScale, 0.95f);
            if (sampler.get1D() >= q) return false;
            s.beta *= 1.f / q;
        }
        ++s.depth;
        return true;
    }

    /// True when shadow rays must be followed through pass-through surfaces
    /// (shadowTransmittance) rather than answered by a plain occlusion test.
    bool shadowsNeedTransmittance() const { return m_scene.hasNullBSDFs(); }
    /// What fraction of a shadow ray's contribution arrives: 0 or 1, or the null surfaces'
    /// transmittance in scenes that have them.
    SampledSpectrum shadowTransmittance(const Ray& ray, const SampledWavelengths& lambda) const {
        if (shadowsNeedTransmittance()) return m_scene.transmittance(ray, lambda);
        return SampledSpectrum(m_scene.occluded(ray) ? 0.f : 1.f);
    }

private:
    std::optional<ShadowRay> sampleLight(const PathState& s, const SurfaceInteraction& si, const IBSDF& bsdf,
                                         const Vector3f& wo, float uSel, const Point2f& u,
                                         const SampledWavelengths& lambda) const {
        std::optional<mis::LightSample> ls = mis::sampleLight(m_scene, si, bsdf, wo, uSel, u, lambda);
        if (!ls) return std::nullopt;
        float w = ls->es.delta ? 1.f
                               : mis::powerHeuristic(ls->pdf, bsdf.pdf(si, wo, ls->wi, lambda, TransportMode::Radiance));
        return ShadowRay{ls->shadow, s.beta * ls->f * ls->es.L * (w / ls->pdf)};
    }

    const Scene& m_scene;
    int m_maxDepth, m_rrDepth;
    bool m_hideEmitters;
};

} // namespace effigi
