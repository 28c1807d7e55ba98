// emitter "projector" — a slide projector: a point light that throws an image onto
// the scene through a pinhole.
//
// The image spans a perspective frustum around the light's local +z (Mitsuba's camera
// conventions: +x is image LEFT, +y image up; the field of view as for the perspective
// camera, the other axis following the image's aspect ratio). A point q in the light's
// frame with q.z > 0 reads the texture at
//   uv = (½ − ½ q.x / (q.z tan(fov_x/2)),  ½ − ½ q.y / (q.z tan(fov_y/2)))
// Mitsuba's normalisation: the intensity toward q is I = π · scale · texture(uv) / cos³θ
// (θ from the axis), so that the plane z = 1 receives the irradiance
// E = I cos θ / dist² = π · scale · texture(uv) everywhere in the image. Outside the
// frustum it is dark.
//
// Parameters (Mitsuba 3's `projector`):
//   irradiance    texture (default 1)  the projected image (a nested texture such as
//                 bitmap; RGB constants are illuminant spectra)
//   scale         float ≥ 0 (default 1)  factor on the irradiance
//   fov, fov_axis, focal_length   field of view, as for the perspective camera (default
//                 a 50 mm lens); the aspect ratio is the texture's resolution
//   to_world      transform  position (translation) and aim (local +z)
//
// Reference: Mitsuba 3 `projector`.
#include "../camera/projection.hpp"
#include "delta_light.hpp"
#include "effigi/core/log.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/interfaces/itexture_resolution.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/render/scene_range.hpp"
#include "effigi/spectral/emission_scale.hpp"

namespace effigi {
namespace {

class ProjectorEmitter final : public Implements<IEmitter> {
public:
    static Schema schema() {
        Schema s("emitter", "projector", "Projector: a point light throwing an image through a pinhole.");
        s.cite("Mitsuba 3 'projector' emitter");
        s.texture("irradiance", 1.f, SpectrumKind::Illuminant, "Projected image (irradiance on the plane z = 1 / π)")
            .atLeast(0.0);
        s.real("scale", 1.0, "Factor on the irradiance").atLeast(0.0);
        camera::addFovParams(s, 0.0);
        s.transform("to_world", "Position (translation) and aim (local +z) of the projector");
        s.ignored("sampling_weight", "lights are chosen by effigi's own selection rule (noise only)");
        // Cases of the emitter conformance suite (conformance/emitter_suite.cpp) and
        // tests/test_emitters_extra.cpp, extremes included.
        s.addConformance({"default", {}});
        s.addConformance({"narrow", {{"fov", 1e-2}}});
        s.addConformance({"wide", {{"fov", 179.0}}});
        s.addConformance({"dark", {{"scale", 0.0}}});
        return s;
    }

    explicit ProjectorEmitter(const Properties& p)
        : m_irradiance(p.getTexture("irradiance", SpectrumKind::Illuminant)), m_scale(p.getFloat("scale")) {
        Transform toWorld = p.getTransform("to_world");
        if (!toWorld.isFinite() || glm::determinant(glm::mat3(toWorld.matrix())) == 0.f)
            failAt(p.whereOf("to_world"), "{}: to_world must be finite and invertible", p.describe());
        m_toWorld = toWorld;
        m_toLocal = toWorld.inverse();
        m_position = toWorld.point(Point3f(0.f));
        if (!inSceneRange(m_position))
            failAt(p.whereOf("to_world"), "{}: the position is beyond effigi's coordinate range ±{:g}", p.describe(),
                   MaxSceneCoordinate);
        m_axis = normalize(toWorld.vector(Vector3f(0.f, 0.f, 1.f)));
        // The irradiance it casts is π · scale · texture (see above).
        checkEmittedPeak(p, "irradiance", double(Pi) * double(m_irradiance->maxValue()), double(m_scale));
        Vector2i res(1);
        if (auto* r = query<ITextureResolution>(static_cast<IComponent*>(m_irradiance.get())))
            res = r->resolution();
        else if (!m_irradiance->isConstant())
            log::warn("{}: texture {} does not report its resolution; assuming a square image", p.describe(),
                      m_irradiance->typeName());
        if (res.x <= 0 || res.y <= 0)
            failAt(p.whereOf("irradiance"), "{}: the irradiance texture has an empty size", p.describe());
        m_half = camera::imagePlaneHalfExtent(p, Vector2f(res));
    }

    std::uint32_t flags() const override { return EmitterDeltaPosition; }

    EmitterSample sampleDirect(const Point3f& ref, const Point2f&, const SampledWavelengths& lambda) const override {
        EmitterSample es;
        if (delta_light::sampleGeometry(ref, m_position, es) == 0.f) return es;
        es.n = m_axis;
        Point3f q = m_toLocal.point(ref);
        float cosTheta = dot(m_axis, -es.wi);
        Point2f uv;
        if (!(q.z > 0.f) || !(cosTheta > 0.f) || !toUV(q, uv)) return es;
        es.pdf = 1.f;
        es.delta = true;
        es.L = m_irradiance->eval(lookup(uv), lambda) * (Pi * m_scale / (q.z * q.z * cosTheta));
        return es;
    }

    EmissionSample sampleEmission(const Point2f&, const Point2f& uDir, const SampledWavelengths& lambda) const override {
        // A uniform point of the image rectangle at z = 1, mapped to a direction; its
        // solid-angle density is the area density times dist³ (distance² / cos θ, with
        // cos θ = 1 / dist).
        Point2f uv = uDir;
        Vector3f local((1.f - 2.f * uv.x) * m_half.x, (1.f - 2.f * uv.y) * m_half.y, 1.f);
        float dist = length(local);
        Vector3f d = normalize(m_toWorld.vector(local / dist));
        float dist3 = dist * dist * dist;
        // Intensity toward the direction: π · scale · texture / cos³θ.
        return delta_light::emissionSample(m_position, d, m_axis, dist3 / (4.f * m_half.x * m_half.y),
                                           m_irradiance->eval(lookup(uv), lambda) * (Pi * m_scale * dist3));
    }

    /// sampleEmission's density: uniform over the image rectangle at z = 1, dist³ / (4 hx hy).
    bool pdfEmission(const Point3f&, const Normal3f&, const Vector3f& d, float& pdfPosition,
                     float& pdfDirection) const override {
        pdfPosition = 1.f;
        pdfDirection = 0.f;
        Vector3f local = m_toLocal.vector(d);
        if (!(local.z > 0.f)) return true;
        Vector3f plane = local / local.z;
        if (!(std::abs(plane.x) <= m_half.x && std::abs(plane.y) <= m_half.y)) return true;
        float dist = length(plane);
        pdfDirection = dist * dist * dist / (4.f * m_half.x * m_half.y);
        return true;
    }

    /// Φ ≈ π · scale · mean texture · (area of the image at unit distance): the flux
    /// through the plane z = 1 (only used to weigh lights).
    float power() const override { return Pi * m_scale * m_irradiance->mean() * 4.f * m_half.x * m_half.y; }

private:
    bool toUV(const Point3f& q, Point2f& uv) const {
        uv = Point2f(0.5f - 0.5f * q.x / (q.z * m_half.x), 0.5f - 0.5f * q.y / (q.z * m_half.y));
        return uv.x >= 0.f && uv.x <= 1.f && uv.y >= 0.f && uv.y <= 1.f;
    }

    SurfaceInteraction lookup(const Point2f& uv) const {
        SurfaceInteraction si;
        si.p = m_position;
        si.uv = uv;
        return si;
    }

    Ref<ITexture> m_irradiance;
    float m_scale = 1.f;
    Transform m_toWorld, m_toLocal;
    Point3f m_position{0.f};
    Vector3f m_axis{0.f, 0.f, 1.f};
    Vector2f m_half{1.f};
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::ProjectorEmitter)
