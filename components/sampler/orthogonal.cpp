// sampler "orthogonal" — orthogonal-array-based Latin hypercube sampling (Jarosz et al.
// 2019), the higher-dimensional generalisation of correlated multi-jittered sampling.
//
// An orthogonal array OA(n = p^t, d, p, t) of strength t lists n rows (samples) of d
// symbols in 0..p−1 such that any t columns (dimensions) show every t-tuple of symbols
// exactly once. Each dimension of a sample takes the stratum its symbol names, and inside
// it a sub-stratum chosen so that the 1D projection is a Latin hypercube of n strata;
// strata and sub-strata are shuffled per dimension and the sample order per pixel.
// Strength 2 (the default) uses the Bose construction for n = p² (p prime): sample
// i = (a, b) in base p has symbol a + c·b mod p in the column of slope c (plus columns a
// and b), so every 2D projection of any two dimensions is stratified like a p × p
// jittered grid. Other strengths use the Bush construction (polynomials of degree < t
// over GF(p)): every t-dimensional projection is stratified on a p^t grid, 2D ones only
// on a p × p grid with p^(t−2) points a cell (no longer one point a cell).
// sample_count is rounded up to p^t with p prime (with a warning), as Mitsuba 3 does.
// Column symbols repeat with period p + 1 (strength 2) or p (Bush) dimensions, with fresh
// permutations, so dimensions that far apart are correlated.
//
// Parameters (Mitsuba 3's):
//   sample_count  int  (default 4)   samples per pixel, rounded up to p^strength, p prime
//   strength      int  (default 2)   strength t of the orthogonal array, 1..4
//   seed          int  (default 0)   changes every permutation and jitter
//   jitter        bool (default true) uniform offset inside the sub-stratum (false: centre)
//
// Reference: W. Jarosz, A. Enayet, A. Kensler, C. Kilpatrick, P. Christensen, "Orthogonal
// Array Sampling for Monte Carlo Rendering", Computer Graphics Forum 38(4), EGSR 2019;
// A. B. Owen, "Orthogonal Arrays for Computer Experiments, Integration and Visualization",
// Statistica Sinica 2, 1992.
#include "effigi/core/log.hpp"
#include "hashed_sampler.hpp"

#include <cmath>

namespace effigi {
namespace {

bool isPrime(std::uint32_t x) {
    if (x < 2) return false;
    for (std::uint32_t d = 2; d * d <= x; ++d)
        if (x % d == 0) return false;
    return true;
}

class OrthogonalSampler final : public HashedSampler<OrthogonalSampler> {
public:
    static Schema schema() {
        Schema s("sampler", "orthogonal",
                 "Orthogonal-array Latin hypercube samples: stratified in every 2D projection.");
        s.cite("W. Jarosz et al., Orthogonal Array Sampling for Monte Carlo Rendering, EGSR 2019");
        s.integer("sample_count", 4, "Samples per pixel, rounded up to p^strength with p prime (warning)")
            .range(1, 1 << 24);
        s.integer("strength", 2, "Strength of the orthogonal array: stratified projections onto this many dimensions")
            .range(1, 4);
        s.integer("seed", 0, "Seed of every permutation and jitter: equal seeds give identical images");
        s.boolean("jitter", true, "Jitter inside each sub-stratum (false: sub-stratum centres)");
        s.addConformance({"default", {}});
        s.addConformance({"49 samples, other seed", {{"sample_count", std::int64_t(49)}, {"seed", std::int64_t(7)}}});
        s.addConformance({"strength 3", {{"sample_count", std::int64_t(27)}, {"strength", std::int64_t(3)}}});
        s.addConformance({"strength 1", {{"sample_count", std::int64_t(5)}, {"strength", std::int64_t(1)}}});
        s.addConformance({"strength 4", {{"sample_count", std::int64_t(81)}, {"strength", std::int64_t(4)}}});
        return s;
    }

    explicit OrthogonalSampler(const Properties& p)
        : HashedSampler(std::uint64_t(p.getInt("seed"))), m_strength(std::uint32_t(p.getInt("strength"))),
          m_jitter(p.getBool("jitter")) {
        const double requested = double(p.getInt("sample_count"));
        // Start at the t-th root (rounded down): counting up from 2 would take seconds for
        // strength 1 and millions of samples.
        m_base = std::max<std::uint32_t>(2, std::uint32_t(std::pow(requested, 1.0 / m_strength)));
        while (std::pow(double(m_base), m_strength) < requested || !isPrime(m_base)) ++m_base;
        m_count = 1;
        for (std::uint32_t k = 0; k < m_strength; ++k) m_count *= m_base;
        if (double(m_count) != requested)
            log::warn("sampler \"orthogonal\": sample_count {} is not a prime to the power {}, using {}",
                      p.getInt("sample_count"), m_strength, m_count);
        startPixel(Point2i(0));
    }

    OrthogonalSampler(const OrthogonalSampler&) = default;

    SamplerClaims claims() const override {
        SamplerClaims c;
        // The stratification checks take 16 samples, which no count p^t equals (but 2^4);
        // the 2D stratification of strength 2 is checked by tests/test_renderers_extra.cpp.
        c.stratification = StratifyLatinHypercube;
        if (!m_jitter) return c;  // deterministic error: no RMS rate to claim
        if (m_strength == 1) {
            // Plain Latin hypercube sampling: the additive part of f converges as N^-3/2, the
            // rest at the Monte Carlo rate (Stein 1987); the fit over N = 4..4096 is ≈ −0.55.
            c.smoothRate = -0.55;
            return c;
        }
        // Strength 2 is correlated multi-jittered sampling in every 2D projection: see
        // multijitter.cpp for why the smooth rate is below jittered sampling's N^-1.
        // Strength ≥ 3 projects onto a coarser p × p grid with p^(t-2) points a cell, each
        // cell's points stratified in 1D; we know no closed form and claim the slopes
        // effigi-conform fits over N = 4..4096 (t = 3: −0.92, −0.69; t = 4: −0.82, −0.65).
        c.smoothRate = -0.85;
        c.discontinuousRate = m_strength == 2 ? -0.75 : -0.67;
        return c;
    }

    float get1D() override {
        const std::uint32_t dim = m_dimension;
        const std::uint64_t key = nextDimensionKey();
        auto [symbol, sub, subCount] = m_strength == 2 ? bose(m_row, dim) : bush(m_row, dim);
        const std::uint32_t stratum = permutationElement(symbol, m_base, mixBits(key + 1));
        const std::uint32_t subStratum = permutationElement(sub, subCount, mixBits(key + 2));
        return toUnit((double(stratum) + (double(subStratum) + jitterOffset(m_jitter, key, 0)) / subCount) / m_base);
    }

    /// The sample's row of the array: one shuffle of the rows per pixel (and round of
    /// indices), shared by all dimensions so that the columns stay orthogonal.
    void startSample(std::uint64_t index) override {
        HashedSampler::startSample(index);
        const std::uint64_t orderKey = mixBits(m_pixelHash ^ mixBits(0x5bd1e995ull ^ (m_index / m_count)));
        m_row = permutationElement(std::uint32_t(m_index % m_count), m_count, orderKey);
    }

    /// Two consecutive dimensions: any two columns of the array are orthogonal.
    Point2f get2D() override {
        const float x = get1D();
        return {x, get1D()};
    }

private:
    struct Symbol {
        std::uint32_t symbol, sub, subCount;
    };

    /// Strength 2, n = p²: sample i = a·p + b. Column 0 is a, column 1 is b, column j ≥ 2
    /// is a + (j − 1)·b mod p; the sub-stratum is the symbol of a neighbouring column, so
    /// (symbol, sub) runs over all p² pairs: a Latin hypercube in 1D.
    Symbol bose(std::uint32_t i, std::uint32_t dim) const {
        const std::uint32_t a = i / m_base, b = i % m_base;
        auto column = [&](std::uint32_t j) -> std::uint32_t {
            if (j == 0) return a;
            if (j == 1) return b;
            return std::uint32_t((a + std::uint64_t(j - 1) * b) % m_base);
        };
        const std::uint32_t j = dim % (m_base + 1);  // p + 1 distinct columns
        const std::uint32_t k = j % 2 ? j - 1 : (j + 1) % (m_base + 1);
        return {column(j), column(k), m_base};
    }

    /// Strength t, n = p^t: the digits of i are the coefficients of a polynomial over
    /// GF(p); column j is its value at x = j mod p. The sub-stratum is i / p, which with
    /// the symbol makes every one of the n strata of the column appear once.
    Symbol bush(std::uint32_t i, std::uint32_t dim) const {
        const std::uint32_t x = dim % m_base;
        std::uint64_t value = 0;
        std::uint32_t digits = i, power = 1;
        for (std::uint32_t k = 0; k < m_strength; ++k, digits /= m_base) {
            value = (value + std::uint64_t(digits % m_base) * power) % m_base;
            power = std::uint32_t(std::uint64_t(power) * x % m_base);
        }
        return {std::uint32_t(value), i / m_base, m_count / m_base};
    }

    std::uint32_t m_strength;
    bool m_jitter;
    std::uint32_t m_base = 2;  // the prime p; m_count = p^strength
    std::uint32_t m_row = 0;   // the current sample's row of the array
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::OrthogonalSampler)
