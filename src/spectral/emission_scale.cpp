// Emitter brightness by factor, luminance or radiant flux (effigi/spectral/emission_scale.hpp).
#include "effigi/spectral/emission_scale.hpp"

#include "effigi/spectral/cie.hpp"

#include <cmath>

namespace effigi {

double radiometricIntegral(const std::function<float(float)>& S) {
    double sum = 0.0;
    for (int i = 0; i < cie::TableSize; ++i) {
        double w = (i == 0 || i == cie::TableSize - 1) ? 0.5 : 1.0;
        sum += w * double(S(float(cie::TableStart + i)));
    }
    return sum;  // × 1 nm
}

void EmissionScale::declare(Schema& s, const std::string& luminanceDoc, const std::string& unit,
                            const std::string& powerDoc) {
    s.real("scale", 1.0, "Factor on the emitted spectrum (applied after luminance or power, if given)").atLeast(0.0);
    s.optional("luminance", ParamType::Float, luminanceDoc + " (Y = ∫S ȳ / ∫ȳ; excludes power)")
        .atLeast(0.0)
        .withUnit(unit);
    if (powerDoc.empty())
        s.optional("power", ParamType::Float, "Not available for this emitter (its power is not finite): an error");
    else
        s.optional("power", ParamType::Float, powerDoc + " (radiant flux over 360-830 nm; excludes luminance)")
            .atLeast(0.0)
            .withUnit("W");
}

EmissionScale::EmissionScale(const Properties& p, bool powerSupported)
    : m_scale(p.getFloat("scale")), m_owner(p.describe()) {
    bool lum = p.has("luminance"), pow = p.has("power");
    if (pow && !powerSupported)
        failAt(p.whereOf("power"), "{}: 'power' is not supported (the emitted power is not finite); give 'luminance' "
               "or 'scale' instead", m_owner);
    if (lum && pow)
        failAt(p.whereOf("power"), "{}: give either 'luminance' or 'power', not both", m_owner);
    if (lum || pow) {
        m_mode = lum ? Mode::Luminance : Mode::Power;
        m_param = lum ? "luminance" : "power";
        m_target = p.getFloat(m_param);
        m_where = p.whereOf(m_param);
        if (!std::isfinite(m_target) || m_target < 0.f)
            failAt(m_where, "{}: '{}' = {} must be finite and not negative", m_owner, m_param, m_target);
    }
    if (!std::isfinite(m_scale) || m_scale < 0.f)
        failAt(p.whereOf("scale"), "{}: 'scale' = {} must be finite and not negative", m_owner, m_scale);
}

float EmissionScale::factor(const std::function<float(float)>& S, float geometry) const {
    if (m_mode == Mode::Factor) return m_scale;
    double current = m_mode == Mode::Luminance ? double(cie::luminance(S)) : double(geometry) * radiometricIntegral(S);
    if (!(current > 0.0) || !std::isfinite(current))
        failAt(m_where, "{}: cannot scale to {} {}: the emitter's {} is {}", m_owner, m_param, m_target,
               m_mode == Mode::Luminance ? "luminance" : "power", current);
    double k = double(m_scale) * double(m_target) / current;
    if (!std::isfinite(k) || k > 3e38)
        failAt(m_where, "{}: {} {} needs a factor {} beyond the float range", m_owner, m_param, m_target, k);
    return float(k);
}

} // namespace effigi
