#pragma once
// Helpers shared by the BSDF suite's files: the surface point BSDFs are probed at,
// directions by angle, relative errors and how failing cases are described.
#include "conformance/conformance.hpp"
#include "effigi/interfaces/ibsdf.hpp"

#include <fmt/format.h>

#include <cmath>
#include <string>

namespace effigi::conform::bsdf {

/// A surface point at the origin whose shading frame is the identity, so the local
/// directions the suite chooses are the directions the BSDF sees.
inline SurfaceInteraction probePoint() {
    SurfaceInteraction si;
    si.p = Point3f(0.f);
    si.t = 1.f;
    si.n = Normal3f(0.f, 0.f, 1.f);
    si.shading = Frame();
    si.uv = Point2f(0.5f);
    si.wo = Vector3f(0.f, 0.f, 1.f);
    return si;
}

/// The unit vector with the given cos θ and φ.
inline Vector3f direction(float cosTheta, float phi) {
    float s = std::sqrt(std::max(0.f, 1.f - cosTheta * cosTheta));
    return {s * std::cos(phi), s * std::sin(phi), cosTheta};
}

/// Uniform direction on the sphere from two uniform numbers.
inline Vector3f uniformDirection(PCG32& rng) {
    float z = 1.f - 2.f * rng.nextFloat();
    return direction(z, 2.f * Pi * rng.nextFloat());
}

/// |a − b| relative to the larger magnitude; values both below `floor` agree.
inline double relativeError(double a, double b, double floor = 1e-12) {
    if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<double>::infinity();
    double scale = std::max({std::abs(a), std::abs(b), floor});
    return std::abs(a - b) / scale;
}

inline std::string vec(const Vector3f& v) { return fmt::format("({:.4g}, {:.4g}, {:.4g})", v.x, v.y, v.z); }

inline std::string spec(const SampledSpectrum& s) {
    return fmt::format("[{:.4g}, {:.4g}, {:.4g}, {:.4g}]", s[0], s[1], s[2], s[3]);
}

inline std::string lambdas(const SampledWavelengths& l) {
    return fmt::format("λ = [{:.1f}, {:.1f}, {:.1f}, {:.1f}] nm", l[0], l[1], l[2], l[3]);
}

inline const char* modeName(TransportMode m) { return m == TransportMode::Radiance ? "radiance" : "importance"; }

/// A spectrum is usable: finite and not negative in every slot.
inline bool usable(const SampledSpectrum& s) {
    for (int i = 0; i < NSpectrumSamples; ++i)
        if (!(s[i] >= 0.f) || !std::isfinite(s[i])) return false;
    return true;
}

/// Above this density (sr⁻¹) a lobe is narrower than a (φ, cos θ) histogram and its
/// cell quadrature can resolve (about 1e-3 sr, GGX α ≈ 0.01): its chi-square runs on a
/// chart centred on the lobe instead (bsdf_lobe.cpp) and the pdf-integral check skips it.
inline constexpr double MaxHistogramPdf = 1000.0;

// The checks, one function each (bsdf_checks.cpp, bsdf_distribution.cpp).
void checkNonNegative(Target& t, const IBSDF& b);
void checkStability(Target& t, const IBSDF& b);
void checkSampleWeight(Target& t, const IBSDF& b);
void checkReciprocity(Target& t, const IBSDF& b);
void checkEnergy(Target& t, const IBSDF& b);
void checkDelta(Target& t, const IBSDF& b);
void checkDistribution(Target& t, const IBSDF& b);
/// The chi-square of checkDistribution for lobes denser than MaxHistogramPdf.
void checkNarrowLobes(Target& t, const IBSDF& b, const SurfaceInteraction& si, const Vector3f& wo,
                      const std::string& name, std::uint64_t n);

} // namespace effigi::conform::bsdf
