// Emitter brightness by factor, luminance or radiant flux (effigi/spectral/emission_scale.hpp).
#include "effigi/spectral/emission_scale.hpp"

#include "effigi/spectral/cie.hpp"

#include <algorithm>
#include <cmath>

namespace effigi {

namespace {

/// The one check behind checkEmittedPeak and EmissionScale::factor.
void checkPeak(const std::string& owner, const std::string& valueParam, const SourceLocation& valueWhere,
               double peak, const std::string& factorParam, const SourceLocation& factorWhere, double factor) {
    constexpr const char* why = "one sample times a path's throughput would overflow float";
    if (!std::isfinite(peak) || peak > MaxEmittedValue)
        failAt(valueWhere, "{}: '{}' peaks at {:g}, beyond the {:g} an emitter may emit ({})", owner, valueParam,
               peak, MaxEmittedValue, why);
    const double emitted = peak * factor;
    if (!std::isfinite(emitted) || emitted > MaxEmittedValue)
        failAt(factorWhere, "{}: with '{}' the emitted '{}' peaks at {:g}, beyond the {:g} an emitter may emit ({})",
               owner, factorParam, valueParam, emitted, MaxEmittedValue, why);
}

/// Largest value of S on the 1 nm grid of [360, 830] nm (NaN wins: it must be refused).
double peakOf(const std::function<float(float)>& S) {
    double peak = 0.0;
    for (int i = 0; i < cie::TableSize; ++i) {
        const double v = double(S(float(cie::TableStart + i)));
        if (std::isnan(v)) return v;
        peak = std::max(peak, v);
    }
    return peak;
}

} // namespace

void checkEmittedPeak(const Properties& p, const std::string& valueParam, double peak, double factor,
                      const std::string& factorParam) {
    checkPeak(p.describe(), valueParam, p.whereOf(valueParam), peak, factorParam, p.whereOf(factorParam), factor);
}

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

EmissionScale::EmissionScale(const Properties& p, bool powerSupported, const std::string& valueParam)
    : m_scale(p.getFloat("scale")), m_owner(p.describe()), m_value(valueParam), m_valueWhere(p.whereOf(valueParam)),
      m_scaleWhere(p.whereOf("scale")) {
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

float EmissionScale::factor(const std::function<float(float)>& S, float geometry, double peak) const {
    if (peak < 0.0) peak = peakOf(S);
    if (m_mode == Mode::Factor) {
        checkPeak(m_owner, m_value, m_valueWhere, peak, "scale", m_scaleWhere, m_scale);
        return m_scale;
    }
    double current = m_mode == Mode::Luminance ? double(cie::luminance(S)) : double(geometry) * radiometricIntegral(S);
    if (!(current > 0.0) || !std::isfinite(current))
        failAt(m_where, "{}: cannot scale to {} {}: the emitter's {} is {}", m_owner, m_param, m_target,
               m_mode == Mode::Luminance ? "luminance" : "power", current);
    double k = double(m_scale) * double(m_target) / current;
    if (!std::isfinite(k) || k > 3e38)
        failAt(m_where, "{}: {} {} needs a factor {} beyond the float range", m_owner, m_param, m_target, k);
    checkPeak(m_owner, m_value, m_valueWhere, peak, m_param, m_where, k);
    return float(k);
}

} // namespace effigi
