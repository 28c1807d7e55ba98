#pragma once
// One sample of bidirectional path tracing: a camera subpath, a light subpath, every
// strategy (s, t) joining them (bdpt_connect.hpp), and the environment's two strategies.
// Shared by renderer `bdpt` (film, strategy channels) and by `pssmlt`'s bidirectional
// inner estimator, which reads the camera subpath, the light subpath and the
// connections from separate streams of primary sample space (`startStream(k)`, k = 0, 1,
// 2; a no-op for ordinary samplers).
// Infinite emitters cannot start light subpaths (their densities are not area
// densities): they are found by the camera subpath leaving the scene (s = 0) and sampled
// from each camera vertex (s = 1), the two weighted by the power heuristic, as in path.
#include "bdpt_connect.hpp"
#include "mis.hpp"

#include <vector>

namespace effigi::bdpt {

/// Per-thread storage of the two subpaths.
struct Subpaths {
    std::vector<Vertex> camera, light;
};

/// The environment's contributions to a camera subpath, each reported as sink(s, t, L).
template <typename Sink>
void environment(const Context& ctx, bool hideEmitters, const std::vector<Vertex>& cam, const Escape& escape,
                 ISampler& sampler, const SampledWavelengths& lambda, Sink&& sink) {
    const Scene& scene = ctx.scene;
    const std::vector<const IEmitter*>& envs = scene.environments();
    if (envs.empty()) return;
    const float selEnv = 1.f / float(envs.size());
    if (!escape.beta.isBlack() && escape.segments <= ctx.maxDepth && !(escape.segments == 1 && hideEmitters)) {
        for (const IEmitter* env : envs) {
            float w = escape.delta ? 1.f
                                   : mis::powerHeuristic(escape.pdfDir,
                                                         selEnv * env->pdfEnvironment(escape.ray.o, escape.ray.d));
            sink(0, escape.segments + 1, escape.beta * env->evalEnvironment(escape.ray.d, lambda) * w);
        }
    }
    for (std::size_t i = 1; i < cam.size() && int(i) + 1 <= ctx.maxDepth; ++i) {
        const Vertex& v = cam[i];
        float uSel = sampler.get1D();
        Point2f u = sampler.get2D();
        if (!v.connectible()) continue;
        const IEmitter* env = envs[std::min(std::size_t(uSel * float(envs.size())), envs.size() - 1)];
        EmitterSample es = env->sampleDirect(v.p(), u, lambda);
        if (!(es.pdf > 0.f) || es.L.isBlack()) continue;
        const Vector3f wo = v.si.toLocal(v.si.wo), wi = v.si.toLocal(es.wi);
        SampledSpectrum f = v.si.bsdf->f(v.si, wo, wi, lambda, TransportMode::Radiance) * std::abs(wi.z);
        if (f.isBlack()) continue;
        Ray shadow = v.si.spawnRay(es.wi);
        SampledSpectrum tr = scene.hasNullBSDFs() ? scene.transmittance(shadow, lambda)
                                                  : SampledSpectrum(scene.occluded(shadow) ? 0.f : 1.f);
        float pdfLight = selEnv * es.pdf;
        float w = es.delta ? 1.f
                           : mis::powerHeuristic(pdfLight, ctx.generator.pdfDirection(v.si, wo, wi, lambda,
                                                                                      TransportMode::Radiance));
        sink(1, int(i) + 1, v.beta * f * es.L * tr * (w / pdfLight));
    }
}

/// Every strategy of the camera ray `ray` (importance weight `weight`). Camera-side
/// contributions go to sink(s, t, L); light-tracing ones (t = 1) to splat(s, L, pFilm),
/// pFilm in full-film pixels. All walks end before the first contribution is reported,
/// so `lambda` (which dispersion may change) is final by then.
template <typename StartStream, typename Sink, typename Splat>
void sample(const Context& ctx, bool hideEmitters, const Ray& ray, const SampledSpectrum& weight, ISampler& sampler,
            SampledWavelengths& lambda, Subpaths& paths, StartStream&& startStream, Sink&& sink, Splat&& splat) {
    std::vector<Vertex>& cam = paths.camera;
    std::vector<Vertex>& light = paths.light;
    Escape escape;
    ctx.generator.cameraSubpath(ctx, ray, weight, sampler, lambda, cam, escape);
    startStream(1);
    ctx.generator.lightSubpath(ctx, ray.time, sampler, lambda, light);
    startStream(2);
    environment(ctx, hideEmitters, cam, escape, sampler, lambda, sink);
    const int nCam = int(cam.size()), nLight = int(light.size());
    for (int t = 1; t <= nCam; ++t) {
        for (int s = 0; s <= nLight; ++s) {
            if (s + t < 2 || (s == 1 && t == 1) || s + t - 1 > ctx.maxDepth) continue;
            if (s == 0 && t == 2 && hideEmitters) continue;
            Point2f pFilm;
            SampledSpectrum L = connect(ctx, light.data(), cam.data(), s, t, sampler, lambda, pFilm);
            if (L.isBlack()) continue;
            if (t != 1) sink(s, t, L);
            else splat(s, L, pFilm);
        }
    }
}

} // namespace effigi::bdpt
