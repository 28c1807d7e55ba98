// Spectral distributions (effigi/spectral/spectrum.hpp): construction, validation and
// evaluation of the four kinds.
#include "effigi/spectral/spectrum.hpp"

#include "effigi/core/error.hpp"
#include "effigi/spectral/cie.hpp"

#include <algorithm>

namespace effigi {
namespace {

// CODATA 2018 exact SI constants.
constexpr double PlanckH = 6.62607015e-34;    // J s
constexpr double LightC = 299792458.0;        // m / s
constexpr double BoltzmannK = 1.380649e-23;   // J / K
constexpr double WienB = 2.897771955e6;       // nm K (Wien's displacement constant)
constexpr double MaxTemperature = 1e9;        // K: keeps the peak normalisation in float range

/// Planck's law B_λ(T) = 2hc² / λ⁵ / (exp(hc / λkT) − 1), per metre of wavelength.
double planckPerMetre(double lambdaNm, double T) {
    double l = lambdaNm * 1e-9;
    double l5 = (l * l) * (l * l) * l;
    return 2.0 * PlanckH * LightC * LightC / (l5 * std::expm1(PlanckH * LightC / (l * BoltzmannK * T)));
}

/// The D65 SPD scaled to luminance Y = 1 (see cie::d65Normalization()).
float d65(float lambda) { return cie::lookup(cie::D65, lambda) * cie::d65Normalization(); }

} // namespace

float planck(float lambdaNm, float temperatureK) {
    if (!(temperatureK > 0.f) || !(lambdaNm > 0.f)) return 0.f;
    return float(planckPerMetre(lambdaNm, temperatureK) * 1e-9);  // per nm
}

Spectrum Spectrum::piecewiseLinear(std::vector<float> lambdas, std::vector<float> values) {
    if (lambdas.size() != values.size())
        fail("piecewise-linear spectrum: {} wavelengths but {} values", lambdas.size(), values.size());
    if (lambdas.empty()) fail("piecewise-linear spectrum: needs at least one (wavelength, value) pair");
    for (std::size_t i = 0; i < lambdas.size(); ++i) {
        if (!std::isfinite(lambdas[i]) || !std::isfinite(values[i]))
            fail("piecewise-linear spectrum: entry {} ({}, {}) is not finite", i, lambdas[i], values[i]);
        if (i > 0 && !(lambdas[i] > lambdas[i - 1]))
            fail("piecewise-linear spectrum: wavelengths must be strictly ascending ({} nm follows {} nm)",
                 lambdas[i], lambdas[i - 1]);
    }
    Spectrum s;
    s.m_type = Type::Piecewise;
    s.m_scale = 1.f;
    s.m_lambdas = std::make_shared<const std::vector<float>>(std::move(lambdas));
    s.m_values = std::make_shared<const std::vector<float>>(std::move(values));
    return s;
}

Spectrum Spectrum::fromRGB(const Vector3f& rgb, SpectrumKind kind) {
    if (!isFinite(rgb)) fail("RGB value ({}, {}, {}) is not finite", rgb.x, rgb.y, rgb.z);
    const RGBToSpectrumTable& table = RGBToSpectrumTable::sRGB();
    Spectrum s;
    s.m_type = Type::RGB;
    if (kind == SpectrumKind::Reflectance) {
        s.m_scale = 1.f;
        s.setPoly(table(glm::clamp(rgb, Vector3f(0.f), Vector3f(1.f))));
        return s;
    }
    // Unbounded and illuminant values: the table fits colours in [0, 1], so scale the
    // triple to have its largest component at ½ (a mid-brightness reflectance whose fit
    // is smooth) and carry the factor separately.
    Vector3f c = glm::max(rgb, Vector3f(0.f));
    float m = maxComponent(c);
    if (m <= 0.f) return Spectrum(0.f);
    float scale = 2.f * m;
    s.m_scale = scale;
    s.setPoly(table(c / scale));
    s.m_illuminant = kind == SpectrumKind::Illuminant;
    s.m_d65Scale = cie::d65Normalization();
    return s;
}

Spectrum Spectrum::blackbody(float temperatureK) {
    if (!(temperatureK > 0.f) || !(temperatureK <= float(MaxTemperature)))
        fail("blackbody temperature {} K is outside (0, {:g}] K", temperatureK, MaxTemperature);
    Spectrum s;
    s.m_type = Type::Blackbody;
    s.m_scale = 1.f;
    s.m_temperature = temperatureK;
    // Wien's displacement law puts the maximum of B_λ at λ = b / T.
    s.m_bbNorm = float(1e9 / planckPerMetre(WienB / temperatureK, temperatureK));
    return s;
}

void Spectrum::setPoly(const RGBSigmoidPolynomial& p) {
    // c0 λ² + c1 λ + c2 with λ = t + λc: c0 t² + (2 c0 λc + c1) t + (c0 λc² + c1 λc + c2),
    // in double; infinite coefficients (exact black or white) stay infinite.
    m_poly = p;
    const double c = PolyCentre;
    m_a0 = p.c0;
    m_a1 = std::isinf(p.c2) ? 0.f : float(2.0 * p.c0 * c + p.c1);
    m_a2 = float(p.polynomial(c));
}

float Spectrum::operator()(float lambda) const {
    switch (m_type) {
    case Type::Constant: return m_scale;
    case Type::Piecewise: {
        const std::vector<float>& l = *m_lambdas;
        const std::vector<float>& v = *m_values;
        if (!(lambda > l.front())) return m_scale * v.front();
        if (lambda >= l.back()) return m_scale * v.back();
        std::size_t i = std::size_t(std::upper_bound(l.begin(), l.end(), lambda) - l.begin());  // l[i-1] <= λ < l[i]
        float t = (lambda - l[i - 1]) / (l[i] - l[i - 1]);
        return m_scale * lerp(t, v[i - 1], v[i]);
    }
    case Type::RGB: {
        float v = m_scale * m_poly(lambda);
        return m_illuminant ? v * d65(lambda) : v;
    }
    case Type::Blackbody: return m_scale * planck(lambda, m_temperature) * m_bbNorm;
    }
    return 0.f;
}

float Spectrum::maxValue() const {
    switch (m_type) {
    case Type::Constant: return m_scale;
    case Type::Piecewise: {
        auto [lo, hi] = std::minmax_element(m_values->begin(), m_values->end());
        return std::max(m_scale * *lo, m_scale * *hi);
    }
    case Type::RGB: {
        float v = m_scale * m_poly.maxValue();
        if (m_illuminant) {
            // A bound, not the exact maximum: max(s · D65) <= max s · max D65.
            static const float d65Max = *std::max_element(cie::D65, cie::D65 + cie::TableSize);
            v *= d65Max * cie::d65Normalization();
        }
        return v;
    }
    case Type::Blackbody: {
        // B_λ is unimodal: the visible maximum is the peak if it is visible, else the
        // nearer end of the range.
        float peak = std::clamp(float(WienB) / m_temperature, LambdaMin, LambdaMax);
        return m_scale * planck(peak, m_temperature) * m_bbNorm;
    }
    }
    return 0.f;
}

} // namespace effigi
