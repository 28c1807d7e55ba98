// integrator "mean" — crude (mean-sample) Monte Carlo integration over [0,1)^d.
//
// Estimates I = ∫ f(u) du by the sample mean of f at n points from the sampler, and
// reports the variance of that mean, s²/n, with s² the unbiased sample variance, kept by
// Welford's update (RunningEstimate).
// With an independent sampler the error is O(n^-1/2) and mean ± 1.96·√variance is an
// asymptotic 95% confidence interval; with stratified or QMC samplers the estimate
// converges faster but the variance reported here is then only an upper bound.
//
// Parameters: none.
//
// Reference: B. P. Welford, "Note on a method for calculating corrected sums of squares
// and products", Technometrics 4(3), 1962; EFFIGI (Leeson et al.) mean-sample integrator.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iintegrator.hpp"
#include "effigi/math/running_estimate.hpp"

#include <limits>

namespace effigi {
namespace {

class MeanIntegrator final : public Implements<IIntegrator> {
public:
    static Schema schema() {
        Schema s("integrator", "mean", "Mean-sample Monte Carlo: sample mean with its standard error.");
        s.cite("B. P. Welford, Technometrics 4(3), 1962 (running variance)");
        s.addConformance({"default", {}});
        return s;
    }

    explicit MeanIntegrator(const Properties&) {}

    using IIntegrator::integrate;
    Estimate integrate(IFunction& f, ISampler& sampler, std::uint64_t first, std::uint64_t budget) const override {
        const int channels = f.channels();
        if (channels < 1 || channels > Estimate::MaxChannels)
            fail("integrator 'mean': function '{}' has {} channels; 1 to {} are supported", f.typeName(), channels,
                 Estimate::MaxChannels);

        RunningEstimate running(channels);
        std::array<double, Estimate::MaxChannels> value{};
        for (std::uint64_t i = 0; i < budget; ++i) {
            sampler.startSample(first + i);
            value.fill(0.0);
            f.eval(sampler, std::span<double>(value.data(), std::size_t(channels)));
            running.add(value);
        }
        return running.estimate();
    }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::MeanIntegrator)
