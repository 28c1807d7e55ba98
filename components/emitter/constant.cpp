// emitter "constant" — a uniform environment: the same radiance from every direction.
//
// Models a sky of constant radiance L surrounding the scene at infinity (a "white
// furnace" when L = 1 and every BSDF has albedo 1). An unoccluded surface facing it
// receives irradiance E = π·L. Direct lighting samples directions uniformly over the
// sphere; emission samples start on a disk outside the scene's bounding sphere so that
// light tracing covers the whole scene with parallel rays.
// Both draw their directions through a warp (issue 14, effigi/render/warp_choice.hpp), in
// world space: by default the compiled-in code of warp `uniform_sphere`; a nested `warp`
// (any warp onto the sphere of directions) replaces it, drawing the direction toward the
// environment in sampleDirect() (pdfEnvironment() says its density) and the direction of
// travel of emitted rays in sampleEmission(). The radiance is the same from everywhere,
// so only a warp covering the whole sphere is unbiased.
//
// Parameters:
//   radiance   spectrum (illuminant, default 1)  radiance of the environment [W m^-2 sr^-1]
//   scale      float ≥ 0 (default 1)  factor on the radiance
//   luminance  float ≥ 0 (optional)   scale the radiance to this luminance Y
//   power      not supported (an environment at infinity has no finite power): an error
//   warp       nested warp (optional)  direction sampler; default uniform over the sphere
//
// Reference: pbrt-v4 §12.5.1 (uniform infinite lights).
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/render/scene_sphere.hpp"
#include "effigi/render/warp_choice.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/emission_scale.hpp"
#include "effigi/spectral/spectrum.hpp"

namespace effigi {
namespace {

using DirectionWarp = WarpChoice<compiled_warp::UniformSphere>;

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
        DirectionWarp::declare(s, "Direction sampler (a warp onto the sphere of directions, world space) of direct "
                                  "lighting and emitted rays; default: the code of warp `uniform_sphere`, compiled in");
        // Cases of the emitter conformance suite (conformance/emitter_suite.cpp), extremes included.
        s.addConformance({"default", {}});
        s.addConformance({"tiny", {{"radiance", 1e-6}}});
        s.addConformance({"huge", {{"radiance", 1e6}}});
        s.addConformance({"dark", {{"radiance", 0.0}}});
        // A nested warp is checked in tests/test_warps_in_use_lights.cpp, not here: a configuration
        // holding one would load the warp module whenever this schema is asked for.
        return s;
    }

    explicit ConstantEmitter(const Properties& p)
        : m_radiance(p.getSpectrum("radiance", SpectrumKind::Illuminant)), m_warp(p) {
        m_radiance = m_radiance.scaled(EmissionScale(p, false, "radiance").factor(m_radiance, 0.f, m_radiance.maxValue()));
        m_luminance = cie::luminance(m_radiance);
    }

    std::uint32_t flags() const override { return EmitterInfinite; }

    void preprocess(const BBox3f& bounds) override { m_sphere = SceneSphere::around(bounds); }

    EmitterSample sampleDirect(const Point3f& ref, const Point2f& u, const SampledWavelengths& lambda) const override {
        EmitterSample es;
        es.wi = m_warp.sample(u);
        // A stand-in point beyond the bounding sphere, for callers that trace a shadow
        // ray to es.p: everything in the scene lies closer than it.
        es.p = m_sphere.beyond(ref, es.wi);
        es.n = -es.wi;
        es.dist = Infinity;
        es.pdf = m_warp.pdf(es.wi);
        es.L = m_radiance.sample(lambda);
        return es;
    }

    SampledSpectrum evalEnvironment(const Vector3f&, const SampledWavelengths& lambda) const override {
        return m_radiance.sample(lambda);
    }

    float pdfEnvironment(const Point3f&, const Vector3f& d) const override { return m_warp.pdf(d); }

    EmissionSample sampleEmission(const Point2f& uPos, const Point2f& uDir,
                                  const SampledWavelengths& lambda) const override {
        // Direction of travel from the warp (uniform on the sphere by default); the origin
        // uniform on a disk outside the bounding sphere (SceneSphere::parallelRay).
        EmissionSample es;
        Vector3f d = m_warp.sample(uDir);
        es.ray = m_sphere.parallelRay(d, uPos);
        es.n = d;
        es.pdfPosition = 1.f / m_sphere.area();
        es.pdfDirection = m_warp.pdf(d);
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
    DirectionWarp m_warp;  // directions toward the environment / of emitted rays
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::ConstantEmitter)
