// renderer "path" — unidirectional spectral path tracing with next-event estimation.
//
// Each pixel is an integral over primary sample space, estimated by the numerical
// IIntegrator nested in the renderer (default `mean`) from the camera's sampler: EFFIGI's
// "pick and mix". The estimator (path_core.hpp) samples four hero wavelengths, adds
// emission found by BSDF sampling and by light sampling, weighted by multiple importance
// sampling with the power heuristic (Veach & Guibas 1995), and ends paths by Russian
// roulette after rr_depth; pass-through (null, mask) surfaces are crossed as in Mitsuba 3.
// Parameters: max_depth (longest path in segments, −1 = unbounded; 0 = black; 1 = emitters
// seen directly, 2 = direct lighting — Mitsuba's convention), rr_depth, hide_emitters, and
// wavefront (effigi's own): render a tile's paths together and trace their rays in
// batches (path_wavefront.hpp), the default for a top-level `path` with the `mean`
// integrator; otherwise (wavefront=false, another integrator, or nested in aov/moment)
// each path runs alone from camera to end, the readable reference loop.
// Reference: Kajiya 1986, "The Rendering Equation"; Veach 1997, PhD thesis, ch. 9.
#include "path_core.hpp"
#include "path_wavefront.hpp"
#include "sampled_renderer.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iintegrator.hpp"
#include "effigi/interfaces/irenderer.hpp"

namespace effigi {
namespace {

class PathRenderer final : public SampledRenderer {
public:
    static Schema schema() {
        Schema s("renderer", "path", "Unidirectional spectral path tracer with next-event estimation and MIS.");
        s.cite("Veach 1997, Robust Monte Carlo Methods for Light Transport Simulation, ch. 9");
        s.integer("max_depth", -1, "Longest path in segments (-1: unbounded; 0: black; 1: emitters only)").atLeast(-1);
        s.integer("rr_depth", 5, "Depth from which Russian roulette may end paths").atLeast(1);
        s.boolean("hide_emitters", false, "Do not show emitters seen directly by the camera");
        s.boolean("wavefront", true,
                  "Advance a tile's paths together and trace rays in batches (same estimator; needs the mean "
                  "integrator, else the one-path loop runs)");
        addSchedulingParams(s);
        // Extremes: no scattering (0), emitters only (1), one bounce short of the exact
        // answer (2, 3), deep paths (1000), Russian roulette from the first bounce.
        s.addConformance({"default", {}});
        for (std::int64_t d : {0, 1, 2, 3, 1000})
            s.addConformance({fmt::format("max_depth {}", d), {{"max_depth", d}}});
        s.addConformance({"rr_depth 1", {{"rr_depth", std::int64_t(1)}}});
        s.addConformance({"hide_emitters", {{"hide_emitters", true}}});
        s.addConformance({"one path at a time", {{"wavefront", false}}});
        return s;
    }

    explicit PathRenderer(const Properties& p)
        : SampledRenderer(p), m_maxDepth(int(p.getInt("max_depth"))), m_rrDepth(int(p.getInt("rr_depth"))),
          m_hideEmitters(p.getBool("hide_emitters")), m_wavefront(p.getBool("wavefront")) {}

    RenderStats render(const Scene& scene, const RenderControl& control) override {
        // The wavefront keeps the mean integrator's per-pixel estimate itself; any other
        // integrator decides how samples are drawn, so it gets the one-path loop.
        if (!m_wavefront || m_integrator->typeName() != "integrator/mean")
            return SampledRenderer::render(scene, control);
        PathIntegrator integrator(scene, m_maxDepth, m_rrDepth, m_hideEmitters);
        return renderPathWavefront(scene, control, integrator, m_variance);
    }

    MediaSupport mediaSupport() const override { return MediaSupport::Ignores; }  // as Mitsuba's path
    bool rendersMotion() const override { return true; }

    /// One camera sample (ISampleRenderer): what moment and aov nest.
    SampledSpectrum sampleRadiance(const Scene& scene, const Ray& ray, SampledWavelengths& lambda,
                                   ISampler& sampler, float*) const override {
        return PathIntegrator(scene, m_maxDepth, m_rrDepth, m_hideEmitters).li(ray, lambda, sampler);
    }

private:
    int m_maxDepth, m_rrDepth;
    bool m_hideEmitters, m_wavefront;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::PathRenderer)
