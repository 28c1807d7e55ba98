#pragma once
// What the hashed samplers (stratified, multijitter, orthogonal, ldsampler) share: random access by (pixel, sample
// index, dimension). Nothing is carried from one sample to the next; each draw is a pure
// function of a per-pixel hash, the sample index and the number of draws made so far in
// the sample (the dimension), so progressive passes may ask for any index range.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/math/sample_sequences.hpp"

#include <algorithm>
#include <memory>

namespace effigi {

/// CRTP base: Derived supplies get1D/get2D/claims and sets m_count in its constructor.
template <typename Derived>
class HashedSampler : public Implements<ISampler> {
public:
    int samplesPerPixel() const override { return int(m_count); }

    void startPixel(const Point2i& pixel) override {
        const std::uint64_t key = (std::uint64_t(std::uint32_t(pixel.x)) << 32) | std::uint32_t(pixel.y);
        m_pixelHash = mixBits(key ^ mixBits(m_seed + 0x9e3779b97f4a7c15ull));
        startSample(0);
    }

    void startSample(std::uint64_t index) override {
        m_index = index;
        m_dimension = 0;
    }

    /// The same sampler with its seed moved by `streamOffset` (one per render thread).
    Ref<ISampler> clone(std::uint64_t streamOffset) const override {
        auto copy = std::make_shared<Derived>(static_cast<const Derived&>(*this));
        copy->setIdentity(typeName(), id());
        static_cast<HashedSampler&>(*copy).m_seed = m_seed + streamOffset;
        copy->startPixel(Point2i(0));
        return copy;
    }

protected:
    explicit HashedSampler(std::uint64_t seed) : m_seed(seed) {}
    HashedSampler(const HashedSampler&) = default;

    /// Key of the next dimension of this pixel (for the stratum samplers: stratified, multijitter,
    /// orthogonal). Rounds of sample indices past m_count get new keys so that repeated
    /// rounds are not copies of the first.
    std::uint64_t nextDimensionKey() {
        const std::uint64_t round = m_index / m_count;
        return mixBits(m_pixelHash ^ mixBits((std::uint64_t(m_dimension++) << 40) ^ round));
    }
    /// A uniform offset in [0, 1), one independent hash per (key, sample index, coordinate);
    /// 0.5 (the stratum's centre) when jitter is off.
    double jitterOffset(bool jitter, std::uint64_t key, std::uint64_t coordinate) const {
        if (!jitter) return 0.5;
        std::uint64_t h = mixBits(key ^ mixBits(m_index * 3 + coordinate + 0x632be59bd9b4e019ull));
        return double(h >> 11) * 0x1p-53;
    }
    /// Rounding to float may reach 1; keep values in [0, 1).
    static float toUnit(double v) { return std::min(float(v), OneMinusEpsilon); }
    /// A 1D draw that is a Latin hypercube over each round of m_count samples: the sample
    /// index picks one of m_count equal strata through a permutation keyed by the next
    /// dimension, and the point is jitterOffset() inside it (stratified, multijitter).
    float permutedStratum1D(bool jitter) {
        std::uint64_t key;
        const std::uint32_t stratum = permutedStratum(key);
        return toUnit((double(stratum) + jitterOffset(jitter, key, 0)) / double(m_count));
    }
    /// Which of m_count strata (or cells) the current sample takes in the next dimension,
    /// through a permutation keyed by that dimension; `key` receives the dimension's key.
    std::uint32_t permutedStratum(std::uint64_t& key) {
        key = nextDimensionKey();
        return permutationElement(std::uint32_t(m_index % m_count), m_count, key);
    }
    /// Claims of a sampler whose 1D draws are Latin hypercubes and 2D draws one point per
    /// grid cell (stratified, multijitter): with jitter, RMS error rates smoothRate for
    /// smooth integrands and N^-3/4 across discontinuities (Mitchell 1996); without jitter
    /// the error is deterministic, so no rate is claimed.
    static SamplerClaims stratumClaims(bool jitter, double smoothRate) {
        SamplerClaims c;
        c.stratification = StratifyLatinHypercube | StratifyJittered2D;
        if (jitter) {
            c.smoothRate = smoothRate;
            c.discontinuousRate = -0.75;
        }
        return c;
    }

    std::uint64_t m_seed;
    std::uint32_t m_count = 1;      // samples per pixel (after rounding)
    std::uint64_t m_pixelHash = 0;  // hash of (pixel, seed)
    std::uint64_t m_index = 0;      // current sample
    std::uint32_t m_dimension = 0;  // draws made in the current sample
};

} // namespace effigi
