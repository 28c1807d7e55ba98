// emitter "directional" — a distant light: parallel rays from a single direction.
//
// Models a source so far away (the sun, roughly) that every point of the scene sees it
// in the same direction and receives the same irradiance E on a surface facing it; a
// surface tilted by θ receives E·cosθ, independent of position. It is a delta light in
// direction: it is reached only by sampling it, never by a ray that happens to escape.
// Emission samples start on a disk just outside the scene's bounding sphere, as Mitsuba
// 3's `directional` does, so light tracing covers the whole scene with parallel rays.
//
// Parameters (Mitsuba 3's `directional`):
//   irradiance  spectrum (illuminant, default 1)  irradiance on a surface facing the
//               light [W m^-2]; must be constant (no textures)
//   direction   vector   direction the light TRAVELS in (alternative to to_world)
//   to_world    transform  the light travels along to_world · (0, 0, 1)
//   scale       float ≥ 0 (default 1)  factor on the irradiance (effigi extension)
//   luminance   float ≥ 0 (optional)   scale the irradiance to this illuminance-like Y
//
// Reference: pbrt-v4 §12.4 (distant lights); Mitsuba 3 `directional`.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/render/scene_sphere.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/emission_scale.hpp"
#include "effigi/spectral/spectrum.hpp"

namespace effigi {
namespace {

class DirectionalEmitter final : public Implements<IEmitter> {
public:
    static Schema schema() {
        Schema s("emitter", "directional", "Distant light: parallel rays from one direction.");
        s.cite("M. Pharr, W. Jakob, G. Humphreys, Physically Based Rendering, 4th ed., §12.4");
        s.spectrum("irradiance", 1.f, SpectrumKind::Illuminant, "Irradiance on a surface facing the light")
            .atLeast(0.0)
            .withUnit("W m^-2");
        s.optional("direction", ParamType::Vector, "Direction the light travels in (or give to_world instead)");
        s.transform("to_world", "The light travels along to_world · (0, 0, 1)");
        EmissionScale::declare(s, "Scale the irradiance to this luminance Y", "W m^-2", "");
        s.ignored("sampling_weight", "lights are chosen by effigi's own selection rule (noise only)");
        // Cases of the emitter conformance suite (conformance/emitter_suite.cpp) and
        // tests/test_emitters_extra.cpp, extremes included.
        s.addConformance({"default", {}});
        s.addConformance({"grazing tilted", {{"direction", VectorValue{Vector3f(1.f, 0.f, -1e-3f)}}}});
        s.addConformance({"dark", {{"irradiance", 0.0}}});
        s.addConformance({"huge", {{"irradiance", 1e6}}});
        return s;
    }

    explicit DirectionalEmitter(const Properties& p)
        : m_irradiance(p.getSpectrum("irradiance", SpectrumKind::Illuminant)) {
        const Properties::Entry* toWorld = p.find("to_world");
        Vector3f d;
        if (p.has("direction")) {
            if (toWorld && !toWorld->fromDefault)
                failAt(p.whereOf("direction"), "{}: give either 'direction' or 'to_world', not both", p.describe());
            d = p.getVector("direction");
        } else {
            d = p.getTransform("to_world").vector(Vector3f(0.f, 0.f, 1.f));
        }
        const char* where = p.has("direction") ? "direction" : "to_world";
        if (!isFinite(d) || !(lengthSquared(d) > 0.f))
            failAt(p.whereOf(where), "{}: the direction must be finite and non-zero", p.describe());
        m_direction = normalize(d);
        m_irradiance =
            m_irradiance.scaled(EmissionScale(p, false, "irradiance").factor(m_irradiance, 0.f, m_irradiance.maxValue()));
        m_luminance = cie::luminance(m_irradiance);
    }

    std::uint32_t flags() const override { return EmitterDeltaDirection | EmitterInfinite; }

    void preprocess(const BBox3f& bounds) override { m_sphere = SceneSphere::around(bounds); }

    EmitterSample sampleDirect(const Point3f& ref, const Point2f&, const SampledWavelengths& lambda) const override {
        EmitterSample es;
        es.wi = -m_direction;
        es.p = m_sphere.beyond(ref, es.wi);
        es.n = m_direction;
        es.dist = Infinity;
        es.pdf = 1.f;
        es.delta = true;
        es.L = m_irradiance.sample(lambda);
        return es;
    }

    // A delta direction is never hit by an escaping ray: evalEnvironment stays 0.

    EmissionSample sampleEmission(const Point2f& uPos, const Point2f&, const SampledWavelengths& lambda) const override {
        EmissionSample es;
        es.ray = m_sphere.parallelRay(m_direction, uPos);
        es.n = m_direction;
        es.pdfPosition = 1.f / m_sphere.area();
        es.pdfDirection = 1.f;
        es.L = m_irradiance.sample(lambda);
        return es;
    }

    /// Flux through the scene's cross-section, π r² · E (only used to weigh lights).
    float power() const override { return m_sphere.area() * m_luminance; }

private:
    Spectrum m_irradiance;
    Vector3f m_direction{0.f, 0.f, 1.f};
    SceneSphere m_sphere;
    float m_luminance = 0.f;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::DirectionalEmitter)
