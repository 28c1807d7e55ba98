// bsdf "roughplastic" — a rough dielectric coating over a diffuse substrate (Mitsuba 3's
// rough plastic): a microfacet reflection lobe off the coating (GGX or Beckmann, the
// Fresnel reflectance of each microfacet) plus the substrate's diffuse light crossing
// the coating twice (components/bsdf/plastic_common.hpp has the model):
//
//   f(wo, wi) = F(wo·h) R_s D(h) G(wo, wi) / (4 cosθo cosθi)
//             + ρ / (1 − R_int·(ρ | 1)) · T(θo) T(θi) / (π η²)
//
// T(θ), the rough coating's transmittance, and R_int, its reflectance for diffuse light
// from inside, are computed as Mitsuba computes them (single scattering on the
// microfacets; light they mask is lost) and T is tabulated over cosθ ∈ [0, 1] (64 nodes,
// linear interpolation): see buildTable(). Unlike the smooth `plastic`, the rough model
// thus loses the light its microfacets mask, as Mitsuba's does: a white roughplastic
// seen from the normal reflects 97 % at GGX α = 1e-4 but only 34 % at α = 1 (both
// renderers agree to 1 %). Deriving R_int from T by reciprocity instead would conserve
// energy but make the diffuse part 8-16 % brighter than Mitsuba's at α = 0.2-0.4. G in the specular lobe is effigi's
// height-correlated Smith term (as roughconductor; Mitsuba uses the product G1 G1, a few
// % brighter at α >= 0.3). Isotropic only, like Mitsuba. One-sided: black seen from below.
//
// Sampling: the microfacet lobe with probability ∝ (1 − T(θo))·w, else cosine-weighted
// diffuse through the nested `warp` if one is given (plastic_common.hpp); sample()'s f and
// pdf are f() and pdf() at the sampled direction. The microfacet lobe samples visible
// normals itself (Heitz & d'Eon 2014), as warp `ggx_visible_normals` does, but with the
// parameters of each call (wo, α), which a nested warp of fixed parameters cannot take.
//
// Parameters (as Mitsuba 3): distribution (beckmann | ggx), alpha (0.1), sample_visible
// (true), int_ior ("polypropylene"), ext_ior ("air"), diffuse_reflectance (0.5),
// specular_reflectance (1), nonlinear (false); and
//   warp  nested warp (optional)  sampler of the diffuse lobe; default cosine-weighted
//
// References: A. Weidlich, A. Wilkie, "Arbitrarily Layered Micro-Facet Surfaces",
// GRAPHITE 2007; B. Walter et al., "Microfacet Models for Refraction through Rough
// Surfaces", EGSR 2007; E. Heitz, E. d'Eon, "Importance Sampling Microfacet-Based BSDFs
// using the Distribution of Visible Normals", EGSR 2014; Mitsuba 3 documentation.
#include "microfacet_params.hpp"
#include "plastic_common.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/render/fresnel.hpp"

#include <array>

namespace effigi {
namespace {

class RoughPlastic final : public Implements<IBSDF> {
public:
    static Schema schema() {
        Schema s("bsdf", "roughplastic", "Rough plastic: a microfacet dielectric coating over a diffuse substrate, one-sided.");
        s.cite("A. Weidlich, A. Wilkie, Arbitrarily Layered Micro-Facet Surfaces, GRAPHITE 2007; B. Walter et al., "
               "EGSR 2007; Mitsuba 3 roughplastic");
        declareMicrofacet(s);
        declarePlastic(s);
        using P = std::vector<std::pair<std::string, PropertyValue>>;
        auto ggx = [](P p) {
            p.emplace_back("distribution", std::string("ggx"));
            return p;
        };
        s.addConformance({"default", {}});
        s.addConformance({"ggx 0.3 nonlinear", ggx({{"alpha", 0.3}, {"nonlinear", true}})});
        s.addConformance({"ggx 1e-4 white", ggx({{"alpha", 1e-4}, {"diffuse_reflectance", 1.0}})});
        s.addConformance({"beckmann 1e-4", {{"alpha", 1e-4}}});
        s.addConformance({"ggx 1 white", ggx({{"alpha", 1.0}, {"diffuse_reflectance", 1.0}})});
        s.addConformance({"beckmann 1 white", {{"alpha", 1.0}, {"diffuse_reflectance", 1.0}}});
        s.addConformance({"ggx 0.2 ior 1.0001", ggx({{"alpha", 0.2}, {"int_ior", 1.0001}, {"ext_ior", 1.0},
                                                      {"diffuse_reflectance", 1.0}})});
        s.addConformance({"ggx 0.2 ior 3.5", ggx({{"alpha", 0.2}, {"int_ior", 3.5}, {"ext_ior", 1.0},
                                                   {"diffuse_reflectance", 1.0}})});
        s.addConformance({"ggx 0.3 black substrate", ggx({{"alpha", 0.3}, {"diffuse_reflectance", 0.0}})});
        s.addConformance({"ggx 0.3 no specular", ggx({{"alpha", 0.3}, {"specular_reflectance", 0.0}})});
        s.addConformance({"ggx 0.3 all normals", ggx({{"alpha", 0.3}, {"sample_visible", false}})});
        s.addConformance({"beckmann 0.3 all normals", {{"alpha", 0.3}, {"sample_visible", false}}});
        return s;
    }

    explicit RoughPlastic(const Properties& p)
        : m_params(p), m_dist(readMicrofacet(p)), m_sampleVisible(p.getBool("sample_visible")) {
        if (m_dist.alphaX() != m_dist.alphaY())
            failAt(p.whereOf("alpha_u"), "{}: roughplastic is isotropic (as Mitsuba's): give 'alpha', not "
                                         "'alpha_u' and 'alpha_v'", p.describe());
        if (m_params.eta == 1.f)
            failAt(p.whereOf("int_ior"), "{}: 'int_ior' and 'ext_ior' must differ (as in Mitsuba)", p.describe());
        buildTable();
    }

    std::uint32_t flags() const override { return BSDFReflection | m_params.lobes(BSDFGlossy); }

    SampledSpectrum f(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                      const SampledWavelengths& lambda, TransportMode) const override {
        if (!(wo.z > 0.f && wi.z > 0.f)) return SampledSpectrum(0.f);
        SampledSpectrum value = m_params.substrate(si, lambda, transmittance(wo.z), transmittance(wi.z), m_rInt);
        if (Vector3f h; reflectionHalfVector(wo, wi, h)) {
            float D = m_dist.D(h), G = m_dist.G(wo, wi);
            if (D > 0.f && G > 0.f) {
                // In double: at α = 1e-4 and grazing, D / cos² alone leaves float range.
                double scale = double(D) * G * fresnelDielectric(dot(wo, h), m_params.eta) / (4.0 * double(wo.z) * wi.z);
                value += m_params.specular->eval(si, lambda) * float(std::min(scale, 1e30));
            }
        }
        return value;
    }

    float pdf(const SurfaceInteraction&, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&,
              TransportMode) const override {
        if (!(wo.z > 0.f && wi.z > 0.f)) return 0.f;
        float pSpecular = m_params.specularProbability(transmittance(wo.z));
        double pdf = (1.0 - pSpecular) * m_params.diffuseWarp.pdf(wi);
        if (Vector3f h; reflectionHalfVector(wo, wi, h)) {
            // Reflection maps m to wi with |dωi / dωm| = 4 (wo·m) (Walter 2007, eq. 14).
            float pm = m_sampleVisible ? m_dist.visiblePdf(wo, h) : m_dist.normalPdf(h);
            pdf += pSpecular * double(pm) / (4.0 * dot(wo, h));
        }
        return float(std::min(pdf, 1e30));
    }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float uc, const Point2f& u,
                                     SampledWavelengths& lambda, TransportMode mode) const override {
        if (!(wo.z > 0.f)) return std::nullopt;  // one-sided
        float pSpecular = m_params.specularProbability(transmittance(wo.z));
        BSDFSample bs;
        if (uc < pSpecular) {
            Vector3f m = m_sampleVisible ? m_dist.sampleVisible(wo, u) : m_dist.sampleNormal(u);
            float cosOM = dot(wo, m);
            if (!(cosOM > 0.f)) return std::nullopt;  // a back-facing normal (only when sampling all of D)
            bs.wi = normalize(2.f * cosOM * m - wo);
            bs.flags = BSDFReflection | BSDFGlossy;
        } else {
            bs.wi = m_params.diffuseWarp.sample(u);
            bs.flags = BSDFReflection | BSDFDiffuse;
        }
        bs.pdf = pdf(si, wo, bs.wi, lambda, mode);
        // Below the surface, the disk's rim, or so unlikely that f·cosθ/pdf would overflow.
        if (!(bs.pdf >= std::numeric_limits<float>::min())) return std::nullopt;
        bs.f = f(si, wo, bs.wi, lambda, mode);
        return bs;
    }

private:
    static constexpr int TableSize = 64, QuadratureSide = 32;

    /// Mitsuba's tables, by the same single-scattering integrals over the normals visible
    /// from w (Heitz & d'Eon 2014), each a 32 × 32 midpoint rule in sample space:
    ///   T(μ)  = E_m[(1 − F(w·m; η)) G1(w_t)]   w_t refracted through m (light entering)
    ///   R(μ)  = E_m[F(w·m; 1/η) G1(w_r)]       w_r reflected (light inside, with TIR)
    /// at the nodes μ_k = k / (TableSize − 1) (the first at 1e-6: the lobe is undefined
    /// exactly at grazing), and R_int = 2 ∫ R(μ) μ dμ by the trapezoidal rule. Light the
    /// microfacets mask is lost, not returned: as in Mitsuba, so images agree with it.
    void buildTable() {
        const float eta = m_params.eta, invEta = 1.f / eta;
        const double h = 1.0 / (TableSize - 1);
        double rInt = 0.0;
        for (int k = 0; k < TableSize; ++k) {
            float mu = std::max(1e-6f, float(k) / (TableSize - 1));
            Vector3f w(safeSqrt(1.f - mu * mu), 0.f, mu);
            double t = 0.0, r = 0.0;
            for (int i = 0; i < QuadratureSide; ++i)
                for (int j = 0; j < QuadratureSide; ++j) {
                    Vector3f m = m_dist.sampleVisible(w, Point2f((i + 0.5f) / QuadratureSide, (j + 0.5f) / QuadratureSide));
                    float c = dot(w, m);
                    if (!(c > 0.f)) continue;
                    Vector3f wr = 2.f * c * m - w;
                    if (wr.z > 0.f) r += fresnelDielectric(c, invEta) * m_dist.G1(wr);
                    // Snell about m: w_t = −w/η + (c/η − cosθt) m, below the surface.
                    float sin2T = (1.f - c * c) * invEta * invEta;
                    if (sin2T >= 1.f) continue;
                    Vector3f wt = -w * invEta + (c * invEta - std::sqrt(1.f - sin2T)) * m;
                    if (wt.z < 0.f) t += (1.f - fresnelDielectric(c, eta)) * m_dist.G1(wt);
                }
            constexpr double N = QuadratureSide * QuadratureSide;
            m_table[k] = float(std::clamp(t / N, 0.0, 1.0));
            rInt += (k == 0 || k == TableSize - 1 ? 0.5 : 1.0) * h * 2.0 * (r / N) * mu;
        }
        m_rInt = float(std::clamp(rInt, 0.0, 1.0 - 1e-6));
    }

    float transmittance(float cosTheta) const {
        float x = std::clamp(cosTheta, 0.f, 1.f) * (TableSize - 1);
        int i = std::min(int(x), TableSize - 2);
        return lerp(x - float(i), m_table[i], m_table[i + 1]);
    }

    PlasticParams m_params;
    MicrofacetDistribution m_dist;
    bool m_sampleVisible;
    std::array<float, TableSize> m_table{};
    float m_rInt = 0.f;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::RoughPlastic)
