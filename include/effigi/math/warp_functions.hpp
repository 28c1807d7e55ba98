#pragma once
// Warps: maps from [0,1)^2 to a domain, with the density of the result and, where it
// exists, the inverse map. Math after Shirley & Chiu 1997 (concentric disk),
// Malley's method (cosine hemisphere) and Arvo 2001 ("Stratified sampling of 2-manifolds").
#include "effigi/math/vector.hpp"

namespace effigi::warp {

/// sin and cos of (π/4)·t for t in [-1, 1], by their Taylor polynomials (the terms left
/// out are below 2.6e-9 there): within 1.1 ulp of the exact values, at a fraction of the
/// cost of sinf/cosf's general argument reduction. The concentric map below runs at every
/// diffuse bounce (measured 2.6 % of a Cornell box render in libm's sincosf).
inline void sinCosQuarterPi(float t, float& s, float& c) {
    const float x = (Pi / 4.f) * t, x2 = x * x;
    s = x * (1.f + x2 * (-1.f / 6.f + x2 * (1.f / 120.f + x2 * (-1.f / 5040.f + x2 * (1.f / 362880.f)))));
    c = 1.f + x2 * (-0.5f + x2 * (1.f / 24.f + x2 * (-1.f / 720.f + x2 * (1.f / 40320.f + x2 * (-1.f / 3628800.f)))));
}

/// Concentric map of the square to the unit disk (Shirley & Chiu 1997): low distortion.
/// φ = (π/4)(y/x) in the left and right wedges, π/2 − (π/4)(x/y) in the others, where
/// cos φ and sin φ swap roles.
/// The wedge is chosen by selects, not a branch: for random u a branch on it is
/// mispredicted half the time (this runs at every diffuse bounce).
inline Point2f squareToUniformDiskConcentric(const Point2f& u) {
    const float x = 2.f * u.x - 1.f, y = 2.f * u.y - 1.f;
    if (x == 0.f && y == 0.f) return {0.f, 0.f};
    const bool horizontal = std::abs(x) > std::abs(y);
    const float r = horizontal ? x : y;
    float s, c;
    sinCosQuarterPi((horizontal ? y : x) / r, s, c);
    return {r * (horizontal ? c : s), r * (horizontal ? s : c)};
}
inline float squareToUniformDiskPdf(const Point2f& p) { return dot(p, p) <= 1.f ? InvPi : 0.f; }
inline Point2f uniformDiskToSquareConcentric(const Point2f& p) {
    float r = std::sqrt(p.x * p.x + p.y * p.y);
    float phi = std::atan2(p.y, p.x);
    if (phi < -Pi / 4.f) phi += 2.f * Pi;  // map to [-π/4, 7π/4)
    float a, b;
    if (phi < Pi / 4.f) {
        a = r;
        b = phi * a / (Pi / 4.f);
    } else if (phi < 3.f * Pi / 4.f) {
        b = r;
        a = -(phi - Pi / 2.f) * b / (Pi / 4.f);
    } else if (phi < 5.f * Pi / 4.f) {
        a = -r;
        b = (phi - Pi) * a / (Pi / 4.f);
    } else {
        b = -r;
        a = -(phi - 3.f * Pi / 2.f) * b / (Pi / 4.f);
    }
    // A point on the rim within an ulp of a wedge's diagonal can land in the neighbouring
    // wedge and map a rounding error past the square's edge: the square is the range.
    return {std::clamp(0.5f * (a + 1.f), 0.f, 1.f), std::clamp(0.5f * (b + 1.f), 0.f, 1.f)};
}

/// Cosine-weighted hemisphere about +z by projecting the concentric disk (Malley).
inline Vector3f squareToCosineHemisphere(const Point2f& u) {
    Point2f d = squareToUniformDiskConcentric(u);
    float z = safeSqrt(1.f - d.x * d.x - d.y * d.y);
    return {d.x, d.y, z};
}
inline float squareToCosineHemispherePdf(const Vector3f& v) { return v.z > 0.f ? v.z * InvPi : 0.f; }
inline Point2f cosineHemisphereToSquare(const Vector3f& v) { return uniformDiskToSquareConcentric({v.x, v.y}); }

inline Vector3f squareToUniformHemisphere(const Point2f& u) {
    float z = u.x;
    float r = safeSqrt(1.f - z * z), phi = 2.f * Pi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float squareToUniformHemispherePdf(const Vector3f& v) { return v.z >= 0.f ? Inv2Pi : 0.f; }

inline Vector3f squareToUniformSphere(const Point2f& u) {
    float z = 1.f - 2.f * u.x;
    float r = safeSqrt(1.f - z * z), phi = 2.f * Pi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float squareToUniformSpherePdf(const Vector3f&) { return Inv4Pi; }
inline Point2f uniformSphereToSquare(const Vector3f& v) {
    float phi = std::atan2(v.y, v.x);
    if (phi < 0.f) phi += 2.f * Pi;
    return {(1.f - v.z) * 0.5f, std::min(phi * Inv2Pi, OneMinusEpsilon)};
}

/// Uniform directions in the cone of half-angle acos(cosThetaMax) about +z.
inline Vector3f squareToUniformCone(const Point2f& u, float cosThetaMax) {
    float z = lerp(u.x, 1.f, cosThetaMax);
    float r = safeSqrt(1.f - z * z), phi = 2.f * Pi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float squareToUniformConePdf(const Vector3f& v, float cosThetaMax) {
    return v.z >= cosThetaMax ? 1.f / (2.f * Pi * (1.f - cosThetaMax)) : 0.f;
}

/// Uniform barycentrics (b0, b1) on a triangle; b2 = 1 − b0 − b1.
inline Point2f squareToUniformTriangle(const Point2f& u) {
    float su0 = std::sqrt(u.x);
    return {1.f - su0, u.y * su0};
}
inline Point2f uniformTriangleToSquare(const Point2f& b) {
    float su0 = 1.f - b.x;
    return {su0 * su0, su0 > 0.f ? b.y / su0 : 0.f};
}

/// Inverse of squareToUniformHemisphere.
inline Point2f uniformHemisphereToSquare(const Vector3f& v) {
    float phi = std::atan2(v.y, v.x);
    if (phi < 0.f) phi += 2.f * Pi;
    return {std::clamp(v.z, 0.f, OneMinusEpsilon), std::min(phi * Inv2Pi, OneMinusEpsilon)};
}

/// Inverse of squareToUniformCone: z = 1 − u.x (1 − cosθmax).
inline Point2f uniformConeToSquare(const Vector3f& v, float cosThetaMax) {
    float phi = std::atan2(v.y, v.x);
    if (phi < 0.f) phi += 2.f * Pi;
    float ux = cosThetaMax < 1.f ? (1.f - v.z) / (1.f - cosThetaMax) : 0.f;
    return {std::clamp(ux, 0.f, OneMinusEpsilon), std::min(phi * Inv2Pi, OneMinusEpsilon)};
}

/// Visible-spectrum wavelength importance sampling (Radziszewski et al. 2009 fit,
/// pdf ∝ 1/cosh²(0.0072 (λ − 538)) over 360–830 nm). The constants: 1/0.0072 =
/// 138.888889; tanh(0.0072·(538 − 360)) = 0.85691062 and the CDF's range
/// tanh(0.0072·178) + tanh(0.0072·292) = 1.82750197.
inline float sampleVisibleWavelength(float u) {
    return 538.f - 138.888889f * std::atanh(0.85691062f - 1.82750197f * u);
}
inline float visibleWavelengthPdf(float lambda) {
    if (lambda < 360.f || lambda > 830.f) return 0.f;
    float c = std::cosh(0.0072f * (lambda - 538.f));
    return 0.0039398042f / (c * c);
}
/// Both at once: with a = 0.85691062 − 1.82750197 u, λ = 538 − atanh(a)/0.0072 and
/// 1/cosh²(atanh(a)) = 1 − a², so the pdf needs no transcendental beyond one log.
inline float sampleVisibleWavelength(float u, float& pdf) {
    float a = 0.85691062f - 1.82750197f * u;
    pdf = 0.0039398042f * (1.f - a * a);
    return 538.f - 69.4444444f * std::log((1.f + a) / (1.f - a));  // atanh(a) = ½ log((1+a)/(1−a))
}

} // namespace effigi::warp
