#pragma once
// The integrand's view of a nested sampler inside an adaptive integrator: every draw of
// the sample passes, one dimension at a time, through the derived class's map(j, u) (j:
// the dimension's index within the sample), which places the point where the integrator
// wants it — vegas's grid bins, adaptive's strata — and multiplies the sample's weight
// (IWeightedSampler) by the density ratio. CRTP, so the per-draw map is not a second
// virtual call. It lives inside one integrate() call and cannot be cloned.
#include "effigi/core/component.hpp"
#include "effigi/core/error.hpp"
#include "effigi/interfaces/iintegrator_hooks.hpp"
#include "effigi/interfaces/isampler.hpp"

#include <cstdint>

namespace effigi {

template <typename Derived> class DimensionMapSampler : public Implements<ISampler, IWeightedSampler> {
public:
    DimensionMapSampler(ISampler& base, const char* integrator) : m_base(base), m_integrator(integrator) {}

    int samplesPerPixel() const override { return m_base.samplesPerPixel(); }
    void startPixel(const Point2i& p) override { m_base.startPixel(p); }
    void startSample(std::uint64_t index) override { m_base.startSample(index), m_dim = 0; }
    float get1D() override { return next(m_base.get1D()); }
    Point2f get2D() override { const float x = get1D(); return {x, get1D()}; }
    Point2f getPixel2D() override {
        const Point2f p = m_base.getPixel2D();
        const float x = next(p.x);
        return {x, next(p.y)};
    }
    Ref<ISampler> clone(std::uint64_t) const override {
        fail("integrator '{}': its sampler cannot be cloned", m_integrator);
    }
    double sampleWeight() const override { return m_weight; }

    /// Dimensions drawn in the current sample.
    int drawn() const { return m_dim; }

protected:
    double m_weight = 1.0;

private:
    float next(float u) { return static_cast<Derived&>(*this).map(m_dim++, u); }

    ISampler& m_base;
    const char* m_integrator;
    int m_dim = 0;
};

} // namespace effigi
