#pragma once
// Microfacet normal distributions for rough surfaces, in the local shading frame (macro
// normal +z): GGX (Trowbridge–Reitz) and Beckmann, with anisotropic roughness (αx, αy)
// along the shading tangent and bitangent.
//
//   D(m)      distribution of microfacet normals, normalised so that ∫ D(m) cosθm dωm = 1
//   Λ(w)      Smith's auxiliary function; G1(w) = 1 / (1 + Λ(w)) is the masking of w
//   G(wo, wi) height-correlated Smith masking-shadowing (Heitz 2014, §6):
//               reflection (wo, wi on one side)    1 / (1 + Λ(wo) + Λ(wi))
//               transmission (opposite sides)      B(1 + Λ(wo), 1 + Λ(wi)), B the Beta
//                                                  function: ∫ C^Λo (1 − C)^Λi dC over the
//                                                  height CDF C, since a point high enough to
//                                                  be seen from above is deep for below.
//   sampleVisible  the distribution of normals visible from w, D_w(m) = G1(w) ⟨w·m⟩ D(m) / |w.z|
//                  (Heitz & d'Eon 2014): GGX by Heitz 2018 (uniform points on the projected
//                  hemisphere of the stretched configuration); Beckmann by inverting the
//                  CDFs of the visible slopes in the stretched configuration (Heitz & d'Eon
//                  2014, §4 and appendix): the slope along the incident azimuth has density
//                  ∝ (cosθ − x̃ sinθ) e^{−x̃²} on x̃ ≤ cotθ, the other is Gaussian. Both maps
//                  are bijections with inverses (visibleToSquare).
//   sampleNormal   D(m) cosθm itself (Mitsuba's sample_visible = false), by the slope CDF.
//
// The microsurface is the same seen from above and below: for w with w.z < 0 every
// function uses −w, and sampled normals always have m.z > 0.
//
// Numerics. α is clamped to [MinAlpha, ∞): at α = 1e-4 the lobe is ~1e-4 rad wide, about
// 2000 float ulps of a unit vector; narrower lobes are below what float directions
// resolve and belong to the smooth (delta) BSDFs. Λ is +∞ exactly at grazing (w.z = 0),
// making G1 = G = 0 there; the Beckmann functions use double precision, where erfc and the
// slope CDFs keep their digits in the tails.
//
// References: B. Walter, S. Marschner, H. Li, K. Torrance, "Microfacet Models for Refraction
// through Rough Surfaces", EGSR 2007; E. Heitz, "Understanding the Masking-Shadowing
// Function in Microfacet-Based BRDFs", JCGT 3(2), 2014; E. Heitz, E. d'Eon, "Importance
// Sampling Microfacet-Based BSDFs using the Distribution of Visible Normals", EGSR 2014;
// E. Heitz, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4), 2018.
#include "effigi/math/vector.hpp"

#include <cmath>
#include <limits>

namespace effigi {

enum class MicrofacetType { Beckmann, GGX };

namespace microfacet_detail {

inline constexpr double SqrtPi = 1.7724538509055160273;
/// Stretched slopes are confined to [−SlopeLimit, SlopeLimit]: a Gaussian slope beyond 7
/// has probability erfc(7)/2 ≈ 2e-23, far below what a float sample can select.
inline constexpr double SlopeLimit = 7.0;

/// Solve g(x) = target for a non-decreasing g on [lo, hi] by Newton's method, falling
/// back to bisection whenever a step leaves the bracket (g' = 0 at an end, flat tails).
template <typename G, typename DG>
double solveIncreasing(const G& g, const DG& dg, double target, double lo, double hi, double x) {
    for (int it = 0; it < 100; ++it) {
        double v = g(x) - target;
        if (v == 0.0) return x;
        (v > 0.0 ? hi : lo) = x;
        double d = dg(x), next = x - v / d;
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (std::abs(next - x) <= 1e-13 * std::max(1.0, std::abs(x))) return next;
        x = next;
    }
    return x;
}

/// ln Γ(x) for x >= 1 (Stirling's series after shifting x above 8; error < 1e-12).
inline double logGamma(double x) {
    double shift = 0.0;
    while (x < 8.0) {
        shift -= std::log(x);
        x += 1.0;
    }
    double r = 1.0 / x, r2 = r * r;
    double series = r * (1.0 / 12.0 - r2 * (1.0 / 360.0 - r2 * (1.0 / 1260.0 - r2 / 1680.0)));
    return shift + (x - 0.5) * std::log(x) - x + 0.91893853320467274178 + series;
}

} // namespace microfacet_detail

class MicrofacetDistribution {
public:
    /// Smallest roughness represented (see the numerics note above).
    static constexpr float MinAlpha = 1e-4f;

    MicrofacetDistribution(MicrofacetType type, float alphaX, float alphaY)
        : m_type(type), m_alphaX(std::max(alphaX, MinAlpha)), m_alphaY(std::max(alphaY, MinAlpha)) {}

    MicrofacetType type() const { return m_type; }
    float alphaX() const { return m_alphaX; }
    float alphaY() const { return m_alphaY; }

    /// D(m); zero for m.z <= 0.
    float D(const Vector3f& m) const {
        if (!(m.z > 0.f)) return 0.f;
        if (m_type == MicrofacetType::GGX) {
            // 1 / (π αx αy ((mx/αx)² + (my/αy)² + mz²)²), Walter 2007 eq. 33 made anisotropic.
            float x = m.x / m_alphaX, y = m.y / m_alphaY;
            float d = x * x + y * y + m.z * m.z;
            return 1.f / (Pi * m_alphaX * m_alphaY * d * d);
        }
        // exp(−tan²θm (cos²φ/αx² + sin²φ/αy²)) / (π αx αy cos⁴θm), Walter 2007 eq. 25.
        // Values below the smallest normal float are flushed to 0: ratios such as
        // f·cosθ/pdf of denormal values overflow.
        double x = double(m.x) / m_alphaX, y = double(m.y) / m_alphaY, z2 = double(m.z) * m.z;
        double d = std::exp(-(x * x + y * y) / z2) / (Pi * double(m_alphaX) * m_alphaY * z2 * z2);
        return d >= double(std::numeric_limits<float>::min()) ? float(d) : 0.f;
    }

    /// Smith's Λ(w); +∞ at w.z = 0.
    float lambda(const Vector3f& w) const {
        double z2 = double(w.z) * w.z;
        if (z2 == 0.0) return Infinity;
        // α² tan²θ along w's azimuth.
        double ax = double(m_alphaX) * w.x, ay = double(m_alphaY) * w.y;
        double a2t2 = (ax * ax + ay * ay) / z2;
        if (m_type == MicrofacetType::GGX) return float(0.5 * (std::sqrt(1.0 + a2t2) - 1.0));
        // Beckmann, a = cotθ / α: Λ = (e^{−a²} / (a √π) − erfc(a)) / 2 (Walter 2007, eq. 27
        // written with erfc so that it stays accurate as Λ → 0).
        if (a2t2 == 0.0) return 0.f;
        double a = 1.0 / std::sqrt(a2t2);
        double l = 0.5 * (std::exp(-a * a) / (a * microfacet_detail::SqrtPi) - std::erfc(a));
        return float(std::max(0.0, l));
    }

    float G1(const Vector3f& w) const { return 1.f / (1.f + lambda(w)); }

    /// Height-correlated masking-shadowing of the pair (see the header comment).
    float G(const Vector3f& wo, const Vector3f& wi) const {
        double lo = lambda(wo), li = lambda(wi);
        if (std::isinf(lo) || std::isinf(li)) return 0.f;
        if (wo.z * wi.z > 0.f) return float(1.0 / (1.0 + lo + li));
        using microfacet_detail::logGamma;
        return float(std::exp(logGamma(1.0 + lo) + logGamma(1.0 + li) - logGamma(2.0 + lo + li)));
    }

    /// Density of visible normals D_w(m) per unit solid angle (w on either side).
    float visiblePdf(const Vector3f& w, const Vector3f& m) const {
        if (w.z == 0.f) return 0.f;
        float cosWM = w.z > 0.f ? dot(w, m) : -dot(w, m);
        if (!(cosWM > 0.f)) return 0.f;
        return G1(w) * cosWM * D(m) / std::abs(w.z);
    }

    /// A normal distributed as D_w(m), from u ∈ [0,1)²; m.z > 0.
    Vector3f sampleVisible(Vector3f w, const Point2f& u) const {
        if (w.z < 0.f) w = -w;
        if (m_type == MicrofacetType::GGX) return sampleVisibleGGX(w, u);
        Vector3d ws;
        double cosPhi, sinPhi;
        stretched(w, ws, cosPhi, sinPhi);
        double sinT = std::hypot(ws.x, ws.y), cosT = ws.z;
        double x = beckmannSlopeX(u.x, cosT, sinT), y = beckmannSlopeY(u.y);
        // Rotate back to w's azimuth and unstretch; the slope (x, y) is the normal ∝ (−x, −y, 1).
        double sx = m_alphaX * (cosPhi * x - sinPhi * y), sy = m_alphaY * (sinPhi * x + cosPhi * y);
        return Vector3f(glm::normalize(Vector3d(-sx, -sy, 1.0)));
    }

    /// The u with sampleVisible(w, u) = m, for m visible from w.
    Point2f visibleToSquare(Vector3f w, const Vector3f& m) const {
        if (w.z < 0.f) w = -w;
        if (m_type == MicrofacetType::GGX) return visibleToSquareGGX(w, m);
        Vector3d ws;
        double cosPhi, sinPhi;
        stretched(w, ws, cosPhi, sinPhi);
        double sinT = std::hypot(ws.x, ws.y), cosT = ws.z;
        double sx = -double(m.x) / (double(m.z) * m_alphaX), sy = -double(m.y) / (double(m.z) * m_alphaY);
        double x = cosPhi * sx + sinPhi * sy, y = -sinPhi * sx + cosPhi * sy;
        double ux = beckmannCdfX(x, cosT, sinT) / beckmannCdfX(slopeXMax(cosT, sinT), cosT, sinT);
        double uy = 0.5 * std::erfc(-y);
        return {std::clamp(float(ux), 0.f, OneMinusEpsilon), std::clamp(float(uy), 0.f, OneMinusEpsilon)};
    }

    /// A normal distributed as D(m) cosθm (all normals, visible or not); m.z > 0.
    Vector3f sampleNormal(const Point2f& u) const {
        // In the stretched (α = 1) configuration the radial slope r has CDF r²/(1 + r²)
        // (GGX) or 1 − e^{−r²} (Beckmann); stretching the slopes by (αx, αy) gives D.
        double v = std::min(double(u.x), 1.0 - 1e-12);
        double r2 = m_type == MicrofacetType::GGX ? v / (1.0 - v) : -std::log1p(-v);
        double r = std::sqrt(r2), phi = 2.0 * std::numbers::pi * u.y;
        return Vector3f(glm::normalize(Vector3d(-m_alphaX * r * std::cos(phi), -m_alphaY * r * std::sin(phi), 1.0)));
    }
    float normalPdf(const Vector3f& m) const { return D(m) * std::max(0.f, m.z); }

private:
    /// w stretched to the α = 1 configuration, and the cosine and sine of its azimuth.
    void stretched(const Vector3f& w, Vector3d& ws, double& cosPhi, double& sinPhi) const {
        ws = glm::normalize(Vector3d(double(m_alphaX) * w.x, double(m_alphaY) * w.y, double(w.z)));
        double s = std::hypot(ws.x, ws.y);
        cosPhi = s > 0.0 ? ws.x / s : 1.0;
        sinPhi = s > 0.0 ? ws.y / s : 0.0;
    }

    // Beckmann visible slopes, α = 1, incidence (sinθ, 0, cosθ). Multiplied by cosθ (which
    // keeps normal and grazing incidence finite) the marginal CDF of the slope x̃ along the
    // incident azimuth is C(x̃) = (cosθ erfc(−x̃) + sinθ e^{−x̃²}/√π) / 2, x̃ <= cotθ, whose
    // derivative is the density (cosθ − x̃ sinθ) e^{−x̃²} / √π; C(cotθ) = cosθ (1 + Λ).
    static double slopeXMax(double cosT, double sinT) {
        using microfacet_detail::SlopeLimit;
        return sinT * SlopeLimit > cosT ? cosT / sinT : SlopeLimit;
    }
    static double beckmannCdfX(double x, double cosT, double sinT) {
        return 0.5 * (cosT * std::erfc(-x) + sinT * std::exp(-x * x) / microfacet_detail::SqrtPi);
    }
    static double beckmannSlopeX(float u, double cosT, double sinT) {
        using microfacet_detail::SlopeLimit;
        double hi = slopeXMax(cosT, sinT), lo = -SlopeLimit;
        double target = double(u) * beckmannCdfX(hi, cosT, sinT);
        return microfacet_detail::solveIncreasing(
            [&](double x) { return beckmannCdfX(x, cosT, sinT); },
            [&](double x) { return (cosT - x * sinT) * std::exp(-x * x) / microfacet_detail::SqrtPi; }, target, lo,
            hi, std::min(0.0, hi));
    }
    /// The transverse slope ỹ is normal with variance 1/2: CDF erfc(−ỹ)/2.
    static double beckmannSlopeY(float u) {
        using microfacet_detail::SlopeLimit;
        return microfacet_detail::solveIncreasing([](double y) { return 0.5 * std::erfc(-y); },
                                                  [](double y) { return std::exp(-y * y) / microfacet_detail::SqrtPi; },
                                                  double(u), -SlopeLimit, SlopeLimit, 0.0);
    }

    // GGX visible normals (Heitz 2018): stretch w to the hemisphere configuration, sample
    // the projected area of the hemisphere seen from it (a disk whose far half is squashed
    // by (1 + cosθ)/2), lift the point to the hemisphere and unstretch.
    Vector3f sampleVisibleGGX(const Vector3f& w, const Point2f& u) const {
        Vector3f vh = normalize(Vector3f(m_alphaX * w.x, m_alphaY * w.y, w.z));
        Vector3f t1, t2;
        diskFrame(vh, t1, t2);
        float r = std::sqrt(u.x), phi = 2.f * Pi * u.y;
        float p1 = r * std::cos(phi), p2 = r * std::sin(phi);
        float s = 0.5f * (1.f + vh.z);
        p2 = (1.f - s) * safeSqrt(1.f - p1 * p1) + s * p2;
        Vector3f nh = p1 * t1 + p2 * t2 + safeSqrt(1.f - p1 * p1 - p2 * p2) * vh;
        // nh.z = 0 on the rim of the disk seen at grazing incidence: keep m above the surface.
        return normalize(Vector3f(m_alphaX * nh.x, m_alphaY * nh.y, std::max(1e-6f, nh.z)));
    }
    /// Inverse of sampleVisibleGGX: stretch m back, project it on the disk spanned by
    /// (t1, t2), undo the squash and read off the polar coordinates of the disk point.
    Point2f visibleToSquareGGX(const Vector3f& w, const Vector3f& m) const {
        Vector3f vh = normalize(Vector3f(m_alphaX * w.x, m_alphaY * w.y, w.z));
        Vector3f t1, t2;
        diskFrame(vh, t1, t2);
        Vector3f nh = normalize(Vector3f(m.x / m_alphaX, m.y / m_alphaY, m.z));
        float p1 = dot(nh, t1), p2 = dot(nh, t2);
        float s = 0.5f * (1.f + vh.z);
        p2 = (p2 - (1.f - s) * safeSqrt(1.f - p1 * p1)) / s;
        float r2 = p1 * p1 + p2 * p2;
        float phi = std::atan2(p2, p1);
        if (phi < 0.f) phi += 2.f * Pi;
        return {std::clamp(r2, 0.f, OneMinusEpsilon), std::min(phi * Inv2Pi, OneMinusEpsilon)};
    }
    static void diskFrame(const Vector3f& vh, Vector3f& t1, Vector3f& t2) {
        float lensq = vh.x * vh.x + vh.y * vh.y;
        t1 = lensq > 0.f ? Vector3f(-vh.y, vh.x, 0.f) / std::sqrt(lensq) : Vector3f(1.f, 0.f, 0.f);
        t2 = cross(vh, t1);
    }

    MicrofacetType m_type;
    float m_alphaX, m_alphaY;
};

} // namespace effigi
