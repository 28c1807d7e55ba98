// phase "isotropic" — scattering equally into every direction.
//
// p(wo, wi) = 1/(4π) for every pair of directions: the phase function of a medium whose
// particles forget where the light came from, and the default of every medium (as in
// Mitsuba 3). Sampled exactly by a uniform direction on the sphere (Archimedes' hat-box
// theorem: z uniform in [−1, 1], φ uniform), whose pdf is the phase function itself.
//
// Parameters: none.
//
// Reference: S. Chandrasekhar, Radiative Transfer, Oxford 1950, §1.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iphasefunction.hpp"
#include "effigi/math/warp_functions.hpp"

namespace effigi {
namespace {

class IsotropicPhase final : public Implements<IPhaseFunction> {
public:
    static Schema schema() {
        Schema s("phase", "isotropic", "Isotropic scattering: p = 1/(4π) for every pair of directions.");
        s.cite("S. Chandrasekhar, Radiative Transfer, Oxford University Press, 1950");
        s.addConformance({"default", {}});
        return s;
    }
    explicit IsotropicPhase(const Properties&) {}

    SampledSpectrum eval(const Vector3f&, const Vector3f&, const SampledWavelengths&) const override {
        return SampledSpectrum(Inv4Pi);
    }
    std::optional<PhaseSample> sample(const Vector3f&, const Point2f& u, const SampledWavelengths&) const override {
        return PhaseSample{warp::squareToUniformSphere(u), Inv4Pi, SampledSpectrum(1.f)};
    }
    float pdf(const Vector3f&, const Vector3f&, const SampledWavelengths&) const override { return Inv4Pi; }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::IsotropicPhase)
