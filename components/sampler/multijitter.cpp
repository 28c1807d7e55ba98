// sampler "multijitter" — correlated multi-jittered sampling (Kensler 2013).
//
// A pixel's n = sample_count samples are stratified in 2D and in both 1D projections at
// once. A 2D draw puts one sample in each cell of an m × k grid (k = ⌊√n⌋, m = ⌈n / k⌉,
// so n may be rounded up, as Mitsuba 3 does, with a warning); inside its cell a sample
// takes the sub-cell that makes the x coordinates of all samples fall in n distinct
// intervals of width 1/n, and the same for y (the "multi-jittered" canonical pattern of
// Chiu, Shirley & Wang 1994). The sub-cells are shuffled by one permutation shared by
// all columns and one by all rows — Kensler's "correlated" variant, which keeps the
// pattern free of clumps — and the order of the samples by a third; a 1D draw is a
// permuted Latin hypercube. Permutations are keyed by (pixel, dimension, seed) and
// evaluated directly for a sample index, so progressive passes may take any index range;
// indices ≥ n start another round with fresh permutations and jitter.
//
// Parameters (Mitsuba 3's):
//   sample_count  int  (default 4, >= 1)  samples per pixel, rounded up to m · k
//   seed          int  (default 0)        changes every permutation and jitter
//   jitter        bool (default true)     uniform offset inside the sub-cell; false
//                                         puts every point at its sub-cell's centre
//
// Reference: A. Kensler, "Correlated Multi-Jittered Sampling", Pixar Technical Memo 13-01,
// 2013; K. Chiu, P. Shirley, C. Wang, "Multi-Jittered Sampling", Graphics Gems IV, 1994.
#include "effigi/core/log.hpp"
#include "hashed_sampler.hpp"

#include <cmath>

namespace effigi {
namespace {

class MultijitterSampler final : public HashedSampler<MultijitterSampler> {
public:
    static Schema schema() {
        Schema s("sampler", "multijitter", "Correlated multi-jittered samples: stratified in 2D and in 1D.");
        s.cite("A. Kensler, Correlated Multi-Jittered Sampling, Pixar Technical Memo 13-01, 2013");
        s.integer("sample_count", 4, "Samples per pixel, rounded up to a near-square grid m x k (warning)")
            .range(1, 1 << 30);
        s.integer("seed", 0, "Seed of every permutation and jitter: equal seeds give identical images");
        s.boolean("jitter", true, "Jitter inside each sub-cell (false: sub-cell centres)");
        s.addConformance({"default", {}});
        s.addConformance(
            {"non-square count, other seed", {{"sample_count", std::int64_t(10)}, {"seed", std::int64_t(7)}}});
        s.addConformance({"one sample", {{"sample_count", std::int64_t(1)}, {"seed", std::int64_t(-1)}}});
        s.addConformance({"prime count", {{"sample_count", std::int64_t(97)}}});
        return s;
    }

    explicit MultijitterSampler(const Properties& p)
        : HashedSampler(std::uint64_t(p.getInt("seed"))), m_jitter(p.getBool("jitter")) {
        const std::int64_t requested = p.getInt("sample_count");
        m_rows = std::max<std::uint32_t>(1, std::uint32_t(std::sqrt(double(requested))));
        m_columns = std::uint32_t((requested + m_rows - 1) / m_rows);
        m_count = m_columns * m_rows;
        if (std::int64_t(m_count) != requested)
            log::warn("sampler \"multijitter\": sample_count {} rounded up to {}", requested, m_count);
        startPixel(Point2i(0));
    }

    MultijitterSampler(const MultijitterSampler&) = default;

    SamplerClaims claims() const override {
        // Correlation costs smooth convergence: all samples of a row share their x offset
        // in the cell, so the error of the x·y interaction of f sums over the k rows as a
        // permuted sum, ∝ √k / n ~ N^-3/4, where jittered sampling has N^-1. Over
        // N = 4..4096 the conformance integrand (smooth parts decaying faster) fits a slope
        // of about −0.85; discontinuities give N^-3/4 as for jittering.
        return stratumClaims(m_jitter, -0.85);
    }

    float get1D() override { return permutedStratum1D(m_jitter); }

    Point2f get2D() override {
        // Which cell this sample takes, then its sub-cell from the column's and the row's
        // shared permutations (the correlation of Kensler's sec. 3).
        std::uint64_t key;
        const std::uint32_t s = permutedStratum(key);
        const std::uint32_t x = s % m_columns, y = s / m_columns;
        const std::uint32_t sx = permutationElement(x, m_columns, mixBits(key + 1));
        const std::uint32_t sy = permutationElement(y, m_rows, mixBits(key + 2));
        const double u = (double(x) + (double(sy) + jitterOffset(m_jitter, key, 1)) / m_rows) / m_columns;
        const double v = (double(y) + (double(sx) + jitterOffset(m_jitter, key, 2)) / m_columns) / m_rows;
        return {toUnit(u), toUnit(v)};
    }

private:
    bool m_jitter;
    std::uint32_t m_columns = 1, m_rows = 1;  // the m × k grid, m_count = m · k
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::MultijitterSampler)
