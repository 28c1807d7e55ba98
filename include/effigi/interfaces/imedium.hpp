#pragma once
// IMedium — a participating medium: what absorbs, scatters and emits light between
// surfaces. A volumetric path tracer asks it three things (after pbrt-v4's split of a
// medium into point queries and majorants along a ray, which serves homogeneous and
// heterogeneous media alike with null-collision estimators):
//  - at(p, λ): the coefficients at a point, σa and σs per unit distance (σt = σa + σs,
//    single-scattering albedo σs/σt ∈ [0, 1]) and the emitted radiance Le;
//  - majorant(ray, t0, t1, λ): a bound σ_maj ≥ σt on a piece of a ray, per wavelength,
//    from which distances are sampled (delta tracking) and transmittance estimated
//    (ratio tracking): include/effigi/render/transmittance.hpp;
//  - phase(): how a scattering event redistributes directions (IPhaseFunction).
// Coefficients are per unit of world distance. Ray parameters t are those of the ray as
// given: a direction d that is not unit length makes a parameter interval [t0, t1] the
// distance (t1 − t0)|d|. Where a medium is bounded (a shape's interior, stage 2), the
// scene decides which medium a ray segment is in; a medium answers for every point.
// effigi-conform's `medium` suite checks these promises.
#include "effigi/core/component.hpp"
#include "effigi/interfaces/iphasefunction.hpp"
#include "effigi/render/ray.hpp"

namespace effigi {

/// A medium's coefficients at one point, at the path's wavelengths.
struct MediumProperties {
    SampledSpectrum sigmaA{0.f};  ///< absorption coefficient [1/distance]
    SampledSpectrum sigmaS{0.f};  ///< scattering coefficient [1/distance]
    SampledSpectrum Le{0.f};      ///< emitted radiance (zero unless isEmissive())
    SampledSpectrum sigmaT() const { return sigmaA + sigmaS; }
};

/// σ_maj bounds σt at every point of the ray for t in [tMin, tMax], per wavelength.
struct MajorantSegment {
    float tMin = 0.f, tMax = 0.f;
    SampledSpectrum sigmaMaj{0.f};
};

class IMedium : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IMedium");
    static constexpr const char* Tag = "medium";

    /// The phase function of every scattering event in this medium.
    virtual const IPhaseFunction& phase() const = 0;
    /// Whether the coefficients are the same at every point (then at() may be asked once
    /// per segment, and transmittance has the closed form exp(−σt d)).
    virtual bool isHomogeneous() const = 0;
    /// Whether Le can be non-zero anywhere.
    virtual bool isEmissive() const { return false; }
    /// Whether a renderer should sample emitters (shadow rays) from inside the medium;
    /// Mitsuba 3's `sample_emitters` (false helps media sealed in a dielectric).
    virtual bool sampleEmitters() const { return true; }

    /// Coefficients at point p: σa, σs ≥ 0 and finite, Le ≥ 0.
    virtual MediumProperties at(const Point3f& p, const SampledWavelengths& lambda) const = 0;

    /// A majorant on the first piece [tMin, t] of the ray interval [tMin, tMax], with
    /// tMin < t ≤ tMax: σ_maj ≥ σt(ray(s)) at every wavelength for s in the piece. A
    /// caller covers [tMin, tMax] by asking again from t until it reaches tMax. tMax may be
    /// infinite. A homogeneous medium answers the whole interval with σ_maj = σt.
    virtual MajorantSegment majorant(const Ray& ray, float tMin, float tMax, const SampledWavelengths& lambda) const = 0;
};

} // namespace effigi
