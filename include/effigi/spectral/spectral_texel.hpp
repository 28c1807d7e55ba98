#pragma once
// An RGB value stored as spectral upsampling coefficients (Jakob & Hanika 2019), evaluated
// at a path's four wavelengths: the texels of RGB bitmap textures and the voxels of RGB
// grid volumes, upsampled once at load time and blended after evaluation.
#include "effigi/spectral/upsample.hpp"
#include "effigi/spectral/wavelengths.hpp"

#include <algorithm>
#include <cmath>

namespace effigi {

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
