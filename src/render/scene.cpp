#include "effigi/render/scene.hpp"

#include "effigi/core/error.hpp"

namespace effigi {

Scene::Scene(std::vector<Ref<IShape>> shapes, std::vector<Ref<IEmitter>> emitters, Ref<ICamera> camera,
             Ref<IIntersect> accel, Ref<IRenderer> renderer)
    : m_shapes(std::move(shapes)), m_emitters(std::move(emitters)), m_camera(std::move(camera)),
      m_accel(std::move(accel)), m_renderer(std::move(renderer)) {
    if (!m_camera) fail("scene has no camera");
    if (!m_accel) fail("scene has no accelerator");
    if (!m_renderer) fail("scene has no renderer");

    for (const auto& s : m_shapes) {
        m_shapePtrs.push_back(s.get());
        m_bbox.expand(s->bbox());
        if (const IEmitter* e = s->emitter()) m_emitterPtrs.push_back(e);
    }
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

} // namespace effigi
