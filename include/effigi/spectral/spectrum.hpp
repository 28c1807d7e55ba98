#pragma once
// Spectral distributions as values: a function of wavelength that is sampled at a
// path's four wavelengths. One small tagged type covers every way a scene states a
// colour (constant, RGB, tabulated, blackbody); no virtual call per sample.
#include "effigi/math/vector.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/upsample.hpp"
#include "effigi/spectral/wavelengths.hpp"

#include <memory>
#if defined(__SSE2__)
#include <immintrin.h>
#endif
#include <vector>

namespace effigi {

/// What a spectral parameter means, which decides how an RGB value is upsampled.
enum class SpectrumKind {
    Reflectance,  ///< bounded to [0, 1] (albedo, transmittance)
    Unbounded,    ///< any non-negative value (scale factors, IOR)
    Illuminant,   ///< emission: RGB is relative to the colour space's white (D65)
};

class Spectrum {
public:
    enum class Type { Constant, Piecewise, RGB, Blackbody };

    Spectrum() : Spectrum(0.f) {}
    /// The same value at every wavelength.
    explicit Spectrum(float c) : m_type(Type::Constant), m_scale(c) {}

    /// Linear interpolation between (λ_i, v_i), λ ascending, constant beyond the ends.
    static Spectrum piecewiseLinear(std::vector<float> lambdas, std::vector<float> values);
    /// Jakob–Hanika upsampling of a linear sRGB triple.
    static Spectrum fromRGB(const Vector3f& rgb, SpectrumKind kind);
    /// Planck's law at temperature T [K], normalised to peak 1.
    static Spectrum blackbody(float temperatureK);

    Type type() const { return m_type; }

    float operator()(float lambda) const;
    /// Values at the path's wavelengths. Constant and RGB spectra (nearly every
    /// parameter of a scene) are evaluated inline: this runs several times per bounce.
    SampledSpectrum sample(const SampledWavelengths& lambda) const {
        SampledSpectrum s;
        if (m_type == Type::Constant) return SampledSpectrum(m_scale);
        if (m_type == Type::RGB) {
            // The four wavelengths at once: the polynomial re-centred at 595 nm (small
            // terms, float is enough), the sigmoid argument clamped so that ±inf
            // coefficients (black, white) stay exact. This runs several times per bounce,
            // so it is written in SSE (the compiler leaves the scalar loop unvectorised);
            // both forms round identically.
#if defined(__SSE2__)
            const __m128 t = _mm_sub_ps(_mm_setr_ps(lambda[0], lambda[1], lambda[2], lambda[3]), _mm_set1_ps(PolyCentre));
            __m128 x = _mm_add_ps(_mm_mul_ps(_mm_add_ps(_mm_mul_ps(_mm_set1_ps(m_a0), t), _mm_set1_ps(m_a1)), t),
                                  _mm_set1_ps(m_a2));
            x = _mm_min_ps(_mm_max_ps(x, _mm_set1_ps(-1e15f)), _mm_set1_ps(1e15f));
            const __m128 y = _mm_div_ps(_mm_mul_ps(_mm_set1_ps(0.5f), x),
                                        _mm_sqrt_ps(_mm_add_ps(_mm_set1_ps(1.f), _mm_mul_ps(x, x))));
            alignas(16) float v[4];
            _mm_store_ps(v, _mm_mul_ps(_mm_set1_ps(m_scale), _mm_add_ps(_mm_set1_ps(0.5f), y)));
            s = SampledSpectrum(v[0], v[1], v[2], v[3]);
#else
            for (int i = 0; i < NSpectrumSamples; ++i) {
                float t = lambda[i] - PolyCentre;
                float x = std::min(std::max((m_a0 * t + m_a1) * t + m_a2, -1e15f), 1e15f);
                s[i] = m_scale * (0.5f + 0.5f * x / std::sqrt(1.f + x * x));
            }
#endif
            if (m_illuminant)
                for (int i = 0; i < NSpectrumSamples; ++i) s[i] *= lambda.d65(i) * m_d65Scale;
            return s;
        }
        for (int i = 0; i < NSpectrumSamples; ++i) s[i] = (*this)(lambda[i]);
        return s;
    }

    /// Upper bound over the visible range.
    float maxValue() const;
    /// Same spectrum multiplied by s.
    Spectrum scaled(float s) const {
        Spectrum r = *this;
        r.m_scale *= s;
        return r;
    }

private:
    Type m_type;
    float m_scale = 1.f;
    RGBSigmoidPolynomial m_poly;  // RGB
    bool m_illuminant = false;    // RGB: multiply by normalised D65
    float m_d65Scale = 1.f;       // cie::d65Normalization(), cached
    static constexpr float PolyCentre = 595.f;
    float m_a0 = 0.f, m_a1 = 0.f, m_a2 = 0.f;  // m_poly in powers of (λ − PolyCentre)
    void setPoly(const RGBSigmoidPolynomial& p);
    float m_temperature = 0.f;    // Blackbody
    float m_bbNorm = 1.f;
    std::shared_ptr<const std::vector<float>> m_lambdas, m_values;  // Piecewise
};

/// Planck's law: spectral radiance of a blackbody [W sr^-1 m^-2 nm^-1] at λ [nm], T [K].
float planck(float lambdaNm, float temperatureK);

} // namespace effigi
