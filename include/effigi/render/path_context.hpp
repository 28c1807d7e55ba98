#pragma once
// What the walks of path space and the strategies joining them share: the scene, the
// camera's importance, the finite emitters light subpaths start from, the depth limits,
// and the path generator whose densities the MIS weights need. Its pdf functions give,
// for any vertex, the area density with which either walk would produce its neighbour —
// the generator's pdfDirection at surfaces, the camera's and the emitters' densities at
// the ends (Veach 1997, §10.2).
#include "effigi/interfaces/icamera_importance.hpp"
#include "effigi/interfaces/ipathgenerator.hpp"
#include "effigi/math/transform.hpp"
#include "effigi/render/scene.hpp"

#include <string>
#include <vector>

namespace effigi {

struct PathContext {
    const Scene& scene;
    const ICameraImportance& camera;
    Transform cameraToLocal;               ///< the lens plane is z = 0 there
    std::vector<const IEmitter*> lights;   ///< finite emitters: where light subpaths start
    int maxDepth;                          ///< segments of the longest path
    int rrDepth;                           ///< segments after which Russian roulette may end walks
    const IPathGenerator& generator;

    /// Probability of choosing e as the start of a light subpath (or as the light of s = 1).
    float lightPdf(const IEmitter* e) const {
        return e && !e->isInfinite() && !lights.empty() ? 1.f / float(lights.size()) : 0.f;
    }

    /// Area density of a light subpath starting at v (an emitter point or area-light hit).
    float pdfLightOrigin(const PathVertex& v) const {
        float pdfPos = 0.f, pdfDir = 0.f;
        const IEmitter* e = v.emitter();
        if (!e || !e->pdfEmission(v.p(), v.si.n, Vector3f(v.si.n), pdfPos, pdfDir)) return 0.f;
        return lightPdf(e) * pdfPos;
    }
    /// Area density at `next` of the direction an emitter at v sends light toward it.
    float pdfLight(const PathVertex& v, const PathVertex& next) const {
        float pdfPos = 0.f, pdfDir = 0.f;
        Vector3f w = normalize(next.p() - v.p());
        if (!v.emitter()->pdfEmission(v.p(), v.si.n, w, pdfPos, pdfDir)) return 0.f;
        return v.toArea(pdfDir, next);
    }
    /// Area density at `next` of v's subpath continuing there, arriving from prev.
    float pdf(const PathVertex& v, const PathVertex* prev, const PathVertex& next,
              const SampledWavelengths& lambda) const {
        Vector3f wn = normalize(next.p() - v.p());
        switch (v.type) {
        case PathVertexType::Camera: return v.toArea(camera.pdfDirection(v.p(), wn), next);
        case PathVertexType::Light: return pdfLight(v, next);
        case PathVertexType::Surface: break;
        }
        if (!prev || !v.si.bsdf) return 0.f;
        Vector3f wp = normalize(prev->p() - v.p());
        float pdfDir = generator.pdfDirection(v.si, v.si.toLocal(wp), v.si.toLocal(wn), lambda,
                                              TransportMode::Radiance);
        return v.toArea(pdfDir, next);
    }

    /// The fraction of light that crosses from a to b: 0 or 1, or the null surfaces'
    /// transmittance in scenes that have them.
    SampledSpectrum transmittance(const PathVertex& a, const PathVertex& b, const SampledWavelengths& lambda) const {
        Vector3f d = b.p() - a.p();
        Point3f o = a.onSurface ? a.si.offsetOrigin(d) : a.p();
        Point3f target = b.onSurface ? b.si.offsetOrigin(-d) : b.p();
        Ray ray{o, target - o, 1.f - ShadowEpsilon, a.si.time};
        if (scene.hasNullBSDFs()) return scene.transmittance(ray, lambda);
        return SampledSpectrum(scene.occluded(ray) ? 0.f : 1.f);
    }
};

/// The context of a scene: its camera's importance (an error naming `who` for cameras
/// without a density of directions, e.g. orthographic) and the finite emitters light
/// subpaths start from. maxDepth < 0 (unbounded) still ends by Russian roulette; the
/// vertex arrays of pathological scenes (facing mirrors) are capped at 1024 segments.
PathContext makePathContext(const Scene& scene, int maxDepth, int rrDepth, const IPathGenerator& generator,
                            const std::string& who);

/// How a camera subpath left the scene: the environment seen along `ray` after the last
/// vertex, with the density of the direction chosen there (MIS against light sampling).
struct PathEscape {
    Ray ray;
    SampledSpectrum beta{0.f};
    float pdfDir = 0.f;
    bool delta = false;  ///< the direction came from a delta lobe (or the camera)
    int segments = 0;    ///< segments of the path once it reaches the environment
};

} // namespace effigi
