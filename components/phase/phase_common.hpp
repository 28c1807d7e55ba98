#pragma once
// What the phase functions share: the angle between wo and wi taken accurately near
// both poles, and a direction built about the forward axis −wo from its cosine.
//
// Peaked phase functions (Henyey–Greenstein with |g| → 1) put all their mass within a
// hair of wi = ∓wo, where 1 ± wo·wi computed as written loses every digit to
// cancellation (1 − 0.99995 in float keeps one digit). In double, with the vectors
// normalised, 1 + cos = |ŵo + ŵi|²/2 and 1 − cos = |ŵo − ŵi|²/2 keep full relative
// precision on their own side, because the sum (difference) of two nearly opposite
// (equal) vectors is formed without rounding error (Sterbenz).
#include "effigi/interfaces/iphasefunction.hpp"
#include "effigi/math/frame.hpp"

#include <cmath>
#include <numbers>

namespace effigi::phase {

/// 1 + wo·wi and 1 − wo·wi for the unit vectors along wo and wi; they add up to 2.
struct AngleTerms {
    double onePlusCos = 1.0, oneMinusCos = 1.0;
    double cosine() const { return onePlusCos < oneMinusCos ? onePlusCos - 1.0 : 1.0 - oneMinusCos; }
};

inline AngleTerms angleTerms(const Vector3f& wo, const Vector3f& wi) {
    const Vector3d a = Vector3d(wo), b = Vector3d(wi);
    const double la = std::sqrt(dot(a, a)), lb = std::sqrt(dot(b, b));
    if (!(la > 0.0 && lb > 0.0) || !std::isfinite(la * lb)) return {};  // no direction: treat as 90°
    const Vector3d sum = a / la + b / lb, diff = a / la - b / lb;
    return {0.5 * dot(sum, sum), 0.5 * dot(diff, diff)};
}

/// The unit direction making angle θ with the forward axis −wo, cos θ = μ given as the
/// pair (1 − μ, 1 + μ) (each accurate on its own side), at azimuth 2π·uPhi about the axis.
inline Vector3f aroundForward(const Vector3f& wo, double oneMinusMu, double onePlusMu, float uPhi) {
    const Frame f(normalize(-wo));
    const double mu = oneMinusMu < onePlusMu ? 1.0 - oneMinusMu : onePlusMu - 1.0;
    const double sinTheta = std::sqrt(std::max(0.0, oneMinusMu * onePlusMu));
    const double phi = 2.0 * std::numbers::pi * double(uPhi);
    const Vector3d local(sinTheta * std::cos(phi), sinTheta * std::sin(phi), mu);
    return Vector3f(Vector3d(f.s) * local.x + Vector3d(f.t) * local.y + Vector3d(f.n) * local.z);
}

/// The sample of a wavelength-independent phase function drawn exactly from its own
/// density: the pdf is p evaluated at the direction actually returned (a float vector),
/// so pdf(wo, wi) reproduces it bit for bit and the weight p/pdf is exactly 1.
template <typename Density>
std::optional<PhaseSample> exactSample(const Vector3f& wo, const Vector3f& wi, Density&& density) {
    const float p = float(density(angleTerms(wo, wi)));
    if (!(p > 0.f) || !std::isfinite(p)) return std::nullopt;
    return PhaseSample{wi, p, SampledSpectrum(1.f)};
}

} // namespace effigi::phase
