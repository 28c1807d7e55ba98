// Integrator suite: every numerical IIntegrator estimates the known integrals of the
// test integrands the registry offers (function components with an exact integral(),
// 1 to 8 dimensions, in each of their conformance configurations). Over repeated
// independently seeded runs the estimate must be unbiased (two-sided z-test) and its
// reported error bar calibrated (the 95 % interval mean ± 1.96 √variance covers the
// exact value in 90 % to 99 % of the runs); tiny budgets and repeated calls must behave
// (integrator_error.cpp); error against samples and against run time is printed, and
// the χ²/dof of the stages of integrators that report them (VEGAS, adaptive).
#include "conformance/histogram.hpp"
#include "conformance/integrator_error.hpp"
#include "conformance/rng_sampler.hpp"
#include "effigi/interfaces/iintegrator.hpp"

#include <fmt/format.h>

namespace effigi::conform {

namespace {

std::vector<Integrand> integrands(Target& t) {
    std::vector<Integrand> out;
    Registry& reg = t.registry();
    for (const auto& [tag, name] : reg.list()) {
        if (tag != "function") continue;
        try {
            std::vector<ConformanceConfig> configs = reg.info(tag, name).schema.conformance();
            if (configs.empty()) configs.push_back({"default", {}});
            for (const ConformanceConfig& c : configs) {
                Properties p(tag, name);
                for (const auto& [k, v] : c.params) p.set(k, v);
                Ref<IFunction> f = query<IFunction>(reg.create(tag, name, p));
                if (!f || f->dimension() < 1 || f->dimension() > 8 || f->channels() != 1) continue;
                auto exact = f->integral();
                if (!exact || exact->empty()) continue;
                out.push_back({name + "/" + c.name, f, (*exact)[0]});
            }
        } catch (const std::exception&) {
            // A broken function component fails its own suite; it is no test integrand.
        }
    }
    return out;
}

/// z-score of the declared integral against a 2^18-sample Monte Carlo estimate; sets
/// g.sigma, the integrand's standard deviation.
double screenIntegral(Integrand& g, std::uint64_t seed) {
    RngSampler sampler(seed);
    MeanVar m;
    double out = 0.0;
    for (std::uint64_t i = 0; i < (1u << 18); ++i) {
        sampler.startSample(i);
        out = 0.0;
        g.f->eval(sampler, std::span<double>(&out, 1));
        m.add(out);
    }
    double se = m.stderror(), diff = m.mean - g.exact;
    g.sigma = std::sqrt(m.variance());
    return se > 0.0 ? diff / se : (std::abs(diff) <= 1e-12 * std::max(1.0, std::abs(g.exact)) ? 0.0 : INFINITY);
}

void checkIntegrand(Target& t, const IIntegrator& integ, const Integrand& g, std::uint64_t seedBase) {
    // Runs and budget are the same with --quick: the coverage criterion needs them (and
    // 400 runs of 4096 samples of all test integrands take a few seconds).
    const int runs = 400;
    const std::uint64_t budget = 4096;
    RngSampler sampler(seedBase);
    MeanVar estimates;
    int covered = 0;
    double used = 0.0;
    ObservedFunction f(g.f);
    for (int r = 0; r < runs; ++r) {
        sampler.startPixel(Point2i(r, 0));
        Estimate e = integ.integrate(f, sampler, budget);
        used += double(e.samples);
        double m = e.mean[0], v = e.variance[0];
        estimates.add(m);
        // A NaN error bar covers nothing; an infinite one covers everything (and then
        // coverage reaches 100 %, which fails as well).
        if (std::abs(m - g.exact) <= 1.959963985 * std::sqrt(v)) ++covered;
    }
    double se = estimates.stderror(), diff = estimates.mean - g.exact;
    double z = se > 0.0 ? diff / se : (std::abs(diff) <= 1e-12 * std::max(1.0, std::abs(g.exact)) ? 0.0 : INFINITY);
    double p = std::isnan(z) ? 0.0 : std::erfc(std::abs(z) / std::sqrt(2.0));
    t.test("unbiased " + g.name, p, fmt::format("z = {:.2f}", z),
           fmt::format("mean of {} runs of {} samples {:.6g} ± {:.2g}, exact {:.6g}", runs, budget, estimates.mean, se,
                       g.exact));
    // Binomial noise of the coverage over 400 runs at a true 95 % is 1.1 %: [90 %, 99 %] is
    // −4.6 to +3.7 standard deviations, so a calibrated error bar fails with probability
    // < 1e-4 per integrand, while one too small by 2× covers only ~67 %.
    double coverage = double(covered) / runs;
    t.expect("error bar " + g.name, coverage >= 0.90 && coverage <= 0.99,
             fmt::format("coverage {:.1f} %", 100.0 * coverage),
             fmt::format("95 % interval (mean ± 1.96 √variance) covers the exact value in {} of {} runs; "
                         "calibrated: 90 % to 99 %",
                         covered, runs));
    if (f.chi2Count > 0)
        t.info("chi2/dof " + g.name, fmt::format("{:.2f}", f.chi2Sum / double(f.chi2Count)),
               fmt::format("mean χ²/dof of the stages about their combined estimate over {} runs (≈ 1: "
                           "consistent); {:.0f} samples a run",
                           f.chi2Count, used / runs));
}

void runIntegratorSuite(Target& t) {
    Ref<IIntegrator> integ = t.as<IIntegrator>();
    if (!integ) {
        t.expect("interface", false, "-", "component does not implement IIntegrator");
        return;
    }
    std::vector<Integrand> gs = integrands(t);
    if (gs.empty()) {
        t.skip("integrands", "no function component with a known integral in 1 to 8 dimensions");
        return;
    }
    checkSmallBudgets(t, *integ, gs);
    // With --quick, configurations after a component's first (its extremes) are checked on
    // every third integrand, a different third for each configuration (by its name).
    const std::vector<ConformanceConfig>& configs = t.registry().info(t.tag(), t.component()).schema.conformance();
    const bool subset = t.quick() && !configs.empty() && t.config() != configs.front().name;
    const std::uint64_t third = t.derivedSeed("quick subset") % 3;
    for (std::size_t i = 0; i < gs.size(); ++i) {
        Integrand& g = gs[i];
        if (subset && (i + third) % 3 != 0) continue;
        std::uint64_t seed = t.derivedSeed(g.name);
        // An integrand whose declared integral() is wrong would fail every integrator; the
        // function suite reports it, here it is only kept out (|z| > 6: p < 2e-9).
        double z = screenIntegral(g, seed ^ 0x5c5c);
        if (!(std::abs(z) <= 6.0)) {
            t.skip("integrand " + g.name,
                   fmt::format("excluded: its integral() disagrees with Monte Carlo (z = {:.1f}); see the function suite", z));
            continue;
        }
        checkIntegrand(t, *integ, g, seed);
        reportError(t, *integ, g, seed);
    }
}

} // namespace

} // namespace effigi::conform

EFFIGI_CONFORMANCE_SUITE("integrator",
                         "unbiased estimates and calibrated error bars on known integrals in 1-8 dimensions, small "
                         "budgets, error vs samples and time",
                         effigi::conform::runIntegratorSuite);
