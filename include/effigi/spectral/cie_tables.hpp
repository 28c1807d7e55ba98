#pragma once
// The CIE tables themselves (1 nm steps over [LambdaMin, LambdaMax]) and their lookup,
// apart from cie.hpp's colour arithmetic: SampledWavelengths looks up D65 when it is
// sampled, and cie.hpp needs SampledWavelengths.
#include <algorithm>

namespace effigi::cie {

inline constexpr int TableStart = 360;
inline constexpr int TableSize = 471;  // 360..830 nm inclusive

extern const float X[TableSize];
extern const float Y[TableSize];
extern const float Z[TableSize];
/// CIE standard illuminant D65, relative SPD (100 at 560 nm).
extern const float D65[TableSize];

/// Piecewise-linear lookup in a 1 nm table; zero outside the table.
inline float lookup(const float* table, float lambda) {
    float x = lambda - float(TableStart);
    if (!(x >= 0.f) || x > float(TableSize - 1)) return 0.f;
    int i = std::min(int(x), TableSize - 2);
    float t = x - float(i);
    return (1.f - t) * table[i] + t * table[i + 1];
}

} // namespace effigi::cie
