#pragma once
// Small statistics toolbox for checking sampling code (tests, conformance): Pearson's
// chi-square goodness-of-fit test with pooling of sparse cells, the regularized
// incomplete gamma functions behind the chi-square distribution, and the standard
// normal CDF and quantile. Header-only, double precision throughout.
//
// References: K. Pearson (1900), chi-square test; W. G. Cochran, "Some methods for
// strengthening the common χ² tests", Biometrics 10(4), 1954 (expected counts >= 5);
// M. Abramowitz & I. Stegun, Handbook of Mathematical Functions, §6.5 (incomplete gamma:
// power series 6.5.29, continued fraction 6.5.31) evaluated with Lentz's method
// (W. J. Lentz, Applied Optics 15(3), 1976).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace effigi::stats {

namespace detail {

/// x^a e^-x / Γ(a), the common prefactor of both incomplete-gamma expansions.
inline double gammaPrefactor(double a, double x) { return std::exp(a * std::log(x) - x - std::lgamma(a)); }

/// P(a, x) by its power series Σ x^n / (a (a+1) ... (a+n)); converges fast for x < a + 1.
inline double gammaPSeries(double a, double x) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 10000; ++n) {
        term *= x / (a + n);
        sum += term;
        if (std::abs(term) < std::abs(sum) * 1e-16) break;
    }
    return sum * gammaPrefactor(a, x);
}

/// Q(a, x) by its continued fraction 1/(x+1−a− 1(1−a)/(x+3−a− 2(2−a)/(x+5−a− ...))),
/// evaluated with the modified Lentz method; converges fast for x >= a + 1.
inline double gammaQContinuedFraction(double a, double x) {
    constexpr double Tiny = 1e-300;
    double b = x + 1.0 - a;
    double c = 1.0 / Tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 10000; ++i) {
        double an = -double(i) * (double(i) - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < Tiny) d = Tiny;
        c = b + an / c;
        if (std::abs(c) < Tiny) c = Tiny;
        d = 1.0 / d;
        double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < 1e-16) break;
    }
    return h * gammaPrefactor(a, x);
}

} // namespace detail

/// Regularized lower incomplete gamma P(a, x) = γ(a, x) / Γ(a), for a > 0, x >= 0.
inline double regularizedGammaP(double a, double x) {
    if (!(a > 0.0) || std::isnan(x)) return std::numeric_limits<double>::quiet_NaN();
    if (x <= 0.0) return 0.0;
    if (std::isinf(x)) return 1.0;
    return x < a + 1.0 ? detail::gammaPSeries(a, x) : 1.0 - detail::gammaQContinuedFraction(a, x);
}

/// Regularized upper incomplete gamma Q(a, x) = 1 − P(a, x), accurate in the far tail.
inline double regularizedGammaQ(double a, double x) {
    if (!(a > 0.0) || std::isnan(x)) return std::numeric_limits<double>::quiet_NaN();
    if (x <= 0.0) return 1.0;
    if (std::isinf(x)) return 0.0;
    return x < a + 1.0 ? 1.0 - detail::gammaPSeries(a, x) : detail::gammaQContinuedFraction(a, x);
}

/// CDF of the chi-square distribution with k degrees of freedom: P(k/2, x/2).
inline double chi2Cdf(double x, double k) { return regularizedGammaP(0.5 * k, 0.5 * x); }
/// Upper tail Pr[χ²_k >= x]: the p-value of a chi-square statistic x.
inline double chi2Survival(double x, double k) { return regularizedGammaQ(0.5 * k, 0.5 * x); }

/// Standard normal CDF Φ(x).
inline double normalCdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

/// Standard normal quantile Φ⁻¹(p), p in (0, 1) (±infinity at the ends). Bisection on
/// Φ to full double precision followed by a Newton polish: slow-ish (~100 erfc calls)
/// but simple and accurate to ~1e-15, which is all tests need.
inline double normalQuantile(double p) {
    if (std::isnan(p)) return p;
    if (p <= 0.0) return -std::numeric_limits<double>::infinity();
    if (p >= 1.0) return std::numeric_limits<double>::infinity();
    double lo = -40.0, hi = 40.0;
    for (int i = 0; i < 200 && hi - lo > 1e-15 * std::max(1.0, std::abs(lo)); ++i) {
        double mid = 0.5 * (lo + hi);
        (normalCdf(mid) < p ? lo : hi) = mid;
    }
    double x = 0.5 * (lo + hi);
    double density = std::exp(-0.5 * x * x) / std::sqrt(2.0 * 3.14159265358979323846);
    if (density > 1e-300) {
        double step = (normalCdf(x) - p) / density;
        if (std::abs(step) < hi - lo + 1e-12) x -= step;
    }
    return x;
}

/// Outcome of a chi-square goodness-of-fit test.
struct ChiSquareResult {
    double statistic = 0.0;  ///< Σ (O − E)² / E over the pooled cells
    int dof = 0;             ///< pooled cells − 1
    double pValue = 1.0;     ///< Pr[χ²_dof >= statistic] under the null hypothesis
    int cells = 0;           ///< cells after pooling
    int pooledCells = 0;     ///< input cells with E < minExpected that were merged
    bool impossibleSample = false;  ///< an observation fell in a cell with E = 0

    /// True when the null hypothesis (samples follow the expected distribution)
    /// survives at significance level alpha.
    bool passes(double alpha) const { return !impossibleSample && pValue >= alpha; }
    std::string summary() const {
        return fmt::format("chi2 = {:.4g}, dof = {}, p = {:.4g}, cells = {} ({} pooled){}", statistic, dof, pValue,
                           cells, pooledCells, impossibleSample ? ", samples where E = 0" : "");
    }
};

/// Pearson's chi-square test of observed counts against expected counts (same totals).
/// Cells whose expected count is below minExpected make the χ² approximation unreliable
/// (Cochran's rule), so they are merged, smallest first, into pooled cells of at least
/// minExpected; a remainder too small to stand alone joins the smallest regular cell.
/// An observation in a cell with zero expectation fails the test outright (p = 0).
inline ChiSquareResult chiSquareTest(std::span<const double> observed, std::span<const double> expected,
                                     double minExpected = 5.0) {
    ChiSquareResult r;
    const std::size_t n = std::min(observed.size(), expected.size());
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return expected[a] < expected[b]; });

    std::vector<double> obs, exp;  // pooled cells
    double poolObs = 0.0, poolExp = 0.0;
    for (std::size_t i : order) {
        double o = observed[i], e = expected[i];
        if (!(e > 0.0)) {
            if (o > 0.0) r.impossibleSample = true;
            continue;
        }
        if (e >= minExpected) {
            obs.push_back(o);
            exp.push_back(e);
            continue;
        }
        ++r.pooledCells;
        poolObs += o;
        poolExp += e;
        if (poolExp >= minExpected) {
            obs.push_back(poolObs);
            exp.push_back(poolExp);
            poolObs = poolExp = 0.0;
        }
    }
    if (poolExp > 0.0) {
        // Too little left to form a cell of its own: merge it with the smallest cell.
        auto smallest = std::min_element(exp.begin(), exp.end());
        if (smallest != exp.end()) {
            obs[std::size_t(smallest - exp.begin())] += poolObs;
            *smallest += poolExp;
        } else {
            obs.push_back(poolObs);
            exp.push_back(poolExp);
        }
    }

    r.cells = int(obs.size());
    r.dof = r.cells - 1;
    for (std::size_t i = 0; i < obs.size(); ++i) r.statistic += (obs[i] - exp[i]) * (obs[i] - exp[i]) / exp[i];
    if (r.impossibleSample)
        r.pValue = 0.0;
    else
        r.pValue = r.dof >= 1 ? chi2Survival(r.statistic, double(r.dof)) : 1.0;
    return r;
}

} // namespace effigi::stats
