// renderer "volpath" — volumetric path tracing: surfaces and participating media.
//
// Media enter a scene as Mitsuba 3 declares them: a `<medium>` named `interior` or
// `exterior` inside a shape makes its surface a medium boundary (a `null` BSDF for an
// index-matched one, or any BSDF such as a dielectric), and a `<medium>` in the sensor is
// the medium the camera sits in. The estimator (volpath_core.hpp) samples free flights
// by delta tracking on the hero wavelength's majorant and carries the other wavelengths
// by spectral MIS (Miller et al. 2019), so chromatic media are rendered without bias;
// next-event estimation reaches lights through media (exact transmittance in homogeneous
// ones, ratio tracking elsewhere) and across null surfaces; emitted light of media is
// gathered at every tentative collision. On a scene without media it computes what `path`
// does (same MIS targets; balance instead of power heuristic). Mitsuba's `volpathmis` is
// read as this renderer.
// Parameters: max_depth (segments, −1 unbounded; 1 = emitters seen directly; a medium
// scattering event counts as a bounce), rr_depth, hide_emitters.
// Reference: Pharr, Jakob, Humphreys, pbrt-v4 (2023), §14.2; Miller, Georgiev, Jarosz,
// "A null-scattering path integral formulation of light transport", SIGGRAPH 2019.
#include "sampled_renderer.hpp"
#include "volpath_core.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/irenderer.hpp"

namespace effigi {
namespace {

class VolPathRenderer final : public SampledRenderer {
public:
    static Schema schema() {
        Schema s("renderer", "volpath",
                 "Volumetric path tracer: surfaces and participating media, spectral MIS over the hero wavelengths.");
        s.cite("Miller, Georgiev, Jarosz 2019, A null-scattering path integral formulation of light transport");
        s.cite("Pharr, Jakob, Humphreys, Physically Based Rendering, 4th ed., 2023, sec. 14.2");
        s.integer("max_depth", -1, "Longest path in segments (-1: unbounded; 0: black; 1: emitters only)").atLeast(-1);
        s.integer("rr_depth", 5, "Depth from which Russian roulette may end paths").atLeast(1);
        s.boolean("hide_emitters", false, "Do not show emitters seen directly by the camera");
        addSchedulingParams(s);
        s.addConformance({"default", {}});
        for (std::int64_t d : {0, 1, 2, 1000})
            s.addConformance({fmt::format("max_depth {}", d), {{"max_depth", d}}});
        s.addConformance({"rr_depth 1", {{"rr_depth", std::int64_t(1)}}});
        s.addConformance({"hide_emitters", {{"hide_emitters", true}}});
        return s;
    }

    explicit VolPathRenderer(const Properties& p)
        : SampledRenderer(p), m_maxDepth(int(p.getInt("max_depth"))), m_rrDepth(int(p.getInt("rr_depth"))),
          m_hideEmitters(p.getBool("hide_emitters")) {}

    MediaSupport mediaSupport() const override { return MediaSupport::Renders; }
    bool rendersMotion() const override { return true; }

    /// One camera sample (ISampleRenderer): the ray starts in the camera's medium.
    SampledSpectrum sampleRadiance(const Scene& scene, const Ray& ray, SampledWavelengths& lambda,
                                   ISampler& sampler, float*) const override {
        return VolPathIntegrator(scene, m_maxDepth, m_rrDepth, m_hideEmitters)
            .li(ray, scene.camera().medium(), lambda, sampler);
    }

private:
    int m_maxDepth, m_rrDepth;
    bool m_hideEmitters;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::VolPathRenderer)
