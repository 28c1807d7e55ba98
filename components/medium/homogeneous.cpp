// medium "homogeneous" — the same absorbing and scattering medium at every point.
//
// Parametrised as Mitsuba 3's `homogeneous`: the extinction σt (per unit of scene
// distance, times `scale` for data in other units) and the single-scattering albedo α,
// so σs = α σt and σa = (1 − α) σt. Both are spectra and may vary with wavelength (σt
// rising towards blue, say); the medium's transmittance over a distance d is exp(−σt d)
// at each wavelength, and its majorant along any ray is σt itself, so delta tracking
// never meets a null collision.
//
// `emission` (effigi's own; Mitsuba 3's homogeneous medium does not emit) makes a glowing
// gas: the medium emits where it absorbs, the source term being σa·Le with Le the
// emission radiance (pbrt-v4's convention), so an optically thick emitting medium shows
// Le itself and a chord of length d through a purely absorbing one Le·(1 − exp(−σa d)).
// Emitted light is found by the renderer's free-flight sampling, not by light sampling.
//
// A spatially varying σt is the `heterogeneous` medium's.
//
// Parameters:
//   sigma_t          spectrum (default 1, ≥ 0)        extinction coefficient [1/distance]
//   albedo           spectrum or volume (default 0.75, [0, 1])  single-scattering albedo
//                    σs/σt; a volume (gridvolume, …) varies it in space, as Mitsuba
//                    allows, while σt stays constant (the medium stays homogeneous for
//                    transmittance)
//   scale            float (default 1, ≥ 0)           multiplies sigma_t (unit conversion)
//   sample_emitters  bool (default true)              renderers cast shadow rays from inside
//   phase            nested phase (default isotropic)
//   emission         spectrum (default 0)             emitted radiance Le, source σa·Le
//   has_spectral_extinction  accepted as in Mitsuba, ignored (σt is always per wavelength)
//
// Reference: pbrt-v4 §11.1 (volume scattering processes), Mitsuba 3's `homogeneous`.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/imedium.hpp"
#include "effigi/interfaces/ivolume.hpp"

#include <algorithm>

namespace effigi {
namespace {

/// How an RGB σt becomes a spectrum. Mitsuba 3 takes RGB coefficients in [0, 1] only and
/// upsamples them as reflectances (then multiplies by `scale`); effigi does the same for
/// such triples, so both renderers see the same spectrum, and fits larger ones as unbounded
/// spectra (a smooth curve scaled to the largest component) instead of refusing them.
SpectrumKind extinctionKind(const Properties& p) {
    const Properties::Entry* e = p.find("sigma_t");
    if (e && std::holds_alternative<RGBValue>(e->value) && maxComponent(std::get<RGBValue>(e->value).v) <= 1.f)
        return SpectrumKind::Reflectance;
    return SpectrumKind::Unbounded;
}

class HomogeneousMedium final : public Implements<IMedium> {
public:
    static Schema schema() {
        Schema s("medium", "homogeneous",
                 "Homogeneous participating medium: constant extinction σt and single-scattering albedo.");
        s.cite("M. Pharr, W. Jakob & G. Humphreys, Physically Based Rendering (4th ed.), §11.1, 2023");
        s.spectrum("sigma_t", 1.f, SpectrumKind::Unbounded, "Extinction coefficient σt = σa + σs per unit distance")
            .atLeast(0.0);
        s.volume("albedo", 0.75f, SpectrumKind::Reflectance, "Single-scattering albedo σs/σt (a volume varies it in space)")
            .range(0.0, 1.0);
        s.real("scale", 1.0, "Factor on sigma_t, for coefficients given in other units than the scene's").atLeast(0.0);
        s.boolean("sample_emitters", true, "Whether renderers sample emitters (shadow rays) from inside the medium");
        s.child("phase", "phase", "Phase function of the scattering events (default: isotropic)");
        s.spectrum("emission", 0.f, SpectrumKind::Illuminant,
                   "Emitted radiance Le where the medium absorbs (source term σa·Le; effigi's own)")
            .atLeast(0.0);
        s.ignored("has_spectral_extinction", "σt is evaluated at every sampled wavelength");
        s.addConformance({"default", {}});
        s.addConformance({"dense", {{"sigma_t", 40.0}, {"albedo", 0.99}}});
        // σt falling from blue to red (a λ⁻⁴-like haze), with a coloured albedo.
        s.addConformance({"chromatic",
                          {{"sigma_t", SpectrumValue{{360.f, 450.f, 550.f, 650.f, 830.f}, {4.f, 2.4f, 1.1f, 0.55f, 0.2f}, 0.f, 1.f, {}}},
                           {"albedo", RGBValue{{0.9f, 0.6f, 0.2f}}}}});
        s.addConformance({"rgb", {{"sigma_t", RGBValue{{0.2f, 0.5f, 0.9f}}}}});
        s.addConformance({"scaled", {{"sigma_t", 0.002}, {"scale", 1000.0}}});
        s.addConformance({"white", {{"albedo", 1.0}}});
        s.addConformance({"black", {{"albedo", 0.0}}});
        s.addConformance({"vacuum", {{"sigma_t", 0.0}}});
        s.addConformance({"emissive", {{"albedo", 0.5}, {"emission", RGBValue{{4.f, 2.f, 0.5f}}}}});
        return s;
    }

    explicit HomogeneousMedium(const Properties& p)
        : m_sigmaT(p.getSpectrum("sigma_t", extinctionKind(p)).scaled(p.getFloat("scale"))),
          m_albedoVolume(albedoVolume(p)),
          m_albedo(m_albedoVolume ? Spectrum(0.f) : p.getSpectrum("albedo", SpectrumKind::Reflectance)),
          m_emission(p.getSpectrum("emission", SpectrumKind::Illuminant)), m_phase(p.get<IPhaseFunction>("phase")),
          m_sampleEmitters(p.getBool("sample_emitters")) {
        // The range check sees plain numbers only; spectra and RGB are checked here, on a
        // 1 nm grid over the visible range (the spectra are piecewise linear or smooth).
        for (float lambda = LambdaMin; lambda <= LambdaMax; lambda += 1.f) {
            const float t = m_sigmaT(lambda), a = m_albedo(lambda);
            if (!(t >= 0.f) || !std::isfinite(t))
                failAt(p.whereOf("sigma_t"), "{}: parameter 'sigma_t' (times scale) is {} at {} nm; it must be finite and >= 0",
                       p.describe(), t, lambda);
            if (!(a >= 0.f && a <= 1.f))
                failAt(p.whereOf("albedo"), "{}: parameter 'albedo' is {} at {} nm; it must lie in [0, 1]", p.describe(), a,
                       lambda);
            const float e = m_emission(lambda);
            if (!(e >= 0.f) || !std::isfinite(e))
                failAt(p.whereOf("emission"), "{}: parameter 'emission' is {} at {} nm; it must be finite and >= 0",
                       p.describe(), e, lambda);
            m_emissive = m_emissive || e > 0.f;
        }
        if (m_albedoVolume && !(m_albedoVolume->maxValue() <= 1.f + 1e-4f))
            failAt(p.whereOf("albedo"), "{}: the albedo volume reaches {}; an albedo must lie in [0, 1]", p.describe(),
                   m_albedoVolume->maxValue());
        if (!m_phase) {
            Properties d("phase", "isotropic", p.where());
            m_phase = query<IPhaseFunction>(Registry::instance().create("phase", "isotropic", d));
        }
    }

    const IPhaseFunction& phase() const override { return *m_phase; }
    bool isHomogeneous() const override { return true; }
    bool sampleEmitters() const override { return m_sampleEmitters; }
    bool isEmissive() const override { return m_emissive; }

    MediumProperties at(const Point3f& p, const SampledWavelengths& lambda) const override {
        const SampledSpectrum sigmaT = m_sigmaT.sample(lambda);
        SampledSpectrum albedo = m_albedo.sample(lambda);
        if (m_albedoVolume) {
            albedo = m_albedoVolume->eval(p, lambda);
            for (int i = 0; i < NSpectrumSamples; ++i) albedo[i] = std::clamp(albedo[i], 0.f, 1.f);
        }
        MediumProperties mp;
        mp.sigmaS = sigmaT * albedo;
        mp.sigmaA = sigmaT * (SampledSpectrum(1.f) - albedo);
        if (m_emissive) mp.Le = m_emission.sample(lambda);
        return mp;
    }

    MajorantSegment majorant(const Ray&, float tMin, float tMax, const SampledWavelengths& lambda) const override {
        // σt (= σa + σs up to rounding, which the suite allows for) bounds itself.
        return {tMin, tMax, m_sigmaT.sample(lambda)};
    }

private:
    /// The nested albedo volume, if the albedo is one.
    static Ref<IVolume> albedoVolume(const Properties& p) {
        const Properties::Entry* e = p.find("albedo");
        return e && std::holds_alternative<ComponentValue>(e->value) ? p.get<IVolume>("albedo") : nullptr;
    }

    Spectrum m_sigmaT;
    Ref<IVolume> m_albedoVolume;  // null: the spectrum m_albedo
    Spectrum m_albedo, m_emission;
    Ref<IPhaseFunction> m_phase;
    bool m_sampleEmitters, m_emissive = false;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::HomogeneousMedium)
