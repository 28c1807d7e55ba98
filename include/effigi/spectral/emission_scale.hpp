#pragma once
// How bright an emitter is, stated the way a lighting designer would: a plain factor
// (`scale`), a target luminance (`luminance`) or a radiant flux (`power`). One helper
// shared by the emitters so that the three use the same definitions:
//
//   luminance  Y(S) = ∫ S ȳ dλ / ∫ ȳ dλ          (CIE 1931 ȳ, 360–830 nm; the film's Y)
//   power      Φ   = G · ∫ S dλ over 360–830 nm  (G from the emitter's geometry: π·A for a
//                                                 Lambertian surface of area A, 4π for an
//                                                 isotropic point)
//
// The emitted spectrum is S' = scale · k · S, with k = target / Y(S) or target / (G ∫S dλ)
// (k = 1 without a target). `luminance` and `power` exclude each other; `scale` multiplies
// the result in either case (as pbrt-v4's `scale` does with its `power`).
#include "effigi/core/schema.hpp"

#include <functional>
#include <string>

namespace effigi {

/// The brightest value an emitter may emit (radiance, intensity or irradiance, after
/// every factor). A sample carries it times a path throughput, whose 1/pdf factors (a
/// small or grazing light, a sharp lobe) reach 1e6-1e8; beyond 1e30 such a product comes
/// within reach of float's 3.4e38 and a pixel of Inf or NaN. Real light sources are
/// some 1e9 W m^-2 sr^-1 (the sun's disk) at most.
inline constexpr double MaxEmittedValue = 1e30;

/// The load check of every emitter: `peak` is the largest value of the parameter
/// `valueParam` (its spectrum's or texture's maximum, unscaled) and `factor` what
/// multiplies it, given by `factorParam`. A peak or product that is not finite or exceeds
/// MaxEmittedValue is an error at that parameter's file:line.
void checkEmittedPeak(const Properties& p, const std::string& valueParam, double peak, double factor,
                      const std::string& factorParam = "scale");

/// ∫ S(λ) dλ over [360, 830] nm, trapezoid rule on the 1 nm grid (exact for spectra
/// piecewise linear between whole nanometres).
double radiometricIntegral(const std::function<float(float)>& S);

class EmissionScale {
public:
    enum class Mode { Factor, Luminance, Power };

    /// Declares `scale`, `luminance` and `power` in an emitter's schema. `luminanceDoc`
    /// says what the luminance is of, `unit` is the emitted quantity's unit; `powerDoc`
    /// empty declares `power` as unsupported (giving it is an error) for emitters
    /// without a finite power.
    static void declare(Schema& s, const std::string& luminanceDoc, const std::string& unit,
                        const std::string& powerDoc);

    /// Reads the parameters declare() added; `valueParam` names the emitted spectrum's
    /// parameter ("radiance", "intensity", ...). Errors (luminance and power together;
    /// power where it is unsupported) name the parameter's file:line.
    EmissionScale(const Properties& p, bool powerSupported, const std::string& valueParam);

    Mode mode() const { return m_mode; }

    /// The factor scale · k for the spectrum S. `geometry` is G above (only read for
    /// Mode::Power). A target for a black spectrum is an error at the parameter's place,
    /// and so is a factor that makes the emission's peak exceed MaxEmittedValue
    /// (checkEmittedPeak); `peak` is S's maximum (< 0: found on S's 1 nm grid).
    float factor(const std::function<float(float)>& S, float geometry = 0.f, double peak = -1.0) const;

private:
    Mode m_mode = Mode::Factor;
    float m_scale = 1.f, m_target = 0.f;
    std::string m_param;     // "luminance" or "power"
    SourceLocation m_where;  // where the target was given
    std::string m_owner;     // "emitter 'area'", for messages
    std::string m_value;     // the emitted spectrum's parameter, and where it and scale are
    SourceLocation m_valueWhere, m_scaleWhere;
};

} // namespace effigi
