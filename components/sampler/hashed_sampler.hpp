#pragma once
// What the stratified and ldsampler samplers share: random access by (pixel, sample
// index, dimension). Nothing is carried from one sample to the next; each draw is a pure
// function of a per-pixel hash, the sample index and the number of draws made so far in
// the sample (the dimension), so progressive passes may ask for any index range.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/math/sample_sequences.hpp"

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

    std::uint64_t m_seed;
    std::uint32_t m_count = 1;      // samples per pixel (after rounding)
    std::uint64_t m_pixelHash = 0;  // hash of (pixel, seed)
    std::uint64_t m_index = 0;      // current sample
    std::uint32_t m_dimension = 0;  // draws made in the current sample
};

} // namespace effigi
