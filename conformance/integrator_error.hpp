#pragma once
// Parts of the integrator suite (integrator_suite.cpp) kept in integrator_error.cpp: the
// test integrands, the measurement of error against samples and time, the checks of
// tiny budgets and determinism, and a wrapper that collects what adaptive integrators
// report (iintegrator_hooks.hpp).
#include "conformance/conformance.hpp"
#include "effigi/interfaces/iintegrator.hpp"
#include "effigi/interfaces/iintegrator_hooks.hpp"

#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace effigi::conform {

struct Integrand {
    std::string name;  // "function/config"
    Ref<IFunction> f;
    double exact = 0.0;
    double sigma = 0.0;  ///< standard deviation of f under uniform sampling (Monte Carlo)
};

/// Forwards to another function, counts evaluations and keeps the χ²/dof and the number
/// of samples of what integrators report.
class ObservedFunction final : public Implements<IFunction, IIntegrationObserver> {
public:
    explicit ObservedFunction(Ref<IFunction> f) : m_f(std::move(f)) {}
    int dimension() const override { return m_f->dimension(); }
    int channels() const override { return m_f->channels(); }
    void eval(ISampler& u, std::span<double> out) override {
        ++evaluations;
        m_f->eval(u, out);
    }
    std::optional<std::vector<double>> integral() const override { return m_f->integral(); }
    void integrated(const IntegrationReport& r) override {
        ++reports;
        if (std::isfinite(r.chi2PerDof)) chi2Sum += r.chi2PerDof, ++chi2Count;
    }

    std::uint64_t evaluations = 0, reports = 0, chi2Count = 0;
    double chi2Sum = 0.0;

private:
    Ref<IFunction> m_f;
};

/// INFO rows "error vs samples" (RMS error against N, as a multiple of plain Monte Carlo's
/// σ/√N, with the RMS reported standard error) and "error vs time", N = 2^6 … 2^14.
void reportError(Target& t, const IIntegrator& integ, const Integrand& g, std::uint64_t seed);

/// Deterministic checks: budgets 0, 1, 2, 3 and 5 (at sample offset 0 and 1000) give at
/// most that many evaluations, Estimate::samples equal to them, a finite mean and a
/// variance that is not NaN or negative; and the same call twice gives the same bits.
void checkSmallBudgets(Target& t, const IIntegrator& integ, const std::vector<Integrand>& gs);

} // namespace effigi::conform
