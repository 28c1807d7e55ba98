#pragma once
// Exposure and tone mapping for display (LDR) output: linear scene RGB in, RGB in [0, 1]
// out, ready for the sRGB transfer function. HDR outputs (EXR) are never tone mapped.
//
//   none      clamp to [0, 1].
//   reinhard  the global operator of Reinhard, Stark, Shirley, Ferwerda, "Photographic Tone
//             Reproduction for Digital Images", SIGGRAPH 2002, eq. 3: L_d = L / (1 + L),
//             applied to luminance L; the colour is scaled by L_d / L, so hue and
//             saturation are kept, then clamped to [0, 1] (a saturated colour may have one
//             channel above its luminance). The key value a / L̄_w of their eq. 2 is left
//             to the exposure.
//   filmic    K. Narkowicz, "ACES Filmic Tone Mapping Curve", 2015 (blog post,
//             https://knarkowicz.wordpress.com/2016/01/06/aces-filmic-tone-mapping-curve/):
//             a rational fit f(x) = x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14) of the
//             ACES RRT + sRGB ODT, applied per channel and clamped to [0, 1].
// Exposure multiplies by 2^stops before the curve.
#include "effigi/math/vector.hpp"

#include <array>
#include <optional>
#include <string_view>

namespace effigi {

enum class ToneMap { None, Reinhard, Filmic };

namespace tonemap {

inline const std::array<const char*, 3>& names() {
    static const std::array<const char*, 3> n{"none", "reinhard", "filmic"};
    return n;
}
inline std::optional<ToneMap> parse(std::string_view name) {
    if (name == "none") return ToneMap::None;
    if (name == "reinhard") return ToneMap::Reinhard;
    if (name == "filmic") return ToneMap::Filmic;
    return std::nullopt;
}

/// Reinhard et al. 2002, eq. 3, on a luminance L ≥ 0.
inline float reinhard(float L) { return L > 0.f ? L / (1.f + L) : 0.f; }

/// Narkowicz 2015 fit of the ACES filmic curve, clamped to [0, 1]. Its derivative's
/// numerator 1.408 x² + 0.7028 x + 0.0042 is positive, so it is monotone for x ≥ 0.
inline float filmic(float x) {
    if (!(x > 0.f)) return 0.f;
    constexpr float a = 2.51f, b = 0.03f, c = 2.43f, d = 0.59f, e = 0.14f;
    return std::clamp(x * (a * x + b) / (x * (c * x + d) + e), 0.f, 1.f);
}

/// Display RGB in [0, 1] from linear RGB. `luminanceWeights` is the Y row of the RGB
/// space's RGB -> XYZ matrix (Reinhard works on luminance). NaN and negative values
/// become 0.
inline Vector3f apply(ToneMap op, Vector3f rgb, float exposureStops, const Vector3f& luminanceWeights) {
    const float scale = std::exp2(exposureStops);
    for (int c = 0; c < 3; ++c) rgb[c] = rgb[c] * scale > 0.f ? rgb[c] * scale : 0.f;  // also NaN -> 0
    switch (op) {
    case ToneMap::None: break;
    case ToneMap::Reinhard: {
        float L = dot(luminanceWeights, rgb);
        if (!(L > 0.f) || !std::isfinite(L)) {
            rgb = Vector3f(L > 0.f ? 1.f : 0.f);  // an infinite luminance is white
            break;
        }
        rgb *= reinhard(L) / L;
        break;
    }
    case ToneMap::Filmic:
        for (int c = 0; c < 3; ++c) rgb[c] = std::isfinite(rgb[c]) ? filmic(rgb[c]) : 1.f;
        break;
    }
    for (int c = 0; c < 3; ++c) rgb[c] = std::clamp(rgb[c], 0.f, 1.f);
    return rgb;
}

/// One channel (grey images): the curves on a luminance value.
inline float applyGrey(ToneMap op, float v, float exposureStops) {
    v *= std::exp2(exposureStops);
    if (!(v > 0.f)) return 0.f;
    switch (op) {
    case ToneMap::None: break;
    case ToneMap::Reinhard: v = std::isfinite(v) ? reinhard(v) : 1.f; break;
    case ToneMap::Filmic: v = std::isfinite(v) ? filmic(v) : 1.f; break;
    }
    return std::clamp(v, 0.f, 1.f);
}

} // namespace tonemap
} // namespace effigi
