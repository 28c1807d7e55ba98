// bsdf "roughdielectric" — a rough interface between two dielectrics (frosted glass):
// reflection and refraction at a random surface of microfacets, each a smooth dielectric
// interface, after Walter, Marschner, Li & Torrance 2007.
//
//   reflection    f = F(wo·h) · R · D(h) G(wo, wi) / (4 |cosθo| |cosθi|),  h ∝ wo + wi
//   transmission  f = |wi·h| |wo·h| / (|cosθi| |cosθo|) · ηo² (1 − F(wo·h)) · T · D(h) G(wo, wi)
//                     / (ηo (wo·h) + ηi (wi·h))²,                        h ∝ −(ηo wo + ηi wi)
//
// (Walter 2007, eqs. 20 and 21), ηo and ηi the indices on the sides of wo and wi, h turned
// to the outside. This is the radiance form, which scales radiance by 1/η² on refraction
// as dielectric does (Veach 1997, §5.2); TransportMode::Importance gives the adjoint,
// f*(wo, wi) = f(wi, wo). D is GGX or Beckmann (effigi/render/microfacet.hpp); G the
// height-correlated Smith term, 1 / (1 + Λo + Λi) for reflection and the Beta function
// B(1 + Λo, 1 + Λi) for transmission (Heitz 2014, §6). The microsurface is the same from
// both sides. Light scattered more than once between microfacets is not modelled.
//
// Sampling (Walter 2007, §5.3, with visible normals, Heitz & d'Eon 2014): a normal m from
// the normals visible from wo (or from D cosθm when sample_visible is false), reflection
// with probability F(wo·m), refraction otherwise. The weight f·|cosθi|/pdf is G/G1(wo) ≤ 1
// in importance mode. sample() returns f(wo, wi) and pdf(wo, wi) recomputed from wi, so
// that the two agree bit for bit at any roughness.
//
// Dispersion: a refracted sample does NOT terminate the secondary wavelengths. Each
// wavelength's f is a density over the whole sphere (its own half vector, its own η), so
// f(λ)·cos/pdf is unbiased for every λ wherever pdf > 0; terminating would bias the path
// tracer, whose light sample at this vertex, taken with all four wavelengths, is MIS-weighted
// against this BSDF's pdf. That pdf is not the hero's alone: the index steering the Fresnel
// choice and the refraction is drawn uniformly among the sampled wavelengths, so pdf is the
// mixture (1/n) Σ_k pdf(wi; η(λk)) — the one-sample form of hero-wavelength MIS (Wilkie et
// al. 2014). With the hero's pdf alone, a narrow lobe (α ≲ 0.01 with bk7) put each
// secondary's f in a cone the hero's directions almost never reach: unbiased but so
// heavy-tailed that at 64 spp a bk7 object at α = 1e-4 rendered ~24 % too dark against
// Mitsuba; with the mixture, f(λk)·cos/pdf ≤ n × the hero's bound. A flat index gives
// n = 1, as before.
//
// Parameters (as Mitsuba 3):
//   distribution            string  beckmann (default) | ggx
//   alpha                   texture 0.1; or alpha_u, alpha_v (anisotropic); float or texture
//   sample_visible          bool    true
//   int_ior, ext_ior        as dielectric: a float, a spectrum or a name (bk7 is dispersive)
//   specular_reflectance    texture (reflectance, default 1), factor on reflection
//   specular_transmittance  texture (reflectance, default 1), factor on transmission
//
// References: B. Walter et al., "Microfacet Models for Refraction through Rough Surfaces",
// EGSR 2007; E. Heitz, "Understanding the Masking-Shadowing Function in Microfacet-Based
// BRDFs", JCGT 3(2), 2014; E. Heitz, E. d'Eon, "Importance Sampling Microfacet-Based BSDFs
// using the Distribution of Visible Normals", EGSR 2014.
#include "dielectric_ior.hpp"
#include "microfacet_params.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/render/fresnel.hpp"

namespace effigi {
namespace {

/// A pair of directions on opposite sides and the microfacet that refracts one into the
/// other: m = ±v/|v|, v = ηo wo + ηi wi (Walter's generalised half vector), m.z > 0.
struct Refraction {
    Vector3f m;
    double cosOM = 0.0, cosIM = 0.0;  ///< wo·m, wi·m
    double v2 = 0.0;                  ///< |v|² = (ηo wo·m + ηi wi·m)²
    double etaO = 1.0, etaI = 1.0;    ///< indices on the sides of wo and wi, relative to the outside

    /// F at m, from the outside direction: the same number for f(wo, wi), f(wi, wo) and
    /// pdf(wo, wi) (1 − F near total reflection is sensitive to the last bit of a cosine).
    double fresnel(const Vector3f& wo, float eta) const { return fresnelDielectric(float(wo.z > 0.f ? cosOM : cosIM), eta); }
};

/// The refracting microfacet of (wo, wi) for the relative index eta = η_int / η_ext, or
/// false when no microfacet facing both directions refracts one into the other. In double:
/// at η → 1 the two terms of v nearly cancel.
bool refractionNormal(const Vector3f& wo, const Vector3f& wi, float eta, Refraction& r) {
    if (!(wo.z * wi.z < 0.f)) return false;
    r.etaO = wo.z > 0.f ? 1.0 : double(eta);
    r.etaI = wo.z > 0.f ? double(eta) : 1.0;
    // The outside direction first, so that f(wo, wi) and f(wi, wo) round alike.
    const Vector3f& out = wo.z > 0.f ? wo : wi;
    const Vector3f& in = wo.z > 0.f ? wi : wo;
    Vector3d v = Vector3d(out) + double(eta) * Vector3d(in);
    r.v2 = glm::dot(v, v);
    if (!(r.v2 > 0.0)) return false;
    Vector3d m = v / std::sqrt(r.v2);
    if (m.z < 0.0) m = -m;
    r.cosOM = glm::dot(Vector3d(wo), m);
    r.cosIM = glm::dot(Vector3d(wi), m);
    r.m = Vector3f(m);
    // Each direction must see the front of m from its own side (Walter 2007, eq. 21's χ⁺).
    return r.m.z > 0.f && r.cosOM * wo.z > 0.0 && r.cosIM * wi.z > 0.0;
}

/// The half vector of a reflection pair (same side), turned up, in double as in
/// roughconductor; and cos = wo·m = wi·m as the mean of the two, the same number for
/// either order of the pair (F near the critical angle is sensitive to its last bit).
bool reflectionNormal(const Vector3f& wo, const Vector3f& wi, Vector3f& m, float& cos) {
    if (!(wo.z * wi.z > 0.f)) return false;
    Vector3d s = Vector3d(wo) + Vector3d(wi);
    double len = glm::length(s);
    if (!(len > 0.0)) return false;
    Vector3d md = s / len;
    if (md.z < 0.0) md = -md;
    double co = glm::dot(Vector3d(wo), md), ci = glm::dot(Vector3d(wi), md);
    m = Vector3f(md);
    cos = float(0.5 * (co + ci));
    return m.z > 0.f && co * wo.z > 0.0 && ci * wi.z > 0.0;
}

class RoughDielectric final : public Implements<IBSDF> {
public:
    static Schema schema() {
        Schema s("bsdf", "roughdielectric", "Rough dielectric interface (frosted glass): GGX or Beckmann microfacets.");
        s.cite("B. Walter et al., Microfacet Models for Refraction through Rough Surfaces, EGSR 2007");
        declareMicrofacet(s, /*textured=*/true);
        declareIOR(s, "int_ior", DefaultIntIOR, "Interior index of refraction");
        declareIOR(s, "ext_ior", DefaultExtIOR, "Exterior index of refraction");
        s.texture("specular_reflectance", 1.f, SpectrumKind::Reflectance, "Factor on the reflected part")
            .range(0.0, 1.0);
        s.texture("specular_transmittance", 1.f, SpectrumKind::Reflectance, "Factor on the transmitted part")
            .range(0.0, 1.0);
        // effigi-conform: ordinary roughness, both distributions, anisotropy, sampling all
        // of D; extremes: near-specular (1e-4), very rough (1), index-matched, dense,
        // inverted, dispersive.
        using P = std::vector<std::pair<std::string, PropertyValue>>;
        auto ggx = [](P p) {
            p.emplace_back("distribution", std::string("ggx"));
            return p;
        };
        s.addConformance({"default", {}});
        s.addConformance({"ggx 0.3/0.1", ggx({{"alpha_u", 0.3}, {"alpha_v", 0.1}})});
        s.addConformance({"ggx 1e-4", ggx({{"alpha", 1e-4}})});
        s.addConformance({"beckmann 1e-4", {{"alpha", 1e-4}}});
        s.addConformance({"ggx 1", ggx({{"alpha", 1.0}})});
        s.addConformance({"beckmann 1", {{"alpha", 1.0}}});
        s.addConformance({"ggx 0.3 ior 1.0001", ggx({{"alpha", 0.3}, {"int_ior", 1.0001}, {"ext_ior", 1.0}})});
        s.addConformance({"ggx 0.3 ior 4", ggx({{"alpha", 0.3}, {"int_ior", 4.0}, {"ext_ior", 1.0}})});
        s.addConformance({"beckmann 0.3 ior 1 in 1.5", {{"alpha", 0.3}, {"int_ior", 1.0}, {"ext_ior", 1.5}}});
        s.addConformance({"ggx 0.3 dispersive bk7",
                          ggx({{"alpha", 0.3}, {"int_ior", SpectrumValue{{}, {}, 0.f, 1.f, "bk7"}}})});
        s.addConformance({"ggx 0.3 all normals", ggx({{"alpha", 0.3}, {"sample_visible", false}})});
        s.addConformance({"beckmann 0.3 all normals", {{"alpha", 0.3}, {"sample_visible", false}}});
        return s;
    }

    explicit RoughDielectric(const Properties& p)
        : m_mf(p), m_sampleVisible(p.getBool("sample_visible")), m_eta(relativeIOR(p)),
          m_reflectance(p.getTexture("specular_reflectance", SpectrumKind::Reflectance)),
          m_transmittance(p.getTexture("specular_transmittance", SpectrumKind::Reflectance)) {
        // Between equal indices the microfacets are invisible and transmission is a delta
        // this model cannot represent (Mitsuba refuses it too).
        if (m_eta.isConstant() && m_eta.eval(SampledWavelengths::constant(550.f))[0] == 1.f)
            failAt(p.whereOf("int_ior"), "{}: 'int_ior' and 'ext_ior' are equal: the interface is invisible",
                   p.describe());
    }

    std::uint32_t flags() const override { return BSDFReflection | BSDFTransmission | BSDFGlossy; }

    SampledSpectrum f(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                      const SampledWavelengths& lambda, TransportMode mode) const override {
        // Importance transport is the adjoint: f*(wo, wi) = f(wi, wo).
        return mode == TransportMode::Radiance ? evalRadiance(si, wo, wi, lambda) : evalRadiance(si, wi, wo, lambda);
    }

    float pdf(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths& lambda,
              TransportMode) const override {
        if (wo.z == 0.f || wi.z == 0.f) return 0.f;
        const MicrofacetDistribution dist = m_mf.at(si);
        // The mixture over the wavelengths that may steer sample() (see the header).
        SampledSpectrum eta = m_eta.eval(lambda);
        int n = steeringCount(eta);
        double sum = 0.0;
        for (int k = 0; k < n; ++k) sum += pdfForEta(dist, wo, wi, eta[k]);
        return toPdf(sum / n);
    }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float uc, const Point2f& u,
                                     SampledWavelengths& lambda, TransportMode mode) const override {
        if (wo.z == 0.f) return std::nullopt;
        // The wavelength whose index steers this sample, uniformly; uc's remainder picks the lobe.
        SampledSpectrum etas = m_eta.eval(lambda);
        int n = steeringCount(etas);
        int k = std::min(int(uc * float(n)), n - 1);
        uc = uc * float(n) - float(k);
        float eta = etas[k];
        const MicrofacetDistribution dist = m_mf.at(si);
        Vector3f m = m_sampleVisible ? dist.sampleVisible(wo, u) : dist.sampleNormal(u);
        float cosOM = dot(wo, m);
        if (!(cosOM * wo.z > 0.f)) return std::nullopt;  // a back-facing normal (only when sampling all of D)
        BSDFSample bs;
        if (uc < fresnelDielectric(cosOM, eta)) {
            bs.wi = normalize(2.f * cosOM * m - wo);
            bs.flags = BSDFReflection | BSDFGlossy;
            if (!(bs.wi.z * wo.z > 0.f)) return std::nullopt;  // reflected through the surface
        } else {
            // Refraction about m (the same construction as refractLocal about +z).
            float e = cosOM > 0.f ? eta : 1.f / eta, cosI = std::abs(cosOM);
            float sin2T = (1.f - cosI * cosI) / (e * e);
            if (sin2T >= 1.f) return std::nullopt;  // total internal reflection: F = 1, not reached
            float cosT = std::sqrt(1.f - sin2T);
            Vector3f n = cosOM > 0.f ? m : -m;
            bs.wi = normalize(-wo / e + (cosI / e - cosT) * n);
            bs.flags = BSDFTransmission | BSDFGlossy;
            bs.eta = cosOM > 0.f ? etas[0] : 1.f / etas[0];  // η(wi side) / η(wo side), at the hero
            if (!(bs.wi.z * wo.z < 0.f)) return std::nullopt;  // refracted back to wo's side
        }
        bs.pdf = pdf(si, wo, bs.wi, lambda, mode);
        // pdf 0: m lost to rounding; below the smallest float: f·cosθ/pdf would overflow
        // (such a direction has probability < 1e-37).
        if (!(bs.pdf >= std::numeric_limits<float>::min())) return std::nullopt;
        bs.f = f(si, wo, bs.wi, lambda, mode);
        return bs;
    }

    /// Directional reflectance + transmittance seen from the normal: the stratified
    /// estimate of the default albedo(), in importance mode, so that it is a ratio of
    /// fluxes without the 1/η² of radiance (as dielectric's).
    SampledSpectrum albedo(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override {
        constexpr int N = 16;
        SampledSpectrum sum(0.f);
        for (int i = 0; i < N * N; ++i) {
            Point2f u((float(i / N) + 0.5f) / N, (float(i % N) + 0.5f) / N);
            // Lobe choices by the golden-ratio sequence: even, and unrelated to the strata.
            float uc = float(std::fmod(0.5 + 0.6180339887498949 * i, 1.0));
            SampledWavelengths l = lambda;
            auto bs = sample(si, Vector3f(0.f, 0.f, 1.f), uc, u, l, TransportMode::Importance);
            if (bs) sum += bs->f * (std::abs(bs->wi.z) / bs->pdf);
        }
        return sum / float(N * N);
    }

private:
    SampledSpectrum evalRadiance(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                                 const SampledWavelengths& lambda) const {
        if (wo.z == 0.f || wi.z == 0.f) return SampledSpectrum(0.f);
        SampledSpectrum eta = m_eta.eval(lambda), out(0.f);
        const MicrofacetDistribution dist = m_mf.at(si);
        if (wo.z * wi.z > 0.f) {
            Vector3f m;
            float cosOM;
            if (!reflectionNormal(wo, wi, m, cosOM)) return out;
            double dg = double(dist.D(m)) * dist.G(wo, wi) / (4.0 * std::abs(double(wo.z) * wi.z));
            if (!(dg > 0.0)) return out;
            for (int i = 0; i < NSpectrumSamples; ++i) out[i] = fresnelDielectric(cosOM, eta[i]);
            return out * m_reflectance->eval(si, lambda) * float(std::min(dg, 1e30));
        }
        // Each wavelength refracts through its own microfacet; a flat index reuses the first.
        for (int i = 0; i < NSpectrumSamples; ++i)
            out[i] = i > 0 && eta[i] == eta[i - 1] ? out[i - 1] : transmission(dist, wo, wi, eta[i]);
        return out * m_transmittance->eval(si, lambda);
    }

    /// Walter's transmission term (radiance) for one relative index.
    static float transmission(const MicrofacetDistribution& dist, const Vector3f& wo, const Vector3f& wi, float eta) {
        Refraction r;
        if (!refractionNormal(wo, wi, eta, r)) return 0.f;
        double D = dist.D(r.m), G = dist.G(wo, wi);
        if (!(D * G > 0.0)) return 0.f;
        double F = r.fresnel(wo, eta);
        double v = std::abs(r.cosIM * r.cosOM) / std::abs(double(wi.z) * wo.z) * r.etaO * r.etaO * (1.0 - F) * G * D /
                   r.v2;
        return float(std::min(v, 1e30));
    }

    /// The wavelengths sample() chooses among: all of them where the index varies, else
    /// the hero alone (the mixture would repeat one density).
    static int steeringCount(const SampledSpectrum& eta) {
        for (int i = 1; i < NSpectrumSamples; ++i)
            if (eta[i] != eta[0]) return NSpectrumSamples;
        return 1;
    }

    /// The density of wi when the lobe choice and refraction follow one relative index.
    double pdfForEta(const MicrofacetDistribution& dist, const Vector3f& wo, const Vector3f& wi, float eta) const {
        if (wo.z * wi.z > 0.f) {
            Vector3f m;
            float cosOM;
            if (!reflectionNormal(wo, wi, m, cosOM)) return 0.0;
            // Reflection maps m to wi with |dωi/dωm| = 4 |wo·m| (Walter 2007, eq. 14).
            return normalPdf(dist, wo, m) * fresnelDielectric(cosOM, eta) / (4.0 * std::abs(cosOM));
        }
        Refraction r;
        if (!refractionNormal(wo, wi, eta, r)) return 0.0;
        // Refraction: |dωi/dωm| = ηi² |wi·m| / (ηo wo·m + ηi wi·m)² (Walter 2007, eq. 17).
        double F = r.fresnel(wo, eta);
        return normalPdf(dist, wo, r.m) * (1.0 - F) * r.etaI * r.etaI * std::abs(r.cosIM) / r.v2;
    }

    double normalPdf(const MicrofacetDistribution& dist, const Vector3f& wo, const Vector3f& m) const {
        return m_sampleVisible ? dist.visiblePdf(wo, m) : dist.normalPdf(m);
    }
    static float toPdf(double p) { return p > 0.0 ? float(std::min(p, 1e30)) : 0.f; }

    MicrofacetParams m_mf;  // the roughness, constant or textured
    bool m_sampleVisible;
    RelativeIOR m_eta;
    Ref<ITexture> m_reflectance, m_transmittance;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::RoughDielectric)
