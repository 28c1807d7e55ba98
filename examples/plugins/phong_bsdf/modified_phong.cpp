// bsdf "modified_phong" — the energy-conserving modified Phong BRDF, as an out-of-tree plugin.
//
// f(wo, wi) = (1 − ks)·kd/π + ks·(n+2)/(2π)·cosⁿα, where α is the angle between wi and the
// mirror direction of wo. The (n+2)/(2π) normalisation makes the lobe's albedo ks at normal
// incidence and less elsewhere, so a diffuse weight plus ks of at most 1 conserves energy:
// the diffuse base gets the (1 − ks) the lobe leaves, at every wavelength. f is symmetric in
// wo and wi (reciprocal); one-sided, like diffuse. Sampling picks the diffuse lobe (cosine
// weighted) or the Phong lobe (density (n+1)/(2π)·cosⁿα about the mirror direction) in
// proportion to their albedos; lobe samples below the horizon are lost.
//
// Parameters:
//   diffuse_reflectance   texture (reflectance, default 0.5)  kd, the colour of the base
//   specular_reflectance  texture (reflectance, default 0.25) ks, the lobe's albedo
//   exponent              float (default 20)                   Phong exponent n
//
// Reference: E. P. Lafortune, Y. D. Willems, "Using the modified Phong reflectance model
// for physically based rendering", Tech. Rep. CW 197, KU Leuven, 1994.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/math/frame.hpp"
#include "effigi/math/warp_functions.hpp"

namespace {
using namespace effigi;

class ModifiedPhong final : public Implements<IBSDF> {
public:
    static Schema schema() {
        Schema s("bsdf", "modified_phong", "Energy-conserving modified Phong reflection (example plugin).");
        s.cite("E. P. Lafortune, Y. D. Willems, Using the modified Phong reflectance model for physically based "
               "rendering, KU Leuven CW 197, 1994");
        s.texture("diffuse_reflectance", 0.5f, SpectrumKind::Reflectance, "Base colour kd; the base reflects (1−ks)·kd")
            .range(0.0, 1.0);
        s.texture("specular_reflectance", 0.25f, SpectrumKind::Reflectance, "Phong lobe albedo ks at normal incidence")
            .range(0.0, 1.0);
        s.real("exponent", 20.0, "Phong exponent n: larger is shinier").range(0.0, 1e5);
        s.addConformance({"default", {}});
        // effigi-conform runs each of these: ordinary, a pure narrow lobe, and n = 0.
        s.addConformance({"glossy", {{"diffuse_reflectance", 0.0}, {"specular_reflectance", 1.0}, {"exponent", 200.}}});
        s.addConformance({"broad", {{"diffuse_reflectance", 1.0}, {"specular_reflectance", 0.5}, {"exponent", 0.}}});
        return s;
    }

    explicit ModifiedPhong(const Properties& p)
        : m_kd(p.getTexture("diffuse_reflectance", SpectrumKind::Reflectance)),
          m_ks(p.getTexture("specular_reflectance", SpectrumKind::Reflectance)), m_n(p.getFloat("exponent")) {}

    std::uint32_t flags() const override { return BSDFReflection | BSDFDiffuse | BSDFGlossy; }

    SampledSpectrum f(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                      const SampledWavelengths& lambda, TransportMode) const override {
        if (!(wo.z > 0.f && wi.z > 0.f)) return SampledSpectrum(0.f);
        SampledSpectrum ks = m_ks->eval(si, lambda);
        return (SampledSpectrum(1.f) - ks) * m_kd->eval(si, lambda) * InvPi +
               ks * ((m_n + 2.f) * Inv2Pi * lobe(wo, wi));
    }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float uc, const Point2f& u,
                                     SampledWavelengths& lambda, TransportMode mode) const override {
        if (!(wo.z > 0.f)) return std::nullopt;
        Vector3f wi;
        if (uc < specularProbability(si)) {
            // cos α = u^(1/(n+1)) has density (n+1)/(2π)·cosⁿα about the mirror direction.
            float cosAlpha = std::pow(u.x, 1.f / (m_n + 1.f));
            float sinAlpha = std::sqrt(std::max(0.f, 1.f - cosAlpha * cosAlpha)), phi = 2.f * Pi * u.y;
            Frame mirror(Vector3f(-wo.x, -wo.y, wo.z));
            wi = mirror.toWorld({sinAlpha * std::cos(phi), sinAlpha * std::sin(phi), cosAlpha});
        } else {
            wi = warp::squareToCosineHemisphere(u);
        }
        BSDFSample bs;
        bs.wi = wi;
        bs.pdf = pdf(si, wo, wi, lambda, mode);  // the mixture density: both lobes can produce wi
        if (!(wi.z > 0.f && bs.pdf > 0.f)) return std::nullopt;
        bs.f = f(si, wo, wi, lambda, mode);
        bs.flags = BSDFReflection | BSDFGlossy;
        return bs;
    }

    float pdf(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&,
              TransportMode) const override {
        if (!(wo.z > 0.f && wi.z > 0.f)) return 0.f;
        float ps = specularProbability(si);
        return (1.f - ps) * warp::squareToCosineHemispherePdf(wi) + ps * (m_n + 1.f) * Inv2Pi * lobe(wo, wi);
    }

private:
    /// cosⁿα, with α between wi and the mirror direction of wo (cos α = dot(reflect(wo), wi)).
    float lobe(const Vector3f& wo, const Vector3f& wi) const {
        float cosAlpha = std::min(-wo.x * wi.x - wo.y * wi.y + wo.z * wi.z, 1.f);
        return cosAlpha > 0.f ? std::pow(cosAlpha, m_n) : 0.f;  // the lobe ends at α = 90° (also for n = 0)
    }
    /// Chance of sampling the Phong lobe: its share of the (wavelength-averaged) albedo.
    float specularProbability(const SurfaceInteraction& si) const {
        float ks = m_ks->evalFloat(si), diffuse = (1.f - ks) * m_kd->evalFloat(si);
        return diffuse + ks > 0.f ? ks / (diffuse + ks) : 0.f;
    }

    Ref<ITexture> m_kd, m_ks;
    float m_n;
};

} // namespace

EFFIGI_EXPORT_COMPONENT(ModifiedPhong)
