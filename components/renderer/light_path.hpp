#pragma once
// The light-path walk shared by the renderers that trace paths from the lights: particle
// tracing (ptracer, whose vertices are connected to the camera) and photon tracing
// (photonmap, sppm, whose vertices leave photons). One emitter is chosen uniformly, as
// in Mitsuba 3 (Scene::sampleEmitter), a ray leaves it (IEmitter::sampleEmission) carrying the power
//     beta = L · |cos θ| / (p_select · p_position · p_direction)
// (no cosine for delta positions and infinite lights, whose rays need none), and the
// path is continued by BSDF sampling in importance transport mode. At every surface
// vertex a visitor sees the power arriving there *before* it scatters; the walk then
// scatters with the adjoint shading-normal correction |wo·ng · wi·ns| / |wo·ns · wi·ng|
// (Veach 1997, §5.3), ends paths that cross the geometric and shading hemispheres
// inconsistently, and plays Russian roulette from rr_depth on with the throughput's
// refraction scale η² removed (as path does), so paths inside glass are not killed for
// being "bright".
//
// Sampler dimensions, in order: emitter choice (1D), position (2D), direction (2D); then
// per vertex whatever the visitor draws, the BSDF sample (1D + 2D) and the roulette (1D).
// `beta` is radiometric power at the path's wavelengths, not yet divided by their pdf
// (cie::toXYZ and Photon do that); a dispersive interface may terminate the secondary
// wavelengths in `lambda` (their pdf becomes 0 and the hero's absorbs the factor 4).
// Reference: Veach 1997, PhD thesis, §4.A, §5.3; Jensen 2001, "Realistic Image Synthesis
// Using Photon Mapping", ch. 5 (photon emission and tracing); pbrt-v4 §13.1.
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/render/scene.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace effigi {

/// What the visitor of traceLightPath sees at a surface vertex.
struct LightVertex {
    const SurfaceInteraction& si;
    const IBSDF& bsdf;
    Vector3f wo;                       ///< local direction back toward the light side
    float woGeo;                       ///< dot(geometric normal, world wo)
    const SampledSpectrum& beta;       ///< power arriving at si, before it scatters
    const SampledWavelengths& lambda;  ///< the path's wavelengths (pdf 0: terminated)
    int depth;                         ///< segments from the light (1: lit directly)
    bool specularChain;                ///< every bounce before si took a delta lobe (true at depth 1)
};

/// The limits of a light path: max_depth (< 0: unbounded; a visit at depth d implies a
/// path of at least d + 1 segments once connected, so vertices stop at max_depth − 1) and
/// rr_depth (Russian roulette once the path has that many segments).
struct LightPathLimits {
    int maxDepth = -1;
    int rrDepth = 5;
};

/// One light path at wavelengths `lambda`; `visit(const LightVertex&)` returns false to
/// end the path there (e.g. photon tracing for a caustic map stops at its first diffuse
/// vertex).
template <typename Visitor>
void traceLightPath(const Scene& scene, ISampler& sampler, SampledWavelengths& lambda, const LightPathLimits& limits,
                    Visitor&& visit) {
    float selPdf;
    const IEmitter* emitter = scene.sampleEmitter(sampler.get1D(), selPdf);
    Point2f uPos = sampler.get2D(), uDir = sampler.get2D();
    if (!emitter) return;
    EmissionSample es = emitter->sampleEmission(uPos, uDir, lambda);
    if (!(es.pdfPosition > 0.f) || !(es.pdfDirection > 0.f) || es.L.isBlack()) return;
    // Power leaving along the ray: radiance · cos for surfaces; intensity (delta
    // positions) and infinite lights (rays through a disk facing them) need no cosine.
    float cosTheta = (emitter->flags() & EmitterSurface) ? std::abs(dot(es.n, es.ray.d)) : 1.f;
    SampledSpectrum beta = es.L * (cosTheta / (selPdf * es.pdfPosition * es.pdfDirection));
    const int maxDepth = limits.maxDepth;
    float eta = 1.f;
    bool specularChain = true;
    Ray ray = es.ray;
    SurfaceInteraction si;
    for (int depth = 1;; ++depth) {  // depth = segments traced so far
        if (!scene.intersect(ray, si) || !si.bsdf) return;
        if (maxDepth >= 0 && depth >= maxDepth) return;
        const IBSDF& bsdf = *si.bsdf;
        const Vector3f wo = si.toLocal(si.wo);
        const float woGeo = dot(si.n, si.wo);
        if (!visit(LightVertex{si, bsdf, wo, woGeo, beta, lambda, depth, specularChain})) return;

        float uc = sampler.get1D();
        Point2f u = sampler.get2D();
        std::optional<BSDFSample> bs = bsdf.sample(si, wo, uc, u, lambda, TransportMode::Importance);
        if (!bs || !(bs->pdf > 0.f) || bs->f.isBlack()) return;
        Vector3f wiWorld = si.toWorld(bs->wi);
        float wiGeo = dot(si.n, wiWorld);
        // Light leaks through shading normals: both sides must agree (Veach §5.3).
        if (!(woGeo * wo.z > 0.f) || !(wiGeo * bs->wi.z > 0.f)) return;
        float correction = std::abs(wo.z * wiGeo / (bs->wi.z * woGeo));
        beta *= bs->f * (std::abs(bs->wi.z) / bs->pdf * correction);
        if (bs->isTransmission()) eta *= bs->eta;
        specularChain = specularChain && (bs->isSpecular() || (bs->flags & BSDFNull));
        if (beta.isBlack()) return;
        if (maxDepth >= 0 && depth + 1 >= maxDepth) return;
        if (depth + 1 > limits.rrDepth) {
            float q = std::min(beta.maxValue() * eta * eta, 0.95f);
            if (!(sampler.get1D() < q)) return;
            beta *= 1.f / q;
        }
        ray = si.spawnRay(wiWorld);
    }
}

} // namespace effigi
