#pragma once
// Fresnel reflectance of smooth interfaces and the specular directions that go with it,
// in the local shading frame (normal = +z), for unpolarised light.
//
// Dielectric: the exact Fresnel equations for the s and p amplitudes (Born & Wolf,
// "Principles of Optics", §1.5.2), averaged in power; beyond the critical angle the
// reflectance is 1 (total internal reflection).
// Conductor: the same equations with a complex relative index n = η + ik (Born & Wolf
// §14.2), evaluated in double-precision complex arithmetic in a form without division by
// n, so that η → 0 (Mitsuba's "none" mirror: η = 0, k = 1), η ≈ 1, k up to 10 and
// cosθ from 1 down to 0 stay finite:
//   w = n cosθt = sqrt(n² − sin²θi)          (principal root, Re w ≥ 0)
//   r_s = (cosθi − w) / (cosθi + w),  r_p = (n² cosθi − w) / (n² cosθi + w)
//   F = (|r_s|² + |r_p|²) / 2.
#include "effigi/math/vector.hpp"
#include "effigi/spectral/wavelengths.hpp"

#include <complex>

namespace effigi {

/// Mirror direction about the normal +z.
inline Vector3f reflectLocal(const Vector3f& wo) { return {-wo.x, -wo.y, wo.z}; }

/// Unpolarised Fresnel reflectance of a smooth dielectric interface. cosThetaI is the
/// cosine of the incident direction with the normal: positive on the outside, negative
/// when the light arrives from inside. eta = η_inside / η_outside (int_ior / ext_ior).
/// Returns 1 under total internal reflection; 0 when eta == 1 (no interface).
inline float fresnelDielectric(float cosThetaI, float eta) {
    cosThetaI = std::clamp(cosThetaI, -1.f, 1.f);
    if (cosThetaI < 0.f) {  // arriving from inside: swap the media
        eta = 1.f / eta;
        cosThetaI = -cosThetaI;
    }
    if (eta == 1.f) return 0.f;
    // Snell: sinθt = sinθi / η, in double so that η ≈ 1 near grazing keeps its digits.
    double ci = cosThetaI, e = eta;
    double sin2T = (1.0 - ci * ci) / (e * e);
    if (sin2T >= 1.0) return 1.f;
    double ct = std::sqrt(1.0 - sin2T);
    double rs = (ci - e * ct) / (ci + e * ct);  // s (perpendicular) amplitude
    double rp = (e * ci - ct) / (e * ci + ct);  // p (parallel) amplitude
    return float(0.5 * (rs * rs + rp * rp));
}

/// The principal square root of a + ib (real part ≥ 0), in the form that does not cancel:
/// the larger of the two parts comes from sqrt((|z| ± a) / 2), the other from b / (2 ·
/// that). Inline arithmetic instead of std::sqrt(std::complex), which is a libm call.
inline std::complex<double> principalSqrt(double a, double b) {
    const double r = std::sqrt(a * a + b * b);
    if (r == 0.0) return {0.0, 0.0};
    if (a >= 0.0) {
        const double re = std::sqrt(0.5 * (r + a));
        return {re, b / (2.0 * re)};
    }
    const double im = std::copysign(std::sqrt(0.5 * (r - a)), b);
    return {std::abs(b) / (2.0 * std::abs(im)), im};
}

/// Unpolarised Fresnel reflectance of a conductor with complex relative index
/// η + ik (relative to the outside medium); cosThetaI in [0, 1] (its absolute value is
/// used). Always in [0, 1] for η, k ≥ 0.
inline float fresnelConductor(float cosThetaI, float eta, float k) {
    using C = std::complex<double>;
    double ci = std::min(1.0, double(std::abs(cosThetaI)));
    double e = std::max(0.0, double(eta)), kk = std::max(0.0, double(k));
    // n² = η² − k² + 2iηk; n² − sin²θ = (η − 1)(η + 1) − k² + cos²θ + 2iηk, written so that
    // η ≈ 1, k = 0 does not lose its digits to cancellation.
    C n2(e * e - kk * kk, 2.0 * e * kk);
    C w = principalSqrt((e - 1.0) * (e + 1.0) - kk * kk + ci * ci, 2.0 * e * kk);
    C ds = ci + w, dp = n2 * ci + w;
    // Both denominators vanish only for n = 1 at exact grazing incidence (no interface).
    const double nds = std::norm(ds), ndp = std::norm(dp);
    if (nds == 0.0 || ndp == 0.0) return 0.f;
    // |a / b|² = |a|² / |b|²: no complex division (libgcc's __divdc3 is slow, and its
    // scaling for huge or tiny operands is not needed for these magnitudes).
    double Rs = std::norm(ci - w) / nds, Rp = std::norm(n2 * ci - w) / ndp;
    double F = 0.5 * (Rs + Rp);
    return std::isfinite(F) ? float(std::clamp(F, 0.0, 1.0)) : 1.f;
}

/// fresnelConductor at each of the path's wavelengths.
inline SampledSpectrum fresnelConductor(float cosThetaI, const SampledSpectrum& eta, const SampledSpectrum& k) {
    SampledSpectrum F;
    for (int i = 0; i < NSpectrumSamples; ++i) F[i] = fresnelConductor(cosThetaI, eta[i], k[i]);
    return F;
}

/// Refraction of wi (pointing away from the surface, either side) through the interface
/// with relative index eta = η_inside / η_outside. Returns false under total internal
/// reflection; otherwise wt (pointing away on the other side) and etaRel = η_t / η_i, the
/// relative index of the crossing as seen along wi.
inline bool refractLocal(const Vector3f& wi, float eta, Vector3f& wt, float& etaRel) {
    float cosI = wi.z;
    if (cosI < 0.f) {  // leaving the inside
        eta = 1.f / eta;
        cosI = -cosI;
    }
    float sin2I = std::max(0.f, 1.f - cosI * cosI);
    float sin2T = sin2I / (eta * eta);
    if (sin2T >= 1.f) return false;
    float cosT = std::sqrt(1.f - sin2T);
    // wt = −wi/η + (cosI/η − cosT) n, with n on wi's side.
    Vector3f n(0.f, 0.f, wi.z < 0.f ? -1.f : 1.f);
    wt = -wi / eta + (cosI / eta - cosT) * n;
    etaRel = eta;
    return true;
}

} // namespace effigi
