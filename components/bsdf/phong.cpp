// bsdf "phong" — the energy-normalised ("modified") Phong model of Mitsuba 0.6: a
// Lambertian base plus a glossy lobe around the mirror direction,
//   f(wo, wi) = ρd/π + ρs (n + 2)/(2π) max(0, wi·R(wo))^n,  R(wo) = (−wo.x, −wo.y, wo.z)
// (Lafortune & Willems 1994). wi·R(wo) = wo·R(wi), so f is reciprocal. The factor
// (n + 2)/(2π) makes the glossy lobe's albedo exactly ρs at normal incidence and at most ρs
// elsewhere, so ρd + ρs <= 1 conserves energy (a warning says so otherwise, as Mitsuba).
// One-sided: black seen from below.
//
// Sampling (Lafortune & Willems 1994, §4): the glossy lobe with probability
// ρs̄/(ρd̄ + ρs̄) (texture means, as Mitsuba 0.6), a direction around R with density
// (n + 1)/(2π) cos^n of its angle to R (directions that end below the surface are lost);
// otherwise cosine-weighted, through a warp (issue 14): by default the compiled-in code of
// warp `cosine_hemisphere`, or a nested `warp` (any warp onto the sphere of directions;
// components/bsdf/cosine_lobe.hpp). pdf() is the mixture of both densities, the diffuse
// one the warp's, so a warp covering the upper hemisphere keeps the estimator unbiased.
//
// Parameters (Mitsuba 0.6 names, snake_case):
//   exponent              texture (float, default 30)         n, the glossiness
//   specular_reflectance  texture (reflectance, default 0.2)  ρs
//   diffuse_reflectance   texture (reflectance, default 0.5)  ρd
//   warp                  nested warp (optional)  sampler of the diffuse lobe; default cosine-weighted
//
// References: E. P. F. Lafortune, Y. D. Willems, "Using the modified Phong reflectance
// model for physically based rendering", Tech. Report CW197, KU Leuven, 1994; Mitsuba 0.6
// documentation, "Modified Phong BRDF (phong)".
#include "cosine_lobe.hpp"

#include "effigi/core/log.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/math/frame.hpp"

namespace effigi {
namespace {

class Phong final : public Implements<IBSDF> {
public:
    static Schema schema() {
        Schema s("bsdf", "phong", "Energy-normalised (modified) Phong BRDF: diffuse plus a glossy cosine-power lobe.");
        s.cite("E. P. F. Lafortune, Y. D. Willems, Using the modified Phong reflectance model for physically based "
               "rendering, KU Leuven CW197, 1994");
        s.texture("exponent", 30.f, SpectrumKind::Unbounded, "Phong exponent n (glossiness)").range(0.0, 1e7);
        s.texture("specular_reflectance", 0.2f, SpectrumKind::Reflectance, "Albedo ρs of the glossy lobe")
            .range(0.0, 1.0);
        s.texture("diffuse_reflectance", 0.5f, SpectrumKind::Reflectance, "Albedo ρd of the diffuse base")
            .range(0.0, 1.0);
        declareDiffuseWarp(s, "the diffuse lobe");
        using P = std::vector<std::pair<std::string, PropertyValue>>;
        auto cfg = [&](const char* name, P p) { s.addConformance({name, std::move(p)}); };
        cfg("default", {});
        cfg("exponent 1e-3 (nearly uniform)", {{"exponent", 1e-3}, {"specular_reflectance", 0.5}});
        cfg("exponent 0", {{"exponent", 0.0}, {"specular_reflectance", 1.0}, {"diffuse_reflectance", 0.0}});
        cfg("exponent 200 rgb", {{"exponent", 200.0}, {"specular_reflectance", RGBValue{{0.6f, 0.3f, 0.1f}}},
                                 {"diffuse_reflectance", RGBValue{{0.1f, 0.3f, 0.4f}}}});
        cfg("exponent 1e6 (near mirror)", {{"exponent", 1e6}, {"specular_reflectance", 0.5}});
        cfg("specular only", {{"specular_reflectance", 1.0}, {"diffuse_reflectance", 0.0}, {"exponent", 5.0}});
        cfg("diffuse only", {{"specular_reflectance", 0.0}, {"diffuse_reflectance", 1.0}});
        cfg("black", {{"specular_reflectance", 0.0}, {"diffuse_reflectance", 0.0}});
        return s;
    }

    explicit Phong(const Properties& p)
        : m_exponent(p.getTexture("exponent", SpectrumKind::Unbounded)),
          m_specular(p.getTexture("specular_reflectance", SpectrumKind::Reflectance)),
          m_diffuse(p.getTexture("diffuse_reflectance", SpectrumKind::Reflectance)), m_warp(p) {
        float d = m_diffuse->mean(), sp = m_specular->mean();
        if (d + sp > 1.f + 1e-3f)
            log::warn("{}: {}: diffuse_reflectance + specular_reflectance exceeds 1 on average: the BRDF gains energy",
                      p.where().str(), p.describe());
        m_specularWeight = d + sp > 0.f ? sp / (d + sp) : 0.5f;
    }

    std::uint32_t flags() const override { return BSDFReflection | BSDFDiffuse | BSDFGlossy; }

    SampledSpectrum f(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                      const SampledWavelengths& lambda, TransportMode) const override {
        if (!(wo.z > 0.f && wi.z > 0.f)) return SampledSpectrum(0.f);
        SampledSpectrum value = m_diffuse->eval(si, lambda) * InvPi;
        double n = exponent(si), c = cosToMirror(wo, wi);
        if (c > 0.0) value += m_specular->eval(si, lambda) * float((n + 2.0) * Inv2Pi * std::pow(c, n));
        return value;
    }

    float pdf(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&,
              TransportMode) const override {
        if (!(wo.z > 0.f && wi.z > 0.f)) return 0.f;
        double n = exponent(si), c = cosToMirror(wo, wi);
        double glossy = c > 0.0 ? (n + 1.0) * Inv2Pi * std::pow(c, n) : 0.0;
        return float(m_specularWeight * glossy + (1.0 - m_specularWeight) * m_warp.pdf(wi));
    }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float uc, const Point2f& u,
                                     SampledWavelengths& lambda, TransportMode mode) const override {
        if (!(wo.z > 0.f)) return std::nullopt;
        BSDFSample bs;
        if (uc < m_specularWeight) {
            // cos of the angle to R distributed ∝ cos^n: its CDF is cos^(n+1), so
            // cos = v^(1/(n+1)) with v = 1 − u in (0, 1] (u = 0 would give the lobe's
            // zero-density rim); sin from expm1 keeps its digits for huge n.
            double n = exponent(si), logU = std::log1p(-double(u.y));
            double cosA = std::exp(logU / (n + 1.0)), sinA = std::sqrt(std::max(0.0, -std::expm1(2.0 * logU / (n + 1.0))));
            double phi = 2.0 * std::numbers::pi * u.x;
            Frame lobe(reflectLocal(wo));
            bs.wi = normalize(lobe.toWorld(Vector3f(float(sinA * std::cos(phi)), float(sinA * std::sin(phi)), float(cosA))));
        } else {
            bs.wi = sampleRimLifted(m_warp, u);
        }
        bs.pdf = pdf(si, wo, bs.wi, lambda, mode);
        if (!(bs.wi.z > 0.f) || !(bs.pdf >= std::numeric_limits<float>::min())) return std::nullopt;
        bs.f = f(si, wo, bs.wi, lambda, mode);
        bs.flags = BSDFReflection | (uc < m_specularWeight ? BSDFGlossy : BSDFDiffuse);
        return bs;
    }

private:
    static Vector3f reflectLocal(const Vector3f& w) { return {-w.x, -w.y, w.z}; }
    /// wi·R(wo) in double, divided by the lengths: the lobe of a huge exponent is narrower
    /// than float rounding of it, and a float unit vector's length is 1 only to ~6e-8, which
    /// cos^n with n = 1e7 would turn into a factor e^0.6 (effigi-conform's lobe chart).
    static double cosToMirror(const Vector3f& wo, const Vector3f& wi) {
        Vector3d a(wo), b(wi);
        double d = -a.x * b.x - a.y * b.y + a.z * b.z;
        return std::min(1.0, d / std::sqrt(glm::dot(a, a) * glm::dot(b, b)));
    }
    double exponent(const SurfaceInteraction& si) const { return std::max(0.0, double(m_exponent->evalFloat(si))); }

    Ref<ITexture> m_exponent, m_specular, m_diffuse;
    float m_specularWeight;
    DiffuseWarp m_warp;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Phong)
