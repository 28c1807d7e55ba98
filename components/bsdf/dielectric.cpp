// bsdf "dielectric" — a smooth interface between two dielectrics (glass, water): specular
// reflection and refraction weighted by the exact Fresnel equations, with total internal
// reflection, and dispersion when the index of refraction varies with wavelength.
//
// Both lobes are Dirac deltas; sample() picks one (f() and pdf() are zero). Reflection is
// chosen with probability P = the Fresnel reflectance F averaged over the path's live
// wavelengths (= F at the hero wavelength when the index is constant or only the hero is
// left), refraction with 1 − P; under total internal reflection P = 1. The weight of a
// sample, f·|cosθi|/pdf, is F(λ)·R/P for reflection and (1 − F(λ))·T/(1 − P)/η² for
// refraction, η being the relative index of the crossing; the 1/η² radiance scaling
// applies in TransportMode::Radiance only (Veach 1997, §5.2).
//
// Dispersion: when the index differs between the live wavelengths, a refracted path can
// follow only one of them; it follows the hero wavelength and calls
// SampledWavelengths::terminateSecondary(). Choosing the lobe with the wavelength-symmetric
// P (rather than F at the hero) keeps the estimator unbiased even for radiance the path
// gathered before this vertex: the chance of terminating does not depend on which of the
// four wavelengths is the hero (tests/test_dispersion.cpp checks it against quadrature).
//
// Parameters (as Mitsuba 3):
//   int_ior, ext_ior        interior / exterior index: a float, a spectrum (dispersive if it
//                           varies), or a name (Mitsuba's names, and the dispersive glasses
//                           "bk7", "sf11", "fused-silica", "diamond" — effigi/spectral/glass.hpp)
//   specular_reflectance    texture (reflectance, default 1), factor on reflection
//   specular_transmittance  texture (reflectance, default 1), factor on transmission
//
// References: M. Born & E. Wolf, Principles of Optics, §1.5; A. Wilkie et al., "Hero
// Wavelength Spectral Sampling", EGSR 2014 (terminating the secondary wavelengths).
#include "delta_bsdf.hpp"
#include "dielectric_ior.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/render/fresnel.hpp"

namespace effigi {
namespace {

class Dielectric final : public DeltaBSDF {
public:
    static Schema schema() {
        Schema s("bsdf", "dielectric", "Smooth dielectric interface (glass), with dispersion for spectral indices.");
        s.cite("M. Born, E. Wolf, Principles of Optics, §1.5; Wilkie et al. 2014, Hero Wavelength Spectral Sampling");
        declareSmoothDielectric(s, "Interior index of refraction", "Exterior index of refraction");
        s.addConformance({"inverted (ior 1 in 1.5)", {{"int_ior", 1.0}, {"ext_ior", 1.5}}});
        return s;
    }

    explicit Dielectric(const Properties& p)
        : m_eta(relativeIOR(p)), m_reflectance(p.getTexture("specular_reflectance", SpectrumKind::Reflectance)),
          m_transmittance(p.getTexture("specular_transmittance", SpectrumKind::Reflectance)) {}

    std::uint32_t flags() const override { return BSDFReflection | BSDFTransmission | BSDFSpecular; }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float uc, const Point2f&,
                                     SampledWavelengths& lambda, TransportMode mode) const override {
        float cosO = wo.z;
        if (cosO == 0.f) return std::nullopt;
        SampledSpectrum eta = m_eta.eval(lambda);
        SampledSpectrum pdfL = lambda.pdf();

        // Fresnel per wavelength; the lobe probability P averages it over the live ones.
        SampledSpectrum F;
        float sumF = 0.f;
        int live = 0;
        bool dispersive = false;
        for (int i = 0; i < NSpectrumSamples; ++i) {
            F[i] = fresnelDielectric(cosO, eta[i]);
            if (pdfL[i] == 0.f && i > 0) continue;
            sumF += F[i];
            ++live;
            // Differences below 1e-6 (float rounding of a flat table) bend rays by < 1e-6 rad.
            dispersive |= std::abs(eta[i] - eta[0]) > 1e-6f * eta[0];
        }
        float P = sumF / float(live);

        BSDFSample bs;
        float absCos = std::max(std::abs(cosO), 1e-30f);
        if (uc < P || P >= 1.f) {
            bs.wi = reflectLocal(wo);
            bs.pdf = P;
            bs.flags = BSDFReflection | BSDFSpecular;
            bs.f = F * m_reflectance->eval(si, lambda) * (1.f / absCos);
            return bs;
        }
        // Refraction follows the hero wavelength.
        float etaRel;
        if (!refractLocal(wo, eta[0], bs.wi, etaRel)) return std::nullopt;  // hero is totally reflected: weight 0
        if (dispersive) lambda.terminateSecondary();
        bs.pdf = 1.f - P;
        bs.flags = BSDFTransmission | BSDFSpecular;
        bs.eta = etaRel;
        SampledSpectrum T = m_transmittance->eval(si, lambda);
        float absCosT = std::max(std::abs(bs.wi.z), 1e-30f);
        for (int i = 0; i < NSpectrumSamples; ++i) {
            float scale = 1.f;
            if (mode == TransportMode::Radiance) {
                // η_t / η_i of this wavelength's crossing (only the hero's survives when dispersive).
                float e = cosO > 0.f ? eta[i] : 1.f / eta[i];
                scale = 1.f / (e * e);
            }
            bs.f[i] = (1.f - F[i]) * T[i] * scale / absCosT;
        }
        return bs;
    }

    /// Directional reflectance + transmittance seen from the normal (AOVs): F + (1 − F)
    /// with the factors, ignoring the 1/η² of radiance (an albedo is a ratio of fluxes).
    SampledSpectrum albedo(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override {
        SampledSpectrum eta = m_eta.eval(lambda), F;
        for (int i = 0; i < NSpectrumSamples; ++i) F[i] = fresnelDielectric(1.f, eta[i]);
        return F * m_reflectance->eval(si, lambda) + (SampledSpectrum(1.f) - F) * m_transmittance->eval(si, lambda);
    }

private:
    RelativeIOR m_eta;
    Ref<ITexture> m_reflectance, m_transmittance;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Dielectric)
