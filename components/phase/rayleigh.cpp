// phase "rayleigh" — scattering by particles much smaller than the wavelength.
//
// Molecules of the air scatter unpolarised light with
//   p(wo, wi) = 3/(16π) (1 + cos²θ),   cos θ = −wo·wi,
// symmetric between forward and backward. The strong λ⁻⁴ dependence of Rayleigh
// scattering lives in the medium's σs, not here: the angular shape is the same at every
// wavelength. Polarisation is ignored (as in Mitsuba 3's `rayleigh`).
//
// Sampling inverts the CDF of μ = cos θ exactly: (3/8)(μ + μ³/3 + 4/3) = ξ is the
// depressed cubic μ³ + 3μ − 2z = 0 with z = 2(2ξ − 1), whose one real root is, by the
// hyperbolic form of Cardano's solution (sinh 3t = 3 sinh t + 4 sinh³ t),
//   μ = 2 sinh(asinh(z)/3),
// free of the cancellation between two cube roots of nearly equal size that the
// radical form suffers near μ = 0, and exact at ξ = 0, ½, 1 (μ = −1, 0, 1).
//
// Parameters: none.
//
// Reference: Lord Rayleigh, "On the light from the sky, its polarization and colour",
// Philosophical Magazine 41, 1871; S. Chandrasekhar, Radiative Transfer, 1950, §17.
#include "phase_common.hpp"

#include "effigi/core/registry.hpp"

namespace effigi {
namespace {

class RayleighPhase final : public Implements<IPhaseFunction> {
public:
    static Schema schema() {
        Schema s("phase", "rayleigh", "Rayleigh scattering by small particles, unpolarised: p = 3(1 + cos²θ)/(16π).");
        s.cite("Lord Rayleigh, On the light from the sky, its polarization and colour, Phil. Mag. 41, 1871");
        s.addConformance({"default", {}});
        return s;
    }
    explicit RayleighPhase(const Properties&) {}

    SampledSpectrum eval(const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&) const override {
        return SampledSpectrum(float(density(phase::angleTerms(wo, wi))));
    }

    std::optional<PhaseSample> sample(const Vector3f& wo, const Point2f& u, const SampledWavelengths&) const override {
        const double z = 2.0 * (2.0 * double(u.x) - 1.0);
        const double mu = std::clamp(2.0 * std::sinh(std::asinh(z) / 3.0), -1.0, 1.0);
        const Vector3f wi = phase::aroundForward(wo, 1.0 - mu, 1.0 + mu, u.y);
        return phase::exactSample(wo, wi, [](const phase::AngleTerms& a) { return density(a); });
    }

    float pdf(const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&) const override {
        return float(density(phase::angleTerms(wo, wi)));
    }

private:
    static double density(const phase::AngleTerms& a) {
        const double c = a.cosine();
        return 3.0 / (16.0 * std::numbers::pi) * (1.0 + c * c);
    }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::RayleighPhase)
