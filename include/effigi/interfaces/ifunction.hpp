#pragma once
// IFunction — f: [0,1)^d -> R^c, EFFIGI's mathematical building block. A pixel's
// integrand in primary sample space, a form-factor kernel and a test integrand are all
// IFunctions; an IIntegrator estimates their integral from an ISampler's points.
#include "effigi/core/component.hpp"
#include "effigi/interfaces/isampler.hpp"

#include <optional>
#include <span>
#include <vector>

namespace effigi {

class IFunction : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IFunction");
    static constexpr const char* Tag = "function";

    /// Number of sample dimensions used; 0 = as many as a given evaluation needs.
    virtual int dimension() const = 0;
    /// Number of output values.
    virtual int channels() const { return 1; }
    /// Evaluate at the point the sampler produces (drawn dimension by dimension).
    virtual void eval(ISampler& u, std::span<double> out) = 0;
    /// The exact integral over [0,1)^d when known (tests, conformance).
    virtual std::optional<std::vector<double>> integral() const { return std::nullopt; }
};

} // namespace effigi
