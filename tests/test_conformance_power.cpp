// The power effigi-conform states (conformance/power.cpp) against simulation: multinomial
// samples from a density off by the stated ε on a tenth of the cells, tested with the
// suites' chi-square test at the suites' per-test level, are caught in about 90 % of the
// trials — and at half that ε in far fewer, so the statement is not merely conservative.
#include "conformance/conformance.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/math/stats.hpp"

#include <catch2/catch.hpp>

#include <algorithm>

using namespace effigi;

namespace {

/// The fraction of `trials` chi-square tests at level alpha that reject n samples drawn
/// from `cells` equal cells whose first tenth has density 1 + ε (the rest compensates).
double detectionRate(double epsilon, int n, int cells, double alpha, int trials, std::uint64_t seed) {
    const int region = cells / 10;
    const double q = double(region) / cells;
    std::vector<double> cdf(static_cast<std::size_t>(cells)), expected(static_cast<std::size_t>(cells), double(n) / cells);
    double acc = 0.0;
    for (int i = 0; i < cells; ++i) {
        acc += (i < region ? 1.0 + epsilon : 1.0 - q * epsilon / (1.0 - q)) / cells;
        cdf[std::size_t(i)] = acc;
    }
    PCG32 rng(seed, 3);
    int caught = 0;
    for (int t = 0; t < trials; ++t) {
        std::vector<double> observed(std::size_t(cells), 0.0);
        for (int s = 0; s < n; ++s) {
            double u = rng.nextDouble() * acc;
            observed[std::size_t(std::min<std::ptrdiff_t>(
                std::lower_bound(cdf.begin(), cdf.end(), u) - cdf.begin(), cells - 1))] += 1.0;
        }
        caught += !stats::chiSquareTest(observed, expected).passes(alpha);
    }
    return double(caught) / trials;
}

} // namespace

TEST_CASE("conformance power: the stated smallest chi-square defect is caught 90 % of the time", "[conformance]") {
    // A quick bsdf run's typical test: 1e5 samples, 201 cells, per-test level 2.3e-5.
    const int n = 100000, cells = 201, trials = 200;
    const double alpha = 2.3e-5;
    const double q = double(cells / 10) / cells;
    const double eps = conform::detectableDensityError(n, cells, alpha, q);
    INFO("stated ε = " << eps);
    CHECK(eps > 0.02);
    CHECK(eps < 0.5);
    // 200 seeded trials: the rate's standard deviation at 0.9 is 0.021, so 0.8 is 4.7 σ
    // below the claim; at ε/2 the noncentrality is a quarter and the power about 0.1.
    double atEps = detectionRate(eps, n, cells, alpha, trials, 11);
    double atHalf = detectionRate(0.5 * eps, n, cells, alpha, trials, 12);
    INFO("detection at ε: " << atEps << ", at ε/2: " << atHalf);
    CHECK(atEps >= 0.8);
    CHECK(atEps <= 0.98);
    CHECK(atHalf <= 0.4);
}
