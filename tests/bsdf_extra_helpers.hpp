#pragma once
// Helpers shared by the BSDF tests of issue 10 (test_bsdf_extra, test_bsdf_perturbed,
// test_bsdf_principled): random directions, effigi-conform's probe point, comparing two
// BSDFs at random direction pairs, and a sampled directional albedo.
#include "bsdf_helpers.hpp"

#include "effigi/math/rng.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace effigi::test {

using Params = std::vector<std::pair<std::string, PropertyValue>>;

inline Vector3f randomDirection(PCG32& rng) {
    float z = 1.f - 2.f * rng.nextFloat(), phi = 2.f * Pi * rng.nextFloat(), s = std::sqrt(std::max(0.f, 1.f - z * z));
    return {s * std::cos(phi), s * std::sin(phi), z};
}

inline Vector3f upperDirection(PCG32& rng) {
    Vector3f w = randomDirection(rng);
    w.z = std::max(std::abs(w.z), 1e-3f);
    return normalize(w);
}

/// The probe point of effigi-conform: identity shading frame, unit (u, v) derivatives.
inline SurfaceInteraction probe() {
    SurfaceInteraction si;
    si.shading = Frame();
    si.n = Normal3f(0.f, 0.f, 1.f);
    si.dpdu = Vector3f(1.f, 0.f, 0.f);
    si.dpdv = Vector3f(0.f, 1.f, 0.f);
    si.uv = Point2f(0.5f);
    return si;
}

/// f and pdf of two BSDFs agree at random direction pairs (relative tolerance tol).
inline void requireSameBSDF(const IBSDF& a, const IBSDF& b, const SurfaceInteraction& si, float tol,
                            std::uint64_t seed) {
    PCG32 rng(seed, 11);
    for (int i = 0; i < 3000; ++i) {
        Vector3f wo = randomDirection(rng), wi = randomDirection(rng);
        SampledWavelengths l = SampledWavelengths::constant(550.f);
        for (TransportMode m : {TransportMode::Radiance, TransportMode::Importance}) {
            float fa = a.f(si, wo, wi, l, m)[0], fb = b.f(si, wo, wi, l, m)[0];
            REQUIRE(fa == Approx(fb).epsilon(tol).margin(1e-6));
            REQUIRE(a.pdf(si, wo, wi, l, m) == Approx(b.pdf(si, wo, wi, l, m)).epsilon(tol).margin(1e-6));
        }
    }
}

/// Mean of the sample weights f·|cos θi|/pdf at wo (the directional albedo) and its
/// standard error, from n seeded samples.
inline std::pair<double, double> sampledAlbedo(const IBSDF& b, const SurfaceInteraction& si, const Vector3f& wo, int n,
                                               std::uint64_t seed, TransportMode mode = TransportMode::Radiance) {
    PCG32 rng(seed, 5);
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
        SampledWavelengths l = SampledWavelengths::constant(550.f);
        auto bs = b.sample(si, wo, rng.nextFloat(), Point2f(rng.nextFloat(), rng.nextFloat()), l, mode);
        double w = bs && bs->pdf > 0.f ? double(weight(*bs)) : 0.0;
        sum += w;
        sum2 += w * w;
    }
    double mean = sum / n, var = std::max(0.0, sum2 / n - mean * mean);
    return {mean, std::sqrt(var / n)};
}

} // namespace effigi::test
