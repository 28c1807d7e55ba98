#pragma once
// What the quasi-Monte Carlo samplers (halton, hammersley, sobol) share: bit reversal,
// Burley's hash-based nested uniform (Owen) scramble in base 2, the prime bases of
// radical inverses, Owen scrambling in a prime base, and conversion to float in [0, 1).
//
// Reference: B. Burley, "Practical Hash-based Owen Scrambling", JCGT 9(4), 2020;
// S. Laine, T. Karras, "Stratified Sampling for Stochastic Transparency", EGSR 2011;
// A. B. Owen, "Randomly Permuted (t,m,s)-Nets and (t,s)-Sequences", 1995;
// M. Pharr, W. Jakob, G. Humphreys, "Physically Based Rendering", 4th ed., §8.6.
#include "hashed_sampler.hpp"

#include <array>
#include <bit>
#include <cstdint>

namespace effigi::qmc {

inline std::uint32_t reverseBits32(std::uint32_t v) {
    v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    v = ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
    v = ((v >> 8) & 0x00ff00ffu) | ((v & 0x00ff00ffu) << 8);
    return (v >> 16) | (v << 16);
}

/// Nested uniform scramble of a 32-bit fixed-point value (Burley 2020): with the bits
/// reversed, digit k of the value becomes bit k from the bottom, and every step of the
/// hash below flips bit k by a function of the bits under it only (xor with a multiple by
/// an even constant, adding the seed, multiplying by an odd number), which is Owen's
/// scramble: each digit permuted by a choice depending on the digits before it. So every
/// (t,m,s)-net stays a net. The hash steps are Laine & Karras's construction with the
/// constants Burley's paper settles on after Vegdahl's search (as in pbrt-v4); the seed
/// must be a well-mixed 32-bit hash.
inline std::uint32_t fastOwenScramble(std::uint32_t v, std::uint32_t seed) {
    v = reverseBits32(v);
    v ^= v * 0x3d20adeau;
    v += seed;
    v *= (seed >> 16) | 1u;
    v ^= v * 0x05526c56u;
    v ^= v * 0x53a22864u;
    return reverseBits32(v);
}

/// Number of primes the radical-inverse samplers use as bases; dimensions past it get
/// independent random values.
inline constexpr int PrimeCount = 256;
inline constexpr std::array<std::uint32_t, PrimeCount> Primes = [] {
    std::array<std::uint32_t, PrimeCount> p{};
    int n = 0;
    for (std::uint32_t c = 2; n < PrimeCount; ++c) {
        bool prime = true;
        for (int i = 0; i < n && p[std::size_t(i)] * p[std::size_t(i)] <= c; ++i)
            if (c % p[std::size_t(i)] == 0) prime = false;
        if (prime) p[std::size_t(n++)] = c;
    }
    return p;
}();

/// Digits of a base-b radical inverse worth computing: the fewest with b^n ≥ 2^24, below
/// which a float cannot tell values apart (pbrt-v4's DigitPermutation uses the same bound).
inline int digitCount(std::uint32_t base) {
    int n = 0;
    for (double v = 1.0; v < 0x1p24; v *= base) ++n;
    return n;
}

/// Radical inverse of `a` in `base`: its digits mirrored about the radix point.
inline double radicalInverse(std::uint64_t a, std::uint32_t base) {
    const double inv = 1.0 / base;
    double scale = 1.0, r = 0.0;
    for (; a; a /= base) {
        scale *= inv;
        r += double(a % base) * scale;
    }
    return r;
}

/// The image of digit d under a random permutation of [0, b), b prime, chosen by the
/// hash h: the affine map d -> (α d + β) mod b with α in [1, b) and β in [0, b) drawn from
/// h. Each digit lands on every value with probability 1/b and any two distinct digits on
/// every pair of distinct values alike (affine maps of GF(b) are 2-transitive), which is all
/// the variance of a scrambled net depends on (Matoušek 1998; Owen 2003): used as the
/// nested permutations it gives Owen scrambling's mean square error. (The cycle-walking
/// permutationElement is visibly non-uniform for bases as small as 3..13.)
inline std::uint32_t permuteDigit(std::uint32_t d, std::uint32_t b, std::uint64_t h) {
    const std::uint64_t alpha = 1 + ((h >> 32) * (b - 1) >> 32), beta = (h & 0xffffffffu) * b >> 32;
    return std::uint32_t((alpha * d + beta) % b);
}

/// Radical inverse of `a` in the prime `base`, Owen-scrambled over digitCount(base)
/// digits: digit k goes through permuteDigit with a hash of `key`, k and the digits before
/// it (pbrt-v4's OwenScrambledRadicalInverse, with the level in the hash so that prefixes
/// of different lengths never share a permutation). Digits past the index's own are zeros
/// permuted like the others, so the value is uniform in its elementary interval.
inline double owenRadicalInverse(std::uint64_t a, std::uint32_t base, std::uint64_t key) {
    const int n = digitCount(base);
    std::uint64_t prefix = 0, reversed = 0, scale = 1;  // prefix: the digits so far, in order
    for (int k = 0; k < n; ++k, a /= base, scale *= base) {
        const std::uint32_t digit = std::uint32_t(a % base);
        const std::uint64_t node = mixBits(key ^ mixBits((prefix + 1) * 0x9e3779b97f4a7c15ull + std::uint64_t(k)));
        reversed = reversed * base + permuteDigit(digit, base, node);
        prefix = prefix * base + digit;
    }
    return double(reversed) / double(scale);
}

/// A uniform double in [0, 1) from a 64-bit hash.
inline double hashToUnit(std::uint64_t h) { return double(h >> 11) * 0x1p-53; }
/// A value in [0, 1] to a float in [0, 1): rounding may reach 1, which is kept off.
inline float toFloat(double v) { return std::min(float(v), OneMinusEpsilon); }
/// 32-bit fixed point to a float in [0, 1) (the top 24 bits, exactly).
inline float toFloat(std::uint32_t v) { return fixedToFloat(v); }
/// A well-mixed 32-bit scramble seed from a 64-bit key.
inline std::uint32_t seed32(std::uint64_t key) { return std::uint32_t(mixBits(key ^ 0xa0761d6478bd642full) >> 32); }

} // namespace effigi::qmc
