#pragma once
// Building blocks of stratified and quasi-random samplers: a random-access permutation of
// [0, n) keyed by a hash, the base-2 (0,2)-sequence (van der Corput + Sobol' dimension 2)
// and a hash-based nested uniform (Owen) scramble. All are pure functions of their
// arguments so a sampler can evaluate any (pixel, index, dimension) without state.
#include "effigi/math/rng.hpp"

#include <bit>
#include <cstdint>

namespace effigi {

/// The image of `i` under a pseudo-random permutation of [0, n) chosen by `key`
/// (i < n). Rounds of odd multiplications and right xor-shifts, each a bijection on
/// w-bit words, permute [0, 2^w) ⊇ [0, n); cycle-walking (Black & Rogaway 2002, "Ciphers
/// with Arbitrary Finite Domains") restricts that to [0, n). Fewer than two walks on average.
inline std::uint32_t permutationElement(std::uint32_t i, std::uint32_t n, std::uint64_t key) {
    if (n <= 1) return 0;
    const int w = std::bit_width(n - 1);
    const std::uint64_t mask = (std::uint64_t(1) << w) - 1;
    const int shift = w > 1 ? (w + 1) / 2 : 1;
    std::uint64_t k[4];
    k[0] = mixBits(key ^ 0x632be59bd9b4e019ull);
    for (int r = 1; r < 4; ++r) k[r] = mixBits(k[r - 1] + 0x9e3779b97f4a7c15ull);
    std::uint64_t x = i;
    do {
        for (std::uint64_t kr : k) {
            x = (x ^ kr) & mask;                    // keyed xor
            x = (x * ((kr >> 32) | 1u)) & mask;     // odd multiplier: low bits feed high bits
            x ^= x >> shift;                        // and high bits feed low bits back
        }
    } while (x >= n);
    return std::uint32_t(x);
}

/// Nested uniform scrambling (Owen 1995) of a 32-bit fixed-point value in [0,1): digit k
/// (from the most significant) is flipped by a hash of the key and the k digits above
/// it, which is Owen's definition with the random permutation tree replaced by a hash
/// (Laine & Karras 2011; Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4)).
/// It preserves every (t,m,s)-net property while randomising the point set uniformly.
inline std::uint32_t owenScramble(std::uint32_t v, std::uint64_t key) {
    std::uint32_t out = v;
    const std::uint64_t base = mixBits(key ^ 0x2545f4914f6cdd1dull);
    for (int k = 0; k < 32; ++k) {
        // The k leading digits, tagged with a marker bit so prefixes of different lengths differ.
        std::uint64_t prefix = (k == 0 ? 0 : std::uint64_t(v >> (32 - k))) | (std::uint64_t(1) << k);
        if (mixBits(base ^ prefix * 0xd6e8feb86659fd93ull) & 1) out ^= std::uint32_t(1) << (31 - k);
    }
    return out;
}

/// First dimension of the base-2 (0,2)-sequence: the van der Corput radical inverse,
/// as 32-bit fixed point.
inline std::uint32_t vanDerCorput(std::uint32_t i) {
    std::uint32_t r = 0;
    for (int b = 0; b < 32; ++b) r |= ((i >> b) & 1u) << (31 - b);
    return r;
}

/// Second dimension of Sobol's sequence (primitive polynomial x + 1): its generator
/// matrix is Pascal's triangle mod 2, column j+1 = column j xor (column j >> 1). Paired
/// with van der Corput every block of 2^m consecutive points (aligned) is a (0,m,2)-net
/// (Sobol' 1967; Kollig & Keller 2002, "Efficient Multidimensional Sampling").
inline std::uint32_t sobolSecond(std::uint32_t i) {
    std::uint32_t r = 0, column = 0x80000000u;
    for (; i; i >>= 1, column ^= column >> 1)
        if (i & 1u) r ^= column;
    return r;
}

/// 32-bit fixed point to a float in [0, 1): the top 24 bits, exactly representable.
inline float fixedToFloat(std::uint32_t v) { return float(v >> 8) * 0x1p-24f; }

} // namespace effigi
