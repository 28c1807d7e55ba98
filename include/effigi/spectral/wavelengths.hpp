#pragma once
// Hero-wavelength spectral sampling (Wilkie et al. 2014): every path carries four
// wavelengths, the first drawn by importance, the others rotated through the range.
#include "effigi/math/log4.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/spectral/cie_tables.hpp"

#include <array>
#include <cmath>
#include <cstring>

namespace effigi {

inline constexpr float LambdaMin = 360.f;
inline constexpr float LambdaMax = 830.f;
inline constexpr int NSpectrumSamples = 4;

/// Values of a spectral quantity at the path's sampled wavelengths.
///
/// Held in one 16-byte vector (a GCC/Clang vector extension, any target): arithmetic is
/// one instruction for the four wavelengths, and — what matters more — the x86-64 ABI
/// passes and returns it in one SSE register. As std::array<float, 4> it came back from
/// every non-inlined call (IBSDF::f, ITexture::eval, IEmitter::eval, ...) as two 8-byte
/// halves that the caller stored and reloaded as one 16-byte value: a failed store
/// forward, ~12 cycles, several times per bounce (bench/RESULTS.md, 2026-11-28).
class SampledSpectrum {
    using V = float __attribute__((vector_size(16), __may_alias__));

public:
    SampledSpectrum() = default;
    explicit SampledSpectrum(float c) : m_v{c, c, c, c} {}
    SampledSpectrum(float a, float b, float c, float d) : m_v{a, b, c, d} {}

    // Element access through float*: V is may_alias, so this is how GCC documents it.
    float& operator[](int i) { return reinterpret_cast<float*>(&m_v)[i]; }
    float operator[](int i) const { return m_v[i]; }

#define EFFIGI_SPECTRUM_OP(op)                                                        \
    SampledSpectrum& operator op##=(const SampledSpectrum& o) {                       \
        m_v op## = o.m_v;                                                             \
        return *this;                                                                 \
    }                                                                                 \
    SampledSpectrum& operator op##=(float s) {                                        \
        m_v op## = s;                                                                 \
        return *this;                                                                 \
    }                                                                                 \
    friend SampledSpectrum operator op(SampledSpectrum a, const SampledSpectrum& b) { \
        return a op## = b;                                                            \
    }                                                                                 \
    friend SampledSpectrum operator op(SampledSpectrum a, float s) { return a op## = s; }
    EFFIGI_SPECTRUM_OP(+)
    EFFIGI_SPECTRUM_OP(-)
    EFFIGI_SPECTRUM_OP(*)
#undef EFFIGI_SPECTRUM_OP
    friend SampledSpectrum operator*(float s, SampledSpectrum a) { return a *= s; }
    /// Division that yields 0 where the divisor is 0 (pdf ratios of absent wavelengths).
    friend SampledSpectrum safeDiv(SampledSpectrum a, const SampledSpectrum& b) {
        for (int i = 0; i < NSpectrumSamples; ++i) a[i] = b[i] != 0.f ? a[i] / b[i] : 0.f;
        return a;
    }
    SampledSpectrum operator/(float s) const { return *this * (1.f / s); }

    bool isBlack() const { return m_v[0] == 0.f && m_v[1] == 0.f && m_v[2] == 0.f && m_v[3] == 0.f; }
    bool isFinite() const {
        for (int i = 0; i < NSpectrumSamples; ++i)
            if (!std::isfinite(m_v[i])) return false;
        return true;
    }
    float maxValue() const { return std::max(std::max(m_v[0], m_v[1]), std::max(m_v[2], m_v[3])); }
    float average() const { return 0.25f * (m_v[0] + m_v[1] + m_v[2] + m_v[3]); }

private:
    V m_v{};
};
static_assert(sizeof(SampledSpectrum) == NSpectrumSamples * sizeof(float));

inline SampledSpectrum exp(SampledSpectrum s) {
    for (int i = 0; i < NSpectrumSamples; ++i) s[i] = std::exp(s[i]);
    return s;
}
inline SampledSpectrum clampZero(SampledSpectrum s) {
    for (int i = 0; i < NSpectrumSamples; ++i) s[i] = std::max(0.f, s[i]);
    return s;
}

class SampledWavelengths {
public:
    /// Visible-range importance sampling with stratified secondary wavelengths.
    /// The four at once: warp::sampleVisibleWavelength(u, pdf) with log4 for its log
    /// (tests/test_wavelengths.cpp checks that both agree).
    static SampledWavelengths sampleVisible(float u) {
        static_assert(NSpectrumSamples == 4);
        Float4 up = u + Float4{0.f, 0.25f, 0.5f, 0.75f};  // u + i / NSpectrumSamples
        up = up > 1.f ? up - 1.f : up;
        const Float4 a = 0.85691062f - 1.82750197f * up;
        const Float4 pdf = 0.0039398042f * (1.f - a * a);
        const Float4 lambda = 538.f - 69.4444444f * log4((1.f + a) / (1.f - a));
        SampledWavelengths w;
        std::memcpy(w.m_lambda.data(), &lambda, sizeof lambda);
        std::memcpy(w.m_pdf.data(), &pdf, sizeof pdf);
        w.lookUpD65();
        return w;
    }
    /// Uniform over [LambdaMin, LambdaMax], stratified the same way.
    static SampledWavelengths sampleUniform(float u) {
        SampledWavelengths w;
        float delta = (LambdaMax - LambdaMin) / NSpectrumSamples;
        float l0 = lerp(u, LambdaMin, LambdaMax);
        for (int i = 0; i < NSpectrumSamples; ++i) {
            float l = l0 + delta * i;
            if (l > LambdaMax) l -= LambdaMax - LambdaMin;
            w.m_lambda[i] = l;
            w.m_pdf[i] = 1.f / (LambdaMax - LambdaMin);
        }
        w.lookUpD65();
        return w;
    }
    /// Four given wavelengths with given pdfs (a cache that traces fixed wavelength nodes,
    /// e.g. renderer irradiancecache: pdf 1 makes each slot the value at its node).
    static SampledWavelengths fromNodes(const std::array<float, NSpectrumSamples>& lambda,
                                        const std::array<float, NSpectrumSamples>& pdf) {
        SampledWavelengths w;
        w.m_lambda = lambda;
        w.m_pdf = pdf;
        w.lookUpD65();
        return w;
    }
    /// The same wavelength in every slot (tests, single-λ queries).
    static SampledWavelengths constant(float lambda) {
        SampledWavelengths w;
        w.m_lambda.fill(lambda);
        w.m_pdf.fill(1.f);
        w.lookUpD65();
        return w;
    }

    float operator[](int i) const { return m_lambda[i]; }
    SampledSpectrum pdf() const { return {m_pdf[0], m_pdf[1], m_pdf[2], m_pdf[3]}; }
    /// The CIE D65 table (relative, 100 at 560 nm; cie::D65) at wavelength i. Every RGB
    /// illuminant evaluation multiplies by it, several times per path segment, so it is
    /// looked up once when the wavelengths are drawn (bench/RESULTS.md, 2026-11-29).
    float d65(int i) const { return m_d65[i]; }

    /// Keep only the hero wavelength (e.g. at a dispersive interface); its pdf absorbs
    /// the probability of having drawn any of the four.
    void terminateSecondary() {
        if (secondaryTerminated()) return;
        for (int i = 1; i < NSpectrumSamples; ++i) m_pdf[i] = 0.f;
        m_pdf[0] /= NSpectrumSamples;
    }
    bool secondaryTerminated() const {
        for (int i = 1; i < NSpectrumSamples; ++i)
            if (m_pdf[i] != 0.f) return false;
        return true;
    }

private:
    /// Every factory ends here: m_d65 for the wavelengths it chose.
    void lookUpD65() {
        for (int i = 0; i < NSpectrumSamples; ++i) m_d65[i] = cie::lookup(cie::D65, m_lambda[i]);
    }

    std::array<float, NSpectrumSamples> m_lambda{};
    std::array<float, NSpectrumSamples> m_pdf{};
    std::array<float, NSpectrumSamples> m_d65{};  ///< cie::D65 at m_lambda (0 outside its table)
};

} // namespace effigi
