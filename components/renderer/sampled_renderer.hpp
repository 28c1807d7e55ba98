#pragma once
// Base of the renderers that estimate each pixel from camera samples through a nested
// numerical integrator (direct, path, aov, moment): the `integrator` child (default: mean),
// rendering through renderSampled(), and the per-pixel variance estimate it records.
#include "effigi/core/registry.hpp"
#include "effigi/render/tile_renderer.hpp"

#include <vector>

namespace effigi {

class SampledRenderer : public Implements<IRenderer, ISampleRenderer, IAccumulator> {
public:
    RenderStats render(const Scene& scene, const RenderControl& control) override {
        return renderSampled(scene, control, *m_integrator, *this, m_variance);
    }
    bool varianceEstimate(std::vector<float>& variance) const override { return m_variance.get(variance); }
    /// IAccumulator: a pass carries only the film and the variance store to the next, so
    /// renders can be checkpointed, resumed and split over MPI ranks.
    AccumulatorSums saveSums() const override { return m_variance.saveSums(); }
    void loadSums(const AccumulatorSums& sums) override { m_variance.loadSums(sums); }

    /// The `integrator` child every such renderer takes.
    static void addIntegratorParam(Schema& s) {
        s.child("integrator", "integrator", "Numerical integrator estimating each pixel (default: mean)");
    }
    /// Mitsuba's scheduling options, which effigi's own passes and tiles replace, and the
    /// integrator child.
    static void addSchedulingParams(Schema& s) {
        s.ignored("samples_per_pass", "effigi renders in passes of its own (see effigi render --spp)");
        s.ignored("timeout", "use effigi render --time for a time budget");
        s.ignored("block_size", "effigi picks its own tile size");
        addIntegratorParam(s);
    }

protected:
    explicit SampledRenderer(const Properties& p) : m_integrator(p.get<IIntegrator>("integrator")) {
        if (!m_integrator) m_integrator = defaultIntegrator();
    }

    Ref<IIntegrator> m_integrator;
    PixelVariance m_variance;
};

} // namespace effigi
