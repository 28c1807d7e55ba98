#pragma once
// ITexture — a spatially varying spectral (or scalar) parameter. Constant colours
// written in XML (<rgb>, <spectrum>, <float>) are textures too, so a BSDF reads every
// parameter the same way.
#include "effigi/core/component.hpp"
#include "effigi/render/interaction.hpp"
#include "effigi/spectral/wavelengths.hpp"

namespace effigi {

class ITexture : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("ITexture");
    static constexpr const char* Tag = "texture";

    virtual SampledSpectrum eval(const SurfaceInteraction& si, const SampledWavelengths& lambda) const = 0;
    /// A scalar reading (roughness, masks): the mean over the visible range for spectra.
    virtual float evalFloat(const SurfaceInteraction& si) const = 0;
    /// Upper bound of eval over all points and wavelengths.
    virtual float maxValue() const = 0;
    /// Average of evalFloat over the texture's domain (lobe-selection weights, as
    /// Mitsuba's Texture::mean). Default: the upper bound.
    virtual float mean() const { return maxValue(); }
    /// Raw three-channel value (normal maps read RGB as a vector, not a colour).
    /// Default: the scalar reading in all three channels.
    virtual Vector3f evalVector(const SurfaceInteraction& si) const { return Vector3f(evalFloat(si)); }
    /// Gradient of evalFloat with respect to (u, v) (bump mapping). Default: zero, right
    /// for textures that are piecewise constant.
    virtual Vector2f evalFloatGradient(const SurfaceInteraction& si) const {
        (void)si;
        return Vector2f(0.f);
    }
    /// True when eval does not depend on the surface point.
    virtual bool isConstant() const { return false; }
};

} // namespace effigi
