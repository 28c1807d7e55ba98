// renderer "bad_scale_renderer" — DELIBERATELY WRONG test plugin: a spectral path tracer
// (BSDF sampling only, emission added where paths hit emitters or escape to the
// environment) whose Russian roulette ends a path with probability 1 − q but forgets to
// scale the survivors' throughput by 1/q. The estimate is then biased low by what the
// killed paths would have carried.
//
// Everything else is right (Mitsuba's max_depth convention; every path is an independent
// camera sample, so the per-pixel variance it reports is honest). With Mitsuba's rr_depth
// 5 only long paths lose weight: the white furnace box and the enclosures; from rr_depth 1
// (q = min(throughput, 0.95) after the first bounce) even one-bounce light does: the sky
// plane (ρ = 0.5) renders 0.25·L instead of 0.5·L, the furnace sphere (ρ = 1) 0.95·L.
// The renderer suite must fail its exact-value checks of those scenes ("sky plane" in
// particular) and nothing else (tests/plugins/run_plugin_tests.cmake).
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/render/tile_renderer.hpp"

#include <algorithm>
#include <cmath>

namespace {
using namespace effigi;

class BadScaleRenderer final : public Implements<IRenderer, ISampleRenderer> {
public:
    static Schema schema() {
        Schema s("renderer", "bad_scale_renderer",
                 "Test plugin: a path tracer whose Russian roulette does not reweight the surviving paths.");
        s.integer("max_depth", -1, "Longest path in segments (-1: unbounded; 1: emitters only)").atLeast(-1);
        s.integer("rr_depth", 5, "Depth from which Russian roulette may end paths").atLeast(1);
        s.addConformance({"default", {}});
        s.addConformance({"rr_depth 1", {{"rr_depth", std::int64_t(1)}}});
        return s;
    }

    explicit BadScaleRenderer(const Properties& p)
        : m_maxDepth(int(p.getInt("max_depth"))), m_rrDepth(int(p.getInt("rr_depth"))),
          m_integrator(defaultIntegrator()) {}

    RenderStats render(const Scene& scene, const RenderControl& control) override {
        return renderSampled(scene, control, *m_integrator, *this, m_variance);
    }
    bool varianceEstimate(std::vector<float>& variance) const override { return m_variance.get(variance); }

    SampledSpectrum sampleRadiance(const Scene& scene, const Ray& cameraRay, SampledWavelengths& lambda,
                                   ISampler& sampler, float*) const override {
        SampledSpectrum L(0.f), beta(1.f);
        Ray ray = cameraRay;
        // depth: the segment `ray` is; emission counts on segments 1..max_depth (Mitsuba).
        for (int depth = 1; m_maxDepth < 0 || depth <= m_maxDepth; ++depth) {
            SurfaceInteraction si;
            if (!scene.intersect(ray, si)) {
                for (const IEmitter* env : scene.environments()) L += beta * env->evalEnvironment(ray.d, lambda);
                break;
            }
            if (si.emitter) L += beta * si.emitter->eval(si, lambda);
            if (!si.bsdf || depth == m_maxDepth) break;
            const float uc = sampler.get1D();
            const Point2f u = sampler.get2D();
            std::optional<BSDFSample> bs = si.bsdf->sample(si, si.toLocal(si.wo), uc, u, lambda, TransportMode::Radiance);
            if (!bs || !(bs->pdf > 0.f) || bs->f.isBlack()) break;
            beta *= bs->f * (std::abs(bs->wi.z) / bs->pdf);
            ray = si.spawnRay(si.toWorld(bs->wi));
            if (depth >= m_rrDepth) {
                const float q = std::min(beta.maxValue(), 0.95f);
                if (sampler.get1D() >= q) break;
                // The bug: the survivors must carry beta / q to make up for the paths ended here.
            }
        }
        return L;
    }

private:
    int m_maxDepth, m_rrDepth;
    Ref<IIntegrator> m_integrator;
    PixelVariance m_variance;
};

} // namespace

EFFIGI_EXPORT_COMPONENT(BadScaleRenderer)
