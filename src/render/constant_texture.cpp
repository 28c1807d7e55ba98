#include "effigi/render/constant_texture.hpp"

namespace effigi {

ConstantTexture::ConstantTexture(Spectrum s) : m_spectrum(std::move(s)) {
    // The scalar reading is the mean over the visible range: the trapezoid rule on the
    // 1 nm grid (the end points weigh ½; a plain average of the 471 samples would count
    // them fully, 0.1 % off for spectra that are high at 360 or 830 nm).
    double sum = 0;
    int n = 0;
    for (float l = LambdaMin; l <= LambdaMax; l += 1.f, ++n) sum += (l == LambdaMin || l == LambdaMax ? 0.5 : 1.0) * m_spectrum(l);
    m_mean = float(sum / (n - 1));
    m_max = m_spectrum.maxValue();
    setIdentity("texture/constant", "");
}

} // namespace effigi
