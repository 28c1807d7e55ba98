#pragma once
// Shared by the phase and medium suites (phase_suite.cpp, phase_distribution.cpp,
// medium_suite.cpp, medium_transmittance.cpp): probe wavelengths and the declarations
// of the checks that live in a file of their own.
#include "conformance/bsdf_common.hpp"
#include "effigi/interfaces/imedium.hpp"

namespace effigi::conform::media {

using bsdf::relativeError;
using bsdf::spec;
using bsdf::uniformDirection;
using bsdf::vec;

/// The i-th probe's wavelengths: random ones, or all four at 360 or at 830 nm in turn.
inline SampledWavelengths probeWavelengths(PCG32& rng, std::size_t i) {
    if (i % 3 == 1) return SampledWavelengths::constant(LambdaMin);
    if (i % 3 == 2) return SampledWavelengths::constant(LambdaMax);
    return SampledWavelengths::sampleUniform(rng.nextFloat());
}

/// Every slot ≥ 0 (NaN is not).
inline bool nonNegative(const SampledSpectrum& s) {
    for (int k = 0; k < NSpectrumSamples; ++k)
        if (!(s[k] >= 0.f)) return false;
    return true;
}

/// Directions wo to condition on: the poles and an axis (where frames built about −wo
/// switch branches) and a random one; two of them in quick mode.
std::vector<Vector3f> conditioningDirections(Target& t);

/// Chi-square of sample() against pdf() for each wo, in (φ, cos θ) cells about the
/// forward axis −wo whose cos θ bands are quantiles of a pilot run (so the lobe of a
/// forward-peaked phase function spreads over every band); and ∫pdf = 1 from the cells.
void checkPhaseDistribution(Target& t, const IPhaseFunction& p);

/// Delta and ratio tracking against the exact transmittance, and against each other.
void checkTransmittance(Target& t, const IMedium& m);

} // namespace effigi::conform::media
