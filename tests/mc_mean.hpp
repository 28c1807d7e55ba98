#pragma once
// A Monte Carlo mean with its standard error, for the statistical tests that estimate an
// expectation over the unit square (test_sampling's warp checks, test_warps_in_use_lights).
#include "effigi/math/rng.hpp"
#include "effigi/math/vector.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

namespace effigi::test {

/// Monte Carlo estimate (mean, standard error) of E[g(U)] for U uniform on [0,1)².
template <typename G> std::pair<double, double> mcMean(G g, int n, std::uint64_t seed) {
    PCG32 rng(seed, 1);
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
        double v = g(Point2f(rng.nextFloat(), rng.nextFloat()));
        sum += v;
        sum2 += v * v;
    }
    double m = sum / n;
    return {m, std::sqrt(std::max(0.0, sum2 / n - m * m) / n)};
}

} // namespace effigi::test
