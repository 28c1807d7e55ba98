#pragma once
// IBSDF — how light scatters at a surface point. Directions are in the local shading
// frame (n = +z); wo points toward the viewer / previous vertex, wi toward the light
// (pbrt-v4 conventions). Values are evaluated at the path's sampled wavelengths.
#include "effigi/core/component.hpp"
#include "effigi/render/interaction.hpp"
#include "effigi/spectral/wavelengths.hpp"

#include <cstdint>
#include <optional>

namespace effigi {

enum BSDFFlags : std::uint32_t {
    BSDFReflection = 1u << 0,
    BSDFTransmission = 1u << 1,
    BSDFDiffuse = 1u << 2,
    BSDFGlossy = 1u << 3,
    BSDFSpecular = 1u << 4,  ///< Dirac delta lobe: f() and pdf() are zero, only sample() reaches it
    /// Pass-through (Mitsuba's Null): light continues along -wo unchanged in direction, the
    /// surface is an index-matched interface (null, the transparent part of mask). Sampled
    /// as a delta transmission with wi = -wo; renderers do not count it as a bounce, and
    /// shadow rays cross it, weighted by evalNullTransmission().
    BSDFNull = 1u << 5,
};

/// Radiance: adjoint of importance. Matters for refraction (η² scaling) and shading normals.
enum class TransportMode { Radiance, Importance };

struct BSDFSample {
    SampledSpectrum f;  ///< BSDF value (for delta lobes: the delta's weight)
    Vector3f wi{0.f};   ///< sampled direction, local frame
    float pdf = 0.f;    ///< solid-angle density (delta lobes: discrete probability)
    std::uint32_t flags = 0;  ///< lobe that was sampled
    float eta = 1.f;    ///< relative IOR crossed (transmission)

    bool isSpecular() const { return flags & BSDFSpecular; }
    bool isTransmission() const { return flags & BSDFTransmission; }
};

class IBSDF : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IBSDF");
    static constexpr const char* Tag = "bsdf";

    /// Union of the lobes this BSDF may have (BSDFFlags).
    virtual std::uint32_t flags() const = 0;

    /// f(wo, wi); zero for delta lobes.
    virtual SampledSpectrum f(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                              const SampledWavelengths& lambda, TransportMode mode) const = 0;

    /// Sample wi given wo; uc picks a lobe, u the direction. May terminate the secondary
    /// wavelengths (dispersion), hence the mutable lambda.
    virtual std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float uc,
                                             const Point2f& u, SampledWavelengths& lambda,
                                             TransportMode mode) const = 0;

    /// Density of sample() producing wi (solid angle); zero for delta lobes.
    virtual float pdf(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                      const SampledWavelengths& lambda, TransportMode mode) const = 0;

    /// Hemispherical-directional reflectance seen from the normal (AOVs, denoisers).
    /// The default integrates f numerically with fixed stratified samples.
    virtual SampledSpectrum albedo(const SurfaceInteraction& si, const SampledWavelengths& lambda) const;

    /// Weight of the pass-through (BSDFNull) part for a ray crossing the surface straight
    /// along −si.wo: 1 for `null`, 1 − opacity for `mask`, the slab's transmittance at that
    /// angle for `thindielectric`, 0 (the default) for an opaque surface.
    virtual SampledSpectrum evalNullTransmission(const SurfaceInteraction& si,
                                                 const SampledWavelengths& lambda) const {
        (void)si;
        (void)lambda;
        return SampledSpectrum(0.f);
    }

    bool hasSpecular() const { return flags() & BSDFSpecular; }
    bool hasNull() const { return flags() & BSDFNull; }
    /// True if every lobe is a delta (no point in light sampling).
    bool isPureSpecular() const { return (flags() & (BSDFDiffuse | BSDFGlossy)) == 0; }
};

} // namespace effigi
