// sampler "independent" — uniform pseudo-random sample values, no stratification.
//
// Every (pixel, sample index) pair gets its own PCG32 stream seeded by hashing the
// pixel, the index and the user seed. Samples are therefore reproducible no matter
// which thread draws them or in which order, and the baseline every smarter sampler
// is compared against (variance ∝ 1/n).
//
// Parameters:
//   sample_count  int (default 4, >= 1)  samples per pixel
//   seed          int (default 0)        changes every sequence; images with different
//                                        seeds have independent noise
//
// Reference: M. E. O'Neill, "PCG: A Family of Simple Fast Space-Efficient Statistically
// Good Algorithms for Random Number Generation", HMC-CS-2014-0905.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/math/rng.hpp"

namespace effigi {
namespace {

class IndependentSampler final : public Implements<ISampler> {
public:
    static Schema schema() {
        Schema s("sampler", "independent", "Independent uniform random samples (PCG32), no stratification.");
        s.cite("M. E. O'Neill, PCG: A Family of ... Random Number Generation, HMC-CS-2014-0905");
        s.integer("sample_count", 4, "Samples per pixel").atLeast(1);
        s.integer("seed", 0, "Seed of every sequence: equal seeds give identical images");
        s.addConformance({"default", {}});
        s.addConformance({"one sample, other seed", {{"sample_count", std::int64_t(1)}, {"seed", std::int64_t(12345)}}});
        s.addConformance({"extreme seed", {{"sample_count", std::int64_t(1024)}, {"seed", std::int64_t(-1)}}});
        return s;
    }

    explicit IndependentSampler(const Properties& p)
        : m_sampleCount(p.getInt("sample_count")), m_seed(std::uint64_t(p.getInt("seed"))) {
        startPixel(Point2i(0));
    }

    IndependentSampler(const IndependentSampler&) = default;

    int samplesPerPixel() const override { return int(std::min<std::int64_t>(m_sampleCount, 0x7fffffff)); }

    void startPixel(const Point2i& pixel) override {
        // Pack both coordinates losslessly (they may be negative in scratch domains).
        std::uint64_t key = (std::uint64_t(std::uint32_t(pixel.x)) << 32) | std::uint32_t(pixel.y);
        m_pixelHash = mixBits(key ^ mixBits(m_seed + 0x9e3779b97f4a7c15ull));
        startSample(0);
    }

    void startSample(std::uint64_t index) override {
        // A fresh generator per sample: the state depends on (pixel, seed, index), the
        // stream on (pixel, seed), so neighbouring indices land far apart in the sequence.
        m_rng.seed(mixBits(m_pixelHash ^ mixBits(index)), m_pixelHash);
    }

    float get1D() override { return m_rng.nextFloat(); }
    Point2f get2D() override {
        float x = m_rng.nextFloat();
        return {x, m_rng.nextFloat()};
    }

    Ref<ISampler> clone(std::uint64_t streamOffset) const override {
        auto copy = std::make_shared<IndependentSampler>(*this);
        copy->setIdentity(typeName(), id());
        copy->m_seed = m_seed + streamOffset;
        copy->startPixel(Point2i(0));
        return copy;
    }

private:
    std::int64_t m_sampleCount;
    std::uint64_t m_seed;
    std::uint64_t m_pixelHash = 0;  // hash of (pixel, seed)
    PCG32 m_rng;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::IndependentSampler)
