#pragma once
// IPhaseFunction — the angular distribution of light scattered inside a participating
// medium: p(wo, wi) per unit solid angle, normalised over the sphere (∫ p dωi = 1 for
// every wo), so a medium's albedo alone says how much light a scattering event keeps.
//
// Directions (pbrt-v4's and Mitsuba 3's convention): wo and wi are unit vectors in one
// frame, both pointing AWAY from the scattering point: wo towards where the light goes
// (the camera side of a path), wi towards where it comes from (the light side). Light
// that keeps its course has wi = −wo, so "forward scattering" peaks at wi = −wo. The
// phase functions shipped so far depend on wo·wi alone, so world space is as good a
// frame as any; a spatially varying or oriented phase function (SGGX, stage 2 and later)
// would add a point or a frame to these calls.
//
// Values are spectral (one per hero wavelength) while the density is one number: a path
// samples one direction for its four wavelengths, and a wavelength-dependent phase
// function (tabulated Mie, a spectral g) then weights each wavelength by p_λ / pdf. The
// phase functions here are wavelength independent and fill the four slots with one value;
// the cost is three copies of a float, and the interface needs no change when a spectral
// one arrives. effigi-conform's `phase` suite checks the promises below.
#include "effigi/core/component.hpp"
#include "effigi/math/vector.hpp"
#include "effigi/spectral/wavelengths.hpp"

#include <optional>

namespace effigi {

struct PhaseSample {
    Vector3f wi{0.f};         ///< sampled direction (unit, away from the scattering point)
    float pdf = 0.f;          ///< its density per unit solid angle, = pdf(wo, wi)
    SampledSpectrum weight;   ///< p(wo, wi) / pdf per wavelength (1 for exact sampling)
};

class IPhaseFunction : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IPhaseFunction");
    static constexpr const char* Tag = "phase";

    /// p(wo, wi) [sr⁻¹] at the path's wavelengths: ≥ 0, finite, reciprocal
    /// (p(wo, wi) = p(wi, wo)) and ∫ p(wo, ωi) dωi = 1 at every wavelength.
    virtual SampledSpectrum eval(const Vector3f& wo, const Vector3f& wi, const SampledWavelengths& lambda) const = 0;

    /// Draw wi for wo from u ∈ [0,1)²; its pdf is pdf(wo, wi) and its weight eval/pdf.
    /// Empty only where no direction can be drawn (never, for a normalised phase function).
    virtual std::optional<PhaseSample> sample(const Vector3f& wo, const Point2f& u,
                                              const SampledWavelengths& lambda) const = 0;

    /// Density of sample() producing wi given wo, per unit solid angle.
    virtual float pdf(const Vector3f& wo, const Vector3f& wi, const SampledWavelengths& lambda) const = 0;
};

} // namespace effigi
