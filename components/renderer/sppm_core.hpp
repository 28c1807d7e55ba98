#pragma once
// The per-pixel parts of stochastic progressive photon mapping (renderer sppm): the
// progressive radius update and the camera pass.
//
// SPPM's camera pass (Hachisuka & Jensen 2009; pbrt-v3 §16.2.2, pbrt-v4's SPPMIntegrator):
// one camera path per pixel and iteration follows delta bounces (glass, mirrors, pass-through
// surfaces) to the first vertex whose BSDF has a non-delta lobe, the *visible point*,
// where photons will be gathered. On the way it adds what the photons cannot supply:
//  - emission seen along the delta chain (no MIS: only delta bounces came before);
//  - direct light at the visible point by next-event estimation, MIS-combined (power
//    heuristic) with the emission a BSDF sample hits, exactly as `path` does
//    (components/renderer/mis.hpp), so photons of depth 1 must not be gathered;
//  - the delta lobes of a mixed BSDF (plastic's coat, mask's pass-through): the BSDF
//    sample that picks one is continued by path tracing (PathIntegrator::li), since
//    f() — and so the photon estimate — sees only the non-delta lobes.
// A dispersive interface may terminate the path's secondary wavelengths; the visible
// point keeps the path's final wavelengths, so its direct light and its photons use the
// same slots.
#include "mis.hpp"
#include "path_core.hpp"

#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/render/scene.hpp"

#include <limits>

namespace effigi {

/// Where a pixel's camera path of one iteration gathers photons.
struct VisiblePoint {
    SurfaceInteraction si;
    Vector3f wo{0.f};              ///< local, toward the camera side
    SampledSpectrum beta{0.f};     ///< camera path throughput up to si (not divided by the λ pdf)
    SampledWavelengths lambda;     ///< the path's wavelengths (secondaries may be terminated)
    Vector3f ld{0.f};              ///< XYZ of emission + direct light found by this path
    int depth = 0;                 ///< segments from the camera to si; 0: no visible point
};

/// What a pixel carries from iteration to iteration: Hachisuka & Jensen's (R, N, τ) and
/// the sum of its direct light.
struct SppmPixel {
    double ld[3] = {0.0, 0.0, 0.0};   ///< Σ over iterations of XYZ of emission and direct light
    double tau[3] = {0.0, 0.0, 0.0};  ///< τ: gathered flux (XYZ), rescaled as R shrinks
    float radius = 0.f, n = 0.f;      ///< R and N

    /// One iteration's photons: M of them within R, carrying flux phi (XYZ; β f Φp summed).
    /// N' = N + αM, R' = R √(N' / (N + M)), τ' = (τ + Φ) R'² / R² (Hachisuka & Jensen 2009,
    /// §4): keeping αM of the new photons, the density over the shrunk disc stays what it was.
    void update(float M, const Vector3f& phi, float alpha) {
        if (!(M > 0.f)) return;  // Φ = 0 too: nothing changes
        const float nNew = n + alpha * M;
        const float rNew = radius * std::sqrt(nNew / (n + M));
        const double shrink = double(rNew) * rNew / (double(radius) * radius);
        for (int c = 0; c < 3; ++c) tau[c] = (tau[c] + phi[c]) * shrink;
        n = nNew, radius = rNew;
    }
    /// The pixel after `iterations` iterations of `emitted` light paths in all:
    /// L = Ld / n + τ / (emitted · π R²).
    double estimate(int c, double iterations, double emitted) const {
        if (!(iterations > 0.0)) return 0.0;
        const double area = double(Pi) * radius * radius;
        return ld[c] / iterations + (area > 0.0 && emitted > 0.0 ? tau[c] / (emitted * area) : 0.0);
    }
};

class SppmCameraPass {
public:
    /// maxDepth < 0: unbounded (Mitsuba's max_depth; rrDepth as path's).
    SppmCameraPass(const Scene& scene, int maxDepth, int rrDepth, bool hideEmitters)
        : m_scene(scene), m_maxDepth(maxDepth < 0 ? std::numeric_limits<int>::max() : maxDepth),
          m_rrDepth(rrDepth), m_hideEmitters(hideEmitters),
          m_offset(scene.camera().film().cropOffset()) {}

    /// The camera path of pixel px (crop frame) at the iteration's wavelengths; the
    /// sampler has been started at this pixel and iteration. Returns the spectral Ld.
    SampledSpectrum trace(const Point2i& px, ISampler& sampler, const SampledWavelengths& lambda,
                          VisiblePoint& vp) const {
        vp.depth = 0;
        vp.lambda = lambda;
        SampledSpectrum L(0.f), beta(1.f);
        const Point2f pFilm = Point2f(px) + sampler.getPixel2D();
        Ray ray = m_scene.camera().generateRay({pFilm + m_offset, sampler.get2D(), 0.f}, vp.lambda, beta);
        float etaScale = 1.f;
        int nullCrossings = 0;
        SurfaceInteraction& si = vp.si;
        for (int depth = 1;;) {
            const bool seen = depth <= m_maxDepth && !(depth == 1 && m_hideEmitters);
            if (!m_scene.intersect(ray, si)) {
                if (seen)
                    for (const IEmitter* env : m_scene.environments()) L += beta * env->evalEnvironment(ray.d, vp.lambda);
                return L;
            }
            if (si.emitter && seen) L += beta * si.emitter->eval(si, vp.lambda);
            if (!si.bsdf) return L;
            const IBSDF& bsdf = *si.bsdf;
            const Vector3f wo = si.toLocal(si.wo);
            if (!bsdf.isPureSpecular()) {
                if (depth < m_maxDepth) {
                    vp.wo = wo, vp.beta = beta, vp.depth = depth;
                    L += atVisiblePoint(vp, sampler);
                }
                return L;
            }
            const float uc = sampler.get1D();
            const Point2f u = sampler.get2D();
            std::optional<BSDFSample> bs = bsdf.sample(si, wo, uc, u, vp.lambda, TransportMode::Radiance);
            if (!bs || !(bs->pdf > 0.f) || bs->f.isBlack()) return L;
            beta *= bs->f * (std::abs(bs->wi.z) / bs->pdf);
            if (bs->flags & BSDFNull) {  // straight on: not a bounce (as path_core.hpp)
                if (++nullCrossings > Scene::MaxNullCrossings) return L;
                ray = si.spawnRay(ray.d);
                continue;
            }
            if (depth >= m_maxDepth) return L;
            if (bs->isTransmission()) etaScale *= sqr(bs->eta);
            ray = si.spawnRay(si.toWorld(bs->wi));
            if (depth >= m_rrDepth) {
                const float q = std::min(beta.maxValue() * etaScale, 0.95f);
                if (sampler.get1D() >= q) return L;
                beta *= 1.f / q;
            }
            ++depth;
        }
    }

private:
    /// Direct light at the visible point (light sample + BSDF sample, MIS) and the delta
    /// lobes of a mixed BSDF by path tracing.
    SampledSpectrum atVisiblePoint(VisiblePoint& vp, ISampler& sampler) const {
        const SurfaceInteraction& si = vp.si;
        const IBSDF& bsdf = *si.bsdf;
        SampledSpectrum L(0.f);
        const float uLight = sampler.get1D();
        const Point2f uLight2 = sampler.get2D();
        if (auto ls = mis::sampleLight(m_scene, si, bsdf, vp.wo, uLight, uLight2, vp.lambda)) {
            const float w = ls->es.delta ? 1.f
                                         : mis::powerHeuristic(ls->pdf, bsdf.pdf(si, vp.wo, ls->wi, vp.lambda,
                                                                                 TransportMode::Radiance));
            SampledSpectrum tr = m_scene.hasNullBSDFs() ? m_scene.transmittance(ls->shadow, vp.lambda)
                                                        : SampledSpectrum(m_scene.occluded(ls->shadow) ? 0.f : 1.f);
            L += vp.beta * ls->f * ls->es.L * tr * (w / ls->pdf);
        }
        const float uc = sampler.get1D();
        const Point2f u = sampler.get2D();
        std::optional<BSDFSample> bs = bsdf.sample(si, vp.wo, uc, u, vp.lambda, TransportMode::Radiance);
        if (!bs || !(bs->pdf > 0.f) || bs->f.isBlack()) return L;
        const SampledSpectrum beta = vp.beta * bs->f * (std::abs(bs->wi.z) / bs->pdf);
        if (bs->isSpecular() || (bs->flags & BSDFNull)) {
            // The rest of the path by path tracing; a null crossing is not a bounce.
            const bool null = bs->flags & BSDFNull;
            const int left = m_maxDepth == std::numeric_limits<int>::max() ? -1 : m_maxDepth - vp.depth + (null ? 1 : 0);
            const Ray next = si.spawnRay(null ? -si.wo : si.toWorld(bs->wi));
            return L + beta * PathIntegrator(m_scene, left, m_rrDepth, false).li(next, vp.lambda, sampler);
        }
        // A non-delta sample: only the emission it hits (indirect light is the photons').
        const Vector3f d = si.toWorld(bs->wi);
        SurfaceInteraction hit;
        if (!m_scene.intersect(si.spawnRay(d), hit)) {
            for (const IEmitter* env : m_scene.environments()) {
                const float w = mis::powerHeuristic(bs->pdf, mis::environmentHitPdf(m_scene, *env, si.p, d));
                L += beta * env->evalEnvironment(d, vp.lambda) * w;
            }
        } else if (hit.emitter) {
            const float w = mis::powerHeuristic(bs->pdf, mis::emitterHitPdf(m_scene, si.p, hit));
            L += beta * hit.emitter->eval(hit, vp.lambda) * w;
        }
        return L;
    }

    const Scene& m_scene;
    int m_maxDepth, m_rrDepth;
    bool m_hideEmitters;
    Point2f m_offset;
};

} // namespace effigi
