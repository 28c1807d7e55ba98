// bsdf "principledthin" — the thin-surface Disney BSDF (Burley 2015, §4) as Mitsuba 3
// defines it: a sheet with no inside (leaves, paper, fabric), the same seen from both sides.
// Everything is evaluated with wo turned to +z (and wi with it); with h the half vector of
// wo and wi mirrored to wo's side:
//   specular reflection    spec_trans F_thin D G / (4 cos θo cos θi), only where spec_trans > 0
//                          (Mitsuba's thin model has no specular lobe on an opaque sheet);
//                          F_thin = lerp(F_dielectric(η), Schlick(tint R0(η)), spec_tint)
//   specular transmission  spec_trans base (1 − F_dielectric) D' G' / (4 cos θo cos θi): the
//                          reflection lobe mirrored through the sheet, its roughness scaled
//                          by 0.65 η − 0.35 (Burley 2015, eq. 3); the direction is not bent
//   diffuse reflection     (1 − spec_trans)(1 − diff_trans/2) base/π × Burley's diffuse
//                          (principled_lobes.hpp), plus the sheen
//   diffuse transmission   (1 − spec_trans) diff_trans/2 base/π (diff_trans runs 0 to 2)
// Every term is symmetric in (wo, wi), so the sheet is reciprocal (η of a crossing is 1).
// Where effigi departs from Mitsuba: GGX masking is effigi's height-correlated Smith G, and
// the tint colour uses the texture's mean as luminance, as in `principled`; a transmitted
// pair is accepted when its mirrored reflection is (both directions on the front of h), the
// condition under which sampling produces it — Mitsuba tests wi against the unmirrored h,
// which is not symmetric in (wo, wi) and rejects some of its own samples.
//
// Sampling (as Mitsuba): a lobe with probabilities ∝ spec_trans/2 × the specular reflection
// and transmission rates, (1 − spec_trans)(1 − diff_trans/2) × the diffuse reflection rate,
// (1 − spec_trans) diff_trans/2 × the diffuse transmission rate; visible GGX normals for the
// specular lobes, cosine-weighted hemispheres for the diffuse ones, drawn through a warp
// (issue 14, cosine_lobe.hpp): by default the compiled-in code of warp `cosine_hemisphere`,
// or a nested `warp` (the transmitted direction is its direction mirrored through the sheet).
//
// Parameters (as Mitsuba 3): base_color (0.5), roughness (0.5), anisotropic, spec_trans,
// spec_tint, sheen, sheen_tint, flatness (textures in [0, 1], 0), diff_trans (texture in
// [0, 2], 0), eta (texture, 1.5), specular_reflectance_sampling_rate,
// specular_transmittance_sampling_rate, diffuse_reflectance_sampling_rate,
// diffuse_transmittance_sampling_rate (1); warp (nested warp, optional: the diffuse lobes' sampler).
//
// References: B. Burley, "Extending the Disney BRDF to a BSDF with Integrated Subsurface
// Scattering", SIGGRAPH 2015 course; Mitsuba 3 documentation, "The Thin Principled BSDF
// (principledthin)".
#include "cosine_lobe.hpp"
#include "principled_lobes.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/render/fresnel.hpp"
#include "effigi/render/microfacet.hpp"

namespace effigi {
namespace {

using namespace principled;

class PrincipledThin final : public Implements<IBSDF> {
    struct Local {
        float roughness, anisotropic, specTrans, specTint, sheen, sheenTint, flatness, diffTrans, eta;
        float pSpecR, pSpecT, pDiffR, pDiffT;  ///< normalised lobe probabilities
    };

public:
    static Schema schema() {
        Schema s("bsdf", "principledthin", "Thin-surface Disney principled BSDF (Burley 2015) as Mitsuba 3 defines it.");
        s.cite("B. Burley, Extending the Disney BRDF to a BSDF with Integrated Subsurface Scattering, SIGGRAPH 2015");
        s.texture("base_color", 0.5f, SpectrumKind::Reflectance, "Base colour").range(0.0, 1.0);
        s.texture("roughness", 0.5f, SpectrumKind::Unbounded, "Roughness r; GGX α = r²").range(0.0, 1.0);
        const char* weights[][2] = {{"anisotropic", "Anisotropy of the specular lobes"},
                                    {"spec_trans", "Specular weight: reflection and straight-through transmission"},
                                    {"spec_tint", "Tints the specular reflection toward the base colour"},
                                    {"sheen", "Sheen weight"},
                                    {"sheen_tint", "Tints the sheen toward the base colour"},
                                    {"flatness", "Blends the diffuse toward a flat, subsurface-like response"}};
        for (auto& w : weights) s.texture(w[0], 0.f, SpectrumKind::Unbounded, w[1]).range(0.0, 1.0);
        s.texture("diff_trans", 0.f, SpectrumKind::Unbounded, "Diffuse transmission (0 none, 1 half, 2 all)")
            .range(0.0, 2.0);
        s.texture("eta", 1.5f, SpectrumKind::Unbounded, "Index of refraction of the sheet").range(1.0, 10.0);
        for (const char* r : {"specular_reflectance_sampling_rate", "specular_transmittance_sampling_rate",
                              "diffuse_reflectance_sampling_rate", "diffuse_transmittance_sampling_rate"})
            s.real(r, 1.0, "Relative probability of sampling this lobe").atLeast(0.0);
        declareDiffuseWarp(s, "the diffuse lobes (transmission: mirrored through the sheet)");
        using P = std::vector<std::pair<std::string, PropertyValue>>;
        auto cfg = [&](const char* name, P p) { s.addConformance({name, std::move(p)}); };
        cfg("default", {});
        cfg("spec_trans 1", {{"spec_trans", 1.0}, {"roughness", 0.3}});
        cfg("spec_trans 0.5 diff_trans 1", {{"spec_trans", 0.5}, {"diff_trans", 1.0}, {"base_color", 0.6}});
        cfg("diff_trans 2", {{"diff_trans", 2.0}, {"base_color", 0.9}});
        cfg("roughness 0", {{"roughness", 0.0}, {"spec_trans", 0.5}});
        cfg("roughness 1 eta 3", {{"roughness", 1.0}, {"spec_trans", 0.7}, {"eta", 3.0}});
        cfg("eta 1", {{"eta", 1.0}, {"spec_trans", 0.8}, {"roughness", 0.8}});
        cfg("anisotropic 1", {{"anisotropic", 1.0}, {"spec_trans", 0.6}, {"roughness", 0.5}});
        cfg("sheen, tints, flatness",
            {{"sheen", 1.0}, {"sheen_tint", 1.0}, {"spec_tint", 1.0}, {"flatness", 1.0}, {"spec_trans", 0.3},
             {"base_color", RGBValue{{0.2f, 0.4f, 0.3f}}}});
        cfg("black", {{"base_color", 0.0}, {"diff_trans", 1.0}});
        cfg("white roughness 1 sheen 1", {{"base_color", 1.0}, {"roughness", 1.0}, {"sheen", 1.0}});
        s.allow({"energy", 1.6, "Burley's diffuse (retro-reflection at grazing) and the sheen lobe gain energy "
                                "with a white base colour: albedo 1.55 at roughness 1, sheen 1, cos θo = 0.05 "
                                "(Burley 2012, §5.3; Burley 2015 for the thin sheet)"});
        return s;
    }

    explicit PrincipledThin(const Properties& p)
        : m_baseColor(p.getTexture("base_color", SpectrumKind::Reflectance)),
          m_roughness(p.getTexture("roughness", SpectrumKind::Unbounded)),
          m_eta(p.getTexture("eta", SpectrumKind::Unbounded)),
          m_rates{p.getFloat("specular_reflectance_sampling_rate"), p.getFloat("specular_transmittance_sampling_rate"),
                  p.getFloat("diffuse_reflectance_sampling_rate"), p.getFloat("diffuse_transmittance_sampling_rate")},
          m_warp(p) {
        auto weight = [&](const char* name, bool* has = nullptr) {
            Ref<ITexture> t = p.getTexture(name, SpectrumKind::Unbounded);
            const Properties::Entry* e = p.find(name);
            // Mitsuba's rule: a lobe is on when its weight is given and not a constant 0.
            if (has) *has = e && !e->fromDefault && !(t->isConstant() && t->maxValue() == 0.f);
            return t;
        };
        m_anisotropic = weight("anisotropic");
        m_specTrans = weight("spec_trans", &m_hasSpecTrans);
        m_specTint = weight("spec_tint");
        m_sheen = weight("sheen");
        m_sheenTint = weight("sheen_tint");
        m_flatness = weight("flatness");
        m_diffTrans = weight("diff_trans", &m_hasDiffTrans);
    }

    std::uint32_t flags() const override {
        return BSDFReflection | BSDFDiffuse | (m_hasSpecTrans ? BSDFGlossy : 0u) |
               (m_hasSpecTrans || m_hasDiffTrans ? BSDFTransmission : 0u);
    }

    SampledSpectrum f(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                      const SampledWavelengths& lambda, TransportMode) const override {
        SampledSpectrum value(0.f);
        if (wo.z == 0.f || wi.z == 0.f) return value;
        // The sheet is the same from both sides: turn wo to +z (and wi with it).
        float side = wo.z > 0.f ? 1.f : -1.f;
        Vector3f o = side * wo, i = side * wi;
        bool reflect = i.z > 0.f;
        Local l = local(si);
        Vector3f h, ir(i.x, i.y, std::abs(i.z));
        if (!halfVector(o, ir, 1.f, h)) return value;
        SampledSpectrum base = m_baseColor->eval(si, lambda);
        const double cosO = o.z, cosI = std::abs(double(i.z));
        float lum = std::max(0.f, m_baseColor->evalFloat(si));
        if (l.specTrans > 0.f && facetCompatible(h, o, ir, true)) {
            float cosOH = dot(o, h), F = fresnelDielectric(cosOH, l.eta);
            MicrofacetDistribution dist = distribution(l, !reflect);
            double DG = double(dist.D(h)) * dist.G(o, ir) / (4.0 * cosO * cosI);
            if (reflect) {
                float r0 = schlickR0(l.eta);
                SampledSpectrum c = tint(base, lum), Fthin;
                for (int k = 0; k < NSpectrumSamples; ++k)
                    Fthin[k] = F + l.specTint * (schlick(c[k] * r0, cosOH, l.eta) - F);
                value += Fthin * float(std::min(l.specTrans * DG, 1e30));
            } else {
                value += base * float(std::min(l.specTrans * (1.0 - F) * DG, 1e30));
            }
        }
        if (l.specTrans < 1.f) {
            if (reflect && l.diffTrans < 1.f) {
                float cosD = dot(h, i), w = (1.f - l.specTrans) * (1.f - l.diffTrans);
                value += base * (w * InvPi * diffuseFactor(float(cosO), float(cosI), cosD, l.roughness, l.flatness));
                if (l.sheen > 0.f) {
                    SampledSpectrum sheenColor =
                        SampledSpectrum(1.f) + (tint(base, lum) - SampledSpectrum(1.f)) * l.sheenTint;
                    value += sheenColor * (l.sheen * w * schlickWeight(std::abs(cosD)));
                }
            } else if (!reflect && l.diffTrans > 0.f) {
                value += base * ((1.f - l.specTrans) * l.diffTrans * InvPi);
            }
        }
        return value;
    }

    float pdf(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&,
              TransportMode) const override {
        if (wo.z == 0.f || wi.z == 0.f) return 0.f;
        float side = wo.z > 0.f ? 1.f : -1.f;
        Vector3f o = side * wo, i = side * wi;
        bool reflect = i.z > 0.f;
        Local l = local(si);
        double pdf = 0.0;
        Vector3f h, ir(i.x, i.y, std::abs(i.z));
        if (halfVector(o, ir, 1.f, h) && facetCompatible(h, o, ir, true)) {
            // Both specular lobes are reflections (one then mirrored): |dh/dwi| = 1/(4 wi·h).
            double lobe = reflect ? l.pSpecR : l.pSpecT;
            pdf += lobe * distribution(l, !reflect).visiblePdf(o, h) / (4.0 * std::abs(double(dot(ir, h))));
        }
        pdf += (reflect ? l.pDiffR : l.pDiffT) * m_warp.pdf(ir);
        return float(std::min(pdf, 1e30));
    }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float uc, const Point2f& u,
                                     SampledWavelengths& lambda, TransportMode mode) const override {
        if (wo.z == 0.f) return std::nullopt;
        float side = wo.z > 0.f ? 1.f : -1.f;
        Vector3f o = side * wo, i;
        Local l = local(si);
        BSDFSample bs;
        if (uc < l.pSpecR + l.pSpecT) {
            bool transmit = uc >= l.pSpecR;
            Vector3f m = distribution(l, transmit).sampleVisible(o, u);
            i = normalize(2.f * dot(o, m) * m - o);
            if (transmit) i.z = -i.z;  // the reflection mirrored through the sheet
            bs.flags = BSDFGlossy | (transmit ? BSDFTransmission : BSDFReflection);
        } else {
            bool transmit = uc >= l.pSpecR + l.pSpecT + l.pDiffR;
            i = sampleRimLifted(m_warp, u);  // below the surface (a nested warp's): refused by the side check
            if (transmit) i.z = -i.z;
            bs.flags = BSDFDiffuse | (transmit ? BSDFTransmission : BSDFReflection);
        }
        if (!((bs.flags & BSDFTransmission) ? i.z < 0.f : i.z > 0.f)) return std::nullopt;
        bs.wi = side * i;
        bs.pdf = pdf(si, wo, bs.wi, lambda, mode);
        if (!(bs.pdf >= std::numeric_limits<float>::min())) return std::nullopt;
        bs.f = f(si, wo, bs.wi, lambda, mode);
        return bs;  // eta stays 1: the sheet does not bend light
    }

private:
    Local local(const SurfaceInteraction& si) const {
        Local l;
        auto w = [&](const Ref<ITexture>& t) { return std::clamp(t->evalFloat(si), 0.f, 1.f); };
        l.roughness = w(m_roughness);
        l.anisotropic = w(m_anisotropic);
        l.specTrans = m_hasSpecTrans ? w(m_specTrans) : 0.f;
        l.specTint = w(m_specTint);
        l.sheen = w(m_sheen);
        l.sheenTint = w(m_sheenTint);
        l.flatness = w(m_flatness);
        l.diffTrans = m_hasDiffTrans ? std::clamp(m_diffTrans->evalFloat(si), 0.f, 2.f) * 0.5f : 0.f;
        l.eta = std::max(1.f, m_eta->evalFloat(si));
        float p[4] = {0.5f * l.specTrans * m_rates[0], 0.5f * l.specTrans * m_rates[1],
                      (1.f - l.specTrans) * (1.f - l.diffTrans) * m_rates[2],
                      (1.f - l.specTrans) * l.diffTrans * m_rates[3]};
        float total = p[0] + p[1] + p[2] + p[3], inv = total > 0.f ? 1.f / total : 0.f;
        l.pSpecR = p[0] * inv;
        l.pSpecT = p[1] * inv;
        l.pDiffR = p[2] * inv;
        l.pDiffT = p[3] * inv;
        return l;
    }

    /// GGX of the specular reflection, or of the transmission with its roughness scaled
    /// by 0.65 η − 0.35 (Burley 2015, eq. 3: a thin sheet's transmission is narrower).
    MicrofacetDistribution distribution(const Local& l, bool transmission) const {
        float r = transmission ? (0.65f * l.eta - 0.35f) * l.roughness : l.roughness;
        auto [ax, ay] = anisotropicAlphas(r, l.anisotropic);
        return {MicrofacetType::GGX, ax, ay};
    }

    Ref<ITexture> m_baseColor, m_roughness, m_eta, m_anisotropic, m_specTrans, m_specTint, m_sheen, m_sheenTint,
        m_flatness, m_diffTrans;
    float m_rates[4];
    bool m_hasSpecTrans = false, m_hasDiffTrans = false;
    DiffuseWarp m_warp;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::PrincipledThin)
