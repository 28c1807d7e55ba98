#pragma once
// The coated diffuse model shared by `plastic` and `roughplastic` (Mitsuba 3's plastics,
// after Weidlich & Wilkie 2007): a dielectric coating of relative index η over a
// Lambertian substrate of albedo ρ. Light either reflects off the coating (a delta lobe
// for `plastic`, a microfacet lobe for `roughplastic`) or enters it with the coating's
// transmittance T(θ), scatters diffusely in the substrate, bounces between substrate
// and coating (the coating reflects a fraction R_int of diffuse light back inside), and
// leaves through the coating again:
//
//   f_diffuse(wo, wi) = ρ / (1 − R_int·(ρ if nonlinear else 1)) · T(θo) T(θi) / (π η²)
//
// The series Σ (ρ R_int)^k = 1 / (1 − ρ R_int) is the `nonlinear` form (colours darken
// and saturate as in a real coated surface); Mitsuba's default divides by 1 − R_int only,
// which keeps the diffuse albedo at ρ (seen from a white, non-absorbing coating).
//
// R_int, the coating's reflectance for diffuse light from inside, is computed by each
// plastic: `plastic` from T by reciprocity (exact for a smooth interface), `roughplastic`
// by Mitsuba's single-scattering quadrature.
//
// Lobe selection (as Mitsuba): the specular lobe is picked with probability
// ∝ (1 − T(θo))·w and the diffuse one ∝ T(θo)·(1 − w), where w = mean(specular) /
// (mean(specular) + mean(diffuse)) is the specular sampling weight. The diffuse lobe is
// drawn through a warp (issue 14): by default the compiled-in code of warp
// `cosine_hemisphere`, or a nested `warp` (components/bsdf/cosine_lobe.hpp); the plastics'
// pdf() use its density, so any warp covering the upper hemisphere keeps them unbiased.
//
// References: A. Weidlich, A. Wilkie, "Arbitrarily Layered Micro-Facet Surfaces",
// GRAPHITE 2007; Mitsuba 3 documentation, "Smooth plastic material (plastic)" and
// "Rough plastic material (roughplastic)"; E. Veach, PhD thesis, 1997, §5.2.
#include "cosine_lobe.hpp"
#include "dielectric_ior.hpp"

#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/itexture.hpp"

namespace effigi {

/// Mitsuba's default coating, "polypropylene".
inline constexpr double PlasticIntIOR = 1.49;
/// The coating's index is one number (Mitsuba's `lookup_ior` returns a scalar); a
/// dispersive spectrum or glass name is read at the sodium d line, 589.3 nm.
inline constexpr float PlasticIORWavelength = 589.3f;

/// The parameters both plastics share, with their conformance-relevant ranges.
inline void declarePlastic(Schema& s) {
    declareIOR(s, "int_ior", PlasticIntIOR, "Coating index of refraction (default polypropylene, 1.49)");
    declareIOR(s, "ext_ior", DefaultExtIOR, "Exterior index of refraction (default air)");
    s.texture("diffuse_reflectance", 0.5f, SpectrumKind::Reflectance, "Albedo ρ of the diffuse substrate")
        .range(0.0, 1.0);
    s.texture("specular_reflectance", 1.f, SpectrumKind::Reflectance,
              "Factor on the coating's specular reflection (not physical; artistic control)")
        .range(0.0, 1.0);
    s.boolean("nonlinear", false, "Account for the colour shift of internal scattering: divide by 1 − ρ R_int");
    declareDiffuseWarp(s, "the diffuse substrate's lobe");
}

/// The substrate and coating parameters read from a plastic's properties.
struct PlasticParams {
    float eta = 1.f;  ///< int_ior / ext_ior at PlasticIORWavelength
    bool nonlinear = false;
    Ref<ITexture> diffuse, specular;
    float specularWeight = 0.5f;  ///< the specular sampling weight w
    DiffuseWarp diffuseWarp;      ///< the sampler of the diffuse lobe

    explicit PlasticParams(const Properties& p)
        : nonlinear(p.getBool("nonlinear")), diffuse(p.getTexture("diffuse_reflectance", SpectrumKind::Reflectance)),
          specular(p.getTexture("specular_reflectance", SpectrumKind::Reflectance)), diffuseWarp(p) {
        eta = readIOR(p, "int_ior")(PlasticIORWavelength) / readIOR(p, "ext_ior")(PlasticIORWavelength);
        float d = std::max(0.f, diffuse->mean()), s = std::max(0.f, specular->mean());
        // Both black: any weight samples nothing but zeros; keep the selection defined.
        specularWeight = d + s > 0.f ? s / (d + s) : 0.5f;
    }

    /// A lobe whose factor is the constant 0 is absent: flags() leave it out, so a
    /// renderer skips it and a black coating is no "delta lobe that is never sampled".
    static bool isBlack(const ITexture& t) { return t.isConstant() && !(t.maxValue() > 0.f); }
    std::uint32_t lobes(std::uint32_t specularLobe) const {
        return (isBlack(*specular) ? 0u : specularLobe) | (isBlack(*diffuse) ? 0u : std::uint32_t(BSDFDiffuse));
    }

    /// Probability of picking the specular lobe, given the coating's transmittance T(θo).
    float specularProbability(float transmittanceO) const {
        float ps = (1.f - transmittanceO) * specularWeight, pd = transmittanceO * (1.f - specularWeight);
        return ps + pd > 0.f ? ps / (ps + pd) : 0.5f;
    }

    /// The diffuse part of f for coating transmittances tO, tI; rInt is R_int.
    SampledSpectrum substrate(const SurfaceInteraction& si, const SampledWavelengths& lambda, float tO, float tI,
                              float rInt) const {
        SampledSpectrum rho = diffuse->eval(si, lambda);
        SampledSpectrum denom = nonlinear ? SampledSpectrum(1.f) - rho * rInt : SampledSpectrum(1.f - rInt);
        float scale = tO * tI * InvPi / (eta * eta);
        SampledSpectrum out;
        for (int i = 0; i < NSpectrumSamples; ++i) out[i] = denom[i] > 0.f ? rho[i] * scale / denom[i] : 0.f;
        return out;
    }
};

} // namespace effigi
