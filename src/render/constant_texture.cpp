#include "effigi/render/constant_texture.hpp"

namespace effigi {

ConstantTexture::ConstantTexture(Spectrum s) : m_spectrum(std::move(s)) {
    // The scalar reading is the mean over the visible range (1 nm steps).
    double sum = 0;
    int n = 0;
    for (float l = LambdaMin; l <= LambdaMax; l += 1.f, ++n) sum += m_spectrum(l);
    m_mean = float(sum / n);
    m_max = m_spectrum.maxValue();
    setIdentity("texture/constant", "");
}

} // namespace effigi
