// bsdf "orennayar" — rough diffuse reflection (Oren–Nayar): a surface of V-shaped
// Lambertian grooves whose facet slope angles are normally distributed with standard
// deviation σ (radians). Unlike a Lambertian surface it looks flatter (back-scatters more)
// as σ grows: the moon's and clay's retro-reflection.
//
// With α = max(θi, θo), β = min(θi, θo) and cosΔφ the cosine of the azimuth difference
// (Oren & Nayar 1994, §4.4 "functional approximation", eq. 30 and 37):
//   full model (default, as Mitsuba 0.6 `roughdiffuse`)
//     L1 = ρ/π [C1 + cosΔφ C2 tanβ + (1 − |cosΔφ|) C3 tan((α + β)/2)]
//     C1 = 1 − σ²/(2(σ² + 0.33)),  C2 = 0.45 σ²/(σ² + 0.09) (sinα, or sinα − (2β/π)³ when cosΔφ < 0)
//     C3 = 0.125 σ²/(σ² + 0.09) (4αβ/π²)²
//     L2 = 0.17 ρ²/π σ²/(σ² + 0.13) (1 − cosΔφ (2β/π)²)   (one inter-reflection)
//     f  = L1 + L2
//   qualitative model (use_fast_approx = true; pbrt's "OrenNayar")
//     f = ρ/π (A + B max(0, cosΔφ) sinα tanβ),  A = 1 − σ²/(2(σ² + 0.33)), B = 0.45 σ²/(σ² + 0.09)
// The full model's fit dips slightly below zero in back-scattering at grazing angles and
// large σ: those values are clamped to 0. σ = 0 is exactly Lambertian. f is symmetric in (wo, wi) (reciprocal). One-sided like
// diffuse. Sampling is cosine-weighted, as Mitsuba 0.6 does, through a warp (issue 14):
// by default the compiled-in code of warp `cosine_hemisphere`; a nested `warp` (any warp
// onto the sphere of directions) replaces it in sample() and pdf() (cosine_lobe.hpp). A
// direction it draws below the surface is no sample; one covering the upper hemisphere
// keeps the estimator unbiased.
//
// Energy: the approximation is not energy-conserving at ρ = 1: the directional albedo
// reaches 1.005 (qualitative, σ ≈ 0.3, near-grazing) and 1.05 (full model, the L2 term)
// — a property of the published fit, kept as is; ρ <= 0.9 stays below 1.
//
// Parameters:
//   reflectance      texture (reflectance, default 0.5)  ρ
//   alpha            texture (float, default 0.2)        RMS facet slope, Mitsuba 0.6's roughness: σ = α/√2
//   sigma            float (optional, radians)           σ directly, instead of alpha
//   use_fast_approx  bool (default false)                the qualitative model
//   warp             nested warp (optional)              the direction sampler; default cosine-weighted
//
// Reference: M. Oren, S. K. Nayar, "Generalization of Lambert's Reflectance Model",
// SIGGRAPH 1994; Mitsuba 0.6 documentation, "Rough diffuse material (roughdiffuse)".
#include "cosine_lobe.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/itexture.hpp"

namespace effigi {
namespace {

class OrenNayar final : public Implements<IBSDF> {
public:
    static Schema schema() {
        Schema s("bsdf", "orennayar", "Rough diffuse reflection (Oren–Nayar), one-sided.");
        s.cite("M. Oren, S. K. Nayar, Generalization of Lambert's Reflectance Model, SIGGRAPH 1994");
        s.texture("reflectance", 0.5f, SpectrumKind::Reflectance, "Albedo ρ of the Lambertian facets")
            .range(0.0, 1.0);
        s.texture("alpha", 0.2f, SpectrumKind::Unbounded,
                  "RMS facet slope (Mitsuba 0.6 roughdiffuse); σ = α/√2 radians")
            .range(0.0, 100.0);
        s.optional("sigma", ParamType::Float, "Standard deviation σ of the facet slope angle (radians), "
                                              "instead of alpha; 0 is Lambertian")
            .range(0.0, 100.0);
        s.boolean("use_fast_approx", false, "Use the qualitative model (no C3 and inter-reflection terms)");
        declareDiffuseWarp(s, "the reflection");
        using P = std::vector<std::pair<std::string, PropertyValue>>;
        auto cfg = [&](const char* name, P p) { s.addConformance({name, std::move(p)}); };
        cfg("default", {});
        cfg("sigma 0 (Lambertian)", {{"sigma", 0.0}, {"reflectance", 0.9}});
        cfg("sigma 0.3 rgb", {{"sigma", 0.3}, {"reflectance", RGBValue{{0.5f, 0.35f, 0.2f}}}});
        cfg("sigma 1.5 (very rough)", {{"sigma", 1.5}, {"reflectance", 0.9}});
        cfg("sigma 50 (limit)", {{"sigma", 50.0}, {"reflectance", 0.9}});
        cfg("fast sigma 0.5", {{"sigma", 0.5}, {"use_fast_approx", true}, {"reflectance", 0.9}});
        cfg("fast sigma 50", {{"sigma", 50.0}, {"use_fast_approx", true}, {"reflectance", 0.9}});
        cfg("black", {{"reflectance", 0.0}, {"alpha", 1.0}});
        // White: the fit's energy gain, held to the allowance below.
        cfg("white sigma 0.5", {{"sigma", 0.5}, {"reflectance", 1.0}});
        cfg("white sigma 1.5", {{"sigma", 1.5}, {"reflectance", 1.0}});
        cfg("white fast sigma 0.3", {{"sigma", 0.3}, {"use_fast_approx", true}, {"reflectance", 1.0}});
        s.allow({"energy", 1.06, "the Oren–Nayar fit is not energy-conserving: at ρ = 1 its albedo reaches about "
                                 "1.05 near grazing (the L2 inter-reflection term; 1.005 for the qualitative model)"});
        return s;
    }

    explicit OrenNayar(const Properties& p)
        : m_reflectance(p.getTexture("reflectance", SpectrumKind::Reflectance)),
          m_alpha(p.getTexture("alpha", SpectrumKind::Unbounded)), m_fast(p.getBool("use_fast_approx")), m_warp(p) {
        if (p.has("sigma")) {
            if (const Properties::Entry* e = p.find("alpha"); e && !e->fromDefault)
                failAt(e->where, "{}: give either 'alpha' or 'sigma', not both", p.describe());
            m_sigma = p.getFloat("sigma");
        }
    }

    std::uint32_t flags() const override { return BSDFReflection | BSDFDiffuse; }

    SampledSpectrum f(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                      const SampledWavelengths& lambda, TransportMode) const override {
        if (!(wo.z > 0.f && wi.z > 0.f)) return SampledSpectrum(0.f);
        return value(si, wo, wi, lambda);
    }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float, const Point2f& u,
                                     SampledWavelengths& lambda, TransportMode) const override {
        if (!(wo.z > 0.f)) return std::nullopt;
        BSDFSample bs;
        bs.wi = sampleRimLifted(m_warp, u);
        bs.pdf = m_warp.pdf(bs.wi);
        if (!(bs.wi.z > 0.f) || !(bs.pdf > 0.f)) return std::nullopt;  // a nested warp's, below the surface
        bs.f = value(si, wo, bs.wi, lambda);
        bs.flags = BSDFReflection | BSDFDiffuse;
        return bs;
    }

    float pdf(const SurfaceInteraction&, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&,
              TransportMode) const override {
        return oneSidedPdf(m_warp, wo, wi);
    }

private:
    /// f for wo, wi both above the surface.
    SampledSpectrum value(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                          const SampledWavelengths& lambda) const {
        SampledSpectrum rho = m_reflectance->eval(si, lambda);
        float sigma = m_sigma >= 0.f ? m_sigma : std::max(0.f, m_alpha->evalFloat(si)) * 0.70710678f;
        double s2 = double(sigma) * sigma;
        if (s2 == 0.0) return rho * InvPi;
        // Angles in double: tan β and tan((α+β)/2) grow without bound toward grazing.
        double cosO = std::min(1.0, double(wo.z)), cosI = std::min(1.0, double(wi.z));
        double sinO = std::sqrt(std::max(0.0, 1.0 - cosO * cosO)), sinI = std::sqrt(std::max(0.0, 1.0 - cosI * cosI));
        double cosDPhi = 0.0;
        if (sinO > 1e-7 && sinI > 1e-7)
            cosDPhi = std::clamp((double(wo.x) * wi.x + double(wo.y) * wi.y) / (sinO * sinI), -1.0, 1.0);
        // α is the angle farther from the normal (smaller cosine), β the nearer one.
        double sinA = cosO < cosI ? sinO : sinI;
        double tanB = cosO < cosI ? sinI / cosI : sinO / cosO;
        double A = 1.0 - 0.5 * s2 / (s2 + 0.33), k = s2 / (s2 + 0.09);
        if (m_fast) return rho * float((A + 0.45 * k * std::max(0.0, cosDPhi) * sinA * tanB) * InvPi);
        double alpha = std::acos(std::min(cosO, cosI)), beta = std::acos(std::max(cosO, cosI));
        double twoBetaPi = 2.0 * beta / std::numbers::pi;
        double C2 = 0.45 * k * (cosDPhi >= 0.0 ? sinA : sinA - twoBetaPi * twoBetaPi * twoBetaPi);
        double fourAB = 4.0 * alpha * beta / (std::numbers::pi * std::numbers::pi);
        double C3 = 0.125 * k * fourAB * fourAB;
        double L1 = A + cosDPhi * C2 * tanB + (1.0 - std::abs(cosDPhi)) * C3 * std::tan(0.5 * (alpha + beta));
        double L2 = 0.17 * s2 / (s2 + 0.13) * (1.0 - cosDPhi * twoBetaPi * twoBetaPi);
        // The fit's negative lobe (cosΔφ < 0, β and α near grazing, large σ) dips below 0
        // by up to 1e-2; a BRDF cannot, so each wavelength's value is clamped there.
        SampledSpectrum v = rho * float(L1 * InvPi) + rho * rho * float(L2 * InvPi);
        for (int i = 0; i < NSpectrumSamples; ++i) v[i] = std::max(0.f, v[i]);
        return v;
    }

    Ref<ITexture> m_reflectance, m_alpha;
    float m_sigma = -1.f;  ///< σ given directly; negative: from alpha
    bool m_fast;
    DiffuseWarp m_warp;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::OrenNayar)
