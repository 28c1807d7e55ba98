#pragma once
// What the renderers that combine light sampling and BSDF sampling (direct, path) share:
// the power heuristic, the unshadowed part of a light sample (next-event estimation), and
// the density with which light sampling would have produced a point that a BSDF sample
// hit, which is the other technique's density in multiple importance sampling.
// Reference: E. Veach, L. Guibas, "Optimally Combining Sampling Techniques for Monte Carlo
// Rendering", SIGGRAPH 1995; E. Veach, PhD thesis, 1997, ch. 9.
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/render/scene.hpp"

#include <cmath>
#include <optional>

namespace effigi::mis {

/// Power heuristic (β = 2) of technique a against b, 0 when both densities vanish.
inline float powerHeuristic(float a, float b) {
    float a2 = a * a, b2 = b * b;
    return a2 + b2 > 0.f ? a2 / (a2 + b2) : 0.f;
}

/// A light sample seen from a surface point, before its shadow ray is traced.
struct LightSample {
    EmitterSample es;   ///< what the emitter returned (world direction, radiance, delta)
    Vector3f wi;        ///< es.wi in the surface's local frame
    SampledSpectrum f;  ///< BSDF value times |cos θi| toward the light
    float pdf;          ///< emitter selection probability times es.pdf
    Ray shadow;         ///< from the surface to the sampled point (or off to infinity)
};

/// Chooses an emitter with uSel and a point on it with u, seen from si; nullopt where no
/// light can arrive (no emitter, zero density, black radiance or a black BSDF value).
inline std::optional<LightSample> sampleLight(const Scene& scene, const SurfaceInteraction& si, const IBSDF& bsdf,
                                              const Vector3f& wo, float uSel, const Point2f& u,
                                              const SampledWavelengths& lambda) {
    float selPdf;
    const IEmitter* emitter = scene.sampleEmitter(uSel, selPdf);
    if (!emitter) return std::nullopt;
    LightSample ls;
    ls.es = emitter->sampleDirect(si.p, u, lambda);
    if (!(ls.es.pdf > 0.f) || ls.es.L.isBlack()) return std::nullopt;
    ls.wi = si.toLocal(ls.es.wi);
    ls.f = bsdf.f(si, wo, ls.wi, lambda, TransportMode::Radiance) * std::abs(ls.wi.z);
    if (ls.f.isBlack()) return std::nullopt;
    ls.shadow = std::isinf(ls.es.dist) ? si.spawnRay(ls.es.wi) : si.spawnRayTo(ls.es.p);
    ls.pdf = selPdf * ls.es.pdf;
    return ls;
}

/// Density (selection times solid angle at `from`) with which sampleLight() would have
/// chosen the point `hit` on its emitter (hit.emitter must be set).
inline float emitterHitPdf(const Scene& scene, const Point3f& from, const SurfaceInteraction& hit) {
    return scene.emitterProbability(hit.emitter) * hit.emitter->pdfDirect(from, hit);
}

/// The same for the environment emitter `env` seen from `from` along the direction d.
inline float environmentHitPdf(const Scene& scene, const IEmitter& env, const Point3f& from, const Vector3f& d) {
    return scene.emitterProbability(&env) * env.pdfEnvironment(from, d);
}

} // namespace effigi::mis
