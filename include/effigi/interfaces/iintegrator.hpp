#pragma once
// IIntegrator — estimates ∫ f over [0,1)^d together with an error estimate (EFFIGI's
// numerical integrator; not Mitsuba's "integrator", which effigi calls a renderer).
#include "effigi/core/component.hpp"
#include "effigi/interfaces/ifunction.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace effigi {

struct Estimate {
    static constexpr int MaxChannels = 8;
    int channels = 0;
    std::array<double, MaxChannels> mean{};
    /// Estimated variance of the mean (squared standard error) per channel.
    std::array<double, MaxChannels> variance{};
    std::uint64_t samples = 0;

    /// Pool two estimates of the same integral from disjoint sample sets: the mean
    /// weighted by sample counts, the variance of the pooled mean from the combined sum of
    /// squares (Chan, Golub & LeVeque 1979).
    void merge(const Estimate& o) {
        if (o.samples == 0) return;
        if (samples == 0) {
            *this = o;
            return;
        }
        double na = double(samples), nb = double(o.samples), n = na + nb;
        for (int c = 0; c < channels; ++c) {
            // Sums of squares about each mean: variance of the mean × n × (n − 1).
            double m2a = std::isfinite(variance[c]) ? variance[c] * na * (na - 1) : 0.0;
            double m2b = std::isfinite(o.variance[c]) ? o.variance[c] * nb * (nb - 1) : 0.0;
            double delta = o.mean[c] - mean[c];
            double m2 = m2a + m2b + delta * delta * na * nb / n;
            mean[c] += delta * nb / n;
            variance[c] = n > 1 ? m2 / (n - 1) / n : std::numeric_limits<double>::infinity();
        }
        samples += o.samples;
    }
};

class IIntegrator : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IIntegrator");
    static constexpr const char* Tag = "integrator";

    /// Estimate ∫f using at most `count` evaluations, drawing sample indices
    /// [first, first + count) of the sampler's current domain (see ISampler::startPixel).
    /// Progressive rendering calls this once per pass with consecutive ranges, so the
    /// passes together use one sequence of the sampler.
    virtual Estimate integrate(IFunction& f, ISampler& sampler, std::uint64_t first,
                               std::uint64_t count) const = 0;
    /// Sample indices [0, budget).
    Estimate integrate(IFunction& f, ISampler& sampler, std::uint64_t budget) const {
        return integrate(f, sampler, 0, budget);
    }
};

} // namespace effigi
