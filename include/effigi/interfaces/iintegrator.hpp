#pragma once
// IIntegrator — estimates ∫ f over [0,1)^d together with an error estimate (EFFIGI's
// numerical integrator; not Mitsuba's "integrator", which effigi calls a renderer).
#include "effigi/core/component.hpp"
#include "effigi/interfaces/ifunction.hpp"

#include <array>
#include <cstdint>

namespace effigi {

struct Estimate {
    static constexpr int MaxChannels = 8;
    int channels = 0;
    std::array<double, MaxChannels> mean{};
    /// Estimated variance of the mean (squared standard error) per channel.
    std::array<double, MaxChannels> variance{};
    std::uint64_t samples = 0;
};

class IIntegrator : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IIntegrator");
    static constexpr const char* Tag = "integrator";

    /// Estimate ∫f using at most `budget` evaluations, drawing sample indices
    /// [0, budget) of the sampler's current domain (see ISampler::startPixel).
    virtual Estimate integrate(IFunction& f, ISampler& sampler, std::uint64_t budget) const = 0;
};

} // namespace effigi
