#pragma once
// The pieces of the Disney "principled" BSDF (Burley 2012, 2015) that `principled` (and a
// thin-surface variant) share, as Mitsuba 3 defines them:
//   schlickWeight(c)        (1 − c)⁵, the Schlick Fresnel interpolant
//   schlick(R0, cosI, eta)  R0 + (1 − R0) (1 − c)⁵ with c the cosine on the optically
//                           denser side (the refracted cosine when the light leaves a
//                           denser medium; 1 under total internal reflection)
//   schlickR0(eta)          ((η − 1)/(η + 1))², normal-incidence reflectance
//   anisotropicAlphas       Burley 2012 §B.2: α = roughness², stretched by the aspect
//                           √(1 − 0.9 anisotropic), at least 0.001
//   GTR1                    the "generalised Trowbridge–Reitz" γ = 1 distribution of the
//                           clearcoat, D = (α² − 1) / (π ln α² (1 + (α² − 1) cos²θ)),
//                           sampled by inverting its cos²θ CDF (Burley 2012, eq. 4 and §B.2)
//   clearcoatG1             Smith G1 of GGX with α = 0.25 (the clearcoat's fixed masking)
//   diffuseFactor           Burley's diffuse with retro-reflection, (1 − Fi/2)(1 − Fo/2) +
//                           Rr (Fo + Fi + Fo Fi (Rr − 1)), Rr = 2 r cos²θd, blended by
//                           flatness toward the Hanrahan–Krueger-like
//                           1.25 (Fss (1/(cosθo + cosθi) − 1/2) + 1/2), Fss90 = Rr/2
//                           (Burley 2012, §5.3); to be multiplied by ρ/π
//   tint                    base colour / luminance, the hue that spec_tint and
//                           sheen_tint blend toward (1 where the luminance is 0)
//
// Reference: B. Burley, "Physically-Based Shading at Disney", SIGGRAPH 2012 course notes;
// B. Burley, "Extending the Disney BRDF to a BSDF with Integrated Subsurface Scattering",
// SIGGRAPH 2015 course notes; Mitsuba 3 documentation, "The Principled BSDF (principled)".
#include "effigi/math/vector.hpp"
#include "effigi/spectral/wavelengths.hpp"

#include <cmath>
#include <utility>

namespace effigi::principled {

inline float schlickWeight(float c) {
    float m = std::clamp(1.f - c, 0.f, 1.f);
    float m2 = m * m;
    return m2 * m2 * m;
}

inline float schlickR0(float eta) {
    float r = (eta - 1.f) / (eta + 1.f);
    return r * r;
}

/// Schlick's approximation with normal-incidence reflectance R0 across an interface of
/// relative index eta (inside / outside); cosI < 0 means arriving from inside.
inline float schlick(float R0, float cosI, float eta) {
    float etaIT = cosI >= 0.f ? eta : 1.f / eta;  // η_incident-side→transmitted
    if (etaIT > 1.f) return R0 + (1.f - R0) * schlickWeight(std::abs(cosI));
    float sin2T = (1.f - cosI * cosI) / (etaIT * etaIT);
    float cosT = safeSqrt(1.f - sin2T);  // 0 under total internal reflection: weight 1
    return R0 + (1.f - R0) * schlickWeight(cosT);
}

inline std::pair<float, float> anisotropicAlphas(float roughness, float anisotropic) {
    float r2 = roughness * roughness;
    float aspect = std::sqrt(std::max(0.f, 1.f - 0.9f * anisotropic));
    return {std::max(0.001f, r2 / aspect), std::max(0.001f, r2 * aspect)};
}

class GTR1 {
public:
    explicit GTR1(float alpha) : m_alpha2(double(alpha) * alpha) {}

    double D(const Vector3f& m) const {
        if (!(m.z > 0.f)) return 0.0;
        double c2 = double(m.z) * m.z;
        return (m_alpha2 - 1.0) / (std::numbers::pi * std::log(m_alpha2) * (1.0 + (m_alpha2 - 1.0) * c2));
    }
    /// Density of sample(): D(m) cos θm.
    double pdf(const Vector3f& m) const { return D(m) * std::max(0.f, m.z); }
    Vector3f sample(const Point2f& u) const {
        // cos²θ = (1 − α^(2(1 − u))) / (1 − α²), the inverse of the CDF of D cos θ.
        double c2 = (1.0 - std::pow(m_alpha2, 1.0 - double(u.y))) / (1.0 - m_alpha2);
        double cosT = std::sqrt(std::clamp(c2, 0.0, 1.0)), sinT = std::sqrt(std::max(0.0, 1.0 - c2));
        double phi = 2.0 * std::numbers::pi * u.x;
        return Vector3f(float(sinT * std::cos(phi)), float(sinT * std::sin(phi)), float(cosT));
    }

private:
    double m_alpha2;
};

/// Smith G1 of GGX with α = 0.25 for direction v and microfacet normal h; 0 when v sees
/// the back of the facet.
inline float clearcoatG1(const Vector3f& v, const Vector3f& h) {
    if (!(dot(v, h) * v.z > 0.f)) return 0.f;
    double c2 = double(v.z) * v.z;
    if (c2 >= 1.0) return 1.f;
    double tan2 = (1.0 - c2) / c2;
    return float(2.0 / (1.0 + std::sqrt(1.0 + 0.0625 * tan2)));
}

/// Burley's diffuse factor (see the header comment) for |cos θ| of the two directions and
/// cos θd = cosine between the light and the half vector.
inline float diffuseFactor(float cosO, float cosI, float cosD, float roughness, float flatness) {
    float Fo = schlickWeight(cosI), Fi = schlickWeight(cosO);
    float Rr = 2.f * roughness * cosD * cosD;
    float d = (1.f - 0.5f * Fi) * (1.f - 0.5f * Fo) + Rr * (Fo + Fi + Fo * Fi * (Rr - 1.f));
    if (flatness > 0.f) {
        float fss90 = 0.5f * Rr;
        float fss = (1.f + (fss90 - 1.f) * Fo) * (1.f + (fss90 - 1.f) * Fi);
        float ss = 1.25f * (fss * (1.f / (cosI + cosO) - 0.5f) + 0.5f);
        d += flatness * (ss - d);
    }
    return d;
}

/// The colour tints blend toward: base / luminance (1 where the luminance is 0).
inline SampledSpectrum tint(const SampledSpectrum& base, float luminance) {
    SampledSpectrum t(1.f);
    if (luminance > 0.f)
        for (int i = 0; i < NSpectrumSamples; ++i) t[i] = base[i] / luminance;
    return t;
}

/// The half vector of a reflection (eta = 1) or of a refraction wo → wi with the relative
/// index etaPath seen from wo's side, turned to the +z side; false if degenerate.
inline bool halfVector(const Vector3f& wo, const Vector3f& wi, float etaPath, Vector3f& h) {
    Vector3d s = Vector3d(wo) + Vector3d(wi) * double(etaPath);
    double len = glm::length(s);
    if (!(len > 0.0)) return false;
    h = Vector3f(s / len);
    if (h.z < 0.f) h = -h;
    return h.z > 0.f;
}

/// Microfacet normal h can produce this pair: for a reflection both directions on h's
/// front (as seen from wo's side), for a refraction wi on the other side of the facet.
inline bool facetCompatible(const Vector3f& h, const Vector3f& wo, const Vector3f& wi, bool reflection) {
    Vector3f hs = wo.z >= 0.f ? h : -h;
    return dot(wo, hs) > 0.f && (reflection ? dot(wi, hs) > 0.f : dot(wi, hs) < 0.f);
}

} // namespace effigi::principled
