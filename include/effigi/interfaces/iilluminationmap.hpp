#pragma once
// IIlluminationMap — light cached over the scene's surfaces by a preprocessing pass and
// looked up at a surface point instead of being traced further: a radiosity solution, a
// photon map, an irradiance cache. A gather pass (renderer `twopass`, final gathering)
// traces the paths the map does not hold (specular bounces) and asks the map where they
// end on a surface it covers.
//
// Units: spectral radiance W m⁻² sr⁻¹ nm⁻¹ and spectral irradiance W m⁻² nm⁻¹, at the
// path's sampled wavelengths, like every radiometric value in effigi.
#include "effigi/core/component.hpp"
#include "effigi/render/interaction.hpp"
#include "effigi/spectral/wavelengths.hpp"

namespace effigi {

class IIlluminationMap : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IIlluminationMap");
    static constexpr const char* Tag = "illuminationmap";

    /// Whether the map holds the light leaving this surface point toward si.wo. Points it
    /// does not cover (specular surfaces, back faces, shapes it was not built on) give
    /// zero below; the caller traces them instead.
    virtual bool covers(const SurfaceInteraction& si) const = 0;

    /// Radiance leaving si.p toward si.wo, emission included; zero where not covered.
    virtual SampledSpectrum radiance(const SurfaceInteraction& si, const SampledWavelengths& lambda) const = 0;

    /// Irradiance arriving at si.p from the side of the geometric normal si.n (emission
    /// excluded); zero where the map knows none.
    virtual SampledSpectrum irradiance(const SurfaceInteraction& si, const SampledWavelengths& lambda) const = 0;
};

} // namespace effigi
