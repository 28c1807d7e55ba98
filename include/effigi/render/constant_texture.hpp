#pragma once
// The texture a constant <float>, <rgb> or <spectrum> parameter becomes.
#include "effigi/core/component.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/spectral/spectrum.hpp"

namespace effigi {

class ConstantTexture final : public Implements<ITexture> {
public:
    explicit ConstantTexture(Spectrum s);

    SampledSpectrum eval(const SurfaceInteraction&, const SampledWavelengths& lambda) const override {
        return m_spectrum.sample(lambda);
    }
    float evalFloat(const SurfaceInteraction&) const override { return m_mean; }
    float maxValue() const override { return m_max; }
    float mean() const override { return m_mean; }
    bool isConstant() const override { return true; }
    const Spectrum& spectrum() const { return m_spectrum; }

private:
    Spectrum m_spectrum;
    float m_mean, m_max;
};

} // namespace effigi
