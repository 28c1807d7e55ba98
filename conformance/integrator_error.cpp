// Integrator suite, part 2: error against samples and time, tiny budgets, determinism.
#include "conformance/integrator_error.hpp"

#include "conformance/rng_sampler.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
#include <cstring>

namespace effigi::conform {

void reportError(Target& t, const IIntegrator& integ, const Integrand& g, std::uint64_t seed) {
    using Clock = std::chrono::steady_clock;
    const int kMax = t.quick() ? 10 : 14, runs = t.quick() ? 16 : 32;
    RngSampler sampler(seed ^ 0x7777);
    std::vector<std::string> timeParts, sampleParts;
    std::vector<double> logN, logE;
    for (int k = 6; k <= kMax; k += 2) {
        const std::uint64_t n = std::uint64_t(1) << k;
        double sq = 0.0, var = 0.0, seconds = 0.0, used = 0.0;
        for (int r = 0; r < runs; ++r) {
            sampler.startPixel(Point2i(r, k));
            auto t0 = Clock::now();
            Estimate e = integ.integrate(*g.f, sampler, n);
            seconds += std::chrono::duration<double>(Clock::now() - t0).count();
            sq += (e.mean[0] - g.exact) * (e.mean[0] - g.exact);
            var += e.variance[0];
            used += double(e.samples);
        }
        const double rms = std::sqrt(sq / runs), mc = g.sigma / std::sqrt(double(n));
        timeParts.push_back(fmt::format("{:.2g} @ {:.2g} ms", rms, 1e3 * seconds / runs));
        std::string part = fmt::format("2^{}: {:.2g} ({:.3g}× MC, reported {:.2g}", k, rms,
                                       mc > 0.0 ? rms / mc : std::numeric_limits<double>::quiet_NaN(),
                                       std::sqrt(var / runs));
        if (used < double(n) * runs) part += fmt::format(", {:.0f} samples", used / runs);
        sampleParts.push_back(part + ")");
        logN.push_back(std::log(double(n)));
        logE.push_back(std::log(std::max(rms, 1e-300)));
    }
    double mx = 0, my = 0, sxy = 0, sxx = 0;
    for (std::size_t i = 0; i < logN.size(); ++i) mx += logN[i] / logN.size(), my += logE[i] / logE.size();
    for (std::size_t i = 0; i < logN.size(); ++i)
        sxy += (logN[i] - mx) * (logE[i] - my), sxx += (logN[i] - mx) * (logN[i] - mx);
    const std::string slope = fmt::format("slope {:.2f}", sxy / sxx);
    t.info("error vs samples " + g.name, slope,
           fmt::format("RMS error over {} runs (÷ plain Monte Carlo σ/√N; RMS reported standard error): {}", runs,
                       fmt::join(sampleParts, "; ")));
    t.info("error vs time " + g.name, slope,
           fmt::format("RMS error @ time per run, N = 2^6..2^{} by 4×: {}", kMax, fmt::join(timeParts, ", ")));
}

void checkSmallBudgets(Target& t, const IIntegrator& integ, const std::vector<Integrand>& gs) {
    Tally budgets, repeat;
    RngSampler sampler(t.derivedSeed("small budgets"));
    for (const Integrand& g : gs) {
        auto f = std::make_shared<ObservedFunction>(g.f);
        for (std::uint64_t first : {0, 1000})
            for (std::uint64_t n : {0, 1, 2, 3, 5}) {
                sampler.startPixel(Point2i(int(n), int(first)));
                f->evaluations = 0;
                Estimate e = integ.integrate(*f, sampler, first, n);
                const double v = e.variance[0];
                const bool ok = f->evaluations <= n && e.samples == f->evaluations && std::isfinite(e.mean[0]) &&
                                (e.samples == 0 || e.channels == 1) && !std::isnan(v) && v >= 0.0;
                budgets.note(ok, fmt::format("{}, budget {} at offset {}: {} evaluations, samples {}, mean {}, "
                                             "variance {}",
                                             g.name, n, first, f->evaluations, e.samples, e.mean[0], v));
            }
        Estimate a = integ.integrate(*g.f, sampler, 7, 300), b = integ.integrate(*g.f, sampler, 7, 300);
        repeat.note(std::memcmp(&a.mean[0], &b.mean[0], sizeof(double)) == 0 &&
                        std::memcmp(&a.variance[0], &b.variance[0], sizeof(double)) == 0 && a.samples == b.samples,
                    fmt::format("{}: {} ± {} then {} ± {}", g.name, a.mean[0], a.variance[0], b.mean[0],
                                b.variance[0]));
    }
    t.expect("small budgets", budgets.bad == 0, budgets.figure(),
             budgets.detail("budgets 0, 1, 2, 3, 5 at offsets 0 and 1000: at most that many evaluations, samples = "
                            "evaluations, finite mean, variance >= 0 or +inf"));
    t.expect("deterministic", repeat.bad == 0, repeat.figure(),
             repeat.detail("the same call (300 samples from offset 7) twice gives the same estimate, bit for bit"));
}

} // namespace effigi::conform
