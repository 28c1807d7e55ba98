// sampler "halton" — the Halton sequence over the image plane (pbrt-v4's HaltonSampler),
// randomised by random digit permutations or Owen scrambling.
//
// One global sequence covers the image: point i is (φ2(i), φ3(i), φ5(i), ...), φb the
// radical inverse in base b, and its first two coordinates, scaled by 2^7 = 128 and
// 3^5 = 243, name a pixel (x mod 128, y mod 128) and the position inside it. The indices
// that land in a given pixel are those whose 7 low base-2 digits and 5 low base-3 digits
// spell its coordinates backwards; by the Chinese remainder theorem they are one residue o
// modulo 128·243 = 31104, found with the multiplicative inverses of 243 mod 128 and of
// 128 mod 243, and the pixel's sample j is point o + 31104·j. So samples are random access
// by (pixel, index). Pixels 128 apart would repeat the same samples (pbrt-v4 does); here
// each 128 × 128 tile starts its pixels' samples at a hashed offset into their subsequence,
// so tiles are decorrelated (not with randomization "none", which is pbrt's plain sequence).
//
// Dimensions: the first 2D draw of a sample (normally getPixel2D) is the position inside
// the pixel; the other draws take bases 5, 7, 11, ... in order. Past the 256th prime (base
// 1619) values are independent pseudo-random numbers hashed from (pixel, index, dimension,
// seed): no low-discrepancy structure there.
//
// The position inside the pixel: pbrt-v4 takes the digits of φ2(i) and φ3(i) below the
// pixel's, (φ2(i >> 7), φ3(i / 243)), unscrambled, which stratifies x for N = 2^k and y for
// N = 3^k only, and makes a pixel's offsets a fixed function of its position (at 1 spp the
// offsets across the image are visibly non-uniform and x and y correlated). That is what
// randomization "none" gives. Randomized, the position is instead the pixel's sample
// number j through the base-2 (0,2)-sequence (van der Corput, Sobol' dimension 2) with a
// hash-based Owen scramble keyed by the pixel: a (0,m,2)-net for N = 2^m, uniform and
// independent from pixel to pixel. The Halton dimensions (bases ≥ 5) are unchanged.
//
// Randomization (pbrt-v4's names) of the Halton dimensions:
//   permutedigits  every digit position of every dimension gets its own random permutation
//                  of [0, b), drawn from the seed (one set for the whole image, built once
//                  per seed and shared);
//   owen           each digit is permuted by a permutation chosen by hashing the digits
//                  above it (nested uniform scrambling, one scramble for the whole image);
//   none           the plain Halton sequence and pbrt's offsets: deterministic, for
//                  reference values and tests (it claims no stratification).
// Values are computed to the digits a float resolves (b^n ≥ 2^24), so a pixel's
// subsequence repeats after ≥ 1.7·10^7 samples; indices wrap modulo 2^64 / 31104.
//
// What holds: the N samples of a pixel are a window of a Halton sequence along an
// arithmetic progression of step 31104, coprime to every base ≥ 5, so the dimension of
// base b is stratified into b^k intervals for N = b^k, for any N well spread (tests/
// test_samplers_ld.cpp measures an RMS error slope of −0.93 for a smooth integrand on
// bases 11 and 13, Monte Carlo's being −0.5). The claims are those of the in-pixel
// position, the draw effigi-conform measures: for N = 2^m a (0,m,2)-net (for other N the
// first N points of the (0,2)-sequence, no promise), RMS error slopes of −1.4 (smooth, N^-3/2
// up to a log factor) and −3/4 (discontinuous) over N = 4..4096.
//
// Parameters:
//   sample_count   int    (default 4, 1..2^30)      samples per pixel
//   seed           int    (default 0)               seed of the permutations and hashes
//   randomization  string (default "permutedigits") "permutedigits", "owen" or "none"
//
// Reference: J. H. Halton, "On the efficiency of certain quasi-random sequences of points
// in evaluating multi-dimensional integrals", Numerische Mathematik 2, 1960; A. B. Owen,
// "Randomly Permuted (t,m,s)-Nets and (t,s)-Sequences", 1995; B. Burley, "Practical
// Hash-based Owen Scrambling", JCGT 9(4), 2020; M. Pharr, W. Jakob, G. Humphreys,
// "Physically Based Rendering", 4th ed., §8.6.
#include "qmc.hpp"

#include <map>
#include <mutex>
#include <tuple>
#include <utility>

namespace effigi {
namespace {

using namespace qmc;

constexpr std::uint64_t Scale2 = 128, Scale3 = 243, Stride = Scale2 * Scale3;  // 2^7, 3^5
constexpr int Digits2 = 7, Digits3 = 5;

/// The index whose `digits` low base-`base` digits, mirrored, are those of `inverse`.
std::uint64_t inverseRadicalInverse(std::uint64_t inverse, std::uint64_t base, int digits) {
    std::uint64_t index = 0;
    for (int i = 0; i < digits; ++i, inverse /= base) index = index * base + inverse % base;
    return index;
}

/// x with a·x ≡ 1 (mod n), by the extended Euclidean algorithm (a, n coprime).
std::uint64_t multiplicativeInverse(std::int64_t a, std::int64_t n) {
    std::int64_t r0 = n, r1 = a % n, t0 = 0, t1 = 1;
    while (r1 != 0) {
        const std::int64_t q = r0 / r1;
        std::tie(r0, r1) = std::pair{r1, r0 - q * r1};
        std::tie(t0, t1) = std::pair{t1, t0 - q * t1};
    }
    return std::uint64_t((t0 % n + n) % n);
}

/// Offsets of each pixel's subsequence: o ≡ (x digits) mod 128 scaled, ≡ (y digits) mod 243.
const std::uint64_t Inverse243Mod128 = multiplicativeInverse(std::int64_t(Scale3), std::int64_t(Scale2));
const std::uint64_t Inverse128Mod243 = multiplicativeInverse(std::int64_t(Scale2), std::int64_t(Scale3));

/// pbrt-v4's random digit permutations: for every prime base b (dimension) and digit
/// position k < digitCount(b), a Fisher–Yates shuffle of [0, b) drawn from the seed.
/// Built once per seed (a few ms, ~1 MB) and shared by every sampler and clone using it.
class DigitPermutations {
public:
    explicit DigitPermutations(std::uint64_t seed) {
        std::size_t size = 0;
        for (int d = 0; d < PrimeCount; ++d) {
            m_offset[std::size_t(d)] = size;
            m_digits[std::size_t(d)] = digitCount(Primes[std::size_t(d)]);
            size += std::size_t(m_digits[std::size_t(d)]) * Primes[std::size_t(d)];
        }
        m_table.resize(size);
        for (int d = 0; d < PrimeCount; ++d) {
            const std::uint32_t b = Primes[std::size_t(d)];
            for (int k = 0; k < m_digits[std::size_t(d)]; ++k) {
                std::uint16_t* perm = &m_table[m_offset[std::size_t(d)] + std::size_t(k) * b];
                for (std::uint32_t i = 0; i < b; ++i) perm[i] = std::uint16_t(i);
                PCG32 rng(mixBits(seed ^ mixBits((std::uint64_t(d) << 8) | std::uint64_t(k))), seed);
                for (std::uint32_t i = b - 1; i > 0; --i)
                    std::swap(perm[i], perm[std::uint32_t(std::uint64_t(rng.nextUInt()) * (i + 1) >> 32)]);
            }
        }
    }

    /// Radical inverse of `a` in the base of dimension `d`, each digit permuted.
    double radicalInverse(std::uint64_t a, int d) const {
        const std::uint32_t b = Primes[std::size_t(d)];
        const std::uint16_t* perm = &m_table[m_offset[std::size_t(d)]];
        std::uint64_t reversed = 0, scale = 1;
        for (int k = 0; k < m_digits[std::size_t(d)]; ++k, a /= b, perm += b, scale *= b)
            reversed = reversed * b + perm[a % b];
        return double(reversed) / double(scale);
    }

    static std::shared_ptr<const DigitPermutations> get(std::uint64_t seed) {
        static std::mutex mutex;
        static std::map<std::uint64_t, std::weak_ptr<const DigitPermutations>> cache;
        std::lock_guard lock(mutex);
        if (auto p = cache[seed].lock()) return p;
        auto p = std::make_shared<const DigitPermutations>(seed);
        cache[seed] = p;
        return p;
    }

private:
    std::vector<std::uint16_t> m_table;
    std::array<std::size_t, PrimeCount> m_offset{};
    std::array<int, PrimeCount> m_digits{};
};

class HaltonSampler final : public HashedSampler<HaltonSampler> {
public:
    static Schema schema() {
        Schema s("sampler", "halton", "Halton sequence over the image plane (pbrt-v4), digit-permuted or Owen-scrambled.");
        s.cite("J. H. Halton, On the efficiency of certain quasi-random sequences of points ..., 1960; A. B. Owen, "
               "Randomly Permuted (t,m,s)-Nets and (t,s)-Sequences, 1995; B. Burley, Practical Hash-based Owen "
               "Scrambling, JCGT 9(4), 2020; M. Pharr et al., Physically Based Rendering 4th ed., §8.6");
        s.integer("sample_count", 4, "Samples per pixel (any count)").range(1, 1 << 30);
        s.integer("seed", 0, "Seed of the digit permutations and scrambles: equal seeds give identical images");
        s.string("randomization", "permutedigits", "Randomization of the sequence: random digit permutations, "
                                                   "Owen scrambling or none (pbrt-v4's plain sequence)")
            .oneOf({"permutedigits", "owen", "none"});
        s.addConformance({"default", {}});
        s.addConformance({"non-power-of-two count, other seed", {{"sample_count", std::int64_t(12)}, {"seed", std::int64_t(7)}}});
        s.addConformance({"one sample", {{"sample_count", std::int64_t(1)}, {"seed", std::int64_t(-1)}}});
        s.addConformance({"owen, 1024 samples", {{"sample_count", std::int64_t(1024)}, {"randomization", std::string("owen")}}});
        return s;
    }

    explicit HaltonSampler(const Properties& p) : HashedSampler(std::uint64_t(p.getInt("seed"))) {
        m_count = std::uint32_t(p.getInt("sample_count"));
        const std::string& r = p.getString("randomization");
        m_mode = r == "owen" ? Mode::Owen : r == "none" ? Mode::None : Mode::PermuteDigits;
        reseed();
        startPixel(Point2i(0));
    }

    HaltonSampler(const HaltonSampler&) = default;

    SamplerClaims claims() const override {
        SamplerClaims c;
        if (m_mode == Mode::None) {
            // pbrt's offsets: x stratified for N = 2^k, y for N = 3^k, no 2D net; the
            // slopes effigi-conform measures for them.
            c.smoothRate = -1.0;
            c.discontinuousRate = -0.75;
            return c;
        }
        // The first 2D draw (the in-pixel position) is a (0,m,2)-net for N = 2^m.
        c.stratification = StratifyElementary2D;
        c.smoothRate = -1.4;  // Owen-scrambled net (ldsampler's rate)
        c.discontinuousRate = -0.75;
        return c;
    }

    void startPixel(const Point2i& pixel) override {
        const std::int64_t x = pixel.x, y = pixel.y;
        const std::uint64_t px = std::uint64_t(((x % 128) + 128) % 128), py = std::uint64_t(((y % 128) + 128) % 128);
        m_pixelIndex = (inverseRadicalInverse(px, 2, Digits2) * Scale3 * Inverse243Mod128 +
                        inverseRadicalInverse(py, 3, Digits3) * Scale2 * Inverse128Mod243) % Stride;
        // The tile of 128 × 128 pixels: its pixels' samples start at a hashed offset.
        const std::uint64_t tile = (std::uint64_t(std::uint32_t(std::int32_t((x - std::int64_t(px)) / 128))) << 32) |
                                   std::uint32_t(std::int32_t((y - std::int64_t(py)) / 128));
        m_tileOffset = m_mode == Mode::None ? 0 : (tile == 0 ? 0 : mixBits(tile ^ mixBits(m_seed + 0x3c6ef372ull)) >> 44);
        HashedSampler::startPixel(pixel);
    }

    void startSample(std::uint64_t index) override {
        HashedSampler::startSample(index);
        m_dimension = 2;
        m_pixelDrawn = false;
        m_halton = m_pixelIndex + (index + m_tileOffset) * Stride;
    }

    float get1D() override { return toFloat(dimension(m_dimension++)); }

    /// The first 2D draw is the position in the pixel; later ones take the next two bases.
    Point2f get2D() override {
        if (!m_pixelDrawn) {
            m_pixelDrawn = true;
            return pixelOffset();
        }
        const int d = int(m_dimension);
        m_dimension += 2;
        return {toFloat(dimension(d)), toFloat(dimension(d + 1))};
    }

    Ref<ISampler> clone(std::uint64_t streamOffset) const override {
        auto copy = std::make_shared<HaltonSampler>(*this);
        copy->setIdentity(typeName(), id());
        copy->m_seed = m_seed + streamOffset;
        copy->reseed();
        copy->startPixel(Point2i(0));
        return copy;
    }

private:
    enum class Mode { PermuteDigits, Owen, None };

    void reseed() { m_perms = m_mode == Mode::PermuteDigits ? DigitPermutations::get(m_seed) : nullptr; }

    /// Key of the global Owen scramble of dimension d.
    std::uint64_t dimensionKey(int d) const { return mixBits(m_seed ^ mixBits(std::uint64_t(d) + 0x51ed27ull)); }

    /// Coordinate d ≥ 2 of the current point: base Primes[d], or a hash past the table.
    double dimension(int d) const {
        if (d >= PrimeCount)
            return hashToUnit(mixBits(m_pixelHash ^ mixBits(m_index * 0x9e3779b97f4a7c15ull + std::uint64_t(d))));
        switch (m_mode) {
        case Mode::PermuteDigits: return m_perms->radicalInverse(m_halton, d);
        case Mode::Owen: return owenRadicalInverse(m_halton, Primes[std::size_t(d)], dimensionKey(d));
        default: return qmc::radicalInverse(m_halton, Primes[std::size_t(d)]);
        }
    }

    /// The position inside the pixel. Unrandomized: pbrt-v4's (φ2, φ3) of the point with
    /// the pixel's digits removed. Randomized: the sample number j through the base-2
    /// (0,2)-sequence (van der Corput, Sobol' dimension 2), scrambled per pixel (see the top).
    Point2f pixelOffset() const {
        if (m_mode == Mode::None)
            return {toFloat(qmc::radicalInverse(m_halton >> Digits2, 2)), toFloat(qmc::radicalInverse(m_halton / Scale3, 3))};
        const auto j = std::uint32_t(m_index);
        const std::uint64_t key = mixBits(m_pixelHash ^ mixBits((m_index >> 32) + 0x7c15ull));
        return {toFloat(fastOwenScramble(vanDerCorput(j), seed32(key))),
                toFloat(fastOwenScramble(sobolSecond(j), seed32(~key)))};
    }

    Mode m_mode = Mode::PermuteDigits;
    std::shared_ptr<const DigitPermutations> m_perms;
    std::uint64_t m_pixelIndex = 0;  // the pixel's residue modulo 31104
    std::uint64_t m_tileOffset = 0;  // sample offset of the pixel's 128 × 128 tile
    std::uint64_t m_halton = 0;      // index of the current point in the global sequence
    bool m_pixelDrawn = false;       // the in-pixel position (first 2D draw) was taken
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::HaltonSampler)
