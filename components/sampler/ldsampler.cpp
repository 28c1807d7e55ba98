// sampler "ldsampler" — Owen-scrambled (0,2)-sequence, padded per dimension pair.
//
// Every 2D draw (get2D, getPixel2D) takes its point from the base-2 (0,2)-sequence
// (van der Corput × Sobol' dimension 2), whose first 2^m points form a (0,m,2)-net:
// every elementary interval of area 2^-m holds exactly one point. 1D draws use van der
// Corput alone (one point per interval of length 2^-m). Each draw gets its own
// hash-based nested uniform (Owen) scramble keyed by (pixel, dimension, seed) — which
// keeps the net property and makes the points uniformly random — and its own random
// permutation of the pixel's sample indices, so that different draws of one sample are
// decorrelated ("padding", Kollig & Keller 2002). Everything is a function of (pixel,
// index, dimension): indices can be asked for in any order or split into passes.
//
// RMS error of Owen-scrambled nets: ~N^-3/2 √log N for smooth integrands (Owen 1997;
// a fitted slope of ≈ -1.4 over N = 4..4096) and ~N^-3/4 for discontinuities along curves, like jittered sampling.
//
// Parameters:
//   sample_count  int (default 4, >= 1)  samples per pixel; rounded UP to a power of two
//                                        (as Mitsuba 3 does, with a warning)
//   seed          int (default 0)        changes every scramble and permutation
//
// Sample indices ≥ sample_count continue with the next aligned block of 2^m points of
// the sequence, itself a (0,m,2)-net.
//
// Reference: A. B. Owen, "Randomly Permuted (t,m,s)-Nets and (t,s)-Sequences", 1995;
// B. Burley, "Practical Hash-based Owen Scrambling", JCGT 9(4), 2020;
// T. Kollig, A. Keller, "Efficient Multidimensional Sampling", Eurographics 2002.
#include "effigi/core/log.hpp"
#include "hashed_sampler.hpp"

#include <algorithm>

namespace effigi {
namespace {

class LowDiscrepancySampler final : public HashedSampler<LowDiscrepancySampler> {
public:
    static Schema schema() {
        Schema s("sampler", "ldsampler",
                 "Owen-scrambled (0,2)-sequence (van der Corput × Sobol'), padded per dimension pair.");
        s.cite("B. Burley, Practical Hash-based Owen Scrambling, JCGT 9(4), 2020; A. B. Owen, Randomly Permuted "
               "(t,m,s)-Nets and (t,s)-Sequences, 1995; T. Kollig, A. Keller, Efficient Multidimensional Sampling, 2002");
        s.integer("sample_count", 4, "Samples per pixel, rounded up to a power of two (warning)").atLeast(1);
        s.integer("seed", 0, "Seed of every scramble and permutation: equal seeds give identical images");
        s.addConformance({"default", {}});
        s.addConformance({"non-power-of-two count, other seed", {{"sample_count", std::int64_t(12)}, {"seed", std::int64_t(7)}}});
        s.addConformance({"one sample", {{"sample_count", std::int64_t(1)}, {"seed", std::int64_t(-1)}}});
        return s;
    }

    explicit LowDiscrepancySampler(const Properties& p) : HashedSampler(std::uint64_t(p.getInt("seed"))) {
        const std::int64_t requested = std::min<std::int64_t>(p.getInt("sample_count"), std::int64_t(1) << 30);
        m_count = std::bit_ceil(std::uint32_t(std::max<std::int64_t>(requested, 1)));
        if (std::int64_t(m_count) != requested)
            log::warn("sampler \"ldsampler\": sample_count {} is not a power of two, using {}", requested, m_count);
        startPixel(Point2i(0));
    }

    LowDiscrepancySampler(const LowDiscrepancySampler&) = default;

    SamplerClaims claims() const override {
        SamplerClaims c;
        // A (0,m,2)-net is also a Latin hypercube and, for square 2^m, a jittered grid.
        c.stratification = StratifyLatinHypercube | StratifyJittered2D | StratifyElementary2D;
        // N^-3/2 up to a log factor (variance ∝ N^-3 log N): over N = 4..4096 the fitted
        // slope is ≈ -1.4, which is what we claim.
        c.smoothRate = -1.4;
        c.discontinuousRate = -0.75;
        return c;
    }

    float get1D() override {
        const std::uint64_t key = nextDimensionKey();
        return fixedToFloat(owenScramble(vanDerCorput(sequenceIndex(key)), key));
    }

    Point2f get2D() override {
        const std::uint64_t key = nextDimensionKey();
        const std::uint32_t i = sequenceIndex(key);
        // Independent scrambles of the two coordinates (keys differ by a constant hashed in).
        return {fixedToFloat(owenScramble(vanDerCorput(i), key)),
                fixedToFloat(owenScramble(sobolSecond(i), mixBits(key ^ 0x5851f42d4c957f2dull)))};
    }

private:
    std::uint64_t nextDimensionKey() { return mixBits(m_pixelHash ^ mixBits(std::uint64_t(m_dimension++) + 1)); }

    /// Index into the sequence for this draw: the sample's place in its block of
    /// sample_count points, permuted per draw (a permutation of a net is the same net),
    /// plus the block's start. Indices past 2^32 wrap, as 32-bit digits allow.
    std::uint32_t sequenceIndex(std::uint64_t key) const {
        const std::uint64_t block = m_index / m_count;
        const std::uint32_t within = permutationElement(std::uint32_t(m_index % m_count), m_count, key);
        return std::uint32_t(block * m_count + within);
    }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::LowDiscrepancySampler)
