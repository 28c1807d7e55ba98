// bsdf "thindielectric" — a thin, non-absorbing dielectric slab (a window pane) modelled as
// one surface: light is reflected specularly or passes straight through (wi = −wo; the
// sideways shift inside a thin pane is neglected).
//
// Summing the inter-reflections between the slab's two faces (a geometric series), the
// slab reflects R' = R + T²R / (1 − R²) = 2R / (1 + R) and transmits T' = 1 − R' of the light,
// R being the Fresnel reflectance of one face at the incidence angle and T = 1 − R. Both
// lobes are Dirac deltas; sample() chooses reflection with probability P = R' averaged
// over the path's live wavelengths (R' at the hero for a constant index), and the sample
// weight is R'(λ)·specular_reflectance/P or T'(λ)·specular_transmittance/(1 − P). The
// direction does not depend on λ, so a spectral index needs no wavelength termination, and
// a straight pass has no net change of medium, hence no η² radiance scaling.
//
// The straight pass is a pass-through (BSDFNull) lobe, as in Mitsuba 3: the surface is an
// index-matched interface for it, so renderers do not count the crossing as a bounce and
// shadow rays cross the pane weighted by evalNullTransmission() = T'·specular_transmittance
// at the shadow ray's angle. A medium sealed in a thin-walled container (Mitsuba's
// volpath scenes) then gets direct light through the wall.
//
// Parameters (as Mitsuba 3): int_ior, ext_ior (float, spectrum or name, as for
// `dielectric`), specular_reflectance, specular_transmittance (textures, default 1).
//
// Reference: M. Born & E. Wolf, Principles of Optics, §1.6 (multiple reflections in a
// plane-parallel plate, incoherent sum).
#include "delta_bsdf.hpp"
#include "dielectric_ior.hpp"
#include "null_lobe.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/render/fresnel.hpp"

namespace effigi {
namespace {

class ThinDielectric final : public DeltaBSDF {
public:
    static Schema schema() {
        Schema s("bsdf", "thindielectric", "Thin dielectric slab (window pane): specular reflection or straight transmission.");
        s.cite("M. Born, E. Wolf, Principles of Optics, §1.6 (plane-parallel plate)");
        declareSmoothDielectric(s, "Index of refraction of the slab", "Index of refraction around the slab");
        return s;
    }

    explicit ThinDielectric(const Properties& p)
        : m_eta(relativeIOR(p)), m_reflectance(p.getTexture("specular_reflectance", SpectrumKind::Reflectance)),
          m_transmittance(p.getTexture("specular_transmittance", SpectrumKind::Reflectance)) {}

    std::uint32_t flags() const override { return BSDFReflection | BSDFTransmission | BSDFSpecular | BSDFNull; }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float uc, const Point2f&,
                                     SampledWavelengths& lambda, TransportMode) const override {
        if (wo.z == 0.f) return std::nullopt;
        SampledSpectrum R = slabReflectance(std::abs(wo.z), lambda);
        SampledSpectrum pdfL = lambda.pdf();
        float sum = 0.f;
        int live = 0;
        for (int i = 0; i < NSpectrumSamples; ++i)
            if (i == 0 || pdfL[i] != 0.f) {
                sum += R[i];
                ++live;
            }
        float P = sum / float(live);

        if (!(uc < P))
            return nullLobeSample(wo, 1.f - P, (SampledSpectrum(1.f) - R) * m_transmittance->eval(si, lambda));
        BSDFSample bs;
        bs.wi = reflectLocal(wo);
        bs.pdf = P;
        bs.flags = BSDFReflection | BSDFSpecular;
        bs.f = R * m_reflectance->eval(si, lambda) * (1.f / std::max(std::abs(wo.z), 1e-30f));
        return bs;
    }

    /// What a straight crossing keeps: T' at the crossing ray's angle (si.wo), times
    /// specular_transmittance.
    SampledSpectrum evalNullTransmission(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override {
        const float cosTheta = std::abs(si.toLocal(si.wo).z);
        return (SampledSpectrum(1.f) - slabReflectance(cosTheta, lambda)) * m_transmittance->eval(si, lambda);
    }

    /// R' + T' at normal incidence, with the factors.
    SampledSpectrum albedo(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override {
        SampledSpectrum R = slabReflectance(1.f, lambda);
        return R * m_reflectance->eval(si, lambda) + (SampledSpectrum(1.f) - R) * m_transmittance->eval(si, lambda);
    }

private:
    /// R' = R + T²R/(1 − R²) = 2R/(1 + R) per wavelength (1 when the face reflects totally).
    SampledSpectrum slabReflectance(float cosTheta, const SampledWavelengths& lambda) const {
        SampledSpectrum eta = m_eta.eval(lambda), R;
        for (int i = 0; i < NSpectrumSamples; ++i) {
            float r = fresnelDielectric(cosTheta, eta[i]);
            R[i] = 2.f * r / (1.f + r);
        }
        return R;
    }

    RelativeIOR m_eta;
    Ref<ITexture> m_reflectance, m_transmittance;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::ThinDielectric)
