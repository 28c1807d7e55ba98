#pragma once
// The assembled scene: shapes, emitters, one accelerator, one camera and a renderer.
// Built by the loader; read-only while rendering.
#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/iintersect.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/interfaces/ishape.hpp"

#include <span>
#include <string>
#include <vector>

namespace effigi {

class Scene {
public:
    /// Emitters attached to shapes are collected from the shapes; `emitters` holds the
    /// free-standing ones (point, constant, ...). Builds the accelerator.
    Scene(std::vector<Ref<IShape>> shapes, std::vector<Ref<IEmitter>> emitters, Ref<ICamera> camera,
          Ref<IIntersect> accel, Ref<IRenderer> renderer);

    /// Closest hit, as a full surface interaction.
    bool intersect(const Ray& ray, SurfaceInteraction& si) const {
        Hit hit;
        if (!m_accel->intersect(ray, hit)) return false;
        si = m_shapePtrs[hit.shape]->interaction(ray, hit);
        si.time = ray.time;
        return true;
    }
    bool occluded(const Ray& ray) const { return m_accel->occluded(ray); }
    /// A batch of closest-hit queries (the accelerator's packet path); hits[i].valid() is
    /// false on a miss. Turn a hit into a surface interaction with interaction().
    void intersect(std::span<const Ray> rays, std::span<Hit> hits) const { m_accel->intersect(rays, hits); }
    /// A batch of shadow rays: blocked[i] = 1 if rays[i] hits anything.
    void occluded(std::span<const Ray> rays, std::span<std::uint8_t> blocked) const { m_accel->occluded(rays, blocked); }
    SurfaceInteraction interaction(const Ray& ray, const Hit& hit) const {
        SurfaceInteraction si = m_shapePtrs[hit.shape]->interaction(ray, hit);
        si.time = ray.time;
        return si;
    }

    /// True if some shape's BSDF has a pass-through (BSDFNull) lobe (null, mask): only
    /// then do shadow rays need transmittance() instead of occluded().
    bool hasNullBSDFs() const { return m_hasNull; }
    /// What a shadow ray keeps on its way (up to ray.tMax): the product of
    /// evalNullTransmission() over the null / mask surfaces it crosses, zero at the first
    /// opaque one. After MaxNullCrossings crossings the ray counts as blocked (so
    /// nothing loops forever; a real scene never stacks that many).
    SampledSpectrum transmittance(Ray ray, const SampledWavelengths& lambda) const;
    static constexpr int MaxNullCrossings = 256;
    /// True if a shape bounds a participating medium or the camera is inside one: only
    /// `volpath` renders media; other renderers refuse such scenes or ignore the media.
    bool hasMedia() const { return m_hasMedia; }
    /// True if a shape or the camera moves during the shutter interval: only renderers
    /// that time every ray (IRenderer::rendersMotion) render such a scene.
    bool hasMotion() const { return m_hasMotion; }

    /// Pick an emitter uniformly (as Mitsuba 3 does);
    /// returns null when the scene has none.
    const IEmitter* sampleEmitter(float u, float& prob) const {
        if (m_emitterPtrs.empty()) return (prob = 0.f, nullptr);
        std::size_t n = m_emitterPtrs.size();
        std::size_t i = std::min(std::size_t(u * float(n)), n - 1);
        prob = 1.f / float(n);
        return m_emitterPtrs[i];
    }
    float emitterProbability(const IEmitter*) const {
        return m_emitterPtrs.empty() ? 0.f : 1.f / float(m_emitterPtrs.size());
    }

    const std::vector<const IShape*>& shapes() const { return m_shapePtrs; }
    const std::vector<const IEmitter*>& emitters() const { return m_emitterPtrs; }
    const std::vector<const IEmitter*>& environments() const { return m_envPtrs; }
    const IIntersect& accelerator() const { return *m_accel; }
    ICamera& camera() const { return *m_camera; }
    IRenderer& renderer() const { return *m_renderer; }
    const BBox3f& bbox() const { return m_bbox; }

    /// Where the scene came from (EXR metadata, error messages).
    std::string sourceFile;

private:
    std::vector<Ref<IShape>> m_shapes;
    std::vector<Ref<IEmitter>> m_emitters;
    Ref<ICamera> m_camera;
    Ref<IIntersect> m_accel;
    Ref<IRenderer> m_renderer;
    std::vector<const IShape*> m_shapePtrs;
    std::vector<const IEmitter*> m_emitterPtrs, m_envPtrs;
    BBox3f m_bbox;
    bool m_hasNull = false;
    bool m_hasMedia = false;
    bool m_hasMotion = false;
};

} // namespace effigi
