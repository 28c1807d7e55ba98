#pragma once
// Sobol' direction numbers: Joe & Kuo's primitive polynomials and initial direction
// numbers for dimensions 2..1024 (dimension 1 is van der Corput and needs none), the first
// 1023 rows of their file new-joe-kuo-6.21201 ("search criterion D(6)", 21201 dimensions).
// Each row {s, a, {m_1 .. m_s}}: s is the degree of the primitive polynomial
//   x^s + c_1 x^(s-1) + ... + c_(s-1) x + 1 over GF(2), a = c_1 c_2 .. c_(s-1) read as a
// binary number, and m_k (odd, < 2^k) the initial direction numbers. sobolMatrices() below
// derives the generator matrices from them with Bratley & Fox's recurrence
//   m_k = 2 c_1 m_(k-1) xor 4 c_2 m_(k-2) xor ... xor 2^s m_(k-s) xor m_(k-s),
// column k of dimension j being v_k = m_k / 2^k in 32-bit fixed point.
//
// Reference: S. Joe, F. Y. Kuo, "Constructing Sobol sequences with better two-dimensional
// projections", SIAM J. Sci. Comput. 30(5), 2635-2654, 2008; I. M. Sobol', "On the
// distribution of points in a cube and the approximate evaluation of integrals", 1967;
// P. Bratley, B. L. Fox, "Algorithm 659: Implementing Sobol's quasirandom sequence
// generator", ACM TOMS 14(1), 1988.
//
// The direction numbers are distributed under this licence:
// -----------------------------------------------------------------------------
// Licence pertaining to sobol.cc and the accompanying sets of direction numbers
// -----------------------------------------------------------------------------
// Copyright (c) 2008, Frances Y. Kuo and Stephen Joe
// All rights reserved.
//
// Redistribution and use in source and binary forms, with or without
// modification, are permitted provided that the following conditions are met:
//
//     * Redistributions of source code must retain the above copyright
//       notice, this list of conditions and the following disclaimer.
//
//     * Redistributions in binary form must reproduce the above copyright
//       notice, this list of conditions and the following disclaimer in the
//       documentation and/or other materials provided with the distribution.
//
//     * Neither the names of the copyright holders nor the names of the
//       University of New South Wales and the University of Waikato
//       and its contributors may be used to endorse or promote products derived
//       from this software without specific prior written permission.
//
// THIS SOFTWARE IS PROVIDED BY THE COPYRIGHT HOLDERS ``AS IS'' AND ANY
// EXPRESS OR IMPLIED WARRANTIES, INCLUDING, BUT NOT LIMITED TO, THE IMPLIED
// WARRANTIES OF MERCHANTABILITY AND FITNESS FOR A PARTICULAR PURPOSE ARE
// DISCLAIMED. IN NO EVENT SHALL THE COPYRIGHT HOLDERS BE LIABLE FOR ANY
// DIRECT, INDIRECT, INCIDENTAL, SPECIAL, EXEMPLARY, OR CONSEQUENTIAL DAMAGES
// (INCLUDING, BUT NOT LIMITED TO, PROCUREMENT OF SUBSTITUTE GOODS OR SERVICES;
// LOSS OF USE, DATA, OR PROFITS; OR BUSINESS INTERRUPTION) HOWEVER CAUSED AND
// ON ANY THEORY OF LIABILITY, WHETHER IN CONTRACT, STRICT LIABILITY, OR TORT
// (INCLUDING NEGLIGENCE OR OTHERWISE) ARISING IN ANY WAY OUT OF THE USE OF THIS
// SOFTWARE, EVEN IF ADVISED OF THE POSSIBILITY OF SUCH DAMAGE.
#include <bit>
#include <cstdint>
#include <vector>

namespace effigi::sobol {

struct JoeKuoRow {
    std::uint8_t degree;       ///< s
    std::uint16_t a;           ///< c_1 .. c_(s-1), most significant first
    std::uint16_t m[13];       ///< m_1 .. m_s
};

/// Dimensions with direction numbers (the table's rows and van der Corput).
inline constexpr int Dimensions = 1024;
/// Columns of each generator matrix: sample indices of up to 64 bits.
inline constexpr int Columns = 64;

inline constexpr JoeKuoRow JoeKuo[Dimensions - 1] = {
#include "sobol_joe_kuo.inc"  // generated from data/sobol/new-joe-kuo-1024.txt
};

/// Generator matrices of dimensions 0 .. Dimensions-1, Columns 32-bit columns each
/// (column k = v_(k+1), most significant bit first), derived once on first use. Columns past
/// 32 are the top 32 bits of v_k: the recurrence only shifts right, so truncating its
/// inputs truncates its output exactly.
inline const std::uint32_t* sobolMatrices() {
    static const std::vector<std::uint32_t> matrices = [] {
        std::vector<std::uint32_t> c(std::size_t(Dimensions) * Columns, 0u);
        for (int k = 0; k < 32; ++k) c[std::size_t(k)] = 0x80000000u >> k;  // van der Corput
        for (int j = 1; j < Dimensions; ++j) {
            const JoeKuoRow& row = JoeKuo[j - 1];
            const int s = row.degree;
            std::uint32_t* v = &c[std::size_t(j) * Columns];
            for (int k = 0; k < s; ++k) v[k] = std::uint32_t(row.m[k]) << (31 - k);
            for (int k = s; k < Columns; ++k) {
                std::uint32_t x = v[k - s] ^ (v[k - s] >> s);
                for (int i = 1; i < s; ++i)
                    if ((row.a >> (s - 1 - i)) & 1u) x ^= v[k - i];
                v[k] = x;
            }
        }
        return c;
    }();
    return matrices.data();
}

/// Coordinate `dimension` (< Dimensions) of point `index` of the unscrambled Sobol'
/// sequence, as 32-bit fixed point: the xor of the columns of the index's set bits.
inline std::uint32_t sample(std::uint64_t index, int dimension) {
    if (dimension == 0) {  // the identity matrix: bit reversal (columns past 32 are 0)
        auto v = std::uint32_t(index);
        v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
        v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
        v = ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
        v = ((v >> 8) & 0x00ff00ffu) | ((v & 0x00ff00ffu) << 8);
        return (v >> 16) | (v << 16);
    }
    const std::uint32_t* column = sobolMatrices() + std::size_t(dimension) * Columns;
    std::uint32_t v = 0;
    for (; index; index &= index - 1) v ^= column[std::countr_zero(index)];
    return v;
}

} // namespace effigi::sobol
