#pragma once
// Unbiased estimators of the transmittance T = exp(−∫ σt ds) along a ray through an
// IMedium, from the medium's majorants alone: they need σt only at the points they visit,
// so they serve heterogeneous media as well as homogeneous ones. Both walk the same
// process of tentative collisions, a Poisson process of rate μ = max_λ σ_maj,λ per unit
// distance (one rate for the four wavelengths, so each wavelength's σt/μ ≤ 1), restarted
// at every majorant segment (the exponential distribution is memoryless):
//  - delta tracking (Woodcock et al. 1965): a tentative collision is real for wavelength
//    λ with probability σt,λ/μ; T̂λ = 1 if the walk leaves the interval before a real
//    collision at λ, else 0. One uniform number decides all four wavelengths, so each
//    one's estimate is exactly delta tracking with majorant μ (correlated across λ,
//    unbiased at each); the walk ends when every wavelength has collided or at tMax.
//  - ratio tracking (Cramer 1978; Novák, Selle & Jarosz 2014): T̂λ is the product of
//    (1 − σt,λ/μ) over the tentative collisions. When the largest of the four estimates
//    falls below 1/8, Russian roulette keeps the walk with probability (largest)/(1/8)
//    and divides by it, which leaves every estimate unbiased, ends long walks through
//    optically thick media after a few steps, and keeps every estimate within [0, 1].
// Both estimates lie in [0, 1] per wavelength. A σt above the majorant is clamped to it
// (the estimate is then biased; the `medium` suite checks majorants). The walks add up
// distances in double, so that a step far below the float spacing of t still advances.
//
// `uniform` is any callable returning a uniform float in [0, 1) (an RNG, or a sampler's
// get1D where a renderer owns the dimensions); the number of draws is random. tMax
// should be finite: over an infinite interval delta tracking ends only once every
// wavelength has collided, never where one of them has σt = 0 all the way.
//
// References: E. R. Woodcock, T. Murphy, P. J. Hemmings & T. C. Longworth, "Techniques
// used in the GEM code for Monte Carlo neutronics calculations in reactors and other
// systems of complex geometry", ANL-7050, 1965; S. N. Cramer, "Application of the
// fictitious scattering radiation transport model for deep-penetration Monte Carlo
// calculations", Nuclear Science and Engineering 65(2), 1978; J. Novák, A. Selle &
// W. Jarosz, "Residual ratio tracking for estimating attenuation in participating
// media", ACM Transactions on Graphics 33(6), 2014.
#include "effigi/interfaces/imedium.hpp"

#include <algorithm>
#include <cmath>

namespace effigi {

namespace detail {

/// Walk the tentative collisions of [0, tMax] on `ray`; `collide(point, μ)` is called at
/// each and returns false to stop the walk.
template <typename Uniform, typename Collide>
void walkTentativeCollisions(const IMedium& medium, const Ray& ray, float tMax, const SampledWavelengths& lambda,
                             Uniform& uniform, Collide&& collide) {
    const double speed = double(length(ray.d));  // distance per unit of t
    if (!(speed > 0.0) || !(tMax > 0.f)) return;
    double t = 0.0;
    while (t < double(tMax)) {
        const MajorantSegment seg = medium.majorant(ray, float(t), tMax, lambda);
        const double end = std::min(double(seg.tMax), double(tMax));
        if (!(end > t)) return;  // a medium that does not advance ends the walk
        const double mu = double(std::max(0.f, seg.sigmaMaj.maxValue()));
        while (true) {
            if (!(mu > 0.0)) break;
            // Distance to the next tentative collision: an exponential of rate μ.
            t -= std::log1p(-double(uniform())) / (mu * speed);
            if (!(t < end)) break;
            if (!collide(ray(float(t)), mu)) return;
        }
        t = end;
    }
}

} // namespace detail

/// Delta-tracking estimate of the transmittance over t ∈ [0, tMax] of `ray`, per
/// wavelength 0 or 1.
template <typename Uniform>
SampledSpectrum deltaTrackingTransmittance(const IMedium& medium, const Ray& ray, float tMax,
                                           const SampledWavelengths& lambda, Uniform&& uniform) {
    SampledSpectrum alive(1.f);
    detail::walkTentativeCollisions(medium, ray, tMax, lambda, uniform, [&](const Point3f& p, double mu) {
        const SampledSpectrum sigmaT = medium.at(p, lambda).sigmaT();
        const double u = double(uniform());
        for (int i = 0; i < NSpectrumSamples; ++i)
            if (u < double(sigmaT[i]) / mu) alive[i] = 0.f;  // a real collision at wavelength i
        return !alive.isBlack();
    });
    return alive;
}

/// Ratio-tracking estimate (with Russian roulette) of the transmittance over
/// t ∈ [0, tMax] of `ray`, per wavelength in [0, 1].
template <typename Uniform>
SampledSpectrum ratioTrackingTransmittance(const IMedium& medium, const Ray& ray, float tMax,
                                           const SampledWavelengths& lambda, Uniform&& uniform) {
    constexpr float RouletteBelow = 0.125f;
    SampledSpectrum tr(1.f);
    detail::walkTentativeCollisions(medium, ray, tMax, lambda, uniform, [&](const Point3f& p, double mu) {
        const SampledSpectrum sigmaT = medium.at(p, lambda).sigmaT();
        for (int i = 0; i < NSpectrumSamples; ++i)
            tr[i] *= float(std::clamp(1.0 - double(sigmaT[i]) / mu, 0.0, 1.0));
        const float largest = tr.maxValue();
        if (!(largest > 0.f)) return false;
        if (largest < RouletteBelow) {
            const float keep = largest / RouletteBelow;
            if (!(uniform() < keep)) {
                tr = SampledSpectrum(0.f);
                return false;
            }
            tr = tr / keep;
        }
        return true;
    });
    return tr;
}

} // namespace effigi
