#pragma once
// The strata of `adaptive` in mode strata (adaptive.cpp, where the method is described):
// a box over the first D dimensions with the samples it holds, and the sampler an
// integrand sees, which places a sample's first D dimensions in the current box and
// reports the sample's weight (IWeightedSampler).
#include "effigi/core/component.hpp"
#include "effigi/core/error.hpp"
#include "effigi/interfaces/iintegrator_hooks.hpp"
#include "effigi/interfaces/isampler.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace effigi {

/// Running mean and sum of squared deviations of one value (Welford).
struct Moments {
    double n = 0, mean = 0, m2 = 0;
    void add(double x) { const double d = x - mean; n += 1, mean += d / n, m2 += d * (x - mean); }
    double variance() const { return n > 1 ? std::max(0.0, m2 / (n - 1)) : 0.0; }
    double sigma() const { return std::sqrt(variance()); }
};

struct Stratum {
    std::vector<double> lower, upper;  // over the D stratified dimensions
    double volume = 1.0;
    Moments seen;                // f (summed over channels) at the points below
    std::vector<double> points;  // every sample it holds (its parent's in it too): x_0..x_{D-1}, f
    std::uint64_t alloc = 0;
};

/// The integrand's view of the nested sampler: dimension j < D placed in the stratum.
class StratumSampler final : public Implements<ISampler, IWeightedSampler> {
public:
    StratumSampler(ISampler& base, int dims) : m_base(base), m_x(std::size_t(dims)) {}
    void place(const Stratum* s, double weight) { m_stratum = s, m_weight = weight; }
    int samplesPerPixel() const override { return m_base.samplesPerPixel(); }
    void startPixel(const Point2i& p) override { m_base.startPixel(p); }
    void startSample(std::uint64_t index) override { m_base.startSample(index), m_dim = 0; }
    float get1D() override { return map(m_base.get1D()); }
    Point2f get2D() override { const float x = get1D(); return {x, get1D()}; }
    Point2f getPixel2D() override {
        const Point2f p = m_base.getPixel2D();
        const float x = map(p.x);
        return {x, map(p.y)};
    }
    Ref<ISampler> clone(std::uint64_t) const override { fail("integrator 'adaptive': its sampler cannot be cloned"); }
    double sampleWeight() const override { return m_weight; }
    int drawn() const { return m_dim; }
    double x(int j) const { return m_x[std::size_t(j)]; }

private:
    float map(float y) {
        const int j = m_dim++;
        if (std::size_t(j) >= m_x.size() || std::size_t(j) >= m_stratum->lower.size()) return y;
        const float lo = float(m_stratum->lower[std::size_t(j)]), hi = float(m_stratum->upper[std::size_t(j)]);
        float u = std::max(lo, float(double(lo) + double(hi - lo) * double(y)));  // lo, hi dyadic: exact
        if (u >= hi) u = std::nextafter(hi, 0.f);
        m_x[std::size_t(j)] = u;
        return u;
    }

    ISampler& m_base;
    const Stratum* m_stratum = nullptr;
    std::vector<double> m_x;
    double m_weight = 1.0;
    int m_dim = 0;
};

} // namespace effigi
