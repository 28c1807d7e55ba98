#include "effigi/render/scene.hpp"

#include <unordered_set>

#include "effigi/core/error.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/render/scene_range.hpp"

namespace effigi {

Scene::Scene(std::vector<Ref<IShape>> shapes, std::vector<Ref<IEmitter>> emitters, Ref<ICamera> camera,
             Ref<IIntersect> accel, Ref<IRenderer> renderer)
    : m_shapes(std::move(shapes)), m_emitters(std::move(emitters)), m_camera(std::move(camera)),
      m_accel(std::move(accel)), m_renderer(std::move(renderer)) {
    if (!m_camera) fail("scene has no camera");
    m_hasMedia = m_camera->medium() != nullptr;
    m_hasMotion = m_camera->moves();
    if (!m_accel) fail("scene has no accelerator");
    if (!m_renderer) fail("scene has no renderer");

    // The loader reports these with the file and line; this catches scenes built in code,
    // so that no accelerator ever sees an invalid ray (scene_range.hpp).
    if (std::string why = cameraRangeProblem(*m_camera); !why.empty()) fail("{}: {}", m_camera->typeName(), why);
    for (const auto& s : m_shapes) {
        if (std::string why = shapeRangeProblem(*s); !why.empty())
            fail("shape {} ({}): {}", m_shapePtrs.size(), s->typeName(), why);
        m_shapePtrs.push_back(s.get());
        m_bbox.expand(s->bbox());
        if (const IEmitter* e = s->emitter()) m_emitterPtrs.push_back(e);
        if (const IBSDF* b = s->bsdf(); b && b->hasNull()) m_hasNull = true;
        if (s->isMediumTransition()) m_hasMedia = true;
        if (s->moves()) m_hasMotion = true;
    }
    // A top-level emitter that a shape references (Mitsuba's <emitter id="x"/> ... <ref
    // id="x"/> inside a shape) is that shape's emitter: listing it twice would double its
    // selection probability and break the MIS weights.
    const std::unordered_set<const IEmitter*> attached(m_emitterPtrs.begin(), m_emitterPtrs.end());
    std::erase_if(m_emitters, [&](const Ref<IEmitter>& e) { return attached.count(e.get()) != 0; });
    for (const auto& e : m_emitters) {
        m_emitterPtrs.push_back(e.get());
        if (e->isInfinite()) m_envPtrs.push_back(e.get());
    }
    // Preprocess needs the bounds of everything, so it runs after all shapes are known.
    BBox3f bounds = m_bbox.valid() ? m_bbox : BBox3f(Point3f(-1.f), Point3f(1.f));
    for (auto& s : m_shapes)
        if (IEmitter* e = s->emitter()) e->preprocess(bounds);
    for (auto& e : m_emitters) e->preprocess(bounds);

    m_accel->build(m_shapePtrs);
}

SampledSpectrum Scene::transmittance(Ray ray, const SampledWavelengths& lambda) const {
    SampledSpectrum T(1.f);
    SurfaceInteraction si;
    for (int crossing = 0; crossing < MaxNullCrossings; ++crossing) {
        if (!intersect(ray, si)) return T;
        if (!si.bsdf || !si.bsdf->hasNull()) return SampledSpectrum(0.f);
        T *= si.bsdf->evalNullTransmission(si, lambda);
        if (T.isBlack()) return T;
        // On along the same line from just beyond the surface; the parameter left shrinks
        // by the distance covered (d is the same vector, so t values carry over).
        Ray next{si.offsetOrigin(ray.d), ray.d, ray.tMax - si.t, ray.time};
        if (!(next.tMax > 0.f)) return T;
        ray = next;
    }
    return SampledSpectrum(0.f);
}

} // namespace effigi
