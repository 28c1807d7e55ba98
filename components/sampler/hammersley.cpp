// sampler "hammersley" — a scrambled Hammersley point set of sample_count points per pixel.
//
// Sample j of N is the point (j/N, φ2(j), φ3(j), φ5(j), ...), φb the radical inverse in
// base b (Hammersley 1964: the Halton sequence with its first coordinate replaced by the
// index). Every pixel gets its own randomization keyed by a hash of (pixel, seed), so the
// pixels' errors are independent:
//   owen  (default) nested uniform (Owen) scrambling of every coordinate: base 2 by
//         Burley's hash, base b by hashed digit permutations over the digits that tell the
//         N points apart, then a uniform random tail (which is what Owen's scramble does to
//         the remaining digits of a finite point set); and the samples of the pixel visit
//         its N points in a random order (a hashed permutation, the same for every
//         dimension), so that any first k < N samples are uniform too: in sample order the
//         j/N coordinate would otherwise cover only [0, k/N) (progressive passes, a time
//         limit). A Cranley–Patterson rotation was tried as the cheaper randomization and
//         dropped: a rotated net is not a net, and its samples are neither stratified as
//         the conformance checks define it nor independent from one sample to the next.
//   none  the plain point set in index order, the same in every pixel: deterministic, for
//         reference values and tests, not for rendering (biased, pixels correlated).
//
// Dimensions: the first 2D draw of a sample (normally getPixel2D) is (j/N, φ2(j)); the
// other draws take bases 3, 5, 7, ... in order. Past the 256th prime (base 1619) values
// are independent pseudo-random numbers hashed from (pixel, index, dimension, seed).
//
// What holds: for N = 2^m the first 2D draw is a (0,m,2)-net (every elementary interval of
// area 1/N holds one point), kept by Owen scrambling; its RMS error then falls as
// ~N^-3/2 √log N for smooth integrands and N^-3/4 across discontinuities (Owen 1997). Base
// b ≥ 3 coordinates are stratified into b^k intervals only for N = b^k. For other N, j/N
// puts one point in each interval [k/N, (k+1)/N) unscrambled, but the Owen scramble works
// on binary intervals and keeps only the dyadic ones: no stratification is promised then;
// the points stay uniform and well spread.
// Indices past N start another round of the same points with a fresh randomization
// (randomization "none" repeats them).
//
// Parameters:
//   sample_count   int    (default 4, 1..2^30)  N, the points per pixel
//   seed           int    (default 0)           seed of every scramble
//   randomization  string (default "owen")      "owen" or "none"
//
// Reference: J. M. Hammersley, D. C. Handscomb, "Monte Carlo Methods", 1964;
// J. H. Halton, Numerische Mathematik 2, 1960; R. Cranley, T. N. L. Patterson,
// "Randomization of number theoretic methods for multiple integration", 1976; A. B. Owen,
// "Randomly Permuted (t,m,s)-Nets and (t,s)-Sequences", 1995; B. Burley, "Practical
// Hash-based Owen Scrambling", JCGT 9(4), 2020; M. Pharr et al., "Physically Based
// Rendering", 4th ed., §8.6.
#include "qmc.hpp"

namespace effigi {
namespace {

using namespace qmc;

class HammersleySampler final : public HashedSampler<HammersleySampler> {
public:
    static Schema schema() {
        Schema s("sampler", "hammersley", "Scrambled Hammersley point set per pixel (j/N, φ2, φ3, φ5, ...).");
        s.cite("J. M. Hammersley, D. C. Handscomb, Monte Carlo Methods, 1964; A. B. Owen, Randomly Permuted "
               "(t,m,s)-Nets and (t,s)-Sequences, 1995; B. Burley, Practical Hash-based Owen Scrambling, JCGT 9(4), 2020");
        s.integer("sample_count", 4, "Points per pixel (any count; a power of two makes the pixel 2D draw a net)")
            .range(1, 1 << 30);
        s.integer("seed", 0, "Seed of every scramble: equal seeds give identical images");
        s.string("randomization", "owen", "Per-pixel Owen scrambling and sample order, or none (the plain point set)")
            .oneOf({"owen", "none"});
        s.addConformance({"default", {}});
        s.addConformance({"non-power-of-two count, other seed", {{"sample_count", std::int64_t(12)}, {"seed", std::int64_t(7)}}});
        s.addConformance({"one sample", {{"sample_count", std::int64_t(1)}, {"seed", std::int64_t(-1)}}});
        s.addConformance({"1024 samples", {{"sample_count", std::int64_t(1024)}}});
        return s;
    }

    explicit HammersleySampler(const Properties& p) : HashedSampler(std::uint64_t(p.getInt("seed"))) {
        m_count = std::uint32_t(p.getInt("sample_count"));
        const std::string& r = p.getString("randomization");
        m_mode = r == "none" ? Mode::None : Mode::Owen;
        startPixel(Point2i(0));
    }

    HammersleySampler(const HammersleySampler&) = default;

    SamplerClaims claims() const override {
        SamplerClaims c;
        // The first 2D draw at N = 2^m: an Owen-scrambled (0,m,2)-net, like ldsampler (the
        // flag promises nothing for other N). Unscrambled, the error is deterministic; the
        // rates are those of the scrambled set.
        c.stratification = StratifyElementary2D;
        c.smoothRate = -1.4;
        c.discontinuousRate = -0.75;
        return c;
    }

    void startSample(std::uint64_t index) override {
        HashedSampler::startSample(index);
        m_dimension = 2;
        m_pixelDrawn = false;
        m_roundKey = mixBits(m_pixelHash ^ mixBits(index / m_count + 0x2545f4914f6cdd1dull));
        m_point = std::uint32_t(index % m_count);
        if (m_mode == Mode::Owen) m_point = permutationElement(m_point, m_count, m_roundKey ^ 0x94d049bb133111ebull);
    }

    float get1D() override { return coordinate(int(m_dimension++)); }

    /// The first 2D draw is (j/N, φ2(j)); later ones take the next two bases.
    Point2f get2D() override {
        int d = 0;
        if (m_pixelDrawn) {
            d = int(m_dimension);
            m_dimension += 2;
        }
        m_pixelDrawn = true;
        const float x = coordinate(d);
        return {x, coordinate(d + 1)};
    }

private:
    enum class Mode { Owen, None };

    /// Coordinate d of point j: 0 is j/N, d ≥ 1 the radical inverse in the d-th prime.
    float coordinate(int d) const {
        const std::uint64_t key = mixBits(m_roundKey ^ mixBits(std::uint64_t(d) * 0x9e3779b97f4a7c15ull + 1));
        const std::uint32_t j = m_point;
        if (d <= 1) {  // base 2 in 32-bit fixed point
            std::uint32_t v = d == 1 ? reverseBits32(j) : std::uint32_t((std::uint64_t(j) << 32) / m_count);
            return qmc::toFloat(m_mode == Mode::Owen ? fastOwenScramble(v, seed32(key)) : v);
        }
        if (d - 1 >= PrimeCount) return qmc::toFloat(hashToUnit(mixBits(key ^ mixBits(j + 0x632be59bd9b4e019ull))));
        const std::uint32_t b = Primes[std::size_t(d - 1)];
        return qmc::toFloat(m_mode == Mode::Owen ? owenFinite(j, b, key) : radicalInverse(j, b));
    }

    /// Owen scrambling of φb(j) among the N points j < N: the first K digits, K the fewest
    /// with b^K ≥ N, are permuted digit by digit (permuteDigit), each by a permutation
    /// chosen by hashing the digits above it; the N points then sit in distinct intervals
    /// of width b^-K, in which Owen's scramble leaves each uniformly distributed,
    /// independently: a hashed tail.
    double owenFinite(std::uint32_t j, std::uint32_t b, std::uint64_t key) const {
        double r = 0.0, scale = 1.0;
        std::uint64_t prefix = 0, power = 1;  // prefix = j mod b^k, the digits above digit k
        std::uint32_t a = j;
        for (int k = 0; power < m_count || k == 0; ++k, a /= b) {
            const std::uint32_t digit = a % b;
            scale /= b;
            r += double(permuteDigit(digit, b, mixBits(key ^ mixBits((std::uint64_t(k) << 48) ^ prefix)))) * scale;
            prefix += digit * power;
            power *= b;
        }
        return r + scale * hashToUnit(mixBits(key ^ mixBits(std::uint64_t(j) + 0x632be59bd9b4e019ull)));
    }

    Mode m_mode = Mode::Owen;
    std::uint32_t m_point = 0;       // j: the sample's point of the set
    std::uint64_t m_roundKey = 0;    // hash of (pixel, seed, round of N indices)
    bool m_pixelDrawn = false;       // the first 2D draw (dimensions 0 and 1) was taken
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::HammersleySampler)
