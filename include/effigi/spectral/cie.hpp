#pragma once
// CIE 1931 2° colour matching functions and the D65 illuminant, 1 nm steps over
// [LambdaMin, LambdaMax]. The tables are compiled in from data/*.csv at build time
// (see data/README.md for their source).
#include "effigi/math/vector.hpp"
#include "effigi/spectral/cie_tables.hpp"
#include "effigi/spectral/wavelengths.hpp"

namespace effigi::cie {

/// ∫ ȳ(λ) dλ of the piecewise-linear table (trapezoid rule = exact for it).
float yIntegral();
/// 1 / ∫ D65(λ) ȳ(λ) dλ · ∫ ȳ dλ: scales D65 so that its luminance Y is 1.
float d65Normalization();

/// Luminance Y = ∫ S ȳ dλ / ∫ ȳ dλ of a spectral function S(λ), summed on the 1 nm grid.
template <typename F> float luminance(F&& S) {
    double num = 0.0, den = 0.0;
    for (int i = 0; i < TableSize; ++i) {
        num += double(S(float(TableStart + i))) * Y[i];
        den += Y[i];
    }
    return float(num / den);
}

/// Monte Carlo estimate of XYZ = ∫ L x̄ / ∫ ȳ from four sampled wavelengths.
inline Vector3f toXYZ(const SampledSpectrum& L, const SampledWavelengths& lambda) {
    SampledSpectrum pdf = lambda.pdf();
    Vector3f xyz(0.f);
    for (int i = 0; i < NSpectrumSamples; ++i) {
        if (pdf[i] == 0.f) continue;
        float w = L[i] / pdf[i];
        xyz += w * Vector3f(lookup(X, lambda[i]), lookup(Y, lambda[i]), lookup(Z, lambda[i]));
    }
    return xyz / (float(NSpectrumSamples) * yIntegral());
}

/// Luminance (Y) part of toXYZ.
inline float toY(const SampledSpectrum& L, const SampledWavelengths& lambda) {
    SampledSpectrum pdf = lambda.pdf();
    float y = 0.f;
    for (int i = 0; i < NSpectrumSamples; ++i)
        if (pdf[i] != 0.f) y += L[i] * lookup(Y, lambda[i]) / pdf[i];
    return y / (float(NSpectrumSamples) * yIntegral());
}

} // namespace effigi::cie
