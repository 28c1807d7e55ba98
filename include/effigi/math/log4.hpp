#pragma once
// The natural logarithm of four floats at once (a GCC/Clang vector extension, any target).
// Hero-wavelength sampling draws four wavelengths per camera sample, each through a
// logarithm; as four calls of libm's logf that was 1.8 % of a Cornell box render.
//
// Method: x = m · 2^e with m in [√½, √2), f = m − 1, and ln(1 + f) = f − f²/2 + f³ P(f)
// with Cephes' degree-8 minimax polynomial P for that interval (S. L. Moshier, "Methods
// and Programs for Mathematical Functions", 1989; the coefficients of its logf);
// e · ln 2 is added in two parts (a short high part that multiplies e exactly).
// Domain: positive, finite, normal floats (what the callers pass); no special cases.
// Accuracy: tests/test_wavelengths.cpp measures the largest error against log in double.
#include <cstdint>
#include <cstring>

namespace effigi {

using Float4 = float __attribute__((vector_size(16)));

inline Float4 log4(Float4 x) {
    using Int4 = std::int32_t __attribute__((vector_size(16)));
    Int4 bits;
    std::memcpy(&bits, &x, sizeof bits);
    Int4 e = ((bits >> 23) & 0xff) - 127;
    bits = (bits & 0x007fffff) | 0x3f800000;  // the mantissa as a float in [1, 2)
    Float4 m;
    std::memcpy(&m, &bits, sizeof m);
    const Int4 big = m > 1.41421356f;  // then m/2 in [√½, 1) and one more power of two
    m = big ? m * 0.5f : m;
    e = big ? e + 1 : e;
    const Float4 fe = __builtin_convertvector(e, Float4);
    const Float4 f = m - 1.f;
    const Float4 z = f * f;
    Float4 p = 7.0376836292e-2f * f - 1.1514610310e-1f;
    p = p * f + 1.1676998740e-1f;
    p = p * f - 1.2420140846e-1f;
    p = p * f + 1.4249322787e-1f;
    p = p * f - 1.6668057665e-1f;
    p = p * f + 2.0000714765e-1f;
    p = p * f - 2.4999993993e-1f;
    p = p * f + 3.3333331174e-1f;
    Float4 y = p * f * z;
    y += -2.12194440e-4f * fe;
    y += -0.5f * z;
    return (f + y) + 0.693359375f * fe;
}

} // namespace effigi
