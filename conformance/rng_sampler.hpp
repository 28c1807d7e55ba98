#pragma once
// A plain PCG32 sampler inside the conformance library: the function and integrator
// suites draw their points from it, so their verdicts do not depend on any sampler
// component (which has a suite of its own).
#include "effigi/interfaces/isampler.hpp"
#include "effigi/math/rng.hpp"

namespace effigi::conform {

class RngSampler final : public Implements<ISampler> {
public:
    explicit RngSampler(std::uint64_t seed) : m_seed(seed) { startPixel(Point2i(0)); }

    int samplesPerPixel() const override { return 1 << 30; }
    void startPixel(const Point2i& p) override {
        m_key = mixBits(m_seed ^ mixBits((std::uint64_t(std::uint32_t(p.x)) << 32) | std::uint32_t(p.y)));
        startSample(0);
    }
    void startSample(std::uint64_t index) override { m_rng.seed(mixBits(m_key ^ mixBits(index + 1)), m_key); }
    float get1D() override {
        ++m_draws;
        return m_rng.nextFloat();
    }
    Point2f get2D() override {
        float x = get1D();
        return {x, get1D()};
    }
    Ref<ISampler> clone(std::uint64_t offset) const override { return std::make_shared<RngSampler>(m_seed + offset); }

    /// Values drawn so far (get2D counts two).
    std::uint64_t draws() const { return m_draws; }
    void resetDraws() { m_draws = 0; }

private:
    std::uint64_t m_seed, m_key = 0, m_draws = 0;
    PCG32 m_rng;
};

} // namespace effigi::conform
