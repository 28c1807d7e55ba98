// Function suite: an IFunction's values are finite, it draws no more sample values than
// its dimension() says, and the exact integral() it declares agrees with a Monte Carlo
// estimate (two-sided z-test). The integrator suite trusts these integrals.
#include "conformance/histogram.hpp"
#include "conformance/rng_sampler.hpp"
#include "effigi/interfaces/ifunction.hpp"
#include "effigi/math/stats.hpp"

#include <fmt/format.h>

namespace effigi::conform {

namespace {

void runFunctionSuite(Target& t) {
    Ref<IFunction> f = t.as<IFunction>();
    if (!f) {
        t.expect("interface", false, "-", "component does not implement IFunction");
        return;
    }
    const int channels = f->channels();
    if (channels < 1 || channels > 64) {
        t.expect("channels", false, fmt::format("{} channels", channels), "expected 1 to 64 output values");
        return;
    }
    RngSampler sampler(t.derivedSeed("function"));
    const std::uint64_t n = t.count(1 << 20, 1 << 17);
    std::vector<double> out(static_cast<std::size_t>(channels));
    std::vector<MeanVar> mv(static_cast<std::size_t>(channels));
    std::uint64_t nonFinite = 0, maxDraws = 0;
    for (std::uint64_t i = 0; i < n; ++i) {
        sampler.startSample(i);
        sampler.resetDraws();
        std::fill(out.begin(), out.end(), 0.0);
        f->eval(sampler, out);
        maxDraws = std::max(maxDraws, sampler.draws());
        for (int c = 0; c < channels; ++c) {
            if (!std::isfinite(out[std::size_t(c)])) ++nonFinite;
            else mv[std::size_t(c)].add(out[std::size_t(c)]);
        }
    }
    t.expect("finite", nonFinite == 0, fmt::format("{} non-finite of {}", nonFinite, n * std::uint64_t(channels)),
             "values at uniform random points");
    const int dim = f->dimension();
    t.expect("dimension", dim == 0 || maxDraws <= std::uint64_t(dim),
             fmt::format("draws {} of dimension() = {}", maxDraws, dim),
             "an evaluation may not draw more sample values than dimension() declares");

    std::optional<std::vector<double>> exact = f->integral();
    if (!exact) {
        t.skip("integral", "integral() unknown");
        return;
    }
    if (exact->size() != std::size_t(channels)) {
        t.expect("integral", false, fmt::format("{} values", exact->size()),
                 fmt::format("integral() has {} values for {} channels", exact->size(), channels));
        return;
    }
    std::vector<double> p;
    double worstZ = 0.0;
    for (int c = 0; c < channels; ++c) {
        const MeanVar& m = mv[std::size_t(c)];
        double se = m.stderror(), diff = m.mean - (*exact)[std::size_t(c)];
        double z = se > 0.0 ? diff / se : (std::abs(diff) <= 1e-12 * std::abs(m.mean) ? 0.0 : INFINITY);
        worstZ = std::max(worstZ, std::abs(z));
        p.push_back(std::erfc(std::abs(z) / std::sqrt(2.0)));  // two-sided
    }
    double pc = combinePValues(p);
    t.test("integral", pc, fmt::format("|z| = {:.2f}", worstZ),
           fmt::format("declared {:.8g}, estimate {:.8g} ± {:.2g} from {} samples", (*exact)[0], mv[0].mean,
                       mv[0].stderror(), n));
}

} // namespace

} // namespace effigi::conform

EFFIGI_CONFORMANCE_SUITE("function", "finite values, dimension() respected, declared integral() against Monte Carlo",
                         effigi::conform::runFunctionSuite);
