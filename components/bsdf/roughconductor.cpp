// bsdf "roughconductor" — a rough metal: specular reflection from a random surface of
// microfacets, each a smooth conductor with the complex index η + ik (Torrance–Sparrow
// with the Smith masking of Walter et al. 2007 and Heitz 2014).
//
//   f(wo, wi) = F(wo·h; η, k) · R · D(h) · G(wo, wi) / (4 cosθo cosθi),  h = (wo + wi)/|wo + wi|
//
// D is GGX or Beckmann (effigi/render/microfacet.hpp), anisotropic along the shading
// tangent; G the height-correlated Smith masking-shadowing 1 / (1 + Λ(wo) + Λ(wi)) (Mitsuba
// 3 uses the uncorrelated product G1 G1, so f differs from it by that factor, at most a
// few % below α = 0.3). Light scattered more than once between the microfacets is not
// modelled: a white metal seen from the normal returns 99 % of the light at α = 0.1 (GGX;
// Beckmann 100 %) but 1 − ln 2 = 31 % at α = 1 (GGX; Beckmann 46 %) (tests/test_microfacet).
// One-sided like conductor: black seen from below (wrap it in twosided for both sides).
//
// Sampling: the microfacet normal from the normals visible from wo (sample_visible, the
// default: weight F·R·G/G1(wo) <= 1) or from D cosθm, then wi = reflect(wo, m); the
// sample's f and pdf are f(wo, wi) and pdf(wo, wi) recomputed from wi, so that they agree
// with those functions to the last bit even for α = 1e-4, where one float ulp of a
// direction is 1e-3 of the lobe's width.
//
// Parameters (as Mitsuba 3):
//   distribution          string  beckmann (default) | ggx
//   alpha                 texture 0.1; or alpha_u, alpha_v (anisotropic); float or texture
//   sample_visible        bool    true
//   material              string  "none" (100 % mirror, η = 0, k = 1) or a measured metal
//   eta, k                texture (unbounded spectrum)  the complex index, instead of material
//   specular_reflectance  texture (reflectance, default 1)  factor R on the Fresnel term
//
// References: B. Walter, S. Marschner, H. Li, K. Torrance, "Microfacet Models for
// Refraction through Rough Surfaces", EGSR 2007; E. Heitz, "Understanding the
// Masking-Shadowing Function in Microfacet-Based BRDFs", JCGT 3(2), 2014.
#include "conductor_ior.hpp"
#include "microfacet_params.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/render/fresnel.hpp"

namespace effigi {
namespace {

class RoughConductor final : public Implements<IBSDF> {
public:
    static Schema schema() {
        Schema s("bsdf", "roughconductor", "Rough conductor (metal): GGX or Beckmann microfacets with a spectral complex IOR.");
        s.cite("B. Walter et al., Microfacet Models for Refraction through Rough Surfaces, EGSR 2007; E. Heitz, "
               "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs, JCGT 3(2), 2014");
        declareMicrofacet(s, /*textured=*/true);
        declareConductorIOR(s);
        s.texture("specular_reflectance", 1.f, SpectrumKind::Reflectance,
                  "Factor on the Fresnel reflectance (not physical; for artistic control)")
            .range(0.0, 1.0);
        // effigi-conform: ordinary roughness, both distributions, anisotropy, sampling all
        // of D; extremes: near-specular (1e-4), very rough (1), index-matched, dense and
        // very absorbing.
        using P = std::vector<std::pair<std::string, PropertyValue>>;
        auto ggx = [](P p) {
            p.emplace_back("distribution", std::string("ggx"));
            return p;
        };
        s.addConformance({"default", {}});
        s.addConformance({"ggx 0.1 gold", ggx({{"alpha", 0.1}, {"material", std::string("Au")}})});
        s.addConformance({"ggx 0.1/0.3", ggx({{"alpha_u", 0.1}, {"alpha_v", 0.3}})});
        s.addConformance({"beckmann 0.3/0.1 copper", {{"alpha_u", 0.3}, {"alpha_v", 0.1}, {"material", std::string("Cu")}}});
        s.addConformance({"ggx 1e-4", ggx({{"alpha", 1e-4}})});
        s.addConformance({"beckmann 1e-4", {{"alpha", 1e-4}}});
        s.addConformance({"ggx 1", ggx({{"alpha", 1.0}})});
        s.addConformance({"beckmann 1", {{"alpha", 1.0}}});
        s.addConformance({"ggx 0.3 eta 4 k 10", ggx({{"alpha", 0.3}, {"eta", 4.0}, {"k", 10.0}})});
        s.addConformance({"ggx 0.3 eta 1.0001 k 0", ggx({{"alpha", 0.3}, {"eta", 1.0001}, {"k", 0.0}})});
        s.addConformance({"ggx 0.3 all normals", ggx({{"alpha", 0.3}, {"sample_visible", false}})});
        s.addConformance({"beckmann 0.3 all normals", {{"alpha", 0.3}, {"sample_visible", false}}});
        return s;
    }

    explicit RoughConductor(const Properties& p)
        : m_mf(p), m_sampleVisible(p.getBool("sample_visible")),
          m_reflectance(p.getTexture("specular_reflectance", SpectrumKind::Reflectance)) {
        ConductorIOR ior = readConductorIOR(p);
        m_eta = ior.eta;
        m_k = ior.k;
    }

    std::uint32_t flags() const override { return BSDFReflection | BSDFGlossy; }

    SampledSpectrum f(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                      const SampledWavelengths& lambda, TransportMode) const override {
        Vector3f h;
        if (!reflectionHalfVector(wo, wi, h)) return SampledSpectrum(0.f);
        const MicrofacetDistribution dist = m_mf.at(si);
        float D = dist.D(h), G = dist.G(wo, wi);
        if (D == 0.f || G == 0.f) return SampledSpectrum(0.f);
        SampledSpectrum F = fresnelConductor(dot(wo, h), m_eta->eval(si, lambda), m_k->eval(si, lambda));
        // D G / (4 cosθo cosθi) in double: at α = 1e-4 and grazing both cosines, D / cos²
        // alone would leave float range before G brings it back.
        double scale = double(D) * G / (4.0 * double(wo.z) * wi.z);
        return F * m_reflectance->eval(si, lambda) * float(std::min(scale, 1e30));
    }

    float pdf(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&,
              TransportMode) const override {
        Vector3f h;
        if (!reflectionHalfVector(wo, wi, h)) return 0.f;
        const MicrofacetDistribution dist = m_mf.at(si);
        // Reflection maps m to wi with |dωi / dωm| = 4 (wo·m) (Walter 2007, eq. 14).
        float pm = m_sampleVisible ? dist.visiblePdf(wo, h) : dist.normalPdf(h);
        return float(std::min(double(pm) / (4.0 * dot(wo, h)), 1e30));
    }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float, const Point2f& u,
                                     SampledWavelengths& lambda, TransportMode mode) const override {
        if (!(wo.z > 0.f)) return std::nullopt;  // one-sided
        const MicrofacetDistribution dist = m_mf.at(si);
        Vector3f m = m_sampleVisible ? dist.sampleVisible(wo, u) : dist.sampleNormal(u);
        float cosOM = dot(wo, m);
        if (!(cosOM > 0.f)) return std::nullopt;  // a back-facing normal (only when sampling all of D)
        BSDFSample bs;
        bs.wi = normalize(2.f * cosOM * m - wo);
        bs.pdf = pdf(si, wo, bs.wi, lambda, mode);
        // Below the surface or m lost to rounding (pdf 0); or a direction so unlikely
        // (probability < 1e-37) that f·cosθ/pdf would overflow: dropped.
        if (!(bs.pdf >= std::numeric_limits<float>::min())) return std::nullopt;
        bs.f = f(si, wo, bs.wi, lambda, mode);
        bs.flags = BSDFReflection | BSDFGlossy;
        return bs;
    }

private:
    MicrofacetParams m_mf;  // the roughness, constant or textured
    bool m_sampleVisible;
    Ref<ITexture> m_reflectance, m_eta, m_k;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::RoughConductor)
