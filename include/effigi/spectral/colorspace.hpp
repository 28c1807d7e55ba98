#pragma once
// Linear RGB colour spaces by their primaries and white (CIE 15:2004 / IEC 61966-2-1).
#include "effigi/math/vector.hpp"

#include <glm/mat3x3.hpp>

namespace effigi {

/// XYZ -> linear sRGB / Rec.709 primaries, D65 white (IEC 61966-2-1).
inline Vector3f xyzToLinearSRGB(const Vector3f& xyz) {
    // GLM matrices are column-major: each glm::vec3 below is a column.
    static const glm::mat3 M(3.2404542f, -0.9692660f, 0.0556434f,   //
                             -1.5371385f, 1.8760108f, -0.2040259f,  //
                             -0.4985314f, 0.0415560f, 1.0572252f);
    return M * xyz;
}

inline Vector3f linearSRGBToXYZ(const Vector3f& rgb) {
    static const glm::mat3 M(0.4124564f, 0.2126729f, 0.0193339f,  //
                             0.3575761f, 0.7151522f, 0.1191920f,  //
                             0.1804375f, 0.0721750f, 0.9503041f);
    return M * rgb;
}

/// The sRGB transfer function (encode linear -> display).
inline float srgbEncode(float v) {
    if (v <= 0.0031308f) return 12.92f * v;
    return 1.055f * std::pow(v, 1.f / 2.4f) - 0.055f;
}
inline float srgbDecode(float v) {
    if (v <= 0.04045f) return v / 12.92f;
    return std::pow((v + 0.055f) / 1.055f, 2.4f);
}

} // namespace effigi
