// The statistical power of a run: the smallest defect of each kind its statistical tests
// catch with probability 0.9 at the run's settings (sample counts, cells, and the
// Šidák-corrected per-test level). Stated after every run so that a pass reads as "no
// defect larger than this", not as "no defect".
//
// Chi-square tests: a sampling routine whose density is off by a factor 1 + ε on a region
// holding a fraction q of the samples (compensated evenly elsewhere) shifts Pearson's
// statistic to a noncentral χ²_k(λ) with λ = n q ε² / (1 − q) (the region taken as a
// union of cells; a defect spread thinner across cells is caught later). The smallest
// detectable λ solves P[χ²_k(λ) > c] = 0.9, c the per-test critical value; the noncentral
// distribution is the Poisson mixture of central ones (Johnson, Kotz, Balakrishnan,
// "Continuous Univariate Distributions", vol. 2, ch. 29).
// z-tests (energy, means, error bars): a mean shifted by (z₁₋α + z₀.₉) standard errors.
#include "conformance/conformance.hpp"
#include "effigi/math/stats.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace effigi::conform {

namespace {

constexpr double Power = 0.9;

/// P[χ²_k(λ) > c]: Σ_j Poisson(j; λ/2) Q(k/2 + j, c/2).
double noncentralSurvival(double c, double k, double lambda) {
    double half = 0.5 * lambda, sum = 0.0;
    int last = int(half + 12.0 * std::sqrt(half + 1.0) + 40.0);
    for (int j = 0; j <= last; ++j) {
        double w = std::exp(-half + j * std::log(std::max(half, 1e-300)) - std::lgamma(j + 1.0));
        if (half == 0.0) w = j == 0 ? 1.0 : 0.0;
        sum += w * stats::chi2Survival(c, k + 2.0 * j);
    }
    return sum;
}

/// The critical value c with P[χ²_k > c] = alpha (bisection).
double chi2Critical(double k, double alpha) {
    double lo = 0.0, hi = k + 40.0 * std::sqrt(2.0 * k) + 200.0;
    for (int i = 0; i < 200; ++i) {
        double mid = 0.5 * (lo + hi);
        (stats::chi2Survival(mid, k) > alpha ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

/// The smallest noncentrality caught with probability Power at level alpha.
double detectableNoncentrality(double k, double alpha) {
    double c = chi2Critical(k, alpha), lo = 0.0, hi = 10.0;
    while (noncentralSurvival(c, k, hi) < Power) hi *= 2.0;
    for (int i = 0; i < 60; ++i) {
        double mid = 0.5 * (lo + hi);
        (noncentralSurvival(c, k, mid) < Power ? lo : hi) = mid;
    }
    return hi;
}

} // namespace

double detectableDensityError(double n, double cells, double alphaSingle, double q) {
    double lambda = detectableNoncentrality(std::max(1.0, cells - 1.0), alphaSingle);
    return std::sqrt(lambda * (1.0 - q) / (n * q));
}

std::vector<std::string> Session::powerLines() const {
    std::vector<std::string> lines;
    if (statisticalTests() == 0) return lines;
    const double a = alphaSingle();
    // Chi-square rows by (samples, cells): the smallest and the largest settings of the run.
    std::map<std::pair<double, int>, int> settings;
    for (const Row& r : m_rows) {
        if (!r.histogram) continue;
        double n = r.histogram->outsideObserved;
        for (double o : r.histogram->observed) n += o;
        if (n > 0.0) settings[{n, r.histogram->nx * r.histogram->ny + 1}] += 1;
    }
    lines.push_back(fmt::format("Statistical power (probability {} of catching the defect, per-test level {:.3g}):",
                                Power, a));
    if (!settings.empty()) {
        auto describe = [&](const std::pair<double, int>& s, int rows) {
            return fmt::format("  chi-square, {:.3g} samples in {} cells ({} rows): a density off by {:.1f} % on "
                               "a tenth of the samples, {:.1f} % on half",
                               s.first, s.second, rows, 100.0 * detectableDensityError(s.first, s.second, a, 0.1),
                               100.0 * detectableDensityError(s.first, s.second, a, 0.5));
        };
        // Most frequent settings first: the run's typical chi-square test.
        std::vector<std::pair<std::pair<double, int>, int>> sorted(settings.begin(), settings.end());
        std::sort(sorted.begin(), sorted.end(), [](const auto& x, const auto& y) { return x.second > y.second; });
        for (std::size_t i = 0; i < std::min<std::size_t>(3, sorted.size()); ++i)
            lines.push_back(describe(sorted[i].first, sorted[i].second));
    }
    double z1 = stats::normalQuantile(1.0 - a), z2 = stats::normalQuantile(1.0 - 0.5 * a), zp = stats::normalQuantile(Power);
    lines.push_back(fmt::format("  z-tests (energy, means, error bars): a mean off by {:.1f} standard errors "
                                "(one-sided), {:.1f} (two-sided); a row combining k sub-tests tests each at 1/k of the level",
                                z1 + zp, z2 + zp));
    return lines;
}

} // namespace effigi::conform
