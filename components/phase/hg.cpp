// phase "hg" — the Henyey–Greenstein phase function.
//
// A one-parameter family from backward (g < 0) through isotropic (g = 0) to forward
// (g > 0) scattering, g being the mean cosine of the scattering angle θ (the angle
// between the light's course before and after, cos θ = −wo·wi):
//   p(wo, wi) = (1 − g²) / (4π (1 + g² + 2g wo·wi)^{3/2}).
//
// Sampling inverts the CDF of cos θ exactly. The textbook inverse
//   cos θ = (1 + g² − s²)/(2g),  s = (1 − g²)/(1 − g + 2gξ),
// divides by g (a special case at g = 0) and, for |g| → 1, cancels away the digits that
// matter: the lobe's width 1 − cos θ ~ (1 − g)² is below float resolution of the
// numerator. Factoring s² − (1 ∓ g)² instead gives both distances from the poles as
// products of positive terms, without division by g or cancellation:
//   1 − cos θ = (1 − g)(1 − ξ)(1 − g + s)/d,   1 + cos θ = (1 + g) ξ (1 + g + s)/d,
//   d = 1 − g + 2gξ  (> 0 for |g| < 1),
// (they add up to 2; at g = 0 they are 2(1 − ξ) and 2ξ, the uniform sphere). The
// evaluation writes the denominator the same way, (1 − g)² + 2g(1 + wo·wi) for g ≥ 0 and
// (1 + g)² + 2|g|(1 − wo·wi) for g < 0, with 1 ± wo·wi taken from the vectors
// (phase_common.hpp), so a lobe a hundredth of a degree wide is evaluated to ~1e-7.
//
// Parameters:
//   g  float (default 0.8, as Mitsuba 3)  mean cosine, strictly inside (−1, 1)
//
// Reference: L. G. Henyey & J. L. Greenstein, "Diffuse radiation in the Galaxy",
// Astrophysical Journal 93, 70–83, 1941.
#include "phase_common.hpp"

#include "effigi/core/registry.hpp"

namespace effigi {
namespace {

class HenyeyGreenstein final : public Implements<IPhaseFunction> {
public:
    static Schema schema() {
        Schema s("phase", "hg",
                 "Henyey–Greenstein phase function: backward (g < 0), isotropic (g = 0) or forward (g > 0) scattering.");
        s.cite("L. G. Henyey & J. L. Greenstein, Diffuse radiation in the Galaxy, Astrophysical Journal 93, 1941");
        // A schema range is a closed interval; the open (−1, 1) is checked by the
        // constructor, at the parameter's line (±1 is a Dirac delta, not a density).
        s.real("g", 0.8, "Mean cosine of the scattering angle, strictly inside (−1, 1)");
        s.addConformance({"default", {}});
        s.addConformance({"isotropic", {{"g", 0.0}}});
        s.addConformance({"moderate", {{"g", 0.5}}});
        s.addConformance({"forward", {{"g", 0.99}}});
        s.addConformance({"backward", {{"g", -0.99}}});
        return s;
    }
    explicit HenyeyGreenstein(const Properties& p) : m_g(double(p.getFloat("g"))) {
        if (!(std::abs(m_g) < 1.0))
            failAt(p.whereOf("g"), "{}: parameter 'g' = {} must lie strictly inside (−1, 1) (±1 is a delta, not a density)",
                   p.describe(), m_g);
    }

    SampledSpectrum eval(const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&) const override {
        return SampledSpectrum(float(density(phase::angleTerms(wo, wi))));
    }

    std::optional<PhaseSample> sample(const Vector3f& wo, const Point2f& u, const SampledWavelengths&) const override {
        const double g = m_g, xi = double(u.x);
        const double d = 1.0 - g + 2.0 * g * xi;
        const double s = (1.0 - g) * (1.0 + g) / d;
        const double oneMinus = (1.0 - g) * (1.0 - xi) * (1.0 - g + s) / d;
        const double onePlus = (1.0 + g) * xi * (1.0 + g + s) / d;
        const Vector3f wi = phase::aroundForward(wo, oneMinus, onePlus, u.y);
        return phase::exactSample(wo, wi, [this](const phase::AngleTerms& a) { return density(a); });
    }

    float pdf(const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&) const override {
        return float(density(phase::angleTerms(wo, wi)));
    }

private:
    /// p for the angle between wo and wi; the denominator 1 + g² + 2g wo·wi is written
    /// about the pole where the lobe peaks, so that it does not cancel there.
    double density(const phase::AngleTerms& a) const {
        const double g = m_g;
        const double den = g >= 0.0 ? (1.0 - g) * (1.0 - g) + 2.0 * g * a.onePlusCos
                                    : (1.0 + g) * (1.0 + g) - 2.0 * g * a.oneMinusCos;
        return (1.0 - g) * (1.0 + g) / (4.0 * std::numbers::pi * den * std::sqrt(den));
    }

    double m_g;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::HenyeyGreenstein)
