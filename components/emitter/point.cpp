// emitter "point" — an isotropic point light.
//
// A point that radiates intensity I [W/sr] equally in all directions. Irradiance on a
// surface facing it at distance d falls off as I·cosθ/d² (inverse-square law). It is a
// delta light: it can only be reached by sampling it, never by hitting it with a ray.
// Emitted rays (light tracing, bdpt, photon maps) leave in directions drawn through a
// warp (issue 14, effigi/render/warp_choice.hpp): by default the compiled-in code of warp
// `uniform_sphere`; a nested `warp` (any warp onto the sphere of directions, in world
// space) replaces it in sampleEmission() and pdfEmission(). The intensity is the same in
// every direction, so only a warp covering the whole sphere is unbiased.
//
// Parameters:
//   position   point      where the light is (alternatively: the translation of to_world)
//   to_world   transform  placement; only its translation matters
//   intensity  spectrum (illuminant, default 1)  radiant intensity [W sr^-1]
//   scale      float ≥ 0 (default 1)  factor on the intensity
//   luminance  float ≥ 0 (optional)   scale the intensity to this luminous intensity Y
//   power      float ≥ 0 (optional)   scale the intensity to this radiant flux [W],
//              Φ = 4π ∫ I dλ over 360–830 nm (excludes luminance)
//   warp       nested warp (optional)  emission direction sampler; default uniform over the sphere
//
// Reference: pbrt-v4 §12.1.1 (point lights).
#include "delta_light.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/render/scene_range.hpp"
#include "effigi/render/warp_choice.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/emission_scale.hpp"
#include "effigi/spectral/spectrum.hpp"

namespace effigi {
namespace {

using DirectionWarp = WarpChoice<compiled_warp::UniformSphere>;

class PointEmitter final : public Implements<IEmitter> {
public:
    static Schema schema() {
        Schema s("emitter", "point", "Isotropic point light.");
        s.cite("M. Pharr, W. Jakob, G. Humphreys, Physically Based Rendering, 4th ed., §12.1");
        s.optional("position", ParamType::Point, "Position of the light (or give to_world instead)");
        s.transform("to_world", "Placement of the light; its translation is the position");
        s.spectrum("intensity", 1.f, SpectrumKind::Illuminant, "Radiant intensity, the same in every direction")
            .atLeast(0.0)
            .withUnit("W sr^-1");
        EmissionScale::declare(s, "Scale the intensity to this luminous intensity", "W sr^-1",
                               "Scale the intensity so that the light emits the flux 4π ∫I dλ");
        // Mitsuba's emitters take a light-selection weight; effigi picks lights by its own
        // rule, which changes noise only, never the expected image.
        s.ignored("sampling_weight", "lights are chosen by effigi's own selection rule");
        DirectionWarp::declare(s, "Emission direction sampler (a warp onto the sphere of directions, world space); "
                                  "default: the code of warp `uniform_sphere`, compiled in");
        // Cases of the emitter conformance suite (conformance/emitter_suite.cpp), extremes included.
        s.addConformance({"default", {}});
        s.addConformance({"offset", {{"position", PointValue{Point3f(100.f, -50.f, 20.f)}}}});
        s.addConformance({"tiny", {{"intensity", 1e-6}}});
        s.addConformance({"huge", {{"intensity", 1e6}}});
        s.addConformance({"dark", {{"intensity", 0.0}}});
        s.addConformance({"power", {{"power", 100.0}}});
        // A nested warp is checked in tests/test_warps_in_use_lights.cpp, not here: a configuration
        // holding one would load the warp module whenever this schema is asked for.
        return s;
    }

    explicit PointEmitter(const Properties& p)
        : m_intensity(p.getSpectrum("intensity", SpectrumKind::Illuminant)), m_warp(p) {
        const Properties::Entry* toWorld = p.find("to_world");
        bool hasToWorld = toWorld && !toWorld->fromDefault;
        if (p.has("position")) {
            if (hasToWorld)
                failAt(p.whereOf("position"), "{}: give either 'position' or 'to_world', not both", p.describe());
            m_position = p.getPoint("position");
        } else {
            m_position = p.getTransform("to_world").point(Point3f(0.f));
        }
        if (!inSceneRange(m_position))
            failAt(p.whereOf(p.has("position") ? "position" : "to_world"),
                   "{}: the position is not finite or beyond effigi's coordinate range ±{:g}", p.describe(),
                   MaxSceneCoordinate);
        EmissionScale emission(p, true, "intensity");
        m_intensity = m_intensity.scaled(emission.factor(m_intensity, 4.f * Pi, m_intensity.maxValue()));
        m_luminance = cie::luminance(m_intensity);
    }

    std::uint32_t flags() const override { return EmitterDeltaPosition; }

    EmitterSample sampleDirect(const Point3f& ref, const Point2f&, const SampledWavelengths& lambda) const override {
        return delta_light::sampleDirect(ref, m_position, [&](const Vector3f&) { return m_intensity.sample(lambda); });
    }

    EmissionSample sampleEmission(const Point2f&, const Point2f& uDir, const SampledWavelengths& lambda) const override {
        Vector3f d = m_warp.sample(uDir);
        return delta_light::emissionSample(m_position, d, Normal3f(d), m_warp.pdf(d), m_intensity.sample(lambda));
    }

    bool pdfEmission(const Point3f&, const Normal3f&, const Vector3f& d, float& pdfPosition,
                     float& pdfDirection) const override {
        pdfPosition = 1.f;
        pdfDirection = m_warp.pdf(d);
        return true;
    }

    /// Φ = 4π · I.
    float power() const override { return 4.f * Pi * m_luminance; }

private:
    Spectrum m_intensity;
    Point3f m_position{0.f};
    float m_luminance = 0.f;
    DirectionWarp m_warp;  // the emission direction sampler
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::PointEmitter)
