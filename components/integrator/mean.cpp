// integrator "mean" — crude (mean-sample) Monte Carlo integration over [0,1)^d.
//
// Estimates I = ∫ f(u) du by the sample mean of f at n points from the sampler, and
// reports the variance of that mean, s²/n, with s² the unbiased sample variance. The
// running mean and variance use Welford's update, which stays accurate when the mean is
// large compared to the spread (the naive Σf² − (Σf)²/n cancels catastrophically).
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

        Estimate e;
        e.channels = channels;
        std::array<double, Estimate::MaxChannels> value{}, m2{};  // m2: Σ (f − mean)²
        for (std::uint64_t i = 0; i < budget; ++i) {
            sampler.startSample(first + i);
            value.fill(0.0);
            f.eval(sampler, std::span<double>(value.data(), std::size_t(channels)));
            const double n = double(i + 1);
            for (int c = 0; c < channels; ++c) {
                double delta = value[c] - e.mean[c];
                e.mean[c] += delta / n;
                m2[c] += delta * (value[c] - e.mean[c]);
            }
        }
        e.samples = budget;
        for (int c = 0; c < channels; ++c)
            e.variance[c] = budget < 2 ? std::numeric_limits<double>::infinity()
                                       : m2[c] / double(budget - 1) / double(budget);
        return e;
    }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::MeanIntegrator)
