#pragma once
// Free-flight sampling through a participating medium against its majorant (delta
// tracking, Woodcock et al. 1965), the loop every volumetric estimator of `volpath`
// shares: the camera and scattered rays (volpath_core.hpp) decide at each tentative
// collision whether it is absorption, real scattering or a null collision; shadow rays
// (ratio tracking, Novák et al. 2014) multiply in the null-collision probability.
//
// Distances are sampled on the hero wavelength's majorant (the first of the four); the
// other wavelengths see the same points and are reweighted by the spectral-MIS ratios r_u
// and r_l of the caller (Miller, Georgiev, Jarosz 2019, "A null-scattering path integral
// formulation of light transport", SIGGRAPH; as pbrt-v4's VolPathIntegrator uses them).
// `callback(p, props, sigmaMaj, Tmaj)` is called at each tentative collision with the
// majorant transmittance since the previous one; returning false stops the walk. The
// result is the majorant transmittance from the last collision to tMax (all ones when the
// callback stopped the walk).
#include "effigi/interfaces/imedium.hpp"
#include "effigi/math/rng.hpp"

#include <bit>
#include <cmath>
#include <limits>

namespace effigi {

/// A generator for one segment's collisions, seeded from two sampler dimensions: the
/// number of collisions is unbounded, so they cannot come from fixed sampler dimensions
/// (pbrt-v4 does the same).
inline PCG32 trackingRng(float u0, float u1) {
    return PCG32(mixBits(std::bit_cast<std::uint32_t>(u0) ^ 0x9e3779b97f4a7c15ull),
                 mixBits(std::bit_cast<std::uint32_t>(u1) + 0x632be59bd9b4e019ull));
}

/// exp(-sigma·d) per wavelength, with d = ∞ (an unbounded segment) giving 0 where sigma > 0.
inline SampledSpectrum majorantTransmittance(const SampledSpectrum& sigma, float d) {
    SampledSpectrum T;
    for (int i = 0; i < NSpectrumSamples; ++i) T[i] = sigma[i] > 0.f ? std::exp(-sigma[i] * d) : 1.f;
    return T;
}

template <typename Callback>
SampledSpectrum sampleMajorant(const IMedium& medium, const Ray& ray, float tMax, PCG32& rng,
                               const SampledWavelengths& lambda, Callback&& callback) {
    // Work in distance units along a unit direction: t·|d| is the distance covered.
    const float len = length(ray.d);
    if (!(len > 0.f)) return SampledSpectrum(1.f);
    const Vector3f dir = ray.d / len;
    const float end = std::isinf(tMax) ? std::numeric_limits<float>::infinity() : tMax * len;
    const Ray unit{ray.o, dir, Infinity, ray.time};
    SampledSpectrum T(1.f);
    for (float t0 = 0.f; t0 < end;) {
        const MajorantSegment seg = medium.majorant(unit, t0, end, lambda);
        const float segEnd = std::min(seg.tMax, end);
        if (!(segEnd > t0)) break;  // a medium that does not advance ends the walk
        const SampledSpectrum& sigmaMaj = seg.sigmaMaj;
        // Distance left in the segment (an unbounded one counts as the largest float).
        auto rest = [&](float from) { return std::min(segEnd, std::numeric_limits<float>::max()) - from; };
        // A hero wavelength without extinction cannot sample distances: the segment's
        // transmittance goes to the other wavelengths whole.
        if (!(sigmaMaj[0] > 0.f)) {
            T *= majorantTransmittance(sigmaMaj, rest(t0));
            t0 = segEnd;
            continue;
        }
        // t in double: a step far below the float spacing of t still advances.
        for (double t = t0;;) {
            // Exponential step on the hero majorant; 1 − u > 0 keeps the log finite.
            const float step = -std::log1p(-rng.nextFloat()) / sigmaMaj[0];
            if (!(t + step < double(segEnd))) {
                T *= majorantTransmittance(sigmaMaj, rest(float(t)));
                break;
            }
            t += step;
            T *= majorantTransmittance(sigmaMaj, step);
            const Point3f p = ray.o + float(t) * dir;
            if (!callback(p, medium.at(p, lambda), sigmaMaj, T)) return SampledSpectrum(1.f);
            T = SampledSpectrum(1.f);
        }
        t0 = segEnd;
    }
    return T;
}

} // namespace effigi
