// emitter "constant" — a uniform environment: the same radiance from every direction.
//
// Models a sky of constant radiance L surrounding the scene at infinity (a "white
// furnace" when L = 1 and every BSDF has albedo 1). An unoccluded surface facing it
// receives irradiance E = π·L. Direct lighting samples directions uniformly over the
// sphere; emission samples start on a disk outside the scene's bounding sphere so that
// light tracing covers the whole scene with parallel rays.
//
// Parameters:
//   radiance   spectrum (illuminant, default 1)  radiance of the environment [W m^-2 sr^-1]
//   scale      float ≥ 0 (default 1)  factor on the radiance
//   luminance  float ≥ 0 (optional)   scale the radiance to this luminance Y
//   power      not supported (an environment at infinity has no finite power): an error
//
// Reference: pbrt-v4 §12.5.1 (uniform infinite lights).
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/render/scene_sphere.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/emission_scale.hpp"
#include "effigi/spectral/spectrum.hpp"

namespace effigi {
namespace {

class ConstantEmitter final : public Implements<IEmitter> {
public:
    static Schema schema() {
        Schema s("emitter", "constant", "Uniform environment light: constant radiance from every direction.");
        s.cite("M. Pharr, W. Jakob, G. Humphreys, Physically Based Rendering, 4th ed., §12.5.1");
        s.spectrum("radiance", 1.f, SpectrumKind::Illuminant, "Radiance arriving from every direction")
            .atLeast(0.0)
            .withUnit("W m^-2 sr^-1");
        EmissionScale::declare(s, "Scale the radiance to this luminance", "W m^-2 sr^-1", "");
        // Mitsuba's emitters take a light-selection weight; effigi picks lights by its own
        // rule, which changes noise only, never the expected image.
        s.ignored("sampling_weight", "lights are chosen by effigi's own selection rule");
        // Cases of the emitter conformance suite (conformance/emitter_suite.cpp), extremes included.
        s.addConformance({"default", {}});
        s.addConformance({"tiny", {{"radiance", 1e-6}}});
        s.addConformance({"huge", {{"radiance", 1e6}}});
        s.addConformance({"dark", {{"radiance", 0.0}}});
        return s;
    }

    explicit ConstantEmitter(const Properties& p) : m_radiance(p.getSpectrum("radiance", SpectrumKind::Illuminant)) {
        m_radiance = m_radiance.scaled(EmissionScale(p, false, "radiance").factor(m_radiance, 0.f, m_radiance.maxValue()));
        m_luminance = cie::luminance(m_radiance);
    }

    std::uint32_t flags() const override { return EmitterInfinite; }

    void preprocess(const BBox3f& bounds) override { m_sphere = SceneSphere::around(bounds); }

    EmitterSample sampleDirect(const Point3f& ref, const Point2f& u, const SampledWavelengths& lambda) const override {
        EmitterSample es;
        es.wi = warp::squareToUniformSphere(u);
        // A stand-in point beyond the bounding sphere, for callers that trace a shadow
        // ray to es.p: everything in the scene lies closer than it.
        es.p = m_sphere.beyond(ref, es.wi);
        es.n = -es.wi;
        es.dist = Infinity;
        es.pdf = warp::squareToUniformSpherePdf(es.wi);
        es.L = m_radiance.sample(lambda);
        return es;
    }

    SampledSpectrum evalEnvironment(const Vector3f&, const SampledWavelengths& lambda) const override {
        return m_radiance.sample(lambda);
    }

    float pdfEnvironment(const Point3f&, const Vector3f&) const override { return Inv4Pi; }

    EmissionSample sampleEmission(const Point2f& uPos, const Point2f& uDir,
                                  const SampledWavelengths& lambda) const override {
        // Direction of travel uniform on the sphere; the origin uniform on a disk outside
        // the bounding sphere (SceneSphere::parallelRay).
        EmissionSample es;
        Vector3f d = warp::squareToUniformSphere(uDir);
        es.ray = m_sphere.parallelRay(d, uPos);
        es.n = d;
        es.pdfPosition = 1.f / m_sphere.area();
        es.pdfDirection = Inv4Pi;
        es.L = m_radiance.sample(lambda);
        return es;
    }

    /// Power through the scene's cross-section: π r² · 4π · L (an estimate; only used
    /// to weigh lights against each other).
    float power() const override { return m_sphere.area() * 4.f * Pi * m_luminance; }

private:
    Spectrum m_radiance;
    float m_luminance = 0.f;
    SceneSphere m_sphere;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::ConstantEmitter)
