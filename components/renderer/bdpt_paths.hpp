#pragma once
// Subpaths of bidirectional path tracing: the camera subpath (radiance transport) and the
// light subpath (importance transport) are random walks by BSDF sampling that record at
// every vertex its forward density and, at the vertex before it, the reverse density
// (Veach 1997, §10.2). Light subpaths start at the finite emitters (area, point, spot,
// projector), chosen uniformly among them; infinite emitters (environment, constant,
// directional) light the scene through the camera-side strategies only (bdpt.cpp), as in
// the path tracer. Russian roulette from rr_depth on, on the throughput with refraction's
// radiance scale removed; it changes the throughput only, not the MIS densities, so every
// strategy stays unbiased.
#include "bdpt_vertex.hpp"

#include "effigi/interfaces/icamera_importance.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/render/scene.hpp"

#include <algorithm>
#include <optional>
#include <vector>

namespace effigi::bdpt {

/// What the strategies share: the scene, the camera's importance, the light choice.
struct Context {
    const Scene& scene;
    const ICameraImportance& camera;
    Transform cameraToLocal;               ///< the lens plane is z = 0 there
    std::vector<const IEmitter*> lights;   ///< finite emitters: where light subpaths start
    int maxDepth;                          ///< segments of the longest path
    int rrDepth;

    /// Probability of choosing e as the start of a light subpath (or as the light of s = 1).
    float lightPdf(const IEmitter* e) const {
        return e && !e->isInfinite() && !lights.empty() ? 1.f / float(lights.size()) : 0.f;
    }

    /// Area density of a light subpath starting at v (an emitter point or area-light hit).
    float pdfLightOrigin(const Vertex& v) const {
        float pdfPos = 0.f, pdfDir = 0.f;
        const IEmitter* e = v.emitter();
        if (!e || !e->pdfEmission(v.p(), v.si.n, Vector3f(v.si.n), pdfPos, pdfDir)) return 0.f;
        return lightPdf(e) * pdfPos;
    }
    /// Area density at `next` of the direction an emitter at v sends light toward it.
    float pdfLight(const Vertex& v, const Vertex& next) const {
        float pdfPos = 0.f, pdfDir = 0.f;
        Vector3f w = normalize(next.p() - v.p());
        if (!v.emitter()->pdfEmission(v.p(), v.si.n, w, pdfPos, pdfDir)) return 0.f;
        return v.toArea(pdfDir, next);
    }
    /// Area density at `next` of v's subpath continuing there, arriving from prev.
    float pdf(const Vertex& v, const Vertex* prev, const Vertex& next, const SampledWavelengths& lambda) const {
        Vector3f wn = normalize(next.p() - v.p());
        switch (v.type) {
        case VertexType::Camera: return v.toArea(camera.pdfDirection(v.p(), wn), next);
        case VertexType::Light: return pdfLight(v, next);
        case VertexType::Surface: break;
        }
        if (!prev || !v.si.bsdf) return 0.f;
        Vector3f wp = normalize(prev->p() - v.p());
        float pdfDir = v.si.bsdf->pdf(v.si, v.si.toLocal(wp), v.si.toLocal(wn), lambda, TransportMode::Radiance);
        return v.toArea(pdfDir, next);
    }

    /// The fraction of light that crosses from a to b: 0 or 1, or the null surfaces'
    /// transmittance in scenes that have them.
    SampledSpectrum transmittance(const Vertex& a, const Vertex& b, const SampledWavelengths& lambda) const {
        Vector3f d = b.p() - a.p();
        Point3f o = a.onSurface ? a.si.offsetOrigin(d) : a.p();
        Point3f target = b.onSurface ? b.si.offsetOrigin(-d) : b.p();
        Ray ray{o, target - o, 1.f - ShadowEpsilon};
        if (scene.hasNullBSDFs()) return scene.transmittance(ray, lambda);
        return SampledSpectrum(scene.occluded(ray) ? 0.f : 1.f);
    }
};

/// How a camera subpath left the scene: the environment seen along `ray` after the last
/// vertex, with the density of the direction chosen there (MIS against light sampling).
struct Escape {
    Ray ray;
    SampledSpectrum beta{0.f};
    float pdfDir = 0.f;
    bool delta = false;  ///< the direction came from a delta lobe (or the camera)
    int segments = 0;    ///< segments of the path once it reaches the environment
};

/// Extend `path` (which holds its start vertex) by BSDF sampling until it holds
/// maxVertices vertices, leaves the scene (recorded in *escape) or is ended.
inline void randomWalk(const Context& ctx, Ray ray, SampledSpectrum beta, float pdfDir, std::size_t maxVertices,
                       TransportMode mode, ISampler& sampler, SampledWavelengths& lambda, std::vector<Vertex>& path,
                       Escape* escape) {
    float etaScale = 1.f;
    bool lastDelta = path.back().type == VertexType::Camera;
    while (path.size() < maxVertices) {
        SurfaceInteraction si;
        if (!ctx.scene.intersect(ray, si)) {
            if (escape) *escape = Escape{ray, beta, pdfDir, lastDelta, int(path.size())};
            return;
        }
        path.push_back(Vertex::surface(si, beta));
        Vertex& v = path.back();
        Vertex& prev = path[path.size() - 2];
        v.pdfFwd = prev.toArea(pdfDir, v);
        if (path.size() >= maxVertices || !si.bsdf) return;

        const IBSDF& bsdf = *si.bsdf;
        const Vector3f wo = si.toLocal(si.wo);
        float uc = sampler.get1D();
        Point2f u = sampler.get2D();
        std::optional<BSDFSample> bs = bsdf.sample(si, wo, uc, u, lambda, mode);
        if (!bs || !(bs->pdf > 0.f) || bs->f.isBlack()) return;
        Vector3f wi = si.toWorld(bs->wi);
        float correction = mode == TransportMode::Importance ? shadingCorrection(si, si.wo, wi) : 1.f;
        beta *= bs->f * (std::abs(bs->wi.z) / bs->pdf * correction);
        pdfDir = bs->pdf;
        float pdfRevDir = bsdf.pdf(si, bs->wi, wo, lambda, mode);
        // Pass-through surfaces are delta transmissions here (each counts as a segment).
        lastDelta = bs->isSpecular() || (bs->flags & BSDFNull);
        if (lastDelta) {
            v.delta = true;
            pdfDir = pdfRevDir = 0.f;
        }
        if (bs->isTransmission()) etaScale *= sqr(bs->eta);
        prev.pdfRev = v.toArea(pdfRevDir, prev);
        if (beta.isBlack()) return;
        if (int(path.size()) - 1 >= ctx.rrDepth) {  // segments traced so far
            float q = std::min(beta.maxValue() * etaScale, 0.95f);
            if (!(sampler.get1D() < q)) return;
            beta *= 1.f / q;
        }
        ray = si.spawnRay(wi);
    }
}

/// The camera subpath of the camera ray `ray` (importance weight `weight`): up to
/// max_depth surface vertices after the camera's.
inline void cameraSubpath(const Context& ctx, const Ray& ray, const SampledSpectrum& weight, ISampler& sampler,
                          SampledWavelengths& lambda, std::vector<Vertex>& path, Escape& escape) {
    path.clear();
    escape = Escape{};
    // The vertex on the lens plane (z = 0): rays may start on the near clip plane.
    Vector3f dLocal = ctx.cameraToLocal.vector(ray.d);
    float t0 = std::abs(dLocal.z) > 0.f ? -ctx.cameraToLocal.point(ray.o).z / dLocal.z : 0.f;
    path.push_back(Vertex::camera(ray.o + ray.d * t0, weight));
    randomWalk(ctx, ray, weight, ctx.camera.pdfDirection(path[0].p(), ray.d), std::size_t(ctx.maxDepth) + 1,
               TransportMode::Radiance, sampler, lambda, path, &escape);
}

/// A light subpath: an emitter point and up to max_depth − 1 surface vertices.
inline void lightSubpath(const Context& ctx, ISampler& sampler, SampledWavelengths& lambda,
                         std::vector<Vertex>& path) {
    path.clear();
    float uSel = sampler.get1D();
    Point2f uPos = sampler.get2D(), uDir = sampler.get2D();
    if (ctx.lights.empty() || ctx.maxDepth < 1) return;
    const IEmitter* e = ctx.lights[std::min(std::size_t(uSel * float(ctx.lights.size())), ctx.lights.size() - 1)];
    EmissionSample es = e->sampleEmission(uPos, uDir, lambda);
    float sel = ctx.lightPdf(e);
    if (!(es.pdfPosition > 0.f) || !(es.pdfDirection > 0.f) || es.L.isBlack()) return;
    path.push_back(Vertex::emitterPoint(e, es.ray.o, es.n, es.L / (sel * es.pdfPosition), sel * es.pdfPosition));
    float cosTheta = (e->flags() & EmitterSurface) ? std::abs(dot(es.n, es.ray.d)) : 1.f;
    SampledSpectrum beta = es.L * (cosTheta / (sel * es.pdfPosition * es.pdfDirection));
    randomWalk(ctx, es.ray, beta, es.pdfDirection, std::size_t(ctx.maxDepth), TransportMode::Importance, sampler,
               lambda, path, nullptr);
}

} // namespace effigi::bdpt
