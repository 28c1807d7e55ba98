#pragma once
// Pieces shared by the texture components: Mitsuba's `to_uv` transform and RGB texels
// stored as spectral upsampling coefficients.
#include "effigi/core/properties.hpp"
#include "effigi/core/schema.hpp"
#include "effigi/spectral/upsample.hpp"
#include "effigi/spectral/wavelengths.hpp"

#include <algorithm>
#include <cmath>

namespace effigi {

/// The affine 2D map Mitsuba applies to texture coordinates (`to_uv`). A 4x4 transform
/// written in XML keeps its x/y rows and columns and its translation, as Mitsuba's
/// Transform4f -> Transform3f extraction does.
struct UVTransform {
    float m00 = 1.f, m01 = 0.f, m10 = 0.f, m11 = 1.f, tx = 0.f, ty = 0.f;

    static UVTransform read(const Properties& p, const std::string& name) {
        UVTransform t;
        if (!p.has(name)) return t;
        const glm::mat4 m = p.getTransform(name).matrix();  // column-major: m[col][row]
        t.m00 = m[0][0], t.m01 = m[1][0], t.tx = m[3][0];
        t.m10 = m[0][1], t.m11 = m[1][1], t.ty = m[3][1];
        if (!(std::isfinite(t.m00) && std::isfinite(t.m01) && std::isfinite(t.m10) && std::isfinite(t.m11) &&
              std::isfinite(t.tx) && std::isfinite(t.ty)))
            failAt(p.whereOf(name), "{}: '{}' is not finite", p.describe(), name);
        return t;
    }

    Point2f apply(const Point2f& uv) const { return {m00 * uv.x + m01 * uv.y + tx, m10 * uv.x + m11 * uv.y + ty}; }
    /// Chain rule for a gradient taken in transformed coordinates: Jᵀ g.
    Vector2f pullBack(const Vector2f& g) const { return {m00 * g.x + m10 * g.y, m01 * g.x + m11 * g.y}; }
};

/// One RGB texel as the Jakob–Hanika sigmoid polynomial, re-centred at 595 nm so float
/// evaluation keeps its digits (as Spectrum does), times a scale for texels above 1.
struct SpectralTexel {
    float a0 = 0.f, a1 = 0.f, a2 = 0.f, scale = 0.f;

    static constexpr float Centre = 595.f;

    /// Texels with every channel in [0, 1] use the bounded fit directly, so a reflectance
    /// stays <= 1 at every wavelength (energy conservation); brighter (HDR) texels are
    /// fitted at half their largest channel and scaled back (pbrt-v4's unbounded RGB).
    /// maxOut, if given, receives the spectrum's largest value over the visible range.
    static SpectralTexel fromRGB(const RGBToSpectrumTable& table, Vector3f rgb, float* maxOut = nullptr) {
        rgb = glm::max(rgb, Vector3f(0.f));
        float m = std::max(rgb.x, std::max(rgb.y, rgb.z));
        SpectralTexel t;
        if (maxOut) *maxOut = 0.f;
        if (!(m > 0.f)) return t;  // black: scale 0
        t.scale = m <= 1.f ? 1.f : 2.f * m;
        RGBSigmoidPolynomial p = table(rgb / t.scale);
        if (maxOut) *maxOut = t.scale * p.maxValue();
        const double c = Centre;
        t.a0 = p.c0;
        t.a1 = std::isinf(p.c2) ? 0.f : float(2.0 * p.c0 * c + p.c1);
        t.a2 = float(p.polynomial(c));
        return t;
    }

    SampledSpectrum eval(const SampledWavelengths& lambda) const {
        SampledSpectrum s;
        for (int i = 0; i < NSpectrumSamples; ++i) {
            float t = lambda[i] - Centre;
            float x = std::min(std::max((a0 * t + a1) * t + a2, -1e15f), 1e15f);
            s[i] = scale * (0.5f + 0.5f * x / std::sqrt(1.f + x * x));
        }
        return s;
    }
};

} // namespace effigi
