#pragma once
// The strata of `adaptive` in mode strata (adaptive.cpp, where the method is described):
// a box over the first D dimensions with the samples it holds, and the sampler an
// integrand sees, which places a sample's first D dimensions in the current box and
// reports the sample's weight (IWeightedSampler).
#include "dimension_map_sampler.hpp"

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
class StratumSampler final : public DimensionMapSampler<StratumSampler> {
public:
    StratumSampler(ISampler& base, int dims) : DimensionMapSampler(base, "adaptive"), m_x(std::size_t(dims)) {}
    void place(const Stratum* s, double weight) { m_stratum = s, m_weight = weight; }
    double x(int j) const { return m_x[std::size_t(j)]; }

    /// Dimension j of this sample, placed in the stratum's interval [lower_j, upper_j).
    float map(int j, float y) {
        if (std::size_t(j) >= m_x.size() || std::size_t(j) >= m_stratum->lower.size()) return y;
        const float lo = float(m_stratum->lower[std::size_t(j)]), hi = float(m_stratum->upper[std::size_t(j)]);
        float u = std::max(lo, float(double(lo) + double(hi - lo) * double(y)));  // lo, hi dyadic: exact
        if (u >= hi) u = std::nextafter(hi, 0.f);
        m_x[std::size_t(j)] = u;
        return u;
    }

private:
    const Stratum* m_stratum = nullptr;
    std::vector<double> m_x;
};

} // namespace effigi
