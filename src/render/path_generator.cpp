// The default walks of IPathGenerator (include/effigi/interfaces/ipathgenerator.hpp):
// random walks by the generator's sampleDirection that record at every vertex its forward
// density and, at the vertex before it, the reverse density (Veach 1997, §10.2). Light
// subpaths start at the finite emitters (area, point, spot, projector), chosen uniformly;
// infinite emitters light the scene through the camera-side strategies only. Russian
// roulette from rr_depth on, on the throughput with refraction's radiance scale removed;
// it changes the throughput only, not the MIS densities, so every strategy stays
// unbiased.
#include "effigi/core/error.hpp"
#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/ipathgenerator.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/render/path_context.hpp"

#include <algorithm>
#include <cmath>

namespace effigi {

PathContext makePathContext(const Scene& scene, int maxDepth, int rrDepth, const IPathGenerator& generator,
                            const std::string& who) {
    constexpr int UnboundedDepth = 1024;
    ICamera& camera = scene.camera();
    const auto* importance = query<ICameraImportance>(&camera);
    if (!importance || !(importance->pdfDirection(camera.toWorld().point(Point3f(0.f)),
                                                  camera.toWorld().vector(Vector3f(0.f, 0.f, 1.f))) > 0.f))
        fail("{}: {} needs a camera with a density of directions (perspective or thinlens), not '{}'",
             scene.sourceFile, who, camera.typeName());
    // Light paths reach the camera through its importance, which knows one pose only.
    if (camera.moves())
        fail("{}: {} does not render a moving camera (an animated to_world); moving shapes are fine",
             scene.sourceFile, who);
    PathContext ctx{scene,   *importance, camera.toWorld().inverse(), {}, maxDepth < 0 ? UnboundedDepth : maxDepth,
                    rrDepth, generator};
    for (const IEmitter* e : scene.emitters())
        if (!e->isInfinite()) ctx.lights.push_back(e);
    return ctx;
}

void IPathGenerator::randomWalk(const PathContext& ctx, Ray ray, SampledSpectrum beta, float pdfDir,
                                std::size_t maxVertices, TransportMode mode, ISampler& sampler,
                                SampledWavelengths& lambda, std::vector<PathVertex>& path, PathEscape* escape) const {
    float etaScale = 1.f;
    bool lastDelta = path.back().type == PathVertexType::Camera;
    while (path.size() < maxVertices) {
        SurfaceInteraction si;
        if (!ctx.scene.intersect(ray, si)) {
            if (escape) *escape = PathEscape{ray, beta, pdfDir, lastDelta, int(path.size())};
            return;
        }
        path.push_back(PathVertex::surface(si, beta));
        PathVertex& v = path.back();
        PathVertex& prev = path[path.size() - 2];
        v.pdfFwd = prev.toArea(pdfDir, v);
        if (path.size() >= maxVertices || !si.bsdf) return;

        const Vector3f wo = si.toLocal(si.wo);
        float uc = sampler.get1D();
        Point2f u = sampler.get2D();
        std::optional<BSDFSample> bs = sampleDirection(si, wo, uc, u, lambda, mode);
        if (!bs || !(bs->pdf > 0.f) || bs->f.isBlack()) return;
        Vector3f wi = si.toWorld(bs->wi);
        float correction = mode == TransportMode::Importance ? shadingCorrection(si, si.wo, wi) : 1.f;
        beta *= bs->f * (std::abs(bs->wi.z) / bs->pdf * correction);
        pdfDir = bs->pdf;
        float pdfRevDir = pdfDirection(si, bs->wi, wo, lambda, mode);
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

void IPathGenerator::cameraSubpath(const PathContext& ctx, const Ray& ray, const SampledSpectrum& weight,
                                   ISampler& sampler, SampledWavelengths& lambda, std::vector<PathVertex>& path,
                                   PathEscape& escape) const {
    path.clear();
    escape = PathEscape{};
    // The vertex on the lens plane (z = 0): rays may start on the near clip plane.
    Vector3f dLocal = ctx.cameraToLocal.vector(ray.d);
    float t0 = std::abs(dLocal.z) > 0.f ? -ctx.cameraToLocal.point(ray.o).z / dLocal.z : 0.f;
    path.push_back(PathVertex::camera(ray.o + ray.d * t0, weight));
    path.back().si.time = ray.time;
    randomWalk(ctx, ray, weight, ctx.camera.pdfDirection(path[0].p(), ray.d), std::size_t(ctx.maxDepth) + 1,
               TransportMode::Radiance, sampler, lambda, path, &escape);
}

void IPathGenerator::lightSubpath(const PathContext& ctx, float time, ISampler& sampler, SampledWavelengths& lambda,
                                  std::vector<PathVertex>& path) const {
    path.clear();
    float uSel = sampler.get1D();
    Point2f uPos = sampler.get2D(), uDir = sampler.get2D();
    if (ctx.lights.empty() || ctx.maxDepth < 1) return;
    const IEmitter* e = ctx.lights[std::min(std::size_t(uSel * float(ctx.lights.size())), ctx.lights.size() - 1)];
    EmissionSample es = e->sampleEmission(uPos, uDir, lambda);
    es.ray.time = time;
    float sel = ctx.lightPdf(e);
    if (!(es.pdfPosition > 0.f) || !(es.pdfDirection > 0.f) || es.L.isBlack()) return;
    path.push_back(PathVertex::emitterPoint(e, es.ray.o, es.n, es.L / (sel * es.pdfPosition), sel * es.pdfPosition));
    path.back().si.time = time;
    float cosTheta = (e->flags() & EmitterSurface) ? std::abs(dot(es.n, es.ray.d)) : 1.f;
    SampledSpectrum beta = es.L * (cosTheta / (sel * es.pdfPosition * es.pdfDirection));
    randomWalk(ctx, es.ray, beta, es.pdfDirection, std::size_t(ctx.maxDepth), TransportMode::Importance, sampler,
               lambda, path, nullptr);
}

} // namespace effigi
